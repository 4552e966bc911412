"""``record`` (w.record, demo --record) never leaves stale frames, a partial video, or a traceback (issue 28.5).

Before: a second recording into a folder left the first one's later frames beside the new ones; a recording into a
read-only folder or onto a full disk ended in a traceback (or ffmpeg's multi-line error) and left a partial MP4.
Now the folder has a manifest (core/files/owned_files.py) and a video is encoded into a temp file that is renamed into
place only once it holds every frame. Full and read-only disks are real: small tmpfs mounts (root), or a file size
limit (RLIMIT_FSIZE) in a child process where mounting is not allowed.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

import wgpurender as w
from wgpurender.core.errors import UserError
from wgpurender.core.files.video import FrameWriter

pytest.importorskip("imageio_ffmpeg")
SMALL = dict(size=(32, 24), fps=10.0)


def _frames(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.glob("frame_*.png"))


def test_a_shorter_recording_replaces_a_longer_one_and_keeps_the_users_files(tmp_path):
    out = tmp_path / "frames"
    w.record("3d", out, seconds=0.5, **SMALL)
    assert _frames(out) == [f"frame_{k:05d}.png" for k in range(5)]
    (out / "notes.txt").write_bytes(b"mine\n")
    w.record("3d", out, seconds=0.2, **SMALL)
    assert _frames(out) == ["frame_00000.png", "frame_00001.png"]  # 0.2 s at 10 fps: the stale 3 are gone
    assert (out / "notes.txt").read_bytes() == b"mine\n"


def test_a_folder_of_other_files_is_refused_unless_forced(tmp_path):
    (tmp_path / "frame_00000.png").write_bytes(b"my own frame")
    with pytest.raises(UserError) as caught:
        w.record("3d", tmp_path, seconds=0.1, **SMALL)
    assert "not empty" in str(caught.value) and "\n" not in str(caught.value)
    assert (tmp_path / "frame_00000.png").read_bytes() == b"my own frame"
    w.record("3d", tmp_path, seconds=0.2, force=True, **SMALL)
    assert _frames(tmp_path) == ["frame_00000.png", "frame_00001.png"]
    assert (tmp_path / "frame_00000.png").read_bytes().startswith(b"\x89PNG")  # --force: our names are replaced


def test_an_error_while_recording_publishes_no_video(tmp_path):
    out = tmp_path / "clip.mp4"
    with pytest.raises(RuntimeError), FrameWriter(out, 10.0) as writer:
        writer.write(np.zeros((24, 32, 3), np.uint8))
        raise RuntimeError("the window closed")
    assert os.listdir(tmp_path) == []


def test_a_whole_video_has_every_frame(tmp_path):
    import imageio_ffmpeg

    out = w.record("3d", tmp_path / "clip.mp4", seconds=0.5, **SMALL)
    assert imageio_ffmpeg.count_frames_and_secs(str(out))[0] == 5
    assert os.listdir(tmp_path) == ["clip.mp4"]


@contextlib.contextmanager
def _tmpfs(options: str):
    folder = Path(tempfile.mkdtemp(prefix="wgpurender-tmpfs-"))
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)], capture_output=True)
    if done.returncode != 0:
        folder.rmdir()
        pytest.skip("cannot mount a tmpfs here (needs root)")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=False)
        folder.rmdir()


@pytest.mark.parametrize("name", ["clip.mp4", "frames"])
def test_a_read_only_folder_is_one_line_before_rendering(name):
    with _tmpfs("ro,size=16k") as folder:
        with pytest.raises(UserError) as caught:
            w.record("3d", folder / name, seconds=0.2, **SMALL)
        message = str(caught.value)
        assert ("Read-only file system" in message or "not writable" in message) and "\n" not in message, message
        assert os.listdir(folder) == []


def test_a_full_disk_is_one_line_and_no_partial_video():
    with _tmpfs("size=4k") as folder:
        with pytest.raises(UserError) as caught:
            w.record("3d", folder / "clip.mp4", seconds=1.0, size=(256, 192), fps=10.0)
        assert "disk is full" in str(caught.value) and "\n" not in str(caught.value)
        assert os.listdir(folder) == []


CHILD = """
import resource, signal, sys
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # inherited by ffmpeg: its writes fail with EFBIG, as on a full disk
resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
from wgpurender.cli import main
import wgpurender as w
from wgpurender.core.errors import UserError
try:
    w.record("3d", sys.argv[1], seconds=1.0, size=(256, 192), fps=10.0)
except UserError as err:
    print(err, file=sys.stderr)
    sys.exit(2)
"""


def test_a_file_size_limit_is_one_line_and_no_partial_video(tmp_path):
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    (tmp_path / "out").mkdir()
    done = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path / "out" / "clip.mp4")], env=env,
                          capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "cannot record to" in done.stderr, done.stderr
    assert os.listdir(tmp_path / "out") == []


def test_a_video_missing_frames_is_not_published(tmp_path, monkeypatch):
    """A file that decodes but holds fewer frames than were sent (an encoder that stopped early) is an error too,
    not only one that does not decode at all."""
    import imageio_ffmpeg

    real = imageio_ffmpeg.count_frames_and_secs
    monkeypatch.setattr(imageio_ffmpeg, "count_frames_and_secs", lambda path: (real(path)[0] - 1, 0.0))
    with pytest.raises(UserError) as caught, FrameWriter(tmp_path / "clip.mp4", 10.0) as writer:
        for k in range(3):
            writer.write(np.full((24, 32, 3), 60 * k, np.uint8))
    assert "2 of 3 frames" in str(caught.value) and os.listdir(tmp_path) == []


@pytest.mark.parametrize("name", ["clip.mp4", "frames"])
def test_demo_record_into_a_read_only_folder_is_one_line_before_a_window_opens(capsys, name):
    from wgpurender.cli import main

    with _tmpfs("ro,size=16k") as folder:
        assert main(["demo", "3d", "--record", str(folder / name), "--frames", "2"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and ("Read-only" in err[0] or "not writable" in err[0]), err
        assert os.listdir(folder) == []
