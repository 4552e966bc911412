"""Every marked figure in the docs equals what its committed run output gives, and no file holds a merge conflict
(issue 32 item 4: a conflict block sat in docs/verification.md, and "12 of 16 bit-identical" was 10 of 17)."""

from __future__ import annotations

import subprocess

import pytest
from doc_figures import DOCS, REPO, compute, figures, provenance

MARKED = [(path, spec, text) for path in DOCS for spec, text in figures(path)]


def test_the_docs_mark_their_figures():
    where = {path.name for path, _, _ in MARKED}
    assert {"verification.md", "benchmarks.md", "backends.md"} <= where


@pytest.mark.parametrize(("path", "spec", "text"), MARKED,
                         ids=[f"{p.name}:{s.get('col', s.get('agg'))}:{t}" for p, s, t in MARKED])
def test_each_figure_is_its_source(path, spec, text):
    assert (REPO / spec["src"]).is_file(), f"{path.name}: source {spec['src']} is not committed"
    assert provenance(spec), f"{spec['src']} says nothing of its machine, date and command"
    assert compute(spec) == text, f"{path.name}: {text!r} is {compute(spec)!r} by {spec['src']}"


def _files() -> list[str]:
    """The tracked files, or every file of a copy without git (tests/mutation_run.py's), but its caches."""
    listed = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True)
    if listed.returncode == 0:
        return listed.stdout.split()
    skip = (".venv", ".git", "__pycache__", "out", "bench-results")
    return [p.relative_to(REPO).as_posix() for p in REPO.rglob("*")
            if p.is_file() and not set(p.relative_to(REPO).parts) & set(skip)]


def test_no_merge_conflict_markers_anywhere():
    files = _files()
    opening, closing = "<" * 7 + " ", ">" * 7 + " "
    found = []
    for name in files:
        try:
            lines = (REPO / name).read_text().splitlines()
        except (UnicodeDecodeError, OSError):
            continue  # binary or absent (a large file left out of a copy)
        found += [f"{name}:{n}" for n, line in enumerate(lines, 1) if line.startswith((opening, closing))]
    assert found == []
