"""Recording a stage or a scene for the page: set-up, the first frame, and the per-frame template.

The recording is cut in two: ``setup`` (every call up to and including the first frame at ``t = 0``, so the
objects the path makes lazily on its first frame are in it) and ``frame`` (the calls of one later frame). A
frame's uploads (``write_buffer`` / ``write_texture``) are its only data; ``samples[k]`` lists their blobs at
``t = k / fps``. A target whose uploads do not depend on ``t`` has one sample.
"""

from __future__ import annotations

import datetime
import json
from pathlib import Path

from wgpurender.core.errors import UserError
from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
from wgpurender.webpage.packing import pack_blobs, png_base64
from wgpurender.webpage.recorder import BROWSER, Recording, recording_context
from wgpurender.wgpu_path.device.context import GPUContext

UPLOADS = ("writeBuffer", "writeTexture")


def _frame(ctx, record, target, t: float) -> None:
    encoder = ctx.device.create_command_encoder(label="frame")
    record(encoder, target, t)
    ctx.queue.submit([encoder.finish()])


def _record_frames(ctx, recording: Recording, record, target, fps: int, seconds: float) -> tuple[list, list]:
    """(frame template, samples): one frame's calls, and each sample's upload blobs in the template's order.

    The wgpu path writes a uniform only when its value changes (issue 22), so a frame may leave out an upload
    that another frame makes; the template is the frame with every upload, and a frame that left one out
    replays the data last written there (the GPU buffer still holds it)."""
    first, frames = len(recording.calls), []
    for k in range(max(1, round(fps * seconds))):
        start = len(recording.calls)
        _frame(ctx, record, target, k / fps)
        frames.append(recording.calls[start:])
        if k == 1 and _uploads(frames[0]) == _uploads(frames[1]):
            return frames[0], [_uploads(frames[0])]  # static: t changes nothing
    shape = _commands(frames[0])
    for k, calls in enumerate(frames):
        if _commands(calls) != shape:
            raise UserError(f"frame {k} records other commands than frame 0: the page cannot replay this animation")
    template = max(frames, key=lambda calls: len(_uploads(calls)))
    slots = [_upload_key(c) for c in template if c.get("m") in UPLOADS]
    last = {_upload_key(c): _blob(c) for c in recording.calls[:first] if c.get("m") in UPLOADS}
    samples = []
    for calls in frames:
        written = {_upload_key(c): _blob(c) for c in calls if c.get("m") in UPLOADS}
        if not set(written) <= set(slots):
            raise UserError("a frame uploads where the others do not: the page cannot replay this animation")
        last.update(written)
        samples.append([last[key] for key in slots])
    return template, samples


def _commands(calls: list[dict]) -> list:
    """A frame's calls without its uploads: what must be the same in every frame."""
    return [c.get("m") for c in calls if c.get("m") not in UPLOADS]


def _blob(call: dict) -> int:
    return call["a"][2 if call["m"] == "writeBuffer" else 1]["#"]


def _upload_key(call: dict) -> str:
    """Which upload a call is: its method and every argument but the data."""
    i = 2 if call["m"] == "writeBuffer" else 1
    return json.dumps([call["m"], call["a"][:i], call["a"][i + 1:]], sort_keys=True)


def _uploads(calls: list[dict]) -> list[int]:
    return [_blob(c) for c in calls if c.get("m") in UPLOADS]


def _reference(real: GPUContext, target) -> dict:
    """wgpu-native's own frame of the recording (t = 0, set-up just replayed here), a PNG (packing.py): the page
    shows its difference from what the browser drew."""
    from wgpurender.core.files.imageio import to_uint8
    from wgpurender.wgpu_path.device.targets import read_texture

    return {"png": png_base64(to_uint8(read_texture(real, target._raw)))}


def _base(ctx: GPUContext, recording: Recording, target, setup_end: int, frame, samples, fps, meta) -> dict:
    return {
        "meta": {**meta, "device": 0, "target": target._id, "format": target.format, "fps": fps,
                 "frames": len(samples), "exported": f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC "
                 f"from {ctx.describe()} (wgpurender export)"},
        "setup": recording.calls[:setup_end], "frame": frame, "samples": samples,
        "blobs": pack_blobs(recording.calls, recording.blobs),
    }


def record_stage(real: GPUContext, name: str, size: tuple[int, int], fps: int, seconds: float) -> dict:
    from wgpurender.wgpu_path.device.targets import check_format, create_target
    from wgpurender.wgpu_path.stages import get_stage

    cls = get_stage(name)
    ctx, recording = recording_context(real)
    fmt = check_format(cls.default_format)
    stage = cls(ctx, fmt, None)
    stage.resize(size)
    target = create_target(ctx, size, fmt)
    _frame(ctx, stage.record, target, 0.0)
    setup_end = len(recording.calls)
    reference = _reference(real, target)
    frame, samples = _record_frames(ctx, recording, stage.record, target, fps, seconds)
    immediates = "no immediates in a browser: per-draw data from a uniform buffer" if name == "3d" else ""
    meta = {"name": name, "kind": "stage", "size": list(size), "orbit": None,
            "summary": f"Course step {cls.course_step()}. {cls.summary}.",
            "plan": "\n".join(x for x in (f"stage {name}: {cls.summary}", f"output {fmt}, {size[0]}x{size[1]}",
                                          immediates, "animated: recorded uploads replayed in a loop" if
                                          len(samples) > 1 else "static") if x),
            "controls": "Animated: the page replays the recorded frames." if len(samples) > 1 else "A still frame."}
    return {**_base(real, recording, target, setup_end, frame, samples, fps, meta), "reference": reference}


def _machine_folders(scene, plan) -> list[Path]:
    """The folders a scene's page could name (issue 28, item 2): the scene's, its models' and textures', home."""
    files = [scene.path, *(m.path for m in scene.models), *(t.path for t in plan.textures)]
    return [Path.home(), Path.cwd(), *(Path(f).parent for f in files)]


def _published(text: str, scene, plan) -> str:
    from wgpurender.core.files.published_text import without_machine_paths

    return without_machine_paths(text, _machine_folders(scene, plan))


def record_scene(real: GPUContext, path: str, size: tuple[int, int], fps: int, seconds: float) -> dict:
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.core.files.published_text import labels_without_machine_paths
    from wgpurender.core.plan import resolve_plan
    from wgpurender.core.scene import load_scene
    from wgpurender.core.scene.credits import scene_credits
    from wgpurender.wgpu_path.scene.frame import SceneRenderer
    from wgpurender.wgpu_path.scene.shader_interface import CAMERA

    scene = load_scene(path)
    ctx, recording = recording_context(real)
    plan = resolve_plan(scene, BROWSER, size=size, anisotropy=REFERENCE_ANISOTROPY)  # the scene as authored
    renderer = SceneRenderer(ctx, scene, plan)
    target = renderer.create_output()
    _frame(ctx, renderer.record, target, 0.0)
    setup_end = len(recording.calls)
    reference = _reference(real, target)
    frame, samples = _record_frames(ctx, recording, renderer.record, target, fps, 0.0)
    cam = scene.camera
    camera = {"buffer": renderer.scene_pass.camera_buffer._id,
              "fields": {f: CAMERA.offsets[f] for f in ("view", "eye")}} if renderer.scene_pass.draws else None
    meta = {"name": Path(path).stem, "kind": "scene", "size": list(size),
            "orbit": {"eye": list(cam.eye), "target": list(cam.target), "up": list(cam.up), "camera": camera,
                      "orthographic": cam.projection_type == "orthographic"},
            "summary": _published(scene.description or f"scene {Path(path).name}", scene, plan),
            "plan": _published(renderer.plan.explain(), scene, plan),
            "controls": "Drag to orbit the camera, scroll to zoom, double-click to reset.",
            "credits": [c.line() for c in scene_credits(resolve_scene(path))]}
    data = _base(real, recording, target, setup_end, frame, samples, fps, meta)
    folders = _machine_folders(scene, plan)
    data["setup"], data["frame"] = (labels_without_machine_paths(data[k], folders) for k in ("setup", "frame"))
    return {**data, "reference": reference}
