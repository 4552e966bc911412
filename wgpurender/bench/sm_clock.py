"""The GPU's SM clock as ``nvidia-smi`` reads it: the one reader for the bench and its probes.

The H100's SM clock is not locked on the device machines: calls saw it fall from 1980 to 1080 MHz mid-run, and the
same draw read 5.7x apart by when it was measured (docs/perf-h100/2026-11-27-late/scale). A timing compared across
rounds is therefore shown with the clock read before each round. Where there is no ``nvidia-smi`` (lavapipe, CI)
there is no clock: :func:`sm_clock` gives ``missing`` and :func:`clock_span` says why.
"""

from __future__ import annotations

import subprocess

QUERY = ("nvidia-smi", "--query-gpu=clocks.sm", "--format=csv,noheader,nounits")
NO_CLOCK = "no SM clock read (no nvidia-smi, or a CPU adapter such as lavapipe)"


def sm_clock(missing: str = "?") -> str:
    """The first GPU's SM clock in MHz, as text (``nvidia-smi``'s answer), or ``missing`` where it cannot be read."""
    try:
        out = subprocess.run(QUERY, capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return missing
    first = out.splitlines()[0].strip() if out else ""
    return first if first.isdigit() else missing


def clock_span(clocks: list[str]) -> str:
    """``"SM clock 1080-1980 MHz"`` over the readings that are numbers (one value when all agree), else
    :data:`NO_CLOCK`."""
    mhz = sorted(int(c) for c in clocks if c.isdigit())
    if not mhz:
        return NO_CLOCK
    return f"SM clock {mhz[0]} MHz" if mhz[0] == mhz[-1] else f"SM clock {mhz[0]}-{mhz[-1]} MHz"
