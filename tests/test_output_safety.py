"""Output safety: a killed run leaves no temp file (SIGTERM, SIGINT) or one that the next run removes (SIGKILL),
and special files (symlinks, FIFOs, devices, directories) are never replaced."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest
from PIL import Image
from reliab_gen import run_cli

from wgpurender.core.verdict.compare import SCALE_BAR


@pytest.fixture
def images(tmp_path):
    a = np.zeros((64, 64, 3), np.uint8)
    b = a.copy()
    b[10:20, 10:20] = 200
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")
    return tmp_path / "a.png", tmp_path / "b.png"


# the 64x64 inputs' heatmap with its colour scale below it (at least 200 px wide: compare.heatmap_with_scale)
HEATMAP_SIZE = (200, 64 + sum(SCALE_BAR))

def _temps(folder):
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


def _start_slow_write(images, out):
    """``wgpurender compare --heatmap out`` in a subprocess that holds its temp file open for 60 s (test hook)."""
    env = {**os.environ, "WGPURENDER_TEST_WRITE_DELAY": "60"}
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", "compare", *map(str, images), "--heatmap", str(out)],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while not _temps(out.parent):
        assert proc.poll() is None, proc.stderr.read().decode()
        assert time.monotonic() < deadline, "the temp file never appeared"
        time.sleep(0.05)
    return proc


@pytest.mark.parametrize("sig, code", [(signal.SIGTERM, 128 + signal.SIGTERM), (signal.SIGINT, 130)])
def test_a_run_killed_mid_write_leaves_no_temp_file_and_no_output(tmp_path, images, sig, code):
    out = tmp_path / "out" / "heat.png"
    out.parent.mkdir()
    proc = _start_slow_write(images, out)
    assert _temps(out.parent) == [f".heat.png.wgpurender-{proc.pid}.tmp"]
    proc.send_signal(sig)
    assert proc.wait(timeout=30) == code
    assert list(out.parent.iterdir()) == []  # neither the temp file nor a partial output


def test_an_old_output_survives_a_kill_whole(tmp_path, images):
    out = tmp_path / "out" / "heat.png"
    out.parent.mkdir()
    out.write_bytes(b"old contents")
    proc = _start_slow_write(images, out)
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=30)
    assert out.read_bytes() == b"old contents" and _temps(out.parent) == []


def test_sigkill_leaves_one_named_temp_file_that_the_next_write_removes(tmp_path, images):
    out = tmp_path / "out" / "heat.png"
    out.parent.mkdir()
    proc = _start_slow_write(images, out)
    proc.kill()
    proc.wait(timeout=30)
    assert _temps(out.parent) == [f".heat.png.wgpurender-{proc.pid}.tmp"]  # what SIGKILL can leave (docs say so)
    assert not out.exists()
    code, _, err = run_cli("compare", *images, "--heatmap", out)
    assert code in (0, 1), err
    assert _temps(out.parent) == [] and Image.open(out).size == HEATMAP_SIZE


def _refused(images, target, needle):
    code, _, err = run_cli("compare", *images, "--heatmap", target)
    assert code == 2 and len(err.splitlines()) == 1 and needle in err, err


def test_a_symlink_is_not_replaced(tmp_path, images):
    real = tmp_path / "real.png"
    real.write_bytes(b"keep me")
    link = tmp_path / "link.png"
    link.symlink_to(real)
    _refused(images, link, "symbolic link")
    assert link.is_symlink() and os.readlink(link) == str(real) and real.read_bytes() == b"keep me"


def test_a_symlink_is_written_through_when_asked(tmp_path, images, monkeypatch):
    real = tmp_path / "real.png"
    real.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(real)
    monkeypatch.setenv("WGPURENDER_FOLLOW_SYMLINKS", "1")
    code, _, err = run_cli("compare", *images, "--heatmap", link)
    assert code in (0, 1), err
    assert link.is_symlink() and Image.open(real).size == HEATMAP_SIZE


def test_a_fifo_is_not_replaced_nor_opened(tmp_path, images):
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    _refused(images, fifo, "FIFO")  # opening it for writing would block: the test would hang
    assert fifo.exists() and not fifo.is_file() and _temps(tmp_path) == []


def test_a_device_is_not_replaced(tmp_path, images):
    """A character device (a twin of /dev/null made in tmp_path) is refused before any rename could replace it.

    Not the real /dev/null: if this check ever regressed, the test itself would replace the machine's /dev/null
    with a PNG (it happened once, on a developer's machine, with the old code).
    """
    device = tmp_path / "null.png"
    try:
        os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    except PermissionError:
        pytest.skip("making a device node needs root (CAP_MKNOD)")
    _refused(images, device, "character device")
    assert stat.S_ISCHR(os.lstat(device).st_mode)


def test_a_directory_is_not_replaced(tmp_path, images):
    folder = tmp_path / "dir.png"
    folder.mkdir()
    _refused(images, folder, "directory")
    assert folder.is_dir()


def test_a_render_refuses_a_special_output_before_rendering(tmp_path):
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    code, out, err = run_cli("render", "triangle", "-o", fifo, "--size", "16x16")
    assert code == 2 and "FIFO" in err and "frame time" not in out
