"""The windows play glTF animations (core/scene/playback.py, ``play(t)`` on both paths' scene drawables).

A window-like loop (the drawable built once from the scene's own plan, then ``play(t)`` and one frame per clock
time, as wgpu_path/window and raw_path/window call them) is compared with the offscreen render at ``--time t``:
exactly within one path. The expectations that do not come from another render come from the test's own
numbers: the clip's end is the largest key time the test wrote, a looped time is ``t mod end``, and the triangle
a rotation channel turns covers the place this file computes in float64 (as tests/test_gltf_animation.py).
Every file is built here at run time (tests/gltf_gen.py).
"""

from __future__ import annotations

import os
import subprocess
import sys
from contextlib import ExitStack
from pathlib import Path

import numpy as np
import pytest
from gltf_gen import GltfWriter, scene_text
from test_gltf_animation import (
    CAMERA_KEYS,
    LIGHT_KEYS,
    TRIANGLE,
    _animated_file,
    _camera_and_lamp_file,
    _coverage,
    _lerp,
    _quat_z,
    _rot_z,
    _skinned_file,
)
from test_gltf_render import SIZE, UNLIT
from xvfb import xvfb_display  # noqa: F401 - the shared Xvfb fixture "display"

from wgpurender import api
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene.playback import Track

PATHS = ("wgpu", "raw")


def _two_model_scene(tmp_path):
    """The skinned strip (its joint turns over keys 0..1 s) and a triangle whose node a rotation channel turns
    0 -> 180 degrees over keys 0..2 s: skins and node animation, two clips of different ends, in one scene."""
    _skinned_file(tmp_path)
    _animated_file(tmp_path, "rotation", [0.0, 1.0, 2.0], [_quat_z(0), _quat_z(90), _quat_z(180)], suffix=".glb")
    scene = tmp_path / "both.toml"
    scene.write_text(scene_text("skin.glb", SIZE) + '\n[[models]]\npath = "anim.glb"\n')
    return scene


def _still_scene(tmp_path) -> Path:
    """One unlit triangle in a glTF file without animations, in a scene of its own."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [0.9, 0.6, 0.2, 1.0]}, **UNLIT)
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(TRIANGLE)}, "material": mat}]))
    g.write(tmp_path / "still.glb")
    scene = tmp_path / "still.toml"
    scene.write_text(scene_text("still.glb", SIZE))
    return scene


def _wgpu_loop(ctx, scene, times, moved_bytes: list | None = None) -> tuple[np.ndarray, list[int]]:
    """The wgpu window's per-frame calls, headless: the renderer built once (the scene's own pose), then for each
    clock time ``play(t)`` and one frame; the last frame's pixels and each frame's buffer writes (``moved_bytes``
    gets the vertex bytes written in all)."""
    from wgpurender.wgpu_path.device.frame_loop import run_frame
    from wgpurender.wgpu_path.scene.frame import SceneRenderer

    plan = resolve_plan(scene, ctx.adapter_facts())
    renderer = SceneRenderer(ctx, plan.scene, plan)
    target = renderer.create_output()
    writes, frame = [], None
    for t in times:
        writes.append(renderer.play(t))
        frame = run_frame(ctx, renderer.record, target, t)
    if moved_bytes is not None:
        moved_bytes.append(renderer.resources.bytes_written)
    return frame.pixels, writes


def _raw_loop(scene, times, moved_bytes: list | None = None) -> tuple[np.ndarray, list[int]]:
    """The raw window's per-frame calls, headless: ``play(t)``, then the frame recorded (the copies first)."""
    from wgpurender.raw_path.device.command_buffers import one_shot
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.device.images import create_image
    from wgpurender.raw_path.device.readback import buffer_to_pixels, record_copy_to_buffer
    from wgpurender.raw_path.scene.frame import SceneFrame
    from wgpurender.raw_path.stages.base import TARGET_USAGE

    vk_ctx = get_vulkan()
    plan = resolve_plan(scene, vk_ctx.adapter_facts())
    writes = []
    with ExitStack() as owned:
        frame = SceneFrame(vk_ctx, owned, plan.scene, plan)
        target = create_image(vk_ctx, owned, plan.size, plan.output_format, TARGET_USAGE)
        for k, t in enumerate(times):
            frame.play(t)
            with one_shot(vk_ctx) as cmd:
                writes.append(frame.record(cmd, target))
                if k == len(times) - 1:
                    buffer = record_copy_to_buffer(vk_ctx, owned, cmd, target)
        pixels = buffer_to_pixels(vk_ctx, buffer, target)
        if moved_bytes is not None:
            moved_bytes.append(frame.resources.bytes_copied)
    vk_ctx.check_validation("the raw window loop")
    return pixels, writes


def _loop(ctx, which, scene, times, moved_bytes: list | None = None):
    return _wgpu_loop(ctx, scene, times, moved_bytes) if which == "wgpu" else _raw_loop(scene, times, moved_bytes)


def _offscreen(which, scene, t) -> np.ndarray:
    draw = api.render if which == "wgpu" else api.reference
    return draw(str(scene), t=t).pixels


# -- the plan: which models play, and the loop ----------------------------------------------------------------------

def test_the_plan_lists_each_animated_model_with_its_clip_end(tmp_path, capsys):
    """The skinned strip's keys end at 1 s, the triangle's at 2 s (the test wrote them); --explain says so."""
    plan = resolve_plan(_two_model_scene(tmp_path), None)
    assert plan.playing == (Track(0, None, 1.0), Track(1, None, 2.0))
    text = plan.explain()
    assert "animation: window plays skin.glb (model 0), animation 0, looping every 1 s" in text
    assert "animation: window plays anim.glb (model 1), animation 0, looping every 2 s" in text


def test_a_named_animation_loops_at_its_own_end(tmp_path):
    def lift(g: GltfWriter) -> list[dict]:  # a second animation: channels whose keys end at 3 s and 1.5 s
        keys, out = g.accessor(np.float32([0.0, 3.0])), g.accessor(np.float32([[0, 0, 0], [0, 4, 0]]))
        short, grow = g.accessor(np.float32([0.0, 1.5])), g.accessor(np.float32([[1, 1, 1], [2, 2, 2]]))
        return [{"name": "lift", "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}},
                                              {"sampler": 1, "target": {"node": 0, "path": "scale"}}],
                 "samplers": [{"input": keys, "output": out}, {"input": short, "output": grow}]}]

    _animated_file(tmp_path, "translation", [0.0, 1.0], [[0, 0, 0], [4, 0, 0]], extra=lift, suffix=".glb")
    scene = tmp_path / "lift.toml"
    scene.write_text(scene_text("anim.glb", SIZE, extra='animation = "lift"\n'))
    assert resolve_plan(scene, None).playing == (Track(0, "lift", 3.0),)


@pytest.mark.parametrize(("t", "local"), [(0.0, 0.0), (0.5, 0.5), (2.0, 0.0), (2.75, 0.75), (7.25, 1.25)])
def test_the_clock_loops_at_the_clip_end(t, local):
    assert Track(0, None, 2.0).local_time(t) == pytest.approx(local)


def test_a_clip_of_one_key_stays_at_zero():
    assert Track(0, None, 0.0).local_time(5.0) == 0.0
    assert Track(0, None, 2.0).local_time(float("inf")) == 0.0


def test_a_still_scene_plays_nothing(tmp_path, capsys):
    scene = _still_scene(tmp_path)
    plan = resolve_plan(scene, None)
    assert plan.playing == ()
    assert "animation:" not in plan.explain()


# -- both paths: the window's frame at t is the offscreen frame at --time t -----------------------------------------

@pytest.mark.parametrize("which", PATHS)
def test_the_window_loop_frame_at_t_is_the_offscreen_frame_at_time_t(ctx, tmp_path, which):
    """Frames at clock 0, 0.3 and 0.6: the last equals ``--time 0.6`` exactly, and differs from the scene's
    own pose (the models moved: not a frozen first frame)."""
    scene = _two_model_scene(tmp_path)
    got, writes = _loop(ctx, which, scene, [0.0, 0.3, 0.6])
    assert np.array_equal(got, _offscreen(which, scene, 0.6)), which
    assert not np.array_equal(got, _offscreen(which, scene, 0.0))
    assert writes[1:] == [2, 2]  # two animated models, one vertex range each per frame


@pytest.mark.parametrize("which", PATHS)
def test_the_window_loops_each_clip_at_its_end(ctx, tmp_path, which):
    """Clock 2.5 s: the strip (end 1 s) is at 0.5 and the triangle (end 2 s) at 0.5: the offscreen frame at 0.5."""
    scene = _two_model_scene(tmp_path)
    got, _ = _loop(ctx, which, scene, [0.0, 2.5])
    assert np.array_equal(got, _offscreen(which, scene, 0.5)), which


@pytest.mark.parametrize("which", PATHS)
def test_a_looped_triangle_lands_at_the_analytic_place(ctx, tmp_path, which):
    """One rotation channel 0 -> 180 degrees over 0..1 s; clock 1.25 s loops to 0.25: 45 degrees. The frame covers
    the float64 triangle turned by 45 degrees (pixels further than 1.5 px from an edge), not the clamped 180."""
    _animated_file(tmp_path, "rotation", [0.0, 1.0], [_quat_z(0), _quat_z(180)], suffix=".glb")
    scene = tmp_path / "turn.toml"
    scene.write_text(scene_text("anim.glb", SIZE))
    got, _ = _loop(ctx, which, scene, [0.0, 1.25])
    covered = got[..., :3].max(axis=2) > 20
    inside, sure = _coverage((TRIANGLE @ _rot_z(45)[:3, :3].T)[None, :, :2], SIZE)
    assert inside.sum() > 100
    assert np.array_equal(covered[sure], inside[sure]), which


@pytest.mark.parametrize("which", PATHS)
def test_a_node_that_turns_mirrored_has_its_winding_rewritten(ctx, tmp_path, which):
    """A STEP scale channel (1, 1, 1) -> (-1, 1, 1) at 1 s: from then on the node mirrors, so the loader reverses
    the triangle's winding (else the single-sided triangle is culled). Frame at 1.5 s = --time 1.5: the triangle
    covers its mirrored float64 place."""
    _animated_file(tmp_path, "scale", [0.0, 1.0, 2.0], [[1, 1, 1], [-1, 1, 1], [-1, 1, 1]], "STEP", suffix=".glb")
    g = GltfWriter()  # a still model first, out of view: the mirrored model's indices do not start at 0
    still = {"attributes": {"POSITION": g.positions(TRIANGLE)}, "indices": g.accessor(np.uint16([0, 1, 2]))}
    g.node(mesh=g.mesh([still]))
    g.write(tmp_path / "still.glb")
    scene = tmp_path / "mirror.toml"
    scene.write_text(scene_text("still.glb", SIZE, extra="[models.transform]\ntranslate = [50, 0, 0]\n")
                     + '\n[[models]]\npath = "anim.glb"\n')
    got, writes = _loop(ctx, which, scene, [0.0, 1.5])
    assert writes[1] == 2  # the vertices and the turned indices
    assert np.array_equal(got, _offscreen(which, scene, 1.5)), which
    covered = got[..., :3].max(axis=2) > 20
    inside, sure = _coverage((TRIANGLE * [-1, 1, 1])[None, :, :2], SIZE)
    assert inside.sum() > 100 and np.array_equal(covered[sure], inside[sure]), which


def _half_moving_file(tmp_path, name: str, both: bool) -> Path:
    """Two nodes of one triangle mesh: node 1 slides right over 0..1 s; node 0 stands still, or slides too."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [0.9, 0.6, 0.2, 1.0]}, **UNLIT)
    mesh = g.mesh([{"attributes": {"POSITION": g.positions(TRIANGLE * 0.5)}, "material": mat}])
    g.node(mesh=mesh, translation=[-1.5, -1.0, 0.0])
    g.node(mesh=mesh, translation=[0.0, 0.5, 0.0])
    keys = g.accessor(np.float32([0.0, 1.0]))
    channels, samplers = [], []
    for node, start in ((0, [-1.5, -1.0, 0.0]), (1, [0.0, 0.5, 0.0]))[(0 if both else 1):]:
        samplers.append({"input": keys, "output": g.accessor(np.float32([start, np.add(start, [0.8, 0, 0])]))})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": "translation"}})
    g.doc["animations"] = [{"channels": channels, "samplers": samplers}]
    g.write(tmp_path / f"{name}.glb", roots=[0, 1])
    scene = tmp_path / f"{name}.toml"
    scene.write_text(scene_text(f"{name}.glb", SIZE))
    return scene


@pytest.mark.parametrize("which", PATHS)
def test_only_the_vertices_that_moved_are_uploaded(ctx, tmp_path, which):
    """A file whose second node moves and first stands still writes half the vertex bytes of the same file with
    both nodes moving (the still node's three vertices are not uploaded again), and the frame is still --time's."""
    half, whole = [], []
    got, _ = _loop(ctx, which, _half_moving_file(tmp_path, "half", False), [0.0, 0.5], half)
    _loop(ctx, which, _half_moving_file(tmp_path, "whole", True), [0.0, 0.5], whole)
    assert half[0] > 0 and 2 * half[0] == whole[0], (half, whole)
    assert np.array_equal(got, _offscreen(which, tmp_path / "half.toml", 0.5)), which


def test_both_paths_draw_the_same_frame_for_the_same_time(ctx, tmp_path):
    """The two loops at one clock time agree within the paths' usual tolerance (the glTF tests': 1/255)."""
    scene = _two_model_scene(tmp_path)
    wgpu_frame, _ = _wgpu_loop(ctx, scene, [0.0, 0.4])
    raw_frame, _ = _raw_loop(scene, [0.0, 0.4])
    assert np.abs(wgpu_frame.astype(int) - raw_frame.astype(int)).max() <= 1


@pytest.mark.parametrize("which", PATHS)
def test_a_paused_clock_writes_nothing(ctx, tmp_path, which):
    """P stops the clock: the same time again re-poses and writes nothing."""
    _, writes = _loop(ctx, which, _two_model_scene(tmp_path), [0.3, 0.3, 0.3])
    assert writes == [2, 0, 0]


def test_a_still_scene_writes_no_buffer_per_frame(ctx, tmp_path, monkeypatch):
    """No animation: the loop makes no playback and no frame writes a buffer after the first (camera uploads
    happen only when the camera changed; wgpu's queue.write_buffer counted over frames 2..4)."""
    import wgpu

    scene = _still_scene(tmp_path)
    from wgpurender.wgpu_path.device.frame_loop import run_frame
    from wgpurender.wgpu_path.scene.frame import SceneRenderer

    plan = resolve_plan(scene, ctx.adapter_facts())
    renderer = SceneRenderer(ctx, plan.scene, plan)
    assert renderer.playback is None
    target = renderer.create_output()
    renderer.play(0.0)
    run_frame(ctx, renderer.record, target, 0.0)
    calls = []
    real = wgpu.GPUQueue.write_buffer
    monkeypatch.setattr(wgpu.GPUQueue, "write_buffer", lambda self, *a, **k: (calls.append(a), real(self, *a, **k)))
    for t in (0.5, 1.0, 1.5):
        assert renderer.play(t) == 0
        run_frame(ctx, renderer.record, target, t)
    assert calls == []


# -- the file camera and KHR lights follow the clock ------------------------------------------------------------------

@pytest.mark.parametrize("t", [0.25, 1.75])
def test_a_file_camera_and_lamp_are_placed_again_each_frame(ctx, tmp_path, t):
    """The rig's camera and lamp nodes slide over keys 0..1 s: after ``play(t)`` the drawn view's eye and the lamp
    sit at the keys' lerp at ``t mod 1``; the scene's own light stays."""
    from wgpurender.wgpu_path.scene.frame import SceneRenderer

    plan = resolve_plan(_camera_and_lamp_file(tmp_path), ctx.adapter_facts())
    renderer = SceneRenderer(ctx, plan.scene, plan)
    renderer.play(t)
    at = t % 1.0
    np.testing.assert_allclose(renderer.scene_pass.scene.camera.eye, _lerp(CAMERA_KEYS, at), atol=1e-6)
    own, lamp = renderer.scene_pass.scene.lights
    np.testing.assert_allclose(own.position, (0.0, 5.0, 0.0))
    np.testing.assert_allclose(lamp.position, _lerp(LIGHT_KEYS, at), atol=1e-6)


# -- the windows themselves (Xvfb) ------------------------------------------------------------------------------------

def _demo_shot(display, scene: Path, raw: bool, size, time: str) -> np.ndarray:
    """The RGB of ``demo SCENE --time TIME``'s last frame (3 frames; the wgpu window without its overlay, or the
    raw window) under the test's Xvfb display."""
    from wgpurender.core.files.imageio import load_png

    shot = scene.parent / "shot.png"
    argv = [sys.executable, "-m", "wgpurender", "demo", *(["--raw"] if raw else ["--no-overlay"]), str(scene),
            "--size", f"{size[0]}x{size[1]}", "--frames", "3", "--time", time, "--screenshot", str(shot)]
    result = subprocess.run(argv, env=dict(os.environ, DISPLAY=display), capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return load_png(shot)[..., :3]


@pytest.mark.parametrize("raw", [False, True], ids=["wgpu-window", "raw-window"])
def test_demo_time_freezes_the_animation_at_t(display, tmp_path, raw):
    """``demo SCENE --time 1.25`` draws every frame at 1.25 s, looped to 0.25 (45 degrees): the screenshot covers
    the float64 triangle at 45 degrees. Before, the window drew the block's pose and refused --time."""
    _animated_file(tmp_path, "rotation", [0.0, 1.0], [_quat_z(0), _quat_z(180)], suffix=".glb")
    scene = tmp_path / "turn.toml"
    scene.write_text(scene_text("anim.glb", SIZE))
    covered = _demo_shot(display, scene, raw, SIZE, "1.25").max(axis=2) > 20
    inside, sure = _coverage((TRIANGLE @ _rot_z(45)[:3, :3].T)[None, :, :2], SIZE)
    assert np.array_equal(covered[sure], inside[sure])


def test_demo_time_on_a_still_scene_is_one_line(tmp_path, capsys):
    from helpers import one_line_refusal

    from wgpurender.cli import main

    scene = _still_scene(tmp_path)
    code = main(["demo", str(scene), "--frames", "1", "--time", "2"])
    one_line_refusal(code, capsys.readouterr().err.strip(), "is static", "--time 2")


@pytest.mark.parametrize("raw", [False, True], ids=["wgpu-window", "raw-window"])
def test_the_window_view_follows_an_animated_file_camera(display, tmp_path, raw):
    """The rig's camera node slides from z = 2 to 6 over 0..1 s and the scene views through it: ``demo --time
    0.25`` shows the view from z = 3, as ``render --time 0.25`` does (the block's own time is 0.5: z = 4), within
    1/255 (the orbit re-derives the eye from its angles)."""
    scene = _camera_and_lamp_file(tmp_path)
    got = _demo_shot(display, scene, raw, (32, 32), "0.25").astype(int)
    draw = api.reference if raw else api.render
    want = np.asarray(draw(str(scene), t=0.25).rgba8())[..., :3].astype(int)
    block = np.asarray(draw(str(scene)).rgba8())[..., :3].astype(int)
    assert np.abs(got - block).max() > 20  # the two views differ: the test can tell them apart
    assert np.abs(got - want).max() <= 1


def test_the_orbit_stays_while_the_file_camera_stands_still():
    """``follow`` restarts the orbit only when a file camera moved: a paused clock (the same pose again) or a
    scene's own camera (no file camera) keep the user's orbit object."""
    from wgpurender.core.scene.model import Camera
    from wgpurender.core.view.orbit import Orbit, follow

    orbit = Orbit.from_look_at((0.0, 0.0, 9.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0))
    file_cam = Camera(eye=(0.0, 0.0, 3.0), target=(0.0, 0.0, 2.0), up=(0.0, 1.0, 0.0), file_camera=(0, 0))
    pose = ((0.0, 0.0, 3.0), (0.0, 0.0, 2.0), (0.0, 1.0, 0.0))
    assert follow(orbit, pose, file_cam) == (orbit, pose)
    own = Camera(eye=(0.0, 0.0, 3.0), target=(0.0, 0.0, 2.0), up=(0.0, 1.0, 0.0))
    assert follow(orbit, None, own) == (orbit, None)
    moved, seen = follow(orbit, None, file_cam)
    assert seen == pose and moved is not orbit
    np.testing.assert_allclose(moved.eye(), (0.0, 0.0, 3.0), atol=1e-9)


def test_finding_the_tracks_of_a_still_scene_reads_no_file(tmp_path, monkeypatch):
    """A still glTF model (no animation: its load found no motion) is skipped without parsing its file again: a
    scene of many still models pays nothing per plan (the parsed-file cache holds only a few files)."""
    from wgpurender.core.scene import gltf_materials, load_scene
    from wgpurender.core.scene.playback import tracks

    scene = _still_scene(tmp_path)
    loaded = load_scene(scene)
    monkeypatch.setattr(gltf_materials, "document", lambda path: pytest.fail(f"{path} parsed again"))
    assert tracks(loaded) == ()


def test_a_skin_without_animations_plays_nothing(tmp_path):
    """A skinned file whose animations are taken out has motion lines (its skin, posed at rest) but nothing to
    play: no track, and no error for the missing animation."""
    import json
    import struct

    from gltf_gen import write_container

    path = _skinned_file(tmp_path)
    data = path.read_bytes()  # the .glb the test wrote: header, JSON chunk, BIN chunk (glTF 2.0, 4.4)
    length = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + length])
    del doc["animations"]
    write_container(path, doc, data[20 + length + 8:])
    scene = tmp_path / "rest.toml"
    scene.write_text(scene_text("skin.glb", SIZE))
    plan = resolve_plan(scene, None)
    assert any("skin 0" in note for note in plan.notes)  # the skin is there (the load's motion line)
    assert plan.playing == ()


def test_a_paused_clock_poses_nothing_again(tmp_path):
    """The same clip time twice (P): the second frame loads no mesh; a new time loads one per animated model (the
    strip's clip ends at 1 s, the triangle's at 2 s: clock 2.5 is 0.5 for both, the poses drawn already)."""
    from wgpurender.core.scene.playback import Playback

    plan = resolve_plan(_two_model_scene(tmp_path), None)
    loads = []
    playback = Playback(plan.scene, plan.playing, lambda key, pose: loads.append((key[0].name, pose.time)))
    for t in (0.5, 0.5, 2.5, 0.7):
        playback.frame(t)
    assert loads == [("skin.glb", 0.5), ("anim.glb", 0.5), ("skin.glb", 0.7), ("anim.glb", 0.7)]
