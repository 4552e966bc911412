"""One resolved plan for every entry point (issue 20): every repository scene, on this machine's adapter.

For each scene file in assets/scenes/ (those that need ../shared/anchors skip when it is absent):
- the plans of all entry points are one plan: ``render --explain`` (CLI), the API's ``plan``/``explain``,
  ``Image.plan`` of ``render`` and of ``reference`` (the raw path resolves for its own device with the same
  function), bench's (and the report's timing) runners on both paths, and the two windows' plans (the same
  plan, for a swapchain image: ``output_storage`` off); the report's plan text is checked in test_report.py;
- ``wgpurender render`` then ``wgpurender reference`` with default flags pass ``wgpurender compare``'s default
  threshold (exit 0);
- the API's image equals the CLI's, byte for byte (one process, one machine);
- ``Image.plan`` is the plan ``--explain`` prints for the adapter used.

The scenes render at their own [render] size: that is what a user's default command does.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import wgpurender as w
from wgpurender.cli import main
from wgpurender.core.files.imageio import load_png

REPO = Path(__file__).resolve().parent.parent
SCENES = sorted((REPO / "assets" / "scenes").glob("*.toml"))
ANCHORS = REPO.parent / "shared" / "anchors"


def needs_anchors(path: Path) -> bool:
    return "shared/anchors" in path.read_text() and not ANCHORS.is_dir()


@pytest.fixture(params=SCENES, ids=[p.stem for p in SCENES])
def scene(request) -> Path:
    if needs_anchors(request.param):
        pytest.skip(f"{request.param.name} needs {ANCHORS} (the tutorial's model and texture), absent")
    return request.param


def cli(capsys, *argv: str) -> str:
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def test_there_are_scenes():
    assert len(SCENES) >= 5


def test_every_entry_point_draws_one_plan(scene, ctx, capsys, tmp_path):
    import dataclasses

    from wgpurender.core.scene import load_scene
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.window import window_plan
    from wgpurender.wgpu_path.window.view import DemoView

    explained = cli(capsys, "render", str(scene), "--explain")
    planned = w.plan(scene)
    assert explained == planned.explain() == w.explain(scene)

    # -- the images: CLI render and reference with default flags, compared by the CLI's compare ------------
    ours, raw = tmp_path / "render.png", tmp_path / "reference.png"
    cli(capsys, "render", str(scene), "-o", str(ours))
    cli(capsys, "reference", str(scene), "-o", str(raw))
    assert main(["compare", str(raw), str(ours)]) == 0, capsys.readouterr().out
    capsys.readouterr()

    image = w.render(scene)
    assert np.array_equal(image.rgba8(), load_png(ours))  # the API's image is the CLI's
    assert image.plan == planned and image.plan.explain() == explained  # Image.plan: the plan drawn, as printed
    reference = w.reference(scene)
    assert np.array_equal(reference.rgba8(), load_png(raw))
    assert reference.plan == planned  # the raw path: its own device's facts, the same function, the same plan

    # -- the windows: the same plan, for a swapchain image ------------------------------------------------
    windowed = dataclasses.replace(planned.knobs, output_storage=False)
    demo = DemoView(ctx, str(scene)).plan(planned.output_format)
    assert demo == planned.with_knobs(output_storage=False) and demo.knobs == windowed
    raw_window = window_plan(get_vulkan(), load_scene(scene), None, None)
    assert raw_window == demo

    # -- bench perf and the report's timings: both paths' runners draw the same plan -----------------------
    from wgpurender.bench.scene import RawSceneRunner, SceneRunner
    from wgpurender.wgpu_path.scene import load_renderer

    assert SceneRunner(ctx, scene, planned.size).renderer.plan == planned
    with RawSceneRunner(scene, planned.size) as runner:
        assert runner.stage.frame.plan == planned
    # verify keeps the scene's anisotropy (its references were made so), through the same function
    assert load_renderer(scene, ctx, anisotropy="scene").plan == w.plan(scene, anisotropy="scene")


def test_the_anisotropy_rule_is_resolved_per_adapter_on_both_paths(ctx):
    """What made render and reference differ before (issue 20): the raw path now applies the same rule."""
    from wgpurender.raw_path.device.context import get_vulkan

    final = REPO / "assets" / "scenes" / "final.toml"
    facts = ctx.adapter_facts()
    assert get_vulkan().adapter_facts() == facts  # one device, two paths, the same facts
    wanted = 1 if facts.adapter_type == "CPU" else 8  # core/plan/anisotropy.py's rule; final.toml asks for 8
    assert [s.spec.max_anisotropy for s in w.plan(final).samplers] == [wanted]
    assert [s.spec.max_anisotropy for s in w.plan(final, anisotropy="scene").samplers] == [8]
    assert w.reference(final, size=(64, 48)).plan.samplers == w.plan(final, size=(64, 48)).samplers


def test_a_stage_refuses_an_anisotropy_rule_instead_of_ignoring_it(ctx):
    """The rule applies to scene files; a stage's samplers are its own, so asking for one is an error."""
    for call in (w.render, w.reference):
        with pytest.raises(w.UserError, match="applies to scene files"):
            call("textured", anisotropy="scene")
    assert w.render("triangle", size=(8, 6), anisotropy="auto").plan is None  # the default is no request


def test_the_api_passes_plan_knobs_to_the_one_function(ctx):
    """A knob through the API reaches the plan drawn (and an unknown one is refused, not ignored)."""
    final = REPO / "assets" / "scenes" / "final.toml"
    image = w.render(final, size=(64, 48), post_path="compute", post_fuse=False)
    assert image.plan.post_path == "compute" and all(not p.fused for p in image.plan.post_passes)
    assert image.plan == w.plan(final, size=(64, 48), post_path="compute", post_fuse=False)
    assert image.plan != w.plan(final, size=(64, 48))
    with pytest.raises(w.UserError, match="unknown plan knob 'gamma'"):
        w.plan(final, gamma=2.2)
    with pytest.raises(w.UserError, match="applies to scene files"):
        w.render("triangle", post_path="compute")
    # the raw path draws a knob only at its default: asking it for another is an error, not a different image
    with pytest.raises(w.UserError, match="plan knob reverse_z = True"):
        w.reference(final, size=(64, 48), reverse_z=True)
    with pytest.raises(w.UserError, match="instance_data = 'vertex': the raw path reads instances from a storage"):
        w.reference(final, size=(64, 48), instance_data="vertex")  # the plan would list a vertex buffer not drawn
    assert w.reference(final, size=(64, 48), scene_format="rgba16float").plan.attachment("scene_color").format == \
        "rgba16float"
