"""The report's closing sections: the accuracy Pareto plot and the measured hard cases' table.

Both are read from the repository's docs, where their runs are written down with machine,
date and command (docs/accuracy.md, docs/numerics.md): the report shows them, it does not
re-measure them (a full accuracy run takes minutes).
"""

from __future__ import annotations

import html
import re
from pathlib import Path

from wgpurender.core.assets import docs_file

PARETO = docs_file("img/accuracy_pareto.png")  # the checkout's docs/, or the wheel's copy of these two files
NUMERICS = docs_file("numerics.md")
HARD_CASES_HEADING = "## Naive vs ours, measured"


def pareto_plot() -> Path | None:
    return PARETO if PARETO.is_file() else None


def hard_cases_table(path: Path = NUMERICS) -> tuple[list[str], list[list[str]], str] | None:
    """(header, rows, the paragraph before the table) of docs/numerics.md's measured table, cells as HTML."""
    if not path.is_file():
        return None
    lines = path.read_text(encoding="utf-8").splitlines()
    try:
        start = lines.index(HARD_CASES_HEADING) + 1
    except ValueError:
        return None
    intro, table = [], []
    for line in lines[start:]:
        if line.startswith("## "):
            break
        if line.startswith("|"):
            table.append(line)
        elif not table and line.strip():
            intro.append(line.strip())
    if len(table) < 3:
        return None
    cells = [_cells(row) for row in table]
    return cells[0], cells[2:], inline(" ".join(intro))


def _cells(row: str) -> list[str]:
    parts = re.split(r"(?<!\\)\|", row.strip().strip("|"))
    return [inline(p.strip().replace("\\|", "|")) for p in parts]


def inline(text: str) -> str:
    """Markdown's inline code and emphasis as HTML (the rest escaped)."""
    out = []
    for k, part in enumerate(text.split("`")):
        escaped = html.escape(part)
        if k % 2:
            out.append(f"<code>{escaped}</code>")
        else:
            out.append(re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", escaped))
    return "".join(out)
