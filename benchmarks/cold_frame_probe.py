"""Where does the final scene's CPU per frame go after a long GPU wait (issue 31.4, frame4's second probe)?

record_ahead_probe.py found that recording the next frame ahead and pinning the thread leave the CPU per frame
where it was on the H100 (docs/perf-h100/2026-11-27-frame4/). This probe asks two more questions, with the frame
as ``bench perf``'s untimed rows draw it, structures in alternating rounds on one process:

- ``after_wait``: today's frame (encoder, ``renderer.record``, finish; submit; the blocking wait);
- ``ahead``: the frame recorded ahead (record_ahead_probe.FramesAhead), again, beside the others;
- ``native``: the same frame's wgpu-native calls replayed with the same arguments (captured once from a frame of
  wgpu-py, the handles it returns substituted), no wgpu-py or renderer Python: how much of the cold frame is native
  (wgpu-core, the driver) and how much is Python;
- ``naps``: today's frame, but the wait is naps of :data:`NAP_S` until :data:`NAP_UNTIL` of the frame's expected
  time (the ``after_wait`` frames' median, measured first), then the blocking wait: does a thread that wakes often
  (the virtual machine's vCPU never idle long) record faster, and what does the waiting itself cost (``wait_thread``)?

Every CPU span is timed in wall and thread CPU time: ``record`` (encoder, record, finish), ``submit``, and the wait.
Before each round the target is zeroed, after it read back and hashed: every structure must draw the same image.

    python benchmarks/cold_frame_probe.py OUT.csv [SCENE] [SIZES] [FRAMES] [ROUNDS]
"""

from __future__ import annotations

import functools
import statistics
import sys
import time

from record_ahead_probe import WARM, FramesAhead, after_wait, ahead_frame, probe_main

NAP_S, NAP_UNTIL = 0.0001, 0.9


class NativeFrame:
    """One frame's wgpu-native calls (wgpu-py's ``libf``), captured once and replayed with new handles."""

    def __init__(self, ctx, record, target) -> None:
        from wgpu.backends.wgpu_native import _api

        self.ffi, self.libf, self.calls = _api.ffi, _api.libf, []
        real = {n: getattr(self.libf, n) for n in dir(self.libf) if n.startswith("wgpu")}
        self.real = real

        def capture(name, fn):
            def call(*args):
                result = fn(*args)
                self.calls.append((fn, args, result))  # the arguments kept alive: their structs stay valid
                return result
            return call

        # wgpu-py's pass encoders call some functions through class attributes (``_set_bind_group_function``...)
        # bound at import: those are captured too; releases are not (the replay releases its own handles)
        bound = [(cls, attr, fn) for cls in vars(_api).values() if isinstance(cls, type)
                 for attr, fn in vars(cls).items()
                 if attr.endswith("_function") and attr != "_release_function" and fn is not None]
        for name, fn in real.items():
            setattr(self.libf, name, capture(name, fn))
        for cls, attr, fn in bound:
            setattr(cls, attr, staticmethod(capture(attr, fn)))
        try:
            encoder = ctx.device.create_command_encoder(label="probe")
            record(encoder, target, 0.0)
            ctx.queue.submit([encoder.finish()])
        finally:
            for name, fn in real.items():
                setattr(self.libf, name, fn)
            for cls, attr, fn in bound:
                setattr(cls, attr, fn)
        ctx.wait_idle()
        self.submit = real["wgpuQueueSubmit"]

    def _address(self, value) -> int | None:
        if isinstance(value, self.ffi.CData) and self.ffi.typeof(value).kind == "pointer":
            return int(self.ffi.cast("uintptr_t", value))
        return None

    def replay(self) -> None:
        """The captured calls in order, each handle a call returned replaced by this replay's; released after."""
        ffi, made, now = self.ffi, [], {}
        for fn, args, result in self.calls:
            if fn is self.submit:
                buffers = ffi.new("WGPUCommandBuffer[]", [now[self._address(b)] for b in args[2][0:args[1]]])
                fn(args[0], args[1], buffers)
                continue
            args = tuple(now.get(self._address(a), a) for a in args)
            new = fn(*args)
            if result is not None and self._address(result) is not None:
                now[self._address(result)] = new
                made.append(new)
        for handle in made:
            kind = ffi.typeof(handle).item.cname.removeprefix("struct ").removeprefix("WGPU").removesuffix("Impl")
            getattr(self.libf, f"wgpu{kind}Release")(handle)


def native_frame(ctx, native: NativeFrame) -> tuple[float, ...]:
    w0, c0 = time.perf_counter(), time.thread_time()
    native.replay()
    w1, c1 = time.perf_counter(), time.thread_time()
    ctx.wait_idle()
    return w1 - w0, c1 - c0, 0.0, 0.0  # the replay's submit is inside its one span


def naps(expected_s: float):
    """A wait (record_ahead_probe.after_wait's ``wait``): naps of NAP_S until NAP_UNTIL of ``expected_s`` after the
    frame's start, then the blocking wait."""
    def wait(ctx, start: float) -> None:
        end = start + NAP_UNTIL * expected_s
        while time.perf_counter() < end:
            time.sleep(NAP_S)
        ctx.wait_idle()

    return wait


def napping_frame(ctx, record, target, expected_s: float) -> tuple[float, ...]:
    """Today's frame, waited for in naps (:func:`naps`)."""
    return after_wait(ctx, record, target, 0.0, wait=naps(expected_s))


def structures(ctx, record, target, ahead: FramesAhead) -> dict:
    """Today's frame, recorded ahead, the native replay, and the napping wait (its expected frame measured now)."""
    for _ in range(WARM):
        after_wait(ctx, record, target, 0.0)
    calibrate = []
    for _ in range(20):
        start = time.perf_counter()
        after_wait(ctx, record, target, 0.0)
        calibrate.append(time.perf_counter() - start)
    native = NativeFrame(ctx, record, target)
    return {"after_wait": functools.partial(after_wait, ctx, record, target, 0.0),
            "ahead": functools.partial(ahead_frame, ctx, ahead, 0.0),
            "native": functools.partial(native_frame, ctx, native),
            "naps": functools.partial(napping_frame, ctx, record, target, statistics.median(calibrate))}


def main() -> int:
    return probe_main(sys.argv[1:], structures)


if __name__ == "__main__":
    raise SystemExit(main())
