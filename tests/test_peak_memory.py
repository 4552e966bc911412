"""tests/peak_memory.py: a child's own peak, not the parent's that getrusage folds in at exec."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

from peak_memory import measured_argv, peak_mib, reported_peak_mib

TESTS = Path(__file__).resolve().parent

# A parent that peaks at BIG MiB, then runs a small child (python -m json.tool) measured both ways.
PARENT = textwrap.dedent("""
    import json, os, subprocess, sys
    sys.path.insert(0, sys.argv[1])
    from peak_memory import measured_argv, reported_peak_mib
    big = bytearray(int(sys.argv[2]) << 20)
    big[::4096] = b"x" * len(big[::4096])  # touch every page
    del big
    report, data = sys.argv[3], sys.argv[4]
    proc = subprocess.Popen(measured_argv("json.tool", [data], report), stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    print(json.dumps({"exit": os.waitstatus_to_exitcode(status), "ru_maxrss_mib": usage.ru_maxrss // 1024,
                      "own_mib": reported_peak_mib(report)}))
""")
BIG = 300


def test_a_child_reports_its_own_peak_where_ru_maxrss_reports_its_parents(tmp_path):
    (tmp_path / "d.json").write_text("[1, 2, 3]")
    run = subprocess.run([sys.executable, "-c", PARENT, str(TESTS), str(BIG), str(tmp_path / "peak.txt"),
                          str(tmp_path / "d.json")], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["exit"] == 0
    assert got["ru_maxrss_mib"] >= BIG  # the case: wait4 reads the parent's peak for a small child
    assert got["own_mib"] is not None and 0 < got["own_mib"] < BIG // 3, got


def test_a_measured_child_keeps_its_exit_code_and_output(tmp_path):
    (tmp_path / "bad.json").write_text("[1, 2,")
    run = subprocess.run(measured_argv("json.tool", [tmp_path / "bad.json"], tmp_path / "peak.txt"),
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 1 and "Expecting value" in run.stderr
    assert reported_peak_mib(tmp_path / "peak.txt") > 0


def test_a_child_killed_by_a_signal_reports_nothing_and_self_is_read(tmp_path):
    proc = subprocess.Popen(measured_argv("http.server", ["0", "--bind", "127.0.0.1"], tmp_path / "peak.txt"),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    proc.kill()
    proc.wait(timeout=60)
    assert reported_peak_mib(tmp_path / "peak.txt") is None
    assert peak_mib() > 0
