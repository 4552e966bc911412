"""The report's progress goes to stdout, all of it: a report that succeeds writes nothing on stderr.

``wgpurender report`` printed its steps on stdout but the accuracy run's 17 progress-bar lines on stderr, so a
successful build (exit 0) filled stderr, where scripts and CI look for what went wrong.
"""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from wgpurender.bench import accuracy_run
from wgpurender.report import extras


class Stop(Exception):
    """Ends the report's measurement once the accuracy run has reported its progress."""


def test_the_accuracy_runs_progress_is_on_stdout(capsys, monkeypatch, tmp_path):
    def one_step(config, ctx, progress_stream=None):
        accuracy_run.Progress(1, progress_stream).step("round 1/1 final")
        raise Stop

    monkeypatch.setattr(accuracy_run, "run_accuracy", one_step)
    with pytest.raises(Stop):
        extras.measure(SimpleNamespace(describe=lambda: "an adapter"), tmp_path, size=(8, 6))
    said = capsys.readouterr()
    assert said.err == "" and "1/1 100%" in said.out and "round 1/1 final" in said.out
