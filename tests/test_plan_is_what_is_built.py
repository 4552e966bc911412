"""The plan is the whole contract: the renderer creates exactly the textures and pipelines its plan lists.

For every scene in assets/scenes that needs nothing from ../shared, on both post paths, the device's
``create_texture``, ``create_render_pipeline`` and ``create_compute_pipeline`` are wrapped while a
renderer is made and draws one frame, and what was created is compared with the plan, count and format:

- textures: every attachment but the output (the caller's), plus every material texture the plan uploads;
- render pipelines: every scene pipeline (variant, formats, winding), every fragment post pipeline (FXAA's
  mask draw included) and one mipmap pipeline per format of the textures that get mip chains;
- compute pipelines: every compute post pipeline;
- buffers (while the renderer is made and records a frame; the readback is the caller's): one per entry of
  ``plan.buffers`` (camera, objects, materials without immediates, each mesh's vertices and indices, each
  post pass's parameters);
- render bundle encoders: the plan's objects of that kind (the scene pass's draws, each fragment post pass).

The device's caches are emptied first (gpu_cache.py), so an object made for an earlier scene on the same
device cannot hide one. Expected values come from the plan; what is counted comes from the device.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from wgpurender.core.plan import build_plan
from wgpurender.core.scene import load_scene
from wgpurender.wgpu_path.post import output_usage
from wgpurender.wgpu_path.scene_render import SceneRenderer
from wgpurender.wgpu_path.scene_render.frame import adapter_facts
from wgpurender.wgpu_path.targets import TARGET_USAGE, create_target

REPO = Path(__file__).resolve().parent.parent
SCENES = sorted(p for p in (REPO / "assets" / "scenes").glob("*.toml") if "shared" not in p.read_text())
SIZE = (96, 72)


class Recorder:
    """Wraps a device's create_* calls and records what they made (kind, format, sample count)."""

    def __init__(self, device, monkeypatch) -> None:
        self.made: Counter = Counter()
        # create_buffer_with_data makes its buffer through create_buffer: counted there, once
        for name in ("create_texture", "create_render_pipeline", "create_compute_pipeline", "create_buffer",
                     "create_render_bundle_encoder"):
            monkeypatch.setattr(device, name, self._wrap(name, getattr(device, name)))

    def _wrap(self, name, real):
        def call(*args, **kwargs):
            if name == "create_texture":
                self.made[("texture", kwargs["format"], kwargs.get("sample_count", 1))] += 1
            elif name == "create_buffer":
                self.made[("buffer",)] += 1
            elif name == "create_render_bundle_encoder":
                self.made[("bundle", kwargs["label"])] += 1
            elif name == "create_render_pipeline":
                self.made[("render", kwargs["fragment"]["targets"][0]["format"])] += 1
            else:
                self.made[("compute", kwargs["label"])] += 1
            return real(*args, **kwargs)

        return call


def expected(plan) -> Counter:
    want: Counter = Counter()
    for a in plan.attachments:
        if a.role != "output":
            want[("texture", a.format, a.sample_count)] += 1
    for t in plan.textures:
        want[("texture", t.format, 1)] += 1
    for p in plan.pipelines:
        want[("render", p.color_format)] += 1
    for pl in plan.post_pipelines:
        if pl.stage == "fragment":
            want[("render", pl.target_format)] += 1
        else:
            want[("compute", f"post-{pl.effects}-{pl.target_format}-compute")] += 1
    for fmt in plan.mipmap_formats:
        want[("render", fmt)] += 1
    if plan.buffers:
        want[("buffer",)] = len(plan.buffers)
    for o in plan.objects:
        if o.kind == "render_bundle_encoder":
            want[("bundle", o.name)] += o.count
    return want


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
@pytest.mark.parametrize("scene_path", SCENES, ids=[p.stem for p in SCENES])
def test_renderer_creates_what_the_plan_lists(ctx, monkeypatch, scene_path, post_path):
    scene = load_scene(scene_path)
    plan = build_plan(scene, size=SIZE).with_knobs(post_path=post_path, adapter=adapter_facts(ctx))
    target = create_target(ctx, SIZE, plan.output_format, usage=TARGET_USAGE | output_usage(plan.post_passes))
    monkeypatch.delattr(ctx.device, "_wgpurender_caches", raising=False)  # a fresh device, as far as caches go
    recorder = Recorder(ctx.device, monkeypatch)
    renderer = SceneRenderer(ctx, scene, plan)
    encoder = ctx.device.create_command_encoder()
    renderer.record(encoder, target)
    monkeypatch.undo()
    ctx.queue.submit([encoder.finish()])
    assert renderer.plan is plan, "the plan knew its adapter: the renderer did not re-plan"
    assert recorder.made == expected(plan), plan.explain()


def test_compute_path_is_planned_and_built_for_a_real_chain(ctx):
    """The check above is not empty: final.toml on the compute path makes compute pipelines, and no mask."""
    plan = build_plan(load_scene(REPO / "assets" / "scenes" / "final.toml"), size=SIZE)
    want = expected(plan.with_knobs(post_path="compute"))
    assert sum(n for key, n in want.items() if key[0] == "compute") == 2
    assert ("texture", "depth16unorm", 1) in expected(plan) and ("texture", "depth16unorm", 1) not in want
