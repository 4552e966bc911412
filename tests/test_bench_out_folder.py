"""bench refuses an --out that is a file before it times anything, in one line (exit 2).

``wgpurender bench perf --quick --out results.txt`` (an existing file) ran the whole benchmark, then died with a
FileExistsError traceback when writing the results: minutes lost and no results. verify --out and report -o
already refuse a file up front.
"""

from __future__ import annotations

import pytest

from wgpurender.cli import main


def _code(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exit_:  # argparse's refusal
        return exit_.code


@pytest.mark.parametrize("suite", [["perf", "--quick"], ["accuracy", "--quick"], ["post-roofline", "--frames", "1"]])
def test_out_that_is_a_file_is_refused(capsys, tmp_path, suite):
    taken = tmp_path / "results.txt"
    taken.write_text("keep me\n")
    assert _code(["bench", *suite, "--out", str(taken)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--out" in err[0] and str(taken) in err[0]
    assert taken.read_text() == "keep me\n"


def test_docs_img_that_is_a_file_is_refused(capsys, tmp_path):
    taken = tmp_path / "img"
    taken.write_text("")
    assert _code(["bench", "perf", "--quick", "--out", str(tmp_path / "r"), "--docs-img", str(taken)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--docs-img" in err[0]
