"""The command line: every user mistake is one clear line on stderr, exit code 2, and no output file."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from wgpurender.cli import main
from wgpurender.core.files import imageio


def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _one_line_error(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def test_stages_lists_every_stage_with_its_course_step(capsys):
    code, out, _ = _run(capsys, "stages")
    assert code == 0
    for name in ("clear", "clear-pass", "triangle", "triangle-buffers", "offscreen", "msaa"):
        assert any(line.startswith(name + " ") for line in out.splitlines())
    assert out.count("course step") >= 6


def test_render_writes_png(capsys, tmp_path):
    path = tmp_path / "tri.png"
    code, out, _ = _run(capsys, "render", "triangle", "-o", str(path), "--size", "64x48", "--format", "rgba8unorm")
    assert code == 0 and "frame time" in out and "adapter" in out
    assert Image.open(path).size == (64, 48)


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["render", "nope", "-o", "{tmp}/x.png"], "valid stages are clear, clear-pass, triangle"),
        (["render", "triangle", "-o", "{tmp}/x.png", "--size", "64by48"], "malformed size"),
        (["render", "triangle", "-o", "{tmp}/x.png", "--size", "0x48"], "out of range"),
        (["render", "msaa", "-o", "{tmp}/x.png", "--msaa", "8"], "supported sample counts are 1, 4"),
        (["render", "triangle", "-o", "{tmp}/missing/dir/x.png"], "does not exist"),
        (["render", "triangle", "-o", "{tmp}/x.png", "--format", "rgb565"], "unsupported colour format"),
        (["render", "triangle", "-o", "{tmp}/x.png", "--backend", "Glide"], "unknown backend"),
        (["demo", "nope"], "valid stages are"),
    ],
)
def test_bad_input_is_one_clear_line(capsys, tmp_path, argv, needle):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    code, _, err = _run(capsys, *argv)
    assert code == 2
    assert needle in _one_line_error(err)
    assert not list(tmp_path.rglob("*.png"))


def test_unwritable_directory(capsys, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        code, _, err = _run(capsys, "render", "triangle", "-o", str(locked / "x.png"))
    finally:
        locked.chmod(0o700)
    import os

    if os.geteuid() == 0:  # root may write anywhere; the check is then moot
        assert code == 0
    else:
        assert code == 2 and "not writable" in _one_line_error(err)


def test_png_write_is_atomic(tmp_path, monkeypatch):
    """A failure while encoding leaves neither a partial PNG nor a temporary file behind."""
    path = tmp_path / "out.png"

    def broken_save(self, fp, *args, **kwargs):
        fp.write(b"\x89PNG partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", broken_save)
    with pytest.raises(imageio.UserError, match="No space left"):
        imageio.save_png(path, np.zeros((4, 4, 4), np.uint8))
    assert list(tmp_path.iterdir()) == []


def test_every_subcommand_has_help(capsys):
    from wgpurender.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name in sub.choices:
        assert main([name, "--help"]) == 0
        assert "usage:" in capsys.readouterr().out
