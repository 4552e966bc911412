"""Shared test set-up: the GPU context, failing any test that triggers a GPU validation message, the
driver class that picks the reference tolerances, and ``--regenerate-references``.

Tests never read or write the machine-wide caches (~/.cache/wgpurender: SPIR-V, pipeline cache, cffi cdefs, the
bandwidth record): $XDG_CACHE_HOME points at a folder of this session's own, made here before anything imports
the package (subprocesses inherit it), and $WGPURENDER_PERF_RECORD is dropped. The suite fails when more tests
skip than tests/skips.py expects (:func:`pytest_sessionfinish`).

The Vulkan validation layer (apt: vulkan-validationlayers) is switched on through
$WGPURENDER_VALIDATION before the first adapter is made; its messages arrive on
the ``wgpu`` logger, and a test during which one arrives fails.
"""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("WGPURENDER_VALIDATION", "1")
os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.gettempdir())
os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp(prefix="wgpurender-test-cache-")  # never ~/.cache/wgpurender
os.environ.pop("WGPURENDER_PERF_RECORD", None)

import pytest  # noqa: E402
import wgpu  # noqa: E402,F401  (imported before logging config: wgpu installs its own logger class)

from wgpurender.wgpu_path.device.validation import collect_validation_messages  # noqa: E402


def pytest_addoption(parser) -> None:
    parser.addoption(
        "--regenerate-references", action="store_true", default=False,
        help="re-render assets/reference/*.png with the raw-Vulkan path (never the wgpu path) before the tests, "
             "and print per image how many pixels changed and by how much",
    )


def pytest_sessionstart(session) -> None:
    """--regenerate-references: the raw path re-renders the committed references, then the tests run."""
    if not session.config.getoption("--regenerate-references"):
        return
    from wgpurender.raw_path.make_references import regenerate

    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    lines = [change.describe() for change in regenerate()]
    session.config._regenerated_references = lines
    if reporter is not None:
        reporter.write_line("regenerated references (raw-Vulkan path):")
        for line in lines:
            reporter.write_line(f"  {line}")


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    lines = getattr(config, "_regenerated_references", None)
    if lines:
        terminalreporter.section("regenerated references (raw-Vulkan path)")
        for line in lines:
            terminalreporter.write_line(line)
    problems = getattr(config, "_skip_problems", None)
    if problems:
        terminalreporter.section("unexpected skips (tests/skips.py)")
        for line in problems:
            terminalreporter.write_line(line)


def pytest_sessionfinish(session, exitstatus) -> None:
    """A suite whose skips grew fails: each skip's reason must be an environment lack tests/skips.py lists, and
    an uncalibrated bound may skip only where the machine's driver class really differs (override the total with
    $WGPURENDER_MAX_SKIPS where the environment lacks more, e.g. no anchors, no browser)."""
    from skips import skip_problems

    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    skipped = reporter.stats.get("skipped", []) if reporter is not None else []
    reasons = [(r.longrepr[2] if isinstance(r.longrepr, tuple) else str(r.longrepr)).removeprefix("Skipped: ")
               for r in skipped]
    problems = skip_problems(reasons, session.testscollected)
    if problems:
        session.config._skip_problems = problems
        if session.exitstatus == 0:
            session.exitstatus = 1


_collector = collect_validation_messages()


@pytest.fixture(autouse=True)
def no_gpu_validation_errors():
    """Fail the test if the Vulkan validation layer reported anything while it ran."""
    _collector.messages.clear()
    yield
    if _collector.messages:
        pytest.fail("GPU validation errors:\n" + "\n".join(_collector.messages[:5]), pytrace=False)


@pytest.fixture(autouse=True)
def own_bandwidth_record(tmp_path_factory, monkeypatch):
    """Each test its own bandwidth record (core/files/bandwidth.py): a plan's --explain quotes it, so a record one
    test's benchmark wrote made another test's two explains differ (test_one_plan was flaky so)."""
    monkeypatch.setenv("WGPURENDER_PERF_RECORD", str(tmp_path_factory.mktemp("bandwidth") / "bandwidth.json"))


@pytest.fixture(scope="session")
def ctx():
    """The Vulkan context every GPU test shares (lavapipe in CI)."""
    from wgpurender.wgpu_path.device.context import get_context

    return get_context("Vulkan")


@pytest.fixture(scope="session")
def raw_driver_class():
    """The tolerance table's driver class ('lavapipe' or 'gpu') of the raw-Vulkan path's device.

    Reference images (assets/reference, and the C++ tutorial's frames) were made on lavapipe;
    another CPU or a GPU rasterises and filters within the Vulkan spec's tolerances but not
    identically, so they are compared with that class's calibrated bounds
    (assets/reference/tolerances.toml), never skipped.
    """
    from wgpurender.core.verdict.tolerances import driver_class
    from wgpurender.raw_path.device.context import get_vulkan

    return driver_class(get_vulkan().device_name)


@pytest.fixture(scope="session")
def wgpu_driver_class(ctx):
    """The tolerance table's driver class of the wgpu path's adapter."""
    from wgpurender.core.verdict.tolerances import driver_class

    return driver_class(ctx.adapter.info["device"])


REPORT_COMMAND = "wgpurender report -o out/report"  # the README tour's line (tests/test_readme_tour.py)


@pytest.fixture(scope="session")
def report_run(tmp_path_factory):
    """The README's report command, run once from an empty folder for test_report.py and test_readme_tour.py:
    ``folder`` (the cwd), ``command``, ``result`` (the CompletedProcess), ``start`` and ``end`` (UTC).
    A fresh bandwidth record (core/files/bandwidth.py): the report's timings write one after each scene's plan text,
    so with the user's cache the plan printed and the one a test explains could differ by a measurement."""
    import datetime
    import shlex
    import shutil
    import subprocess
    import sys
    import time
    from types import SimpleNamespace

    if shutil.which("glslc") is None:
        pytest.skip("the raw path needs glslc (apt-get install glslc)")
    folder = tmp_path_factory.mktemp("report_run")
    (folder / "out").mkdir()  # as `make demo` leaves it (the README's tour runs after it)
    env = dict(os.environ, WGPURENDER_PERF_RECORD=str(folder / "bandwidth.json"),
               XDG_CACHE_HOME=str(folder / "cache"))
    start = datetime.datetime.now(datetime.UTC).replace(second=0, microsecond=0)
    argv = [sys.executable, "-m", *shlex.split(REPORT_COMMAND)]
    began = time.perf_counter()
    result = subprocess.run(argv, cwd=folder, capture_output=True, text=True, timeout=900, env=env)
    return SimpleNamespace(folder=folder, command=REPORT_COMMAND, result=result, start=start,
                           end=datetime.datetime.now(datetime.UTC), seconds=time.perf_counter() - began)

