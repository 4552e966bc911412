"""Record what the wgpu path creates and records, as data a small generic JavaScript player replays.

The wgpu path runs unchanged on the real device, through a :class:`Rec` proxy around the device: every call on
a GPU object (``create_*``, ``begin_*_pass``, ``set_*``, ``draw*``, ``write_*``, ``copy_*``, ``submit`` ...) is
forwarded to wgpu-py and appended to :attr:`Recording.calls` as plain JSON: the object it was called on and the
one it returned as ids, bytes as indices into :attr:`Recording.blobs`, dictionary keys in WebGPU's JavaScript
spelling (``entry_point`` -> ``entryPoint``). Keyword-only wgpu-py methods take one descriptor in JavaScript
(``{"d": {...}}``); the others take positional arguments (``{"a": [...]}``, defaults filled in from wgpu-py's
signature, which follows the WebGPU IDL's order). Readbacks (mapping, ``read_texture``) are not recorded.

:class:`RecordingContext` is the :class:`GPUContext` the path sees: the real adapter and a recorded device,
with the browser's guarantees instead of this adapter's: no optional features (so the plan falls back where a
browser would: immediates, clear-texture, timestamps) and WebGPU's default limits where they are stricter.
"""

from __future__ import annotations

import hashlib
import inspect
import re
from dataclasses import dataclass, field

import numpy as np
import wgpu

from wgpurender.core.plan.model import AdapterFacts
from wgpurender.wgpu_path.device.context import GPUContext

NOT_RECORDED = {"map_async", "map_sync", "read_mapped", "write_mapped", "unmap", "read_texture", "read_buffer",
                "on_submitted_work_done_sync", "on_submitted_work_done_async", "get_mapped_range"}
# WebGPU's default limits (https://www.w3.org/TR/webgpu/#limit-default): what any browser guarantees.
WEBGPU_DEFAULT_LIMITS = {
    "max-texture-dimension-2d": 8192, "max-bind-groups": 4, "max-color-attachments": 8,
    "max-uniform-buffer-binding-size": 65536, "max-storage-buffer-binding-size": 134217728,
    "min-uniform-buffer-offset-alignment": 256, "min-storage-buffer-offset-alignment": 256,
    "max-immediate-size": 0,
}
ALIGNMENT_LIMITS = ("min-uniform-buffer-offset-alignment", "min-storage-buffer-offset-alignment")
BROWSER = AdapterFacts("", frozenset(), "the browser's WebGPU", "WebGPU",
                       max_storage_binding=WEBGPU_DEFAULT_LIMITS["max-storage-buffer-binding-size"])


class RecordingError(RuntimeError):
    """The path handed a recorded call an object the recording did not see being made."""


def camel(name: str) -> str:
    return re.sub(r"_([a-z0-9])", lambda m: m.group(1).upper(), name)


def _is_bytes(value) -> bool:
    return isinstance(value, (bytes, bytearray, memoryview, np.ndarray))


@dataclass
class Recording:
    """The calls, the byte blobs they reference (deduplicated), and the ids of recorded objects."""

    calls: list[dict] = field(default_factory=list)
    blobs: list[bytes] = field(default_factory=list)
    _blob_ids: dict[bytes, int] = field(default_factory=dict)
    _proxies: dict[int, Rec] = field(default_factory=dict)
    _next_id: int = 0

    def wrap(self, raw, made_by: dict | None = None) -> Rec:
        """The proxy of a GPU object (one per object); ``made_by`` is the call that returned it."""
        proxy = self._proxies.get(id(raw))
        if proxy is None:
            proxy = Rec(raw, self, self._next_id)
            self._next_id += 1
            self._proxies[id(raw)] = proxy
            if made_by is not None:
                made_by["r"] = proxy._id
        return proxy

    def blob(self, data) -> int:
        raw = np.ascontiguousarray(data).tobytes() if isinstance(data, np.ndarray) else bytes(memoryview(data))
        key = hashlib.sha1(raw).digest()
        if key not in self._blob_ids:
            self._blob_ids[key] = len(self.blobs)
            self.blobs.append(raw)
        return self._blob_ids[key]

    def encode(self, value, key: str = ""):
        """A call argument as JSON: proxies -> {"$": id}, bytes -> {"#": blob}, dict keys camelCased."""
        if isinstance(value, Rec):
            return {"$": value._id}
        if _is_bytes(value):
            return {"#": self.blob(value)}
        if isinstance(value, wgpu.GPUObjectBase):  # made outside the recording: the page could not name it
            raise RecordingError(f"{type(value).__name__} {value.label!r} was made outside the recording (a cache "
                                 "held beyond the recorded device?)")
        if isinstance(value, dict):
            keep = key == "constants"  # WGSL override names stay as written
            return {(k if keep else camel(k)): self.encode(v, k) for k, v in value.items() if v is not None}
        if isinstance(value, (list, tuple)):
            return [self.encode(v) for v in value]
        if isinstance(value, (np.integer, np.floating)):
            return value.item()
        return value


def _unwrap(value):
    if isinstance(value, Rec):
        return value._raw
    if isinstance(value, dict):
        return {k: _unwrap(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_unwrap(v) for v in value]
    if isinstance(value, tuple):
        return tuple(_unwrap(v) for v in value)
    return value


class Rec:
    """A GPU object seen through the recording: calls are forwarded and logged, attributes read through.

    ``isinstance(proxy, wgpu.GPUBuffer)`` holds (``__class__`` is the wrapped object's), so the path's own
    type checks behave as on the real object."""

    __slots__ = ("_raw", "_rec", "_id", "_attrs")

    def __init__(self, raw, recording: Recording, ident: int) -> None:
        object.__setattr__(self, "_raw", raw)
        object.__setattr__(self, "_rec", recording)
        object.__setattr__(self, "_id", ident)
        object.__setattr__(self, "_attrs", {})

    @property
    def __class__(self):  # noqa: D401 - isinstance() sees the wrapped type
        return type(self._raw)

    def __getattr__(self, name: str):
        if name in self._attrs:
            return self._attrs[name]
        if name.startswith("_wgpurender"):  # the path's own caches on the raw object hold unrecorded objects
            raise AttributeError(name)
        value = getattr(self._raw, name)
        if name.startswith("_") or name in NOT_RECORDED:
            return value
        if inspect.ismethod(value):
            return self._method(name, value)
        if isinstance(value, wgpu.GPUObjectBase):
            call = {"o": self._id, "g": name}
            proxy = self._rec.wrap(value, call)
            if "r" in call:
                self._rec.calls.append(call)
            return proxy
        return value

    def __setattr__(self, name: str, value) -> None:
        """Kept on the proxy: the path's per-device caches (gpu_cache.py) then belong to this recording, so
        a second export in one process records its objects again instead of finding the first one's."""
        self._attrs[name] = value

    def __hash__(self) -> int:
        return hash(self._raw)

    def __eq__(self, other) -> bool:
        return self._raw is (other._raw if isinstance(other, Rec) else other)

    def _method(self, name: str, method):
        rec = self._rec

        def call(*args, **kwargs):
            result = method(*_unwrap(args), **_unwrap(kwargs))
            entry = {"o": self._id, "m": camel(name)}
            params = list(inspect.signature(method).parameters.values())
            if params and all(p.kind is inspect.Parameter.KEYWORD_ONLY for p in params):
                entry["d"] = rec.encode(kwargs)
            else:
                bound = inspect.signature(method).bind(*args, **kwargs)
                bound.apply_defaults()
                entry["a"] = [rec.encode(v) for v in bound.args]
            rec.calls.append(entry)
            if isinstance(result, wgpu.GPUObjectBase):
                return rec.wrap(result, entry)
            return result

        return call


class RecordingContext(GPUContext):
    """The context the wgpu path renders through while it is recorded for a browser (see the module doc)."""

    def adapter_facts(self) -> AdapterFacts:
        return BROWSER

    def limit(self, name: str) -> int:
        real = super().limit(name)
        default = WEBGPU_DEFAULT_LIMITS.get(name)
        if default is None:
            return real
        return max(real, default) if name in ALIGNMENT_LIMITS else min(real, default)


def recording_context(ctx: GPUContext) -> tuple[RecordingContext, Recording]:
    """A context over ``ctx``'s device whose every call is recorded, with no optional features."""
    recording = Recording()
    device = recording.wrap(ctx.device, {"g": "device"})
    return RecordingContext(adapter=ctx.adapter, device=device, features=frozenset()), recording
