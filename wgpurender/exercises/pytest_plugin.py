"""The wgpurender pytest plugin (entry point ``pytest11``): grade learners' stages headless, one test each.

Two ways in:

- the ``wgpurender_check`` fixture, which a starter's test_<STEP>.py uses:
  ``wgpurender_check(file, step="2a", path="wgpu")`` fails the test with the check's report unless it passes;
- grading a folder of submissions: ``pytest --wgpurender-step 2a [--wgpurender-path raw]
  [--wgpurender-html report.html] SUBMISSIONS/`` (or ``--wgpurender-step folder`` for SUBMISSIONS/<step>/*.py)
  collects every ``*.py`` there that is not a test or conftest as one item, prints one line per submission,
  writes an HTML summary page (images, heatmaps, diagnosis) and exits 1 when any failed. With pytest-xdist
  (``-n auto``) the items spread over worker processes; each learner's code runs in a process of its own
  anyway (sandbox.py), with a time limit.

Only pytest is imported here at start-up: the renderer loads when the first item runs. A scene step's
submissions are shader files (step 6: ``*.wgsl`` on the wgpu path, ``*.frag`` on the raw path).
"""

from __future__ import annotations

import html
import json
import os
from pathlib import Path

import pytest

LINE, IMAGES = "wgpurender_line", "wgpurender_images"
BY_FOLDER = "folder"  # --wgpurender-step folder: a submission's step is its folder's name


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("wgpurender", "grading course exercises (wgpurender)")
    group.addoption("--wgpurender-step", metavar="STEP", default=None,
                    help="grade every *.py submission in the given folders as course step STEP; 'folder': "
                    "each as the step its folder is named for (a class's 2a/alice.py, 4/bob.py, ...)")
    group.addoption("--wgpurender-path", metavar="PATH", default="wgpu", choices=("wgpu", "raw"),
                    help="the path the submissions are written for: wgpu (default) or raw")
    group.addoption("--wgpurender-html", metavar="FILE", default="wgpurender-grades.html",
                    help="the HTML summary page (default wgpurender-grades.html); its images go beside it")
    group.addoption("--wgpurender-timeout", metavar="S", type=float, default=None,
                    help="seconds one submission may take to render (default 120)")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "wgpurender: a graded course exercise")


def pytest_collect_file(file_path: Path, parent: pytest.Collector):
    config = parent.config
    step = config.getoption("wgpurender_step")
    if not step or file_path.suffix != _suffix(file_path.parent.name if step == BY_FOLDER else step,
                                                  config.getoption("wgpurender_path")):
        return None
    if file_path.name.startswith(("test_", "conftest")) or file_path.name.endswith("_test.py"):
        return None
    return SubmissionFile.from_parent(parent, path=file_path)


def _suffix(step: str, path: str) -> str:
    """What a submission's file name ends with: .py, or a scene step's shader kind (.wgsl, .frag)."""
    from wgpurender.core.errors import UserError
    from wgpurender.exercises.catalogue import exercise
    from wgpurender.exercises.check import learner_suffix

    try:
        return learner_suffix(exercise(step, path))
    except UserError:
        return ".py"  # reported when the item runs


class SubmissionFile(pytest.File):
    def collect(self):
        yield Submission.from_parent(self, name=self.path.name)


class Submission(pytest.Item):
    """One learner's stage, checked against the step's reference."""

    def runtest(self) -> None:
        config = self.config
        step = config.getoption("wgpurender_step")
        step = self.path.parent.name if step == BY_FOLDER else step
        verdict = run_check(self.path, step, config.getoption("wgpurender_path"),
                            images_folder(config) / step, config.getoption("wgpurender_timeout"))
        self.user_properties.append((LINE, verdict.line()))
        self.user_properties.append((IMAGES, json.dumps({k: str(v) for k, v in verdict.images.items()})))
        if verdict.exit_code:
            raise SubmissionFailed(verdict.report())

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, SubmissionFailed):
            return str(excinfo.value)
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, None, f"submission {self.path.name}"


class SubmissionFailed(Exception):
    """The submission's verdict is not a pass (its report is the message)."""


def images_folder(config: pytest.Config) -> Path:
    page = Path(config.getoption("wgpurender_html"))
    return page.with_name(page.stem + "-images").resolve()


def run_check(file: Path, step: str, path: str, out: Path | None, timeout: float | None):
    from wgpurender.core.errors import UserError
    from wgpurender.exercises.catalogue import exercise
    from wgpurender.exercises.check import check_file
    from wgpurender.exercises.sandbox import DEFAULT_TIMEOUT

    try:
        ex = exercise(step, path)
    except UserError as err:
        raise pytest.UsageError(str(err)) from None
    return check_file(Path(file).resolve(), ex, out, timeout or DEFAULT_TIMEOUT)


@pytest.fixture
def wgpurender_check():
    """``wgpurender_check(file, step, path="wgpu")``: fails the test unless the stage in ``file`` passes."""

    def check(file, step: str, path: str = "wgpu") -> None:
        file = Path(file)
        verdict = run_check(file, step, path, file.parent / f"check-{file.stem}", None)
        if verdict.exit_code:
            pytest.fail(verdict.report(), pytrace=False)

    return check


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    """Collected on the controller (xdist sends each worker's reports there): the call phase of a submission."""
    props = dict(report.user_properties)
    if report.when == "call" and LINE in props:
        _lines.append((report.nodeid, report.outcome, props[LINE], json.loads(props.get(IMAGES, "{}"))))


_lines: list[tuple[str, str, str, dict]] = []  # (nodeid, outcome, line, images) per graded submission


def pytest_terminal_summary(terminalreporter, exitstatus, config: pytest.Config) -> None:
    if not config.getoption("wgpurender_step") or hasattr(config, "workerinput"):
        return
    terminalreporter.section("wgpurender grades")
    for _, _, line, _ in sorted(_lines):
        terminalreporter.write_line(line)
    page = Path(config.getoption("wgpurender_html"))
    write_page(page, config.getoption("wgpurender_step"), sorted(_lines))
    terminalreporter.write_line(f"summary page: {page}")


def write_page(page: Path, step: str, rows: list[tuple[str, str, str, dict]]) -> None:
    """The HTML summary: one table row per submission, its verdict line and its images (relative links)."""
    from wgpurender.core.files.safe_write import atomic_write

    cells = []
    for _, outcome, line, images in rows:
        imgs = "".join(f'<figure><img src="{html.escape(_relative(p, page))}" alt="{html.escape(k)}">'
                       f"<figcaption>{html.escape(k)}</figcaption></figure>" for k, p in images.items())
        cells.append(f'<tr class="{outcome}"><td>{html.escape(outcome)}</td><td>{html.escape(line)}</td>'
                     f"<td>{imgs}</td></tr>")
    passed = sum(1 for _, outcome, _, _ in rows if outcome == "passed")
    text = ("<!doctype html><meta charset=utf-8><title>wgpurender grades, step " + html.escape(step) + "</title>"
            "<style>td{vertical-align:top;padding:4px}tr.failed td:first-child{color:#b00}"
            "tr.passed td:first-child{color:#070}figure{display:inline-block;margin:2px}</style>"
            f"<h1>Course step {html.escape(step)}: {passed} of {len(rows)} passed</h1>"
            "<table><tr><th>result</th><th>verdict</th><th>images</th></tr>" + "".join(cells) + "</table>\n")
    atomic_write(page, text.encode())


def _relative(path: str, page: Path) -> str:
    return os.path.relpath(path, page.resolve().parent)
