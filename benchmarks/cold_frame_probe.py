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
from pathlib import Path

from probe_csv import write_rows
from record_ahead_probe import SIZES, WARM, FramesAhead, after_wait, ahead_frame, image_hash, rows_for, wipe

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


def napping_frame(ctx, record, target, expected_s: float) -> tuple[float, ...]:
    """Today's frame, waited for in naps until NAP_UNTIL of ``expected_s``, then blocking."""
    w0, c0 = time.perf_counter(), time.thread_time()
    encoder = ctx.device.create_command_encoder(label="probe")
    record(encoder, target, 0.0)
    buffer = encoder.finish()
    w1, c1 = time.perf_counter(), time.thread_time()
    ctx.queue.submit([buffer])
    w2, c2 = time.perf_counter(), time.thread_time()
    end = w0 + NAP_UNTIL * expected_s
    while time.perf_counter() < end:
        time.sleep(NAP_S)
    ctx.wait_idle()
    return w1 - w0, c1 - c0, w2 - w1, c2 - c1


def main() -> int:
    out = Path(sys.argv[1])
    scene = sys.argv[2] if len(sys.argv) > 2 else "final.toml"
    sizes = [tuple(int(v) for v in s.split("x")) for s in (sys.argv[3] if len(sys.argv) > 3 else SIZES).split(",")]
    frames = int(sys.argv[4]) if len(sys.argv) > 4 else 200
    rounds = int(sys.argv[5]) if len(sys.argv) > 5 else 4

    from wgpurender.bench.frames import frames_without_gc, settle_garbage
    from wgpurender.bench.scene import SceneRunner
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context()
    rows = []
    for size in sizes:
        runner = SceneRunner(ctx, resolve_scene(scene), size)
        record, target = runner.renderer.record, runner.target
        ahead = FramesAhead(ctx, record, target, label="probe")
        for _ in range(WARM):
            after_wait(ctx, record, target, 0.0)
        calibrate = []
        for _ in range(20):
            start = time.perf_counter()
            after_wait(ctx, record, target, 0.0)
            calibrate.append(time.perf_counter() - start)
        native = NativeFrame(ctx, record, target)
        structures = {"after_wait": functools.partial(after_wait, ctx, record, target, 0.0),
                      "ahead": functools.partial(ahead_frame, ctx, ahead, 0.0),
                      "native": functools.partial(native_frame, ctx, native),
                      "naps": functools.partial(napping_frame, ctx, record, target, statistics.median(calibrate))}
        spans = {name: [] for name in structures}
        frame_ms, wait_cpu = {name: [] for name in structures}, {name: [] for name in structures}
        hashes = {name: set() for name in structures}
        settle_garbage()
        for k in range(rounds):
            for name in (list(structures) if k % 2 == 0 else list(structures)[::-1]):
                ahead.drop()
                wipe(ctx, target)
                with frames_without_gc():
                    for i in range(WARM + frames // rounds):
                        start, c_start = time.perf_counter(), time.thread_time()
                        s = structures[name]()
                        if i >= WARM:
                            spans[name].append(s)
                            frame_ms[name].append((time.perf_counter() - start) * 1e3)
                            wait_cpu[name].append((time.thread_time() - c_start - s[1] - s[3]) * 1e3)
                hashes[name].add(image_hash(ctx, target))
        text = f"{size[0]}x{size[1]}"
        for name in structures:
            rows.append({**rows_for(name, text, spans[name], frame_ms[name], hashes[name]),
                         "wait_thread_ms": statistics.median(wait_cpu[name])})
            r = rows[-1]
            print(f"{text} {name}: cpu {r['cpu_wall_ms']:.3f} ms wall (p99 {r['cpu_wall_p99_ms']:.3f}), "
                  f"{r['cpu_thread_ms']:.3f} thread; record {r['record_wall_ms']:.3f}, submit "
                  f"{r['submit_wall_ms']:.3f}; wait CPU {r['wait_thread_ms']:.3f}; frame {r['frame_ms']:.3f}; "
                  f"image {r['image_sha256']}", flush=True)
        ahead.drop()
    write_rows(out, rows, digits=4)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
