"""A process's own peak memory, for the tests that bound it.

getrusage's ru_maxrss is not a process's own peak on Linux: exec folds the replaced memory's high-water mark into
it, and that memory is the forked (or vfork-shared) parent's. A pytest-xdist worker, or a child of one, reads the
parent's peak that way (447-453 MiB for a child that peaked near 53, tests/test_gltf_untrusted.py). VmHWM in
/proc/PID/status is the high-water mark of the memory exec gave the process: its own.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

# Run as `python -c WRAPPER REPORT MODULE ARGS...`: runs MODULE as __main__ with ARGS and, at exit (a normal one,
# an exit code or an exception: not a kill by a signal), writes its own peak in MiB to REPORT.
WRAPPER = """
import atexit, runpy, sys
report, module = sys.argv[1], sys.argv[2]
def _write_peak():
    with open("/proc/self/status") as status:
        kib = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
    with open(report, "w") as out:
        out.write(str(kib // 1024))
atexit.register(_write_peak)
sys.argv = [module, *sys.argv[3:]]
runpy.run_module(module, run_name="__main__", alter_sys=True)
"""


def peak_mib(pid: int | str = "self") -> int:
    """VmHWM of /proc/PID/status in MiB: the process's own peak resident memory since its exec."""
    with open(f"/proc/{pid}/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmHWM:")) // 1024


def measured_argv(module: str, args: list, report: Path) -> list:
    """``python -m MODULE ARGS`` that writes its own peak (MiB) to ``report`` when it exits."""
    return [sys.executable, "-c", WRAPPER, os.fspath(report), module, *map(os.fspath, args)]


def reported_peak_mib(report: Path) -> int | None:
    """The peak a measured_argv child wrote; None when it wrote none (killed by a signal) or the report is gone."""
    try:
        return int(Path(report).read_text())
    except (FileNotFoundError, ValueError):
        return None
