"""Every row of tests/mutation_run.py still seeds its bug: a row whose original text is no longer in its file
exactly once is skipped by the run (and counted in no score), so a rewrite of the code it mutates would silently
drop it. Fails naming the stale rows (1-based, as ``--only`` takes them)."""

from __future__ import annotations

from pathlib import Path

import mutation_run

REPO = Path(__file__).resolve().parent.parent


def test_every_row_mutates_text_that_is_in_its_file_once():
    stale = []
    for number, (path, old, new, tests) in enumerate(mutation_run.MUTATIONS, 1):
        source = REPO / path
        found = source.read_text().count(old) if source.is_file() else -1
        if found != 1:
            stale.append(f"row {number}: the original is in {path} {found} times (-1: no such file), not once")
        if old == new:
            stale.append(f"row {number}: the mutant is the original")
        stale.extend(f"row {number}: test file {t} does not exist" for t in tests
                     if not (REPO / t.partition("|")[0]).is_file())
    assert not stale, "\n".join(stale)
