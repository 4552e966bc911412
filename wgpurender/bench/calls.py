"""Native calls per frame: every wgpu call a frame makes, counted by wrapping the device, queue and encoders.

What is counted is what the frame asks wgpu-py for (each such call crosses into wgpu-native once, or
a few times for a pass's begin): the device's methods (``create_*``, which a steady-state frame should
never call), the queue's (``write_buffer``, ``submit``...), the command encoder's (``begin_*_pass``,
``copy_*``, ``resolve_query_set``, ``finish``) and every call on the pass encoders it hands out
(``set_pipeline``, ``draw``, ``execute_bundles``, ``end``...). Property reads (a texture's size or
format) are Python-only and not counted. The counting is done here, in the bench, by wrapping: the
renderer is not told it is being counted.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import wgpu

from wgpurender.wgpu_path.device.context import GPUContext

_PASS_MAKERS = ("begin_render_pass", "begin_compute_pass")
_ABSENT = object()


class _Counted:
    """A proxy of a wgpu object whose method calls are counted as ``"Kind.method"``; passes it makes are too."""

    def __init__(self, real: object, kind: str, counter: Counter, times: Counter | None = None) -> None:
        self._real, self._kind, self._counter, self._times = real, kind, counter, times

    def __getattr__(self, name: str):
        attr = getattr(self._real, name)
        if not callable(attr):
            return attr
        key = f"{self._kind}.{name}"

        def call(*args, **kwargs):
            self._counter[key] += 1
            start = time.perf_counter()
            result = attr(*args, **kwargs)
            if self._times is not None:
                self._times[key] += time.perf_counter() - start
            if name in _PASS_MAKERS:
                return _Counted(result, name.removeprefix("begin_"), self._counter, self._times)
            return result

        return call


@contextmanager
def counting(ctx: GPUContext, counter: Counter, times: Counter | None = None) -> Iterator[None]:
    """Count every device and queue method call made inside the block (instance attributes, restored after)."""
    patched = []
    for obj, kind in ((ctx.device, "device"), (ctx.queue, "queue")):
        for name in dir(type(obj)):
            if name.startswith("_") or not callable(getattr(type(obj), name, None)):
                continue
            patched.append((obj, name, obj.__dict__.get(name, _ABSENT)))  # an instance attribute set by someone else
            setattr(obj, name, _counting_call(getattr(obj, name), f"{kind}.{name}", counter, times))
    try:
        yield
    finally:
        for obj, name, before in reversed(patched):
            if before is _ABSENT:
                delattr(obj, name)
            else:
                setattr(obj, name, before)


def _counting_call(real: Callable, key: str, counter: Counter, times: Counter | None) -> Callable:
    def call(*args, **kwargs):
        counter[key] += 1
        start = time.perf_counter()
        try:
            return real(*args, **kwargs)
        finally:
            if times is not None:
                times[key] += time.perf_counter() - start

    return call


def count_frame(ctx: GPUContext, record: Callable, target: wgpu.GPUTexture, t: float = 0.0,
                times: Counter | None = None) -> Counter:
    """The calls of one frame as a window makes it: an encoder, ``record``, finish, submit (no readback, no timer).

    ``times``: seconds spent inside each kind of call are added to it (``"python"``: the frame's time outside
    every counted call: our code and the wrappers'). The GPU is waited for afterwards, outside the count.
    """
    counter: Counter = Counter()
    inner: Counter = Counter()
    start = time.perf_counter()
    with counting(ctx, counter, inner):
        encoder = ctx.device.create_command_encoder(label="counted-frame")
        record(_Counted(encoder, "encoder", counter, inner), target, t)
        counter["encoder.finish"] += 1
        t0 = time.perf_counter()
        buffer = encoder.finish()
        inner["encoder.finish"] += time.perf_counter() - t0
        ctx.queue.submit([buffer])
    total = time.perf_counter() - start
    ctx.wait_idle()
    if times is not None:
        times.update(inner)
        times["python"] += total - sum(inner.values())
    return counter


def call_profile(ctx: GPUContext, record: Callable, target: wgpu.GPUTexture, frames: int = 10) -> str:
    """Mean microseconds per frame in each kind of call over ``frames`` steady frames, largest first."""
    times: Counter = Counter()
    for _ in range(frames):
        count_frame(ctx, record, target, times=times)
    return ", ".join(f"{k} {v / frames * 1e6:.0f}" for k, v in times.most_common())


def steady_calls(ctx: GPUContext, record: Callable, target: wgpu.GPUTexture, warmup: int = 2) -> Counter:
    """The calls of the frame after ``warmup`` frames (caches filled, uniforms uploaded): the steady state."""
    for _ in range(warmup):
        count_frame(ctx, record, target)
    return count_frame(ctx, record, target)
