"""``render --explain`` shows each pass's bytes and what the last benchmark on this adapter measured (issue 22.4).

The record (wgpurender/core/files/bandwidth.py) lives in a file per test here ($WGPURENDER_PERF_RECORD). Checked:
"not measured" before any run and for another adapter; after a record, the pass's line shows the time, GB/s
and the % of a same-run copy computed from the recorded numbers (formulas written here); and the
post-roofline benchmark, run for real at a tiny size, records every pass of the plan it measured.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from wgpurender.core.files import bandwidth
from wgpurender.core.plan import AdapterFacts, resolve_plan
from wgpurender.core.scene import load_scene

SUBPASS = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final_subpass.toml"


@pytest.fixture(autouse=True)
def record_file(tmp_path, monkeypatch):
    monkeypatch.setenv(bandwidth.RECORD_ENV, str(tmp_path / "bandwidth.json"))


def _plan(adapter: str):
    facts = AdapterFacts("DiscreteGPU", frozenset({"timestamp-query"}), adapter)
    return resolve_plan(load_scene(SUBPASS), facts, size=(3840, 2160), post_path="compute")


def test_explain_says_not_measured_then_shows_the_record():
    plan = _plan("Test GPU 9000")
    assert plan.explain().count("bandwidth: not measured at 3840x2160 on Test GPU 9000") == 1 + len(plan.post_passes)
    fused = plan.post_passes[0]
    assert fused.effect == "tonemap+vignette" and fused.path == "compute"
    bandwidth.save("Test GPU 9000", {bandwidth.pass_key("final_subpass", fused.effect, "compute"): bandwidth.PassRecord(
        ms=0.080, mb=99.5, copy_ms=0.040, size="3840x2160", date="2026-11-24", command="bench")})
    text = plan.explain()
    gbps = 99.5 / 1e3 / 0.080e-3  # 1244 GB/s
    assert f"measured 0.080 ms = {gbps:.3g} GB/s, 50% of a copy of the same bytes (2.49e+03 GB/s)" in text
    assert "bandwidth: not measured at 3840x2160 on Test GPU 9000" in text  # the scene pass: still not measured
    assert "bandwidth: measured" not in _plan("Another GPU").explain()


def test_post_roofline_records_what_it_measured(ctx):
    from wgpurender.bench.post_roofline import record_bandwidth, run_roofline

    if not ctx.has("timestamp-query"):
        pytest.skip("post-roofline needs timestamp queries")
    rows = run_roofline(ctx, SUBPASS, (32, 24), 1)
    record_bandwidth(ctx, SUBPASS, (32, 24), rows, "pytest")
    for path in ("fragment", "compute"):
        plan = resolve_plan(load_scene(SUBPASS), ctx.adapter_facts(), size=(32, 24), post_path=path)
        lines = [ln for ln in plan.explain().splitlines() if "bandwidth: measured" in ln]
        assert len(lines) == len(plan.post_passes) and all("32x24" in ln and "`pytest`" in ln for ln in lines)


def test_a_record_at_another_size_is_not_shown():
    """Issue 32 item 5: a record made at 96x64 was quoted for a 3840x2160 plan. Only a measurement at the plan's
    own size is shown; otherwise "not measured" with the command that measures this size."""
    plan = _plan("Test GPU 9000")
    fused = plan.post_passes[0]
    bandwidth.save("Test GPU 9000", {bandwidth.pass_key("final_subpass", fused.effect, "compute"): bandwidth.PassRecord(
        ms=0.001, mb=0.05, copy_ms=0.001, size="96x64", date="2026-11-24", command="wgpurender bench post-roofline")})
    text = plan.explain()
    assert "bandwidth: measured" not in text and "96x64" not in text
    assert "`wgpurender bench post-roofline SCENE --size 3840x2160` measures it" in text


def test_a_bench_run_by_another_program_is_not_labelled_with_its_arguments(monkeypatch):
    """The record's command: a wgpurender command as typed, or which program ran the bench (a pytest run's
    arguments once read as ``wgpurender -q -p no:cacheprovider -rfEs``)."""
    from wgpurender.bench.report import command_line

    monkeypatch.setattr("sys.argv", ["/usr/bin/pytest", "-q", "-p", "no:cacheprovider"])
    assert command_line() == "run from pytest, not a wgpurender command"
    monkeypatch.setattr("sys.argv", ["/venv/bin/wgpurender", "bench", "post-roofline", "--size", "64x48"])
    assert command_line() == "wgpurender bench post-roofline --size 64x48"
    monkeypatch.setattr("sys.argv", ["/src/wgpurender/__main__.py", "bench", "perf"])
    assert command_line() == "wgpurender bench perf"


@pytest.mark.parametrize(("immediates", "shown"), [("on", " + immediates"), ("off", "")])
def test_immediates_in_the_layout_only_when_on(immediates, shown):
    """The scene pipeline layout says "+ immediates" when the plan pushes them, nothing when it does not."""
    facts = AdapterFacts("DiscreteGPU", frozenset({"immediates"}), "Test GPU 9000", "Vulkan")
    plan = resolve_plan(load_scene(SUBPASS), facts, immediates=immediates)
    layouts = [o.reason for o in plan.objects if o.kind == "pipeline_layout" and o.name.startswith("scene")]
    assert layouts and all(why == f"groups 0-2{shown} of its variant" for why in layouts)
    assert all("immediates" not in why for why in layouts) or immediates == "on"
