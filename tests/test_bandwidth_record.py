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
from wgpurender.core.plan import AdapterFacts, build_plan
from wgpurender.core.scene import load_scene

SUBPASS = Path(__file__).resolve().parent.parent / "assets" / "scenes" / "final_subpass.toml"


@pytest.fixture(autouse=True)
def record_file(tmp_path, monkeypatch):
    monkeypatch.setenv(bandwidth.RECORD_ENV, str(tmp_path / "bandwidth.json"))


def _plan(adapter: str):
    facts = AdapterFacts("DiscreteGPU", frozenset({"timestamp-query"}), adapter)
    return build_plan(load_scene(SUBPASS), size=(3840, 2160)).with_knobs(adapter=facts, post_path="compute")


def test_explain_says_not_measured_then_shows_the_record():
    plan = _plan("Test GPU 9000")
    assert plan.explain().count("bandwidth: not measured on Test GPU 9000") == 1 + len(plan.post_passes)
    fused = plan.post_passes[0]
    assert fused.effect == "tonemap+vignette" and fused.path == "compute"
    bandwidth.save("Test GPU 9000", {bandwidth.pass_key("final_subpass", fused.effect, "compute"): bandwidth.PassRecord(
        ms=0.080, mb=99.5, copy_ms=0.040, size="3840x2160", date="2026-11-24", command="bench")})
    text = plan.explain()
    gbps = 99.5 / 1e3 / 0.080e-3  # 1244 GB/s
    assert f"measured 0.080 ms = {gbps:.3g} GB/s, 50% of a copy of the same bytes (2.49e+03 GB/s)" in text
    assert "bandwidth: not measured on Test GPU 9000" in text  # the scene pass: still not measured
    assert "bandwidth: measured" not in _plan("Another GPU").explain()


def test_post_roofline_records_what_it_measured(ctx):
    from wgpurender.bench.post_roofline import record_bandwidth, run_roofline
    from wgpurender.wgpu_path.scene.frame import adapter_facts

    if not ctx.has("timestamp-query"):
        pytest.skip("post-roofline needs timestamp queries")
    rows = run_roofline(ctx, SUBPASS, (32, 24), 1)
    record_bandwidth(ctx, SUBPASS, (32, 24), rows, "pytest")
    for path in ("fragment", "compute"):
        plan = build_plan(load_scene(SUBPASS), size=(32, 24)).with_knobs(adapter=adapter_facts(ctx), post_path=path)
        lines = [ln for ln in plan.explain().splitlines() if "bandwidth: measured" in ln]
        assert len(lines) == len(plan.post_passes) and all("32x24" in ln and "`pytest`" in ln for ln in lines)
