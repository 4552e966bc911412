"""Live reload for the demo window: notice edited files, and say where a broken one is broken.

The window polls a :class:`FileWatcher` a few times a second (a stat per file: the watched
set is the WGSL files the running pipelines loaded plus the scene file, a handful). When one
changed, the window rebuilds its drawable; a rebuild that fails leaves the old drawable
running, so the last good image stays on screen, and :func:`error_line` turns the failure
into one ``file:line: message`` line.

naga reports WGSL errors against the source it was given (``wgsl:18:11``). The course's
shaders are often generated from a file (cube3d.wgsl gets its structs inserted, post effects
have post_common.wgsl prepended), so that line number may not be the file's: the error's
quoted source line is looked up in the watched files instead, and the file's own line
number is reported.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

NAGA_LOCATION = re.compile(r"wgsl:(\d+):(\d+)")
NAGA_SOURCE_LINE = re.compile(r"^\s*(\d+)\s*│\s?(.*)$")
NAGA_MESSAGE = re.compile(r"(?:parsing|validation) error: (.*)$|^error: (.*)$", re.MULTILINE)


class FileWatcher:
    """Which of a set of files changed (modification time or size) since the last :meth:`changed` call."""

    def __init__(self, paths: Iterable[Path]) -> None:
        self.paths = sorted({Path(p).resolve() for p in paths})
        self._stamps = {p: self._stamp(p) for p in self.paths}

    @staticmethod
    def _stamp(path: Path) -> tuple[int, int] | None:
        try:
            st = path.stat()
        except OSError:  # deleted or being replaced by an editor: a change too
            return None
        return st.st_mtime_ns, st.st_size

    def changed(self) -> list[Path]:
        out = []
        for path in self.paths:
            stamp = self._stamp(path)
            if stamp != self._stamps[path]:
                self._stamps[path] = stamp
                out.append(path)
        return out


def drop_shader_caches(device) -> None:
    """Forget pipelines cached on the device across drawables, so a rebuild compiles the files again.

    The device keeps its GPU caches (wgpurender/wgpu_path/device/gpu_cache.py: the textured stage's pipelines, mip
    generation, the post passes' modules, layouts and pipelines); a rebuilt drawable would otherwise
    reuse the old shader. Only the demo window calls this, before each (re)build.
    """
    from wgpurender.wgpu_path.device.gpu_cache import clear_caches

    clear_caches(device)


def error_line(err: BaseException, files: Iterable[Path]) -> str:
    """One line for a failed rebuild: ``path:line:col: message`` for a WGSL error, else the error's text."""
    text = str(err).strip()
    location = NAGA_LOCATION.search(text)
    if location is None:
        return " ".join(line.strip() for line in text.splitlines() if line.strip())
    message = _naga_message(text)
    source_line = next((m.group(2) for line in text.splitlines() if (m := NAGA_SOURCE_LINE.match(line))
                        and m.group(1) == location.group(1)), None)
    where = _find_line(source_line, files) if source_line is not None else None
    if where is None:
        name = re.search(r"shader (\S+) failed", text)
        where = f"{name.group(1) if name else 'shader'} (generated line {location.group(1)})"
    return f"{where}:{location.group(2)}: {message}"


def _naga_message(text: str) -> str:
    m = NAGA_MESSAGE.search(text)
    if m:
        return (m.group(1) or m.group(2)).strip()
    return text.splitlines()[0]


def _find_line(source_line: str, files: Iterable[Path]) -> str | None:
    """``path:N`` of the one watched WGSL file line equal to ``source_line``, if exactly one matches."""
    wanted = source_line.rstrip()
    if not wanted.strip():
        return None
    hits = []
    for path in files:
        if path.suffix != ".wgsl":
            continue
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except OSError:
            continue
        hits += [f"{path}:{k}" for k, line in enumerate(lines, start=1) if line.rstrip() == wanted]
    return hits[0] if len(hits) == 1 else None
