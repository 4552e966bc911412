"""A probe's rows (dicts of one shape) as a CSV file: the one writer of the probe scripts here (tail_probe.py,
tail_cause_probe.py, first_pixel_phases.py), which are run as scripts, so this folder is on their path."""

from __future__ import annotations

import csv
from pathlib import Path


def write_rows(path: Path, rows: list[dict], digits: int | None = None) -> None:
    """``rows`` under a header of the first row's keys; floats rounded to ``digits`` where given."""
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows if digits is None else
                         ({k: round(v, digits) if isinstance(v, float) else v for k, v in r.items()} for r in rows))
