"""What changed in the code from the previous course step, per path: a unified diff (difflib) of the excerpts.

The report shows each step's code whole; a learner also asks "what is new here?". For each path, a step's
excerpts are compared with those of the nearest earlier step that has code on that path; the page shows the
unified diff under the excerpts (added lines green, removed red), or says that the code is the same.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

CONTEXT = 2  # unchanged lines shown around each change


@dataclass(frozen=True)
class CodeDiff:
    """One path's change from ``previous`` (a step key) to this step: unified diff lines, no trailing newlines."""

    previous: str
    lines: list[str]

    @property
    def added(self) -> int:
        return sum(1 for x in self.lines if x.startswith("+") and not x.startswith("+++"))

    @property
    def removed(self) -> int:
        return sum(1 for x in self.lines if x.startswith("-") and not x.startswith("---"))


def _text(excerpts) -> list[str]:
    """The excerpts of one side as one list of lines, each function headed by its location."""
    lines: list[str] = []
    for x in excerpts:
        lines += [f"# {x.location}", *x.source.splitlines()]
    return lines


def step_diffs(steps) -> None:
    """Set ``step.diffs[side]`` for every step after the first with code on that side."""
    last: dict[str, tuple[str, list[str]]] = {}
    for step in steps:
        for side, excerpts in step.code.items():
            if not excerpts:
                continue
            now = _text(excerpts)
            if side in last:
                key, before = last[side]
                diff = difflib.unified_diff(before, now, fromfile=key, tofile=step.key, n=CONTEXT, lineterm="")
                step.diffs[side] = CodeDiff(key, list(diff))
            last[side] = (step.key, now)
