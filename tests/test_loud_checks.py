"""A check that cannot go quiet (issue 32 item 8).

Before: when the matrix's driver class or tolerance row did not match, every bound read "none (info)" and
``verify --implementations`` exited 0, and the browser and GL tests skipped (one inverted comparison turned 34
tests into skips) with the suite still green. Now an uncalibrated cell fails, the suite fails when its skips are
not the environment's or grow past the expected few, and tests keep off the machine-wide caches.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from skips import DEFAULT_MAX_SKIPS, skip_problems

from wgpurender.core.verdict.tolerances import Uncalibrated, implementation_tolerance

TABLE = {"implementations": {"browser": {"driver_class": "lavapipe", "bounded_by": "here", "targets": {
    "triangle": {"max_abs": 3, "changed": 0.02, "flip_mean": 0.004, "measured": "x"}}}}}


def test_bounds_apply_only_on_their_driver_class():
    assert implementation_tolerance("browser", "triangle", TABLE, cls="lavapipe").max_abs == 3
    with pytest.raises(Uncalibrated, match="calibrated on lavapipe, not nvidia"):
        implementation_tolerance("browser", "triangle", TABLE, cls="nvidia")


@pytest.mark.parametrize("why", [Uncalibrated("the browser bounds were calibrated on lavapipe, not nvidia: run x"),
                                 Exception("no browser tolerance for 'triangle'")])
def test_an_uncalibrated_cell_fails(tmp_path, monkeypatch, why):
    """A matrix cell whose bound does not apply here is a FAIL that says why, never a passing "info"."""
    from wgpurender import verify_matrix
    from wgpurender.core.errors import UserError

    def no_bound(a, b, target):
        raise why if isinstance(why, Uncalibrated) else UserError(str(why))

    monkeypatch.setattr(verify_matrix, "_bound", no_bound)
    a = np.zeros((4, 4, 4), np.uint8)
    b = a.copy()
    b[0, 0, 0] = 9
    for pair in ((a, b), (a, a)):  # different or identical: the missing bound is the failure
        cell = verify_matrix._compare(tmp_path, "triangle", "wgpu-vulkan", "browser", *pair)
        assert cell.status == "FAIL" and cell.note.startswith("uncalibrated: ") and str(why) in cell.note


ENVIRONMENT = ["chromium is not installed (apt-get install chromium)", "this machine has no OpenGL adapter",
               "glslc not installed (apt install glslc)", "could not import 'nbformat': No module named 'nbformat'",
               "vulkan_tutorial_28.toml needs /x/shared/anchors (the tutorial's model and texture), absent",
               "the wgpu-gl bounds were calibrated on lavapipe, not nvidia: run `wgpurender verify ...`"]


def test_environment_skips_pass_the_check():
    assert skip_problems(ENVIRONMENT, 100) == []


@pytest.mark.parametrize("reason", [
    "the browser bounds were calibrated on lavapipe, not lavapipe: run `wgpurender verify ...`",  # inverted test
    "flaky on Tuesdays",
])
def test_a_skip_that_is_no_environment_fails_the_suite(reason):
    assert skip_problems([*ENVIRONMENT, reason], 100) == [f"unexpected skip: {reason}"]


def test_too_many_skips_fail_the_suite(monkeypatch):
    monkeypatch.delenv("WGPURENDER_MAX_SKIPS", raising=False)
    many = ["this machine has no OpenGL adapter"] * (DEFAULT_MAX_SKIPS + 1)
    problems = skip_problems(many, 2000)
    assert len(problems) == 1 and f"{DEFAULT_MAX_SKIPS + 1} of 2000 tests skipped" in problems[0]
    assert skip_problems(many[:-1], 2000) == []
    monkeypatch.setenv("WGPURENDER_MAX_SKIPS", str(DEFAULT_MAX_SKIPS + 1))  # a machine that lacks more
    assert skip_problems(many, 2000) == []


def test_the_session_fails_on_an_unexpected_skip(pytester):
    """The hook itself: a suite of one passing test and one test skipped for no environment reason fails."""
    conftest = Path(__file__).with_name("conftest.py").read_text()
    pytester.makeconftest(conftest)
    pytester.makepyfile(skips=Path(__file__).with_name("skips.py").read_text())
    pytester.makepyfile(test_a="import pytest\n\ndef test_ok():\n    pass\n\n"
                               "def test_quiet():\n    pytest.skip('calibrated on lavapipe, not lavapipe: x')\n")
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider")
    assert result.ret == 1
    result.stdout.fnmatch_lines(["*unexpected skip: calibrated on lavapipe, not lavapipe: x*"])


def test_tests_keep_off_the_machine_cache():
    """conftest points $XDG_CACHE_HOME at this session's own folder and each test at its own bandwidth record."""
    cache = Path(os.environ["XDG_CACHE_HOME"])
    assert cache != Path.home() / ".cache" and cache.name.startswith("wgpurender-test-cache-")
    from wgpurender.core.files.bandwidth import record_path

    assert not record_path().is_relative_to(Path.home() / ".cache")


def test_the_matrix_picks_its_bound_by_the_rules(monkeypatch):
    """raw vs wgpu-vulkan: the post-chain bound for a scene with two or more post effects (brick has 2), exact for
    one without (unlit); another implementation: its row, for the driver class the Vulkan adapter's *device name*
    gives (an llvmpipe device is lavapipe whatever its description says)."""
    from types import SimpleNamespace

    from wgpurender import verify_matrix
    from wgpurender.verify import CHAIN_BOUND, EXACT

    assert verify_matrix._bound("raw", "wgpu-vulkan", "brick") is CHAIN_BOUND
    assert verify_matrix._bound("wgpu-vulkan", "raw", "unlit") is EXACT
    assert verify_matrix._bound("raw", "browser", "brick") is None  # two non-reference implementations: info
    adapter = SimpleNamespace(info={"device": "llvmpipe (LLVM 15.0.6, 256 bits)", "description": "NVIDIA 580"})
    monkeypatch.setattr("wgpurender.wgpu_path.device.context.get_context", lambda backend=None: SimpleNamespace(
        adapter=adapter))
    asked = []
    monkeypatch.setattr(verify_matrix, "implementation_tolerance", lambda impl, name, cls=None: asked.append(
        (impl, name, cls)))
    verify_matrix._bound("browser", "wgpu-vulkan", "final")
    assert asked == [("browser", "final", "lavapipe")]


def test_implementation_calibration_keeps_its_margin(tmp_path, monkeypatch):
    """verify --calibrate's rows follow the header's rule (CPU drivers): a measured spread of max 5/255, 3% of
    pixels, FLIP 0.004 becomes max 6, changed 6%, FLIP 0.008, with the spread and the driver class written; a
    larger size measured in the same run becomes its own class (max 9 -> 10); the size-free bounds come from the
    worst over both sizes (radial 0 -> 1/255, detail 2 x 0.07 = 0.14)."""
    import tomllib

    from wgpurender import implementations
    from wgpurender.core.verdict import tolerances
    from wgpurender.core.verdict.structure import Structure
    from wgpurender.core.verdict.tolerances import Metrics

    path = tmp_path / "implementations.toml"
    monkeypatch.setattr(tolerances, "IMPLEMENTATIONS_PATH", path)
    implementations.calibrate("browser", {
        "320x240": {"final": (Metrics(9, 0.02, 1536, 0.003, 76800), Structure(0.0, -0.07))},
        "160x120": {"final": (Metrics(5, 0.03, 576, 0.004, 19200), Structure(0.0, 0.05))}}, "here, today", "lavapipe")
    table = tomllib.loads(path.read_text())["implementations"]["browser"]
    row = table["targets"]["final"]
    assert (row["max_abs"], row["changed"], row["flip_mean"]) == (6, 0.06, 0.008)
    assert table["driver_class"] == "lavapipe" and "576 of 19200" in row["measured"] and table["size"] == "160x120"
    big = row["sizes"]["320x240"]
    assert (big["max_abs"], big["changed"], big["flip_mean"]) == (10, 0.04, 0.006)
    assert (row["radial"], row["detail"]) == (1.0, 0.14) and "160x120, 320x240" in row["structure_measured"]
