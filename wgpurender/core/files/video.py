"""Frames to a file: an MP4 (H.264 through imageio-ffmpeg, whose wheel bundles an ffmpeg binary) or a PNG sequence.

``w.record`` and ``demo --record`` write through :class:`FrameWriter`. A path ending in ``.mp4`` is a video;
anything else (``frames/``) is a folder of ``frame_00000.png`` ... (lossless, no dependency). imageio-ffmpeg
is an optional dependency (``pip install 'wgpurender[notebook]'``); without it an MP4 is refused with the way
out in one line. H.264 in yuv420p needs even sizes: an odd width or height is padded by one edge pixel.
API-free: numpy, Pillow and imageio-ffmpeg only.
"""

from __future__ import annotations

import contextlib
import errno
import os
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.safe_write import output_target

VIDEO_SUFFIXES = (".mp4",)


def is_video(path: str | Path) -> bool:
    return Path(path).suffix.lower() in VIDEO_SUFFIXES


def check_output(path: str | Path) -> Path:
    """Refuse what cannot be written, before anything is rendered."""
    path = Path(path)
    if is_video(path):
        if not path.parent.is_dir():  # first: the same answer with or without imageio-ffmpeg
            raise UserError(f"cannot write {path}: folder {path.parent} does not exist")
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise UserError(f"cannot write {path}: MP4 needs imageio-ffmpeg (pip install imageio-ffmpeg, or "
                            "'wgpurender[notebook]'); give a folder instead for a PNG sequence") from None
    elif path.suffix:
        raise UserError(f"cannot record to {path}: give a .mp4 file or a folder (for PNG frames)")
    elif path.exists() and not path.is_dir():
        raise UserError(f"cannot record to {path}: it is a file, not a folder")
    elif not path.parent.is_dir():
        raise UserError(f"cannot record to {path}: folder {path.parent} does not exist")
    return path


class FrameWriter:
    """``write(pixels)`` for each (H, W, 3 or 4) uint8 frame, then ``close()``; also a context manager.

    A video is encoded into a temp file beside ``path`` (``.NAME.wgpurender-PID.tmp``) and renamed onto it by
    ``close()``, so a failed recording (read-only folder, full disk, an error, Ctrl-C) leaves no partial MP4:
    ``abort()`` (or leaving the ``with`` block by an exception) removes it. A PNG folder is an owned folder
    (core/files/owned_files.py): frames of an earlier recording that this one did not write are removed at
    ``close()``, the user's other files are never touched; ``force`` writes into a folder without a manifest.
    """

    def __init__(self, path: str | Path, fps: float, force: bool = False) -> None:
        self.path, self.fps = check_output(path), float(fps)
        if not np.isfinite(self.fps) or self.fps <= 0:
            raise UserError(f"fps must be > 0, got {fps}")
        self.count = 0
        self._video = None
        self._size: tuple[int, int] | None = None
        self._tmp: Path | None = None
        self._folder = None
        if is_video(self.path):
            from wgpurender.core.files.owned_files import probe_writable

            self.path = output_target(self.path)
            probe_writable(self.path.parent, "cannot record to", named=self.path)
        else:
            from wgpurender.core.files.owned_files import OwnedFolder

            self._folder = OwnedFolder(self.path, "record", force, "cannot record to")
            self.path = self._folder.folder

    def write(self, pixels: np.ndarray) -> None:
        rgb = np.ascontiguousarray(pixels[..., :3], dtype=np.uint8)
        if self._folder is None:
            self._write_video(rgb)
        else:
            from wgpurender.core.files.imageio import encode_png

            self._folder.write(f"frame_{self.count:05d}.png", encode_png(rgb))
        self.count += 1

    def _write_video(self, rgb: np.ndarray) -> None:
        h, w = rgb.shape[:2]
        padded = np.pad(rgb, ((0, h % 2), (0, w % 2), (0, 0)), mode="edge")
        if self._video is None:
            self._size = (padded.shape[1], padded.shape[0])
            self._start_video()
        elif (padded.shape[1], padded.shape[0]) != self._size:
            raise UserError(f"the frame size changed while recording {self.path} (resize the window before)")
        try:
            self._video.send(padded)
        except (OSError, RuntimeError) as err:
            self.abort()
            raise UserError(f"cannot record to {self.path}: {_reason(err)}") from None

    def _start_video(self) -> None:
        import imageio_ffmpeg

        from wgpurender.core.files.safe_write import temp_name

        self._tmp = temp_name(self.path)
        self._video = imageio_ffmpeg.write_frames(str(self._tmp), self._size, fps=self.fps, codec="libx264",
                                                  pix_fmt_in="rgb24", pix_fmt_out="yuv420p", quality=8,
                                                  macro_block_size=2, ffmpeg_log_level="quiet",
                                                  output_params=["-f", "mp4"])
        self._video.send(None)  # start the generator

    def close(self) -> Path:
        """Finish: the video renamed into place, or the folder's stale frames removed and its manifest written."""
        if self._folder is not None:
            self._folder.finish()
            return self.path
        if self._video is None:
            return self.path
        try:
            self._video.close()
            self._video = None
            self._check_whole()
            os.replace(self._tmp, output_target(self.path))
        except (OSError, RuntimeError) as err:
            self.abort()
            raise UserError(f"cannot record to {self.path}: {_reason(err)}") from None
        finally:
            self.abort()
        return self.path

    def _check_whole(self) -> None:
        """The encoder's exit status is not reported (imageio-ffmpeg): count the frames of the written file, so
        that a full disk (ffmpeg stops writing, quietly) is an error, not a truncated video."""
        import imageio_ffmpeg

        try:
            frames, _ = imageio_ffmpeg.count_frames_and_secs(str(self._tmp))
        except (OSError, RuntimeError):
            frames = -1
        if frames != self.count:
            raise OSError(errno.ENOSPC if _disk_full(self._tmp.parent) else errno.EIO,
                          f"the video came out with {max(frames, 0)} of {self.count} frames "
                          f"({'the disk is full' if _disk_full(self._tmp.parent) else 'the encoder stopped'})")

    def abort(self) -> None:
        """Stop without publishing: the temp video removed (frames written to a folder stay listed)."""
        video, self._video = self._video, None
        if video is not None:
            with contextlib.suppress(Exception):
                video.close()
        if self._tmp is not None:
            with contextlib.suppress(OSError):
                self._tmp.unlink(missing_ok=True)

    def __enter__(self) -> FrameWriter:
        return self

    def __exit__(self, exc_type, *exc) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


def _disk_full(folder: Path) -> bool:
    try:
        return os.statvfs(folder).f_bavail == 0
    except OSError:
        return False


def _reason(err: BaseException) -> str:
    """One line for an encoder failure: the OS's words when there are some (a full disk: ENOSPC, EFBIG)."""
    if isinstance(err, OSError) and err.strerror:
        return err.strerror
    first = (str(err).strip().splitlines() or ["the encoder failed"])[0]
    return f"the encoder failed ({first[:120]})"
