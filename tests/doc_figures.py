"""Figures in the docs, each computed from a committed run output (issue 32 item 4).

A figure is written between two markers; the opening one says where it comes from and how it is computed::

    <!-- figure src=assets/reference/implementations.toml table=implementations.wgpu-gl.targets
         where=measured^=max diff 0/255 agg=count -->10<!-- /figure -->

``src``: a committed CSV (its rows), TOML or JSON file (``table``: the dotted path of a table whose entries are
the rows, each with its key as ``name``); the source carries its machine, date and command (a CSV's folder a
``machine.txt`` or ``README.md``; a TOML/JSON table a ``bounded_by`` or ``machine`` beside ``table``'s rows).
``where``: ``;``-separated conditions ``field=value`` or ``field^=prefix``. ``agg``: ``value`` (exactly one
row's ``col``, the default), ``count``, ``min``, ``max`` or ``median`` of ``col``; ``per=N`` shows N / the value
(``per=1000`` of a frame time in ms: frames per second). ``fmt``: a Python format spec (default ``g``).
``python tests/doc_figures.py --write`` rewrites every figure from its source; tests/test_doc_figures.py fails
when one differs.
"""

from __future__ import annotations

import csv
import json
import re
import shlex
import statistics
import sys
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DOCS = (*sorted((REPO / "docs").glob("*.md")), REPO / "README.md")
MARKER = re.compile(r"<!-- figure (?P<spec>.*?) -->(?P<text>.*?)<!-- /figure -->", re.S)
AGGREGATES = ("value", "count", "min", "max", "median")


def _spec(text: str) -> dict[str, str]:
    return dict(part.split("=", 1) for part in shlex.split(" ".join(text.split())))


def _rows(spec: dict[str, str]) -> list[dict]:
    src = REPO / spec["src"]
    if src.suffix == ".csv":
        with src.open(newline="") as f:
            return list(csv.DictReader(f))
    data = tomllib.loads(src.read_text()) if src.suffix == ".toml" else json.loads(src.read_text())
    for key in spec["table"].split("."):
        data = data[key]
    return [{"name": name, **row} for name, row in data.items()]


def provenance(spec: dict[str, str]) -> str:
    """Where the source says its machine, date and command ('' when it does not)."""
    src = REPO / spec["src"]
    if src.suffix == ".csv":
        beside = (src.parent / "machine.txt", src.parent / "README.md", src.parent / "report.md")
        return next((p.name for p in beside if p.is_file()), "")
    data = tomllib.loads(src.read_text()) if src.suffix == ".toml" else json.loads(src.read_text())
    keys = spec["table"].split(".")
    for key in keys[:-1]:
        data = data[key]
    return next((str(data[k]) for k in ("bounded_by", "machine") if k in data), "")


def _matches(row: dict, condition: str) -> bool:
    if "^=" in condition:
        field, prefix = condition.split("^=", 1)
        return str(row.get(field, "")).startswith(prefix)
    field, value = condition.split("=", 1)
    return str(row.get(field, "")) == value


def compute(spec: dict[str, str]) -> str:
    """The figure's text from its source."""
    conditions = [c for c in spec.get("where", "").split(";") if c]
    rows = [r for r in _rows(spec) if all(_matches(r, c) for c in conditions)]
    agg, fmt = spec.get("agg", "value"), spec.get("fmt", "g")
    if agg not in AGGREGATES:
        raise ValueError(f"agg={agg}: choose one of {', '.join(AGGREGATES)}")
    if agg == "count":
        return format(len(rows), fmt if fmt != "g" else "d")
    if agg == "value":
        if len(rows) != 1:
            raise ValueError(f"{len(rows)} rows match {spec}: a value needs exactly one")
        value = rows[0][spec["col"]]
        return format(_per(spec, float(value)), fmt) if fmt != "s" else str(value)
    numbers = [float(r[spec["col"]]) for r in rows]
    return format(_per(spec, {"min": min, "max": max, "median": statistics.median}[agg](numbers)), fmt)


def _per(spec: dict[str, str], value: float) -> float:
    return float(spec["per"]) / value if "per" in spec else value


def figures(path: Path) -> list[tuple[dict[str, str], str]]:
    return [(_spec(m["spec"]), m["text"]) for m in MARKER.finditer(path.read_text())]


def write() -> int:
    for path in DOCS:
        text = path.read_text()
        new = MARKER.sub(lambda m: f"<!-- figure {m['spec']} -->{compute(_spec(m['spec']))}<!-- /figure -->", text)
        if new != text:
            path.write_text(new)
            print(f"rewrote {path.relative_to(REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(write() if sys.argv[1:] == ["--write"] else print("usage: python tests/doc_figures.py --write") or 2)
