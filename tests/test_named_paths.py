"""Every repository path named in code, docs and printed notes exists (issue 32 item 3).

A reader follows ``tests/test_vulkan_ref_scene.py`` from a tolerance note that ``wgpurender verify`` prints, or
``wgpurender/core/verdict/tolerances.py`` from a doc; when a file is renamed or moved, the names left behind point
at nothing. This reads the checkout's code (``.py``), docs (``.md``), data files whose comments are printed or
read (``.toml``), shaders and scripts, finds the paths they name, and checks each exists:

- ``wgpurender/...``, ``tests/...``, ``docs/...``, ``assets/...``, ``shaders_wgsl/...``, ``shaders_glsl/...``,
  ``benchmarks/...``, ``examples/...``;
- the package's short spellings ``core/...py``, ``wgpu_path/...py``, ``raw_path/...py`` (under ``wgpurender/``),
  also with a name after the module (``core/verdict/tolerances.calibrate``);
- a bare test file name ``test_x.py`` (anywhere under ``tests/``).

A plain glob (``tests/test_vulkan_ref*.py``) must match at least one file. Not checked: placeholders
(``docs/perf-<gpu>/``, ``assets/scenes/NAME.toml``) and brace lists (``{a,b}.py``), a path
a command is told to write (``--out docs/perf-h200/x``, ``> docs/x.md``), the wheel's own folders
(``wgpurender/_shaders``...: setup.py makes them in the build tree), and the committed run records under
``docs/perf-*/`` (they name the files as they were when the run was made).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
TOPS = ("wgpurender", "tests", "docs", "assets", "shaders_wgsl", "shaders_glsl", "benchmarks", "examples")
SUFFIXES = (".py", ".md", ".toml", ".wgsl", ".frag", ".vert", ".comp", ".sh", ".in", ".cfg")
TOP_FILES = ("Makefile", "README.md", "setup.py", "pyproject.toml", "MANIFEST.in")
# a path-like run of characters; what follows decides whether it is a glob or a placeholder
PREFIXES = "|".join(TOPS + ("core", "wgpu_path", "raw_path"))
TOKEN = re.compile(r"(?<![\w/.\-~$])((?:" + PREFIXES + r")/[\w./\-*{},<>]*)")
TEST_FILE = re.compile(r"(?<![\w/.\-*])(test_\w+\.py)\b")
GLOB = re.compile(r"[*{}<>]|/[A-Z]+[./]|/[A-Z]+$")
WRITTEN = re.compile(r"(--out[ =]|-o |> ?)$")
WHEEL_ONLY = ("wgpurender/_",)
# Files a test writes at run time, with where it does.
MADE_BY_TESTS = {"tests/test_probe.py": "test_reference_tolerances.py writes it into its copy of the checkout"}


def scanned_files(root: Path = REPO) -> list[Path]:
    """The checkout's text files that name paths: code, docs, data with comments, shaders, scripts."""
    out = [root / name for name in TOP_FILES if (root / name).is_file()]
    me = Path(__file__).resolve()
    for top in TOPS:
        for path in sorted((root / top).rglob("*")):
            rel = path.relative_to(root).parts
            if not path.is_file() or path.suffix not in SUFFIXES or "__pycache__" in rel or path.resolve() == me:
                continue
            if rel[0] == "docs" and len(rel) > 2 and rel[1].startswith("perf-"):
                continue  # a run's record: the names as they were when it ran
            out.append(path)
    return out


def _as_repo_path(token: str) -> str:
    path = token.rstrip(".,;:)")
    if path.split("/")[0] in ("core", "wgpu_path", "raw_path"):
        path = "wgpurender/" + path
    return path


def _exists(path: str, root: Path) -> bool:
    """``path`` is a file or folder, or a module's path bare or with a name after it (``core/x``, ``core/x.attr``)."""
    if (root / path).exists() or (root / (path + ".py")).is_file():  # a module named without ".py"
        return True
    head, dot, _ = path.rpartition(".")
    return bool(dot) and "/" in head and (root / (head + ".py")).is_file()


def named_paths(text: str) -> list[tuple[int, str]]:
    """(line, repository path) for each path ``text`` names, globs, placeholders and written outputs left out."""
    out = []
    for number, line in enumerate(text.splitlines(), 1):
        for match in TOKEN.finditer(line):
            token = match.group(1)
            if WRITTEN.search(line[:match.start()]):
                continue
            if GLOB.search(token):
                glob = token.rstrip(".,;:)`'\"")
                if re.fullmatch(r"[\w./\-*]*\*[\w./\-*]*", glob):  # a plain glob names at least one file
                    out.append((number, "glob:" + _as_repo_path(glob)))
                continue
            path = _as_repo_path(token)
            if "/" in path.rstrip("/") and not path.startswith(WHEEL_ONLY):
                out.append((number, path.rstrip("/")))
        out += [(number, f"tests/**/{m.group(1)}") for m in TEST_FILE.finditer(line)]
    return out


def missing_paths(root: Path = REPO) -> list[str]:
    found = []
    for file in scanned_files(root):
        for number, path in named_paths(file.read_text(encoding="utf-8", errors="replace")):
            if path.startswith("glob:"):
                ok = any(root.glob(path.removeprefix("glob:")))
            elif path.startswith("tests/**/"):
                name = path.removeprefix("tests/**/")
                ok = any((root / "tests").rglob(name)) or any(p.endswith("/" + name) for p in MADE_BY_TESTS)
            else:
                ok = path in MADE_BY_TESTS or _exists(path, root)
            if not ok:
                found.append(f"{file.relative_to(root)}:{number}: {path.replace('tests/**/', '').replace('glob:', '')}")
    return found


def test_every_named_path_exists():
    missing = missing_paths()
    assert missing == [], "paths named but not in the repository (renamed or moved away?):\n" + "\n".join(missing)


def test_the_notes_verify_prints_are_scanned():
    """The tolerance notes verify prints live in verify.py and assets/reference/*.toml: both are read."""
    names = {p.relative_to(REPO).as_posix() for p in scanned_files()}
    assert {"wgpurender/verify.py", "assets/reference/tolerances.toml", "assets/reference/implementations.toml",
            "docs/verification.md", "tests/test_layering.py", "Makefile"} <= names
    assert not any(n.startswith("docs/perf-") and not n.endswith("README.md") and n.count("/") > 2 for n in names)


@pytest.mark.parametrize("line, stale", [
    ("# measured by tests/test_gone_away.py", "tests/test_gone_away.py"),
    ('NOTE = "lavapipe: max 1/255 (test_gone_away.py)"', "test_gone_away.py"),
    ("see wgpurender/core/no_such_module.py", "wgpurender/core/no_such_module.py"),
    ("(core/no_such_module.py)", "wgpurender/core/no_such_module.py"),
    ("the rule (wgpurender/core/no_such_module.calibrate)", "wgpurender/core/no_such_module.calibrate"),
    ("`raw_path/device/no_such.py`", "wgpurender/raw_path/device/no_such.py"),
    ("docs/no_such_doc.md", "docs/no_such_doc.md"),
    ("0 pixels differ (tests/test_gone*.py)", "tests/test_gone*.py"),
])
def test_a_stale_name_is_found(tmp_path, line, stale):
    """A checkout with one file naming a path that is not there: exactly that name is reported."""
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_x1.py").write_text("")
    (tmp_path / "wgpurender" / "core").mkdir(parents=True)
    (tmp_path / "wgpurender" / "core" / "errors.py").write_text("")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "guide.md").write_text(f"fine: wgpurender/core/errors.py, core/errors.UserError\n{line}\n")
    assert missing_paths(tmp_path) == [f"docs/guide.md:2: {stale}"]


@pytest.mark.parametrize("line", [
    "tests/test_x*.py", "docs/perf-<gpu>/", "wgpurender/wgpu_path/post/{passes,chain}.py",
    "wgpurender bench post-roofline --out docs/perf-h200/post-roofline", "python -m x > docs/new.md",
    "assets/scenes/NAME.toml", "wgpurender/_shaders/wgsl", "wgpurender/core/errors.py", "core/errors.UserError",
])
def test_globs_placeholders_outputs_and_real_paths_pass(tmp_path, line):
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_x1.py").write_text("")
    (tmp_path / "wgpurender" / "core").mkdir(parents=True)
    (tmp_path / "wgpurender" / "core" / "errors.py").write_text("")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "guide.md").write_text(line + "\n")
    assert missing_paths(tmp_path) == []
