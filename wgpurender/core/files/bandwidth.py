"""What the last benchmark measured per pass on an adapter: time, GB/s and % of a same-run copy of the same bytes.

``wgpurender bench post-roofline`` (post passes) and ``wgpurender bench perf`` (the final scene's scene pass)
record here; ``render --explain`` reads it, so a plan's passes show what they cost the last time they were
measured on this adapter, or "not measured". One JSON file, per adapter name (wgpu's ``info["device"]``), per
pass key ``SCENE|PASS|PATH`` (e.g. ``final_subpass|tonemap+vignette|compute``), the newest run winning.

The file is ``$WGPURENDER_PERF_RECORD``, else ``$XDG_CACHE_HOME/wgpurender/bandwidth.json`` (``~/.cache``).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import asdict, dataclass
from pathlib import Path

from wgpurender.core.files.cache_entry import cache_root

RECORD_ENV = "WGPURENDER_PERF_RECORD"


@dataclass(frozen=True)
class PassRecord:
    ms: float  # GPU time of the pass (timestamps, median)
    mb: float  # bytes the pass must move (the plan's compulsory traffic), in MB
    copy_ms: float  # a compute copy moving the same bytes, same run
    size: str  # "3840x2160"
    date: str
    command: str

    @property
    def gbps(self) -> float:
        return self.mb / 1e3 / (self.ms / 1e3) if self.ms > 0 else float("nan")

    @property
    def copy_gbps(self) -> float:
        return self.mb / 1e3 / (self.copy_ms / 1e3) if self.copy_ms > 0 else float("nan")

    @property
    def percent_of_copy(self) -> float:
        return 100.0 * self.copy_ms / self.ms if self.ms > 0 else float("nan")

    def text(self) -> str:
        return (f"measured {self.ms:.3f} ms = {self.gbps:.3g} GB/s, {self.percent_of_copy:.0f}% of a copy of the "
                f"same bytes ({self.copy_gbps:.3g} GB/s) at {self.size}, {self.date} (`{self.command}`)")


FIELDS = {"ms": (int, float), "mb": (int, float), "copy_ms": (int, float), "size": str, "date": str, "command": str}


def record_path() -> Path:
    if os.environ.get(RECORD_ENV):
        return Path(os.environ[RECORD_ENV])
    return cache_root() / "bandwidth.json"


def pass_key(scene: str, effects: str, path: str) -> str:
    return f"{scene}|{effects}|{path}"


def _read() -> dict:
    try:
        data = json.loads(record_path().read_text())
    except (OSError, ValueError):
        return {}  # absent or unreadable: nothing measured
    return data if isinstance(data, dict) else {}  # another shape: nothing measured (and replaced on save)


def save(adapter: str, records: dict[str, PassRecord]) -> Path:
    """Merge ``records`` (pass key -> record) into the adapter's entry; a pass measured again is replaced."""
    from wgpurender.core.files.safe_write import atomic_write

    data = _read()
    entry = data.get(adapter)
    if not isinstance(entry, dict):
        entry = data[adapter] = {}
    entry.update({key: asdict(r) for key, r in records.items()})
    path = record_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(path, (json.dumps(data, indent=1, sort_keys=True) + "\n").encode())


def lookup(adapter: str | None, key: str) -> PassRecord | None:
    """The record of a pass, or None ("not measured"): also for a file of another shape (another version wrote
    it, or it was edited): a record is data read from disk, and only a complete one of the right types counts."""
    if not adapter:
        return None
    data = _read()
    entry = data.get(adapter) if isinstance(data, dict) else None
    found = entry.get(key) if isinstance(entry, dict) else None
    if not isinstance(found, dict) or set(found) != set(FIELDS):
        return None
    if not all(isinstance(found[name], kind) and not isinstance(found[name], bool) for name, kind in FIELDS.items()):
        return None
    if not all(math.isfinite(found[name]) and found[name] > 0 for name in ("ms", "mb", "copy_ms")):
        return None
    return PassRecord(**found)
