"""The plan is the whole contract: the renderer creates exactly the objects its plan lists, every kind counted.

Every ``device.create_*`` call (textures, buffers, samplers, bind group layouts, bind groups, shader
modules, pipeline layouts, render and compute pipelines, command encoders, query sets, render bundle
encoders: whatever the device offers) is wrapped while a renderer is made and records one frame, and
what was created is compared per kind with ``plan.object_counts()`` (``--explain`` lists each object
and why; render bundle encoders: the scene pass's draws and each fragment post pass, as the plan lists
them). A call made inside another (``create_buffer_with_data`` makes its buffer through ``create_buffer``)
counts once, as the outer call. The device's caches are emptied first
(gpu_cache.py), so an object made for an earlier scene on the same device cannot hide one.

Scenes: every scene in assets/scenes that needs nothing from ../shared, and five scenes the project
never saw, written here, each with facts checked from the device's calls and pixels, not from the plan:

- ``empty``: a camera only, msaa 4 at 800x600: no texture and no pipeline at all, one render pass that
  only clears the output (no resolve, no depth), every pixel the sRGB-encoded clear colour;
- ``lit_no_lights``: a lit, albedo- and normal-mapped material and no [[lights]]: no lighting code in
  any shader, vertices of position + uv only, no normal map uploaded, and the image of the same scene
  with one light of intensity 0 (the lit shader: ambient x albedo) within 1/255;
- ``no_post``: no post chain, msaa 1, a plain rgba8unorm output, two models sharing one mesh, one of
  them mirrored: no post object, one vertex/index pair, two scene pipelines (two windings);
- ``textured_no_normal_map``: albedo and roughness maps, no normal map, FXAA: no tangent attribute, and
  as many mip-chain bind groups as the two images have levels below the top (log2 of their sides);
- ``unlit_chain``: an unlit textured material through grayscale then sharpen at msaa 1: two post passes
  with an intermediate, no lighting, no normal attribute.

Each runs on both post paths (the repository scenes also on the compute path into a swapchain-like output,
which a compute pass cannot write directly). The raw-Vulkan scene renderer, which shares the plan, is checked where it
shares it: the render pass's images and the scene pipelines it creates.
"""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import load_scene
from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target, read_texture
from wgpurender.wgpu_path.post import output_usage
from wgpurender.wgpu_path.scene import SceneRenderer

REPO = Path(__file__).resolve().parent.parent
ASSETS = REPO / "assets"
SCENES = sorted(p for p in (ASSETS / "scenes").glob("*.toml") if "shared" not in p.read_text())
SIZE = (96, 72)
CAMERA = "[camera]\neye = [0.0, 1.6, 4.2]\ntarget = [0.0, 0.2, 0.0]\n"
CLEAR = (0.2, 0.4, 0.6, 1.0)

NEW_SCENES = {
    "empty": f"""[camera]
eye = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
[render]
size = [800, 600]
msaa = 4
clear_color = {list(CLEAR)}
""",
    "lit_no_lights": CAMERA + """
[materials.lit]
albedo_map = "ASSETS/textures/brick_albedo.png"
normal_map = "ASSETS/textures/brick_normal.png"
sampler = { filter = "linear", mipmaps = true }
[[models]]
path = "ASSETS/models/brick_cube.obj"
material = "lit"
transform = { rotate = { euler = [0, 30, 0] } }
[render]
size = [96, 72]
msaa = 4
hdr = true
clear_color = [0.02, 0.02, 0.03, 1.0]
[[post]]
effect = "tonemap"
exposure = 8.0
[[post]]
effect = "vignette"
""",
    "no_post": CAMERA + """
[materials.red]
albedo_color = [0.8, 0.2, 0.1, 1.0]
roughness = 0.5
[[models]]
path = "ASSETS/models/brick_cube.obj"
material = "red"
transform = { translate = [-1.0, 0.0, 0.0] }
[[models]]
path = "ASSETS/models/brick_cube.obj"
material = "red"
transform = { translate = [1.0, 0.0, 0.0], scale = [-1.0, 1.0, 1.0] }
[[lights]]
type = "point"
position = [0.0, 2.0, 2.0]
intensity = 6.0
[render]
size = [96, 72]
msaa = 1
hdr = false
output_format = "rgba8unorm"
""",
    "textured_no_normal_map": CAMERA + """
[materials.rough]
albedo_map = "ASSETS/textures/mirror_albedo.png"
roughness_map = "ASSETS/textures/brick_roughness.png"
sampler = { filter = "linear", mipmaps = true, anisotropy = 4 }
[[models]]
path = "ASSETS/models/brick_torus.glb"
material = "rough"
[[lights]]
type = "directional"
direction = [-0.4, -1.0, -0.6]
intensity = 2.0
[render]
size = [96, 72]
msaa = 4
hdr = false
[[post]]
effect = "fxaa"
""",
    "unlit_chain": CAMERA + """
[materials.flat]
albedo_map = "ASSETS/textures/brick_albedo.png"
unlit = true
sampler = { filter = "linear", mipmaps = false }
[[models]]
path = "ASSETS/models/brick_cube.obj"
material = "flat"
[render]
size = [96, 72]
msaa = 1
hdr = false
[[post]]
effect = "grayscale"
amount = 0.5
[[post]]
effect = "sharpen"
""",
}


def write_scene(tmp_path: Path, name: str, text: str | None = None) -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text((text or NEW_SCENES[name]).replace("ASSETS", ASSETS.as_posix()))
    return path


class Recorder:
    """Wraps every ``create_*`` method of a device and records each outermost call: (kind, kwargs)."""

    def __init__(self, device, monkeypatch) -> None:
        self.calls: list[tuple[str, dict]] = []
        self._depth = 0
        names = [n for n in dir(type(device)) if n.startswith("create_")]
        assert {"create_bind_group", "create_sampler", "create_shader_module", "create_pipeline_layout"} <= set(names)
        for name in names:
            monkeypatch.setattr(device, name, self._wrap(name, getattr(device, name)))

    @staticmethod
    def kind(name: str) -> str:
        return name.removeprefix("create_").removesuffix("_async").replace("buffer_with_data", "buffer")

    def _wrap(self, name, real):
        def call(*args, **kwargs):
            if self._depth == 0:
                self.calls.append((self.kind(name), kwargs))
            self._depth += 1
            try:
                return real(*args, **kwargs)
            finally:
                self._depth -= 1

        return call

    @property
    def made(self) -> Counter:
        return Counter(kind for kind, _ in self.calls)

    def of(self, kind: str) -> list[dict]:
        return [kwargs for k, kwargs in self.calls if k == kind]


class Encoder:
    """The frame's command encoder, recording the passes begun on it (and delegating everything)."""

    def __init__(self, encoder) -> None:
        self.encoder, self.render_passes, self.compute_passes = encoder, [], []

    def begin_render_pass(self, **kwargs):
        self.render_passes.append(kwargs)
        return self.encoder.begin_render_pass(**kwargs)

    def begin_compute_pass(self, **kwargs):
        self.compute_passes.append(kwargs)
        return self.encoder.begin_compute_pass(**kwargs)

    def __getattr__(self, name):
        return getattr(self.encoder, name)


def build_and_record(ctx, monkeypatch, scene_path: Path, post_path: str, size=SIZE, timer=None):
    """(plan, recorder, encoder proxy, output pixels) of one renderer made and one frame recorded.
    ``post_path`` "compute-swapchain": the compute path into an output that cannot be a storage texture."""
    scene = load_scene(scene_path)
    knobs = {"post_path": "compute", "output_storage": False} if post_path == "compute-swapchain" else {
        "post_path": post_path}
    plan = resolve_plan(scene, None, size=size).with_knobs(**knobs, adapter=ctx.adapter_facts())
    target = create_target(ctx, plan.size, plan.target_format, usage=TARGET_USAGE | output_usage(plan.post_passes))
    encoder = Encoder(ctx.device.create_command_encoder())
    monkeypatch.delattr(ctx.device, "_wgpurender_caches", raising=False)  # a fresh device, as far as caches go
    recorder = Recorder(ctx.device, monkeypatch)
    renderer = SceneRenderer(ctx, scene, plan)
    if timer is not None:
        timer.reset()
    renderer.record(encoder, target, timer=timer)
    if timer is not None:
        timer.resolve(encoder.encoder)
    monkeypatch.undo()
    ctx.queue.submit([encoder.finish()])
    assert renderer.plan is plan, "the plan knew its adapter: the renderer did not re-plan"
    return plan, recorder, encoder, read_texture(ctx, target)


def listed(plan) -> Counter:
    """What the plan's own lists (attachments, textures, pipelines, buffers) say, without plan.objects."""
    want: Counter = Counter()
    want["texture"] = sum(a.role != "output" for a in plan.attachments) + len(plan.textures)
    want["render_pipeline"] = (len(plan.pipelines) + len(plan.mipmap_formats)
                               + sum(p.stage == "fragment" for p in plan.post_pipelines))
    want["compute_pipeline"] = (sum(p.stage == "compute" for p in plan.post_pipelines) + bool(plan.culled_draws)
                                + len(plan.ibl_passes))
    want["buffer"] = len(plan.buffers)
    return +want


def check_counts(plan, recorder: Recorder) -> None:
    made = recorder.made
    assert all(o.reason and o.count > 0 for o in plan.objects), "every object says why it is there"
    assert made == Counter(plan.object_counts()), plan.explain()
    kinds = ("texture", "render_pipeline", "compute_pipeline", "buffer")
    assert +Counter({k: made[k] for k in kinds}) == listed(plan), plan.explain()


@pytest.mark.parametrize("post_path", ["fragment", "compute", "compute-swapchain"])
@pytest.mark.parametrize("scene_path", SCENES, ids=[p.stem for p in SCENES])
def test_renderer_creates_what_the_plan_lists(ctx, monkeypatch, scene_path, post_path):
    plan, recorder, _, _ = build_and_record(ctx, monkeypatch, scene_path, post_path)
    check_counts(plan, recorder)
    for call in recorder.of("texture"):
        label = call["label"]
        fmt = plan.attachment(label).format if plan.has_attachment(label) else next(
            t.format for t in plan.textures if t.path.name == label)
        assert call["format"] == fmt


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
@pytest.mark.parametrize("name", sorted(NEW_SCENES))
def test_new_scenes_create_what_the_plan_lists(ctx, monkeypatch, tmp_path, name, post_path):
    size = None if name == "empty" else SIZE  # the empty scene at its own 800x600 (it only clears)
    plan, recorder, _, _ = build_and_record(ctx, monkeypatch, write_scene(tmp_path, name), post_path, size)
    check_counts(plan, recorder)
    assert recorder.made["bind_group"] == plan.object_counts().get("bind_group", 0)


def test_a_culled_scene_creates_what_the_plan_lists(ctx, monkeypatch, tmp_path):
    """GPU culling (core/plan/culling.py) adds its buffers, compute pipeline and bind groups: all listed."""
    text = NEW_SCENES["no_post"]
    path = write_scene(tmp_path, "culled", text.replace("[[models]]", "[[models]]\ninstances = { grid = [3, 2, 1] }"))
    monkeypatch.setattr("wgpurender.core.plan.culling.GPU_CULL_MIN", 2)
    plan, recorder, _, _ = build_and_record(ctx, monkeypatch, path, "fragment")
    assert len(plan.culled_draws) == 2, plan.explain()  # the mirrored model's copies are a draw of their own
    check_counts(plan, recorder)


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
def test_a_timed_frame_creates_nothing_more(ctx, monkeypatch, post_path):
    """Timestamps on every pass (a benchmark's timer, whose query set is its own) add no object to the plan's."""
    from wgpurender.wgpu_path.device.timing import PassTimer

    if not ctx.has("timestamp-query"):
        pytest.skip("this adapter has no timestamp queries")
    timer = PassTimer(ctx, max_passes=8)
    plan, recorder, _, _ = build_and_record(ctx, monkeypatch, ASSETS / "scenes" / "final.toml", post_path,
                                            timer=timer)
    check_counts(plan, recorder)
    assert len(timer.labels) == 1 + len(plan.post_passes), "every pass was timed"


def srgb8(linear: float) -> int:
    encoded = 12.92 * linear if linear <= 0.0031308 else 1.055 * linear ** (1 / 2.4) - 0.055
    return round(encoded * 255)


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
def test_an_empty_scene_only_clears(ctx, monkeypatch, tmp_path, post_path):
    plan, recorder, encoder, pixels = build_and_record(ctx, monkeypatch, write_scene(tmp_path, "empty"), post_path,
                                                       size=None)
    assert plan.size == (800, 600)
    assert recorder.calls == [], "a camera-only scene needs no texture, buffer, pipeline or bind group"
    assert len(encoder.render_passes) == 1 and not encoder.compute_passes
    (only,) = encoder.render_passes
    (color,) = only["color_attachments"]
    assert color["load_op"] == "clear" and "resolve_target" not in color and only["depth_stencil_attachment"] is None
    want = [srgb8(c) for c in CLEAR[:3]] + [255]
    assert np.array_equal(np.unique(pixels.reshape(-1, 4), axis=0), [want])
    text = plan.explain()
    assert "msaa_color: none <- render.msaa = 4, but there are no models" in text
    assert "clear output to (0.2, 0.4, 0.6, 1), nothing to draw" in text


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
def test_a_lit_material_without_lights_builds_the_unlit_variant(ctx, monkeypatch, tmp_path, post_path):
    path = write_scene(tmp_path, "lit_no_lights")
    plan, recorder, _, pixels = build_and_record(ctx, monkeypatch, path, post_path)
    modules = [m["code"] for m in recorder.of("shader_module")]
    scene_modules = [code for code in modules if "fn vs_main(in: VertexIn" in code]
    assert len(scene_modules) == 1 and "blinn_phong" not in scene_modules[0] and "fn shade(" not in scene_modules[0]
    (pipeline,) = [p for p in recorder.of("render_pipeline") if p["vertex"]["buffers"]]
    assert pipeline["vertex"]["buffers"][0]["array_stride"] == (3 + 2) * 4, "position and uv only: no normal"
    assert [t["label"] for t in recorder.of("texture") if t["label"].endswith(".png")] == ["brick_albedo.png"]
    assert "lighting: none <- the scene has no [[lights]]" in plan.explain()
    # The lit shader with a light of intensity 0 computes ambient x albedo: the same image.
    dark = path.read_text() + '[[lights]]\ntype = "directional"\ndirection = [0.0, -1.0, 0.0]\nintensity = 0.0\n'
    lit_plan, _, _, lit_pixels = build_and_record(ctx, monkeypatch, write_scene(tmp_path, "dark_light", dark),
                                                  post_path)
    assert "lighting" in lit_plan.features
    diff = np.abs(pixels.astype(int) - lit_pixels.astype(int))
    assert diff.max() <= 1, f"{(diff > 1).sum()} channels differ by more than 1/255"
    assert np.unique(pixels.reshape(-1, 4), axis=0).shape[0] > 10, "the cube is drawn, not only the background"


def test_no_post_scene_shares_its_mesh_and_splits_its_winding(ctx, monkeypatch, tmp_path):
    plan, recorder, encoder, _ = build_and_record(ctx, monkeypatch, write_scene(tmp_path, "no_post"), "compute")
    assert [t["label"] for t in recorder.of("texture")] == ["depth"]
    meshes = [b["label"] for b in recorder.of("buffer") if b["label"] in ("scene-vertices", "scene-indices")]
    assert meshes == ["scene-vertices", "scene-indices"], "two models of one mesh and one variant: one buffer pair"
    assert "1 mesh(es)" in dict(plan.buffers)["scene-vertices"], "the one mesh is uploaded once"
    windings = sorted(p["primitive"]["front_face"] for p in recorder.of("render_pipeline"))
    assert windings == ["ccw", "cw"]
    assert not recorder.of("compute_pipeline") and not encoder.compute_passes and len(encoder.render_passes) == 1
    text = plan.explain()
    assert "scene_color, post passes: none <- no [[post]] effects" in text
    assert "msaa_color: none <- render.msaa = 1" in text


def test_textures_without_a_normal_map_have_no_tangents(ctx, monkeypatch, tmp_path):
    plan, recorder, _, _ = build_and_record(ctx, monkeypatch, write_scene(tmp_path, "textured_no_normal_map"),
                                            "fragment")
    (scene_pipeline,) = [p for p in recorder.of("render_pipeline") if p["vertex"]["buffers"]]
    assert scene_pipeline["vertex"]["buffers"][0]["array_stride"] == (3 + 3 + 2) * 4, "position, normal, uv"
    # levels below the top of a 256x256 and a 512x512 image: one bind group each
    mip_groups = int(math.log2(256)) + int(math.log2(512))
    assert recorder.made["bind_group"] == mip_groups + 2 + 1 + 1, "camera, objects, one material, one FXAA pass"


@pytest.mark.parametrize("name", sorted(NEW_SCENES) + [p.stem for p in SCENES])
def test_the_raw_path_builds_the_plans_images_and_pipelines(monkeypatch, tmp_path, name):
    """The raw scene renderer: the render pass's images and its scene pipelines, as the plan lists them."""
    from wgpurender.raw_path.scene import frame as raw_frame
    from wgpurender.raw_path.scene import scene_subpass

    path = write_scene(tmp_path, name) if name in NEW_SCENES else ASSETS / "scenes" / f"{name}.toml"
    images, pipelines = [], []
    real_image, real_pipeline = raw_frame.create_image, scene_subpass.create_pipeline

    def image(ctx, owned, size, fmt, usage, samples=1, **kwargs):
        images.append((fmt, samples))
        return real_image(ctx, owned, size, fmt, usage, samples, **kwargs)

    def pipeline(ctx, owned, desc, layout, render_pass):
        pipelines.append(desc.samples)
        return real_pipeline(ctx, owned, desc, layout, render_pass)

    monkeypatch.setattr(raw_frame, "create_image", image)
    monkeypatch.setattr(scene_subpass, "create_pipeline", pipeline)
    size = None if name == "empty" else SIZE
    raw_frame.render_scene_reference(path, size=size)
    plan = resolve_plan(load_scene(path), None, size=size)
    shared = [(a.format, a.sample_count) for a in plan.attachments
              if a.role in ("msaa-color", "depth") or (a.role == "scene-color" and plan.post_steps)]
    target = (plan.output_format, 1)
    assert Counter(images) - Counter([target]) >= Counter(shared) and images.count(target) >= 1
    assert not any(samples > 1 for _, samples in images) or plan.has_attachment("msaa_color")
    assert sorted(pipelines) == sorted(p.sample_count for p in plan.pipelines)
