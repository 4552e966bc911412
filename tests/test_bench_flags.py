"""bench perf refuses a flag that cannot apply to the families asked for, in one line (exit 2), before timing.

``--frames`` sets the frame families' timed frames; the startup family times first pixels over fresh processes
(bench/startup.py's rounds), so ``--only startup --frames 7`` ran 11 rounds and the 7 went nowhere, silently."""

from __future__ import annotations

from wgpurender.cli import main


def test_frames_for_the_startup_family_alone_is_refused(capsys, tmp_path):
    out = tmp_path / "r"
    # --quick: were it not refused, two rounds rather than eleven
    assert main(["bench", "perf", "--quick", "--only", "startup", "--frames", "7", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--frames" in err[0] and "startup" in err[0], err
    assert not out.exists()


def test_frames_with_a_frame_family_passes_that_check(capsys, tmp_path):
    """The next check (an --out that is a file) answers instead: --frames applied to the frames family."""
    taken = tmp_path / "results.txt"
    taken.write_text("")
    assert main(["bench", "perf", "--only", "startup,frames", "--frames", "7", "--out", str(taken)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--out" in err[0] and "--frames" not in err[0], err
