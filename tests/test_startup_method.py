"""The startup family's method (issue 31.5): interleaved rounds, paired per-round ratios, the judged row.

The children are stood in for (their totals made up here, per round), so what is checked is the method: which
child runs when, which totals are paired, and which figure the target judges. The children themselves are run
for real in test_bench.py and test_early_context.py.
"""

from __future__ import annotations

import statistics

import pytest

from wgpurender.bench import startup
from wgpurender.bench.markdown_scale import first_pixel_ratio
from wgpurender.bench.report import Result
from wgpurender.bench.startup_child import PHASES

QUICK_LABEL = "no caches"


def _fake(totals: dict[str, list[float]], calls: list[str]):
    """A run_child that logs (path) and returns the next made-up total of its path."""
    seen: dict[str, int] = {}

    def run(path, stage, size, env, preload=True):
        name = path if preload else f"{path} no-preload"
        calls.append(name)
        k = seen[name] = seen.get(name, -1) + 1
        total = totals[name][k]
        out = {**{p: total / 4 for p in PHASES}, "total_ms": total, "spawn_ms": total + 20.0}
        return {**out, "make_ms": total / 2} if path == "wgpu" else out

    return run


def test_rounds_interleave_every_configuration_and_reverse_every_other_round(monkeypatch):
    calls: list[str] = []
    # one warming run each, then 4 rounds
    monkeypatch.setattr(startup, "run_child", _fake({"wgpu": [1.0] * 5, "raw": [1.0] * 5}, calls))
    startup.bench_startup("triangle", (8, 8), rounds=4, quick=True, log=lambda _: None)
    assert calls == ["wgpu", "raw",  # warming
                     "wgpu", "raw", "raw", "wgpu", "wgpu", "raw", "raw", "wgpu"]


def test_the_ratio_rows_pair_each_round_and_their_median_is_not_the_ratio_of_medians(monkeypatch):
    # made so the two differ: raw is slow in the rounds where wgpu is slow (a host that drifts)
    wgpu = [0.0, 500.0, 520.0, 300.0, 310.0, 700.0]
    raw = [0.0, 450.0, 480.0, 290.0, 250.0, 650.0]
    monkeypatch.setattr(startup, "run_child", _fake({"wgpu": wgpu, "raw": raw}, []))
    rows = startup.bench_startup("triangle", (8, 8), rounds=5, quick=True, log=lambda _: None)
    ratio = next(r for r in rows if r.metric == startup.RATIO)
    expected = [w / r for w, r in zip(wgpu[1:], raw[1:], strict=True)]
    assert ratio.path == "wgpu/raw" and ratio.n == 5
    assert ratio.median == pytest.approx(statistics.median(expected))
    assert ratio.p10 == pytest.approx(min(expected) + 0.4 * (sorted(expected)[1] - min(expected)))
    medians = statistics.median(wgpu[1:]) / statistics.median(raw[1:])
    assert abs(ratio.median - medians) > 0.01
    totals = {r.path: r.median for r in rows if r.metric == "total_ms"}
    assert totals == {"wgpu": statistics.median(wgpu[1:]), "raw": statistics.median(raw[1:])}
    spawn = next(r for r in rows if r.metric == "spawn_ms" and r.path == "raw")
    assert spawn.median == pytest.approx(statistics.median(raw[1:]) + 20.0)
    assert {r.path for r in rows if r.metric == "make_ms"} == {"wgpu"}  # the device thread's time: wgpu only
    make = next(r for r in rows if r.metric == "make_ms")
    assert make.median == pytest.approx(statistics.median(wgpu[1:]) / 2)


def test_a_label_only_one_path_ran_gets_no_ratio():
    samples = {("wgpu", "a"): [{"total_ms": 2.0}], ("raw", "a"): [{"total_ms": 1.0}],
               ("wgpu", "wgpu only"): [{"total_ms": 3.0}], ("raw", "raw only"): [{"total_ms": 3.0}]}
    assert startup.paired_ratios(samples) == {"a": [2.0]}


def _rows(label: str, paired: float, wgpu: float, raw: float) -> list[Result]:
    case = f"3d: {label}"
    return [Result("startup", case, "wgpu/raw", "800x600", startup.RATIO, paired, paired - 0.05, paired + 0.05, 11),
            Result("startup", case, "wgpu", "800x600", "total_ms", wgpu, wgpu, wgpu, 11),
            Result("startup", case, "raw", "800x600", "total_ms", raw, raw, raw, 11)]


def _verdict(met: bool, applies: str = "") -> str:
    return "met" if met else "not met"


@pytest.mark.parametrize(("paired", "status"), [(1.19, "met"), (1.21, "not met")])
def test_the_target_judges_the_paired_median(paired, status):
    # the ratio of the medians (500 / 400 = 1.25) would say otherwise in the first case
    row = first_pixel_ratio(_rows(QUICK_LABEL, paired, 500.0, 400.0), QUICK_LABEL, _verdict, judged=True)
    assert row[0] == "first pixel <= 1.2x raw (bytecode cached)"
    assert row[2] == status
    assert f"{paired:.2f}x, paired over 11 interleaved rounds" in row[1]
    assert "500" in row[1] and "400" in row[1]


def test_without_bytecode_the_ratio_is_reported_not_judged_and_without_a_pair_there_is_no_row():
    label = "no caches, no bytecode"
    row = first_pixel_ratio(_rows(label, 1.5, 1.0, 1.0), label, _verdict, judged=False)
    assert row[0] == "first pixel vs raw (no bytecode (every module compiled))" and row[2] == "reported"
    assert first_pixel_ratio(_rows(label, 1.5, 1.0, 1.0)[2:], label, _verdict, judged=False) is None  # no wgpu


def test_a_run_from_before_the_paired_rounds_shows_its_medians_and_is_not_judged():
    def verdict(met, applies=""):
        return f"not judged ({applies})" if applies else ("met" if met else "not met")

    row = first_pixel_ratio(_rows(QUICK_LABEL, 1.0, 473.5, 381.1)[1:], QUICK_LABEL, verdict, judged=True)
    assert row[1] == "473.5 / 381.1 ms = 1.24x (medians of back-to-back runs)"
    assert row[2] == "not judged (no paired rounds in this run)"


def test_only_the_comparison_row_leaves_the_drivers_to_the_loader(monkeypatch):
    calls: list[str] = []
    n = len(startup.configurations(startup.Path("w")))
    monkeypatch.setattr(startup, "run_child", _fake({"wgpu": [1.0] * 3 * n, "wgpu no-preload": [1.0] * 3,
                                                      "raw": [1.0] * 3 * n}, calls))
    rows = startup.bench_startup("triangle", (8, 8), rounds=2, log=lambda _: None)
    assert calls.count("wgpu no-preload") == 3  # warming and 2 rounds
    assert len(calls) == 3 * n
    labels = {r.case for r in rows if r.path == "wgpu" and r.metric == "total_ms"}
    assert f"triangle: {startup.NO_PRELOAD}" in labels and len(labels) == 5
    paired = {r.case for r in rows if r.metric == startup.RATIO}  # the labels both paths ran
    assert paired == {"triangle: no caches", "triangle: no caches, no bytecode", f"triangle: {startup.DRIVER_WARM}"}


def test_the_warm_driver_cache_rows_warm_mesas_and_nvidias_caches_and_no_caches_turns_both_off():
    configs = {(path, label): env for path, label, env, _ in startup.configurations(startup.Path("w"))}
    warm = configs["wgpu", startup.DRIVER_WARM]
    assert warm["MESA_SHADER_CACHE_DISABLE"] == "false" and warm["__GL_SHADER_DISK_CACHE"] == "1"
    assert warm["MESA_SHADER_CACHE_DIR"].startswith("w") and warm["__GL_SHADER_DISK_CACHE_PATH"].startswith("w")
    for (path, label), env in configs.items():
        if label != startup.DRIVER_WARM:
            assert env["MESA_SHADER_CACHE_DISABLE"] == "true" and env["__GL_SHADER_DISK_CACHE"] == "0", (path, label)
