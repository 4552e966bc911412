"""An unknown argument is refused by the command it was given to, pointing at that command's --help.

``wgpurender export final -o d --time 2`` said "wgpurender: error: unrecognized arguments: --time 2 (see
wgpurender --help)": the top-level help, which lists commands but not export's flags. Every other usage error
names its command ("wgpurender export: error: ... (see wgpurender export --help)").
"""

from __future__ import annotations

import pytest

from wgpurender.cli import main


@pytest.mark.parametrize(("argv", "prog", "extra"), [
    (["export", "final", "-o", "d", "--time", "2"], "wgpurender export", "--time 2"),
    (["stages", "nosuch"], "wgpurender stages", "nosuch"),
    (["bench", "perf", "--quick", "--nosuch"], "wgpurender bench perf", "--nosuch"),
    (["compare", "a.png", "b.png", "c.png"], "wgpurender compare", "c.png"),
])
def test_unknown_argument_names_its_command(capsys, tmp_path, monkeypatch, argv, prog, extra):
    monkeypatch.chdir(tmp_path)
    try:
        code = main(argv)
    except SystemExit as exit_:
        code = exit_.code
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert err[0] == f"{prog}: error: unrecognized arguments: {extra} (see {prog} --help)"
    assert list(tmp_path.iterdir()) == []


def test_known_arguments_still_parse(capsys):
    assert main(["stages"]) == 0 and "triangle" in capsys.readouterr().out
