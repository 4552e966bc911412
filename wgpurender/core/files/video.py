"""Frames to a file: an MP4 (H.264 through imageio-ffmpeg, whose wheel bundles an ffmpeg binary) or a PNG sequence.

``w.record`` and ``demo --record`` write through :class:`FrameWriter`. A path ending in ``.mp4`` is a video;
anything else (``frames/``) is a folder of ``frame_00000.png`` ... (lossless, no dependency). imageio-ffmpeg
is an optional dependency (``pip install 'wgpurender[notebook]'``); without it an MP4 is refused with the way
out in one line. H.264 in yuv420p needs even sizes: an odd width or height is padded by one edge pixel.
API-free: numpy, Pillow and imageio-ffmpeg only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError

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
    """``write(pixels)`` for each (H, W, 3 or 4) uint8 frame, then ``close()``; also a context manager."""

    def __init__(self, path: str | Path, fps: float) -> None:
        self.path, self.fps = check_output(path), float(fps)
        if self.fps <= 0:
            raise UserError(f"fps must be > 0, got {fps}")
        self.count = 0
        self._video = None
        self._size: tuple[int, int] | None = None
        if not is_video(self.path):
            self.path.mkdir(exist_ok=True)

    def write(self, pixels: np.ndarray) -> None:
        rgb = np.ascontiguousarray(pixels[..., :3], dtype=np.uint8)
        if is_video(self.path):
            self._write_video(rgb)
        else:
            from wgpurender.core.files.imageio import save_png

            save_png(self.path / f"frame_{self.count:05d}.png", rgb)
        self.count += 1

    def _write_video(self, rgb: np.ndarray) -> None:
        h, w = rgb.shape[:2]
        padded = np.pad(rgb, ((0, h % 2), (0, w % 2), (0, 0)), mode="edge")
        if self._video is None:
            import imageio_ffmpeg

            self._size = (padded.shape[1], padded.shape[0])
            self._video = imageio_ffmpeg.write_frames(str(self.path), self._size, fps=self.fps, codec="libx264",
                                                      pix_fmt_in="rgb24", pix_fmt_out="yuv420p", quality=8,
                                                      macro_block_size=2, ffmpeg_log_level="error")
            self._video.send(None)  # start the generator
        elif (padded.shape[1], padded.shape[0]) != self._size:
            raise UserError(f"the frame size changed while recording {self.path} (resize the window before)")
        self._video.send(padded)

    def close(self) -> Path:
        if self._video is not None:
            self._video.close()
            self._video = None
        return self.path

    def __enter__(self) -> FrameWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
