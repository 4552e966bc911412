"""Does recording the next frame ahead cut the final scene's CPU per frame (issue 31.4)? A probe, run on the device.

The frame as ``bench perf``'s untimed rows draw it (one offscreen target, no timestamps, no readback, the blocking
GPU wait after each frame), in two structures with the same calls, in alternating rounds on one process:

- ``after_wait`` (today's): encoder + ``renderer.record`` + ``finish``, then ``submit``, then the wait;
- ``ahead`` (:class:`FramesAhead`): ``submit`` of the frame recorded ahead, then encoder + record +
  ``finish`` of the next frame, then the wait: the record runs right after the submit, before the thread sleeps.

Every CPU span of a frame is timed in wall time and thread CPU time (``time.thread_time``): ``record`` (encoder,
record, finish) and ``submit``; ``cpu`` is their sum, the CPU per frame; ``wait_thread`` is the CPU the wait
burns. Before each round the target is zeroed, after it read back and hashed: every structure must draw the same
image. (The first H100 call ran an earlier form of this file, without the zeroing and the wait column:
docs/perf-h100/2026-11-27-frame4/README.md.)

Each structure runs a second time with the thread pinned to the CPU it was on (``_pinned``, os.sched_setaffinity
for this thread only): after a long sleep the scheduler may wake the thread on another CPU, whose caches hold none
of the frame's code and objects; pinning asks whether that is the cold start.

    python benchmarks/record_ahead_probe.py OUT.csv [SCENE] [SIZES] [FRAMES] [ROUNDS]
"""

from __future__ import annotations

import functools
import hashlib
import os
import statistics
import sys
import time
from pathlib import Path

from probe_csv import write_rows


class FramesAhead:
    """Frames recorded one ahead, as the Vulkan tutorial's frames in flight (the raw path's window,
    FRAMES_IN_FLIGHT = 2): the next frame's command buffer is recorded and finished right after this frame's submit,
    before the wait for this frame's GPU work. wgpu cannot reuse a command buffer, but a finished one can wait to be
    submitted, and ``queue.write_buffer`` stays ordered with the submits around it. The target must stay the same
    texture between the record and the submit; :meth:`drop` forgets a frame recorded for an old target or state.
    Tried on the H100 and not adopted (docs/perf-h100/2026-11-27-frame4/README.md)."""

    def __init__(self, ctx, record, target, label: str = "frame-ahead") -> None:
        """``record(encoder, target, t)`` records a frame (a SceneRenderer's ``record``)."""
        self.ctx, self.record, self.target, self.label = ctx, record, target, label
        self.pending = None  # the finished command buffer of the frame recorded ahead

    def record_next(self, t: float) -> None:
        """Record and finish the next frame at clock time ``t``; it waits for :meth:`submit`."""
        encoder = self.ctx.device.create_command_encoder(label=self.label)
        self.record(encoder, self.target, t)
        self.pending = encoder.finish()

    def submit(self, t: float) -> None:
        """Submit the frame recorded ahead (recorded now, at ``t``, when none is: the first frame, or after
        :meth:`drop`)."""
        if self.pending is None:
            self.record_next(t)
        pending, self.pending = self.pending, None
        self.ctx.queue.submit([pending])

    def frame(self, t: float, t_next: float | None = None) -> None:
        """Submit this frame, then record the next one at ``t_next`` (``t`` when not given) before any wait."""
        self.submit(t)
        self.record_next(t if t_next is None else t_next)

    def drop(self) -> None:
        """Forget the frame recorded ahead (a new target, size or scene state it did not see)."""
        self.pending = None


SIZES = "800x600,1280x720,1920x1080,3840x2160"
WARM = 10  # untimed frames at the start of each round


def block(ctx, start: float) -> None:
    """The frame loop's wait: wgpuDevicePoll(wait=True) until the GPU is done."""
    ctx.wait_idle()


def after_wait(ctx, record, target, t: float, wait=block) -> tuple[float, ...]:
    """One frame of today's structure: (record wall, record cpu, submit wall, submit cpu) in seconds; then
    ``wait(ctx, start)`` (``start``: the frame's first perf_counter)."""
    w0, c0 = time.perf_counter(), time.thread_time()
    encoder = ctx.device.create_command_encoder(label="probe")
    record(encoder, target, t)
    buffer = encoder.finish()
    w1, c1 = time.perf_counter(), time.thread_time()
    ctx.queue.submit([buffer])
    w2, c2 = time.perf_counter(), time.thread_time()
    wait(ctx, w0)
    return w1 - w0, c1 - c0, w2 - w1, c2 - c1


def ahead_frame(ctx, ahead, t: float) -> tuple[float, ...]:
    """One frame recorded ahead: submit the pending buffer, record the next, then wait."""
    w0, c0 = time.perf_counter(), time.thread_time()
    ahead.submit(t)
    w1, c1 = time.perf_counter(), time.thread_time()
    ahead.record_next(t)
    w2, c2 = time.perf_counter(), time.thread_time()
    ctx.wait_idle()
    return w2 - w1, c2 - c1, w1 - w0, c1 - c0


def this_cpu() -> int:
    """The CPU this thread runs on now (field 39 of /proc/thread-self/stat)."""
    return int(Path("/proc/thread-self/stat").read_text().rsplit(")", 1)[1].split()[36])


def wipe(ctx, target) -> None:
    """Zeros into the target, so the hash after a round shows what that round drew (cold_frame_probe.py)."""
    import numpy as np

    w, h = target.size[0], target.size[1]
    bpp = 8 if "16float" in target.format else 4
    ctx.queue.write_texture({"texture": target}, np.zeros(w * h * bpp, np.uint8),
                            {"bytes_per_row": w * bpp, "rows_per_image": h}, (w, h, 1))
    ctx.wait_idle()


def image_hash(ctx, target) -> str:
    from wgpurender.wgpu_path.device.targets import Readback

    readback = Readback(ctx)
    encoder = ctx.device.create_command_encoder(label="probe-readback")
    readback.record(encoder, target)
    ctx.queue.submit([encoder.finish()])
    return hashlib.sha256(readback.read().tobytes()).hexdigest()[:16]


def rows_for(structure: str, size: str, spans: list[tuple[float, ...]], frames_ms: list[float], hashes: set,
             wait_ms: list[float] = ()) -> dict:
    """One CSV row: the medians (and p99s) of a structure's spans, in ms; ``wait_ms``: the thread CPU of each
    frame's wait (a column only where given)."""
    ms = [[v * 1e3 for v in s] for s in spans]
    cpu_wall = [s[0] + s[2] for s in ms]
    cpu_thread = [s[1] + s[3] for s in ms]

    def p99(values):
        return sorted(values)[min(len(values) - 1, int(0.99 * len(values)))]

    med = statistics.median
    return {"structure": structure, "size": size, "frames": len(ms),
            "cpu_wall_ms": med(cpu_wall), "cpu_wall_p99_ms": p99(cpu_wall),
            "cpu_thread_ms": med(cpu_thread), "cpu_thread_p99_ms": p99(cpu_thread),
            "record_wall_ms": med(s[0] for s in ms), "record_thread_ms": med(s[1] for s in ms),
            "submit_wall_ms": med(s[2] for s in ms), "submit_thread_ms": med(s[3] for s in ms),
            "frame_ms": med(frames_ms), "image_sha256": "/".join(sorted(hashes)),
            **({"wait_thread_ms": med(wait_ms)} if wait_ms else {})}


def arguments(argv: list[str]) -> tuple[Path, str, list[tuple[int, int]], int, int]:
    """OUT.csv [SCENE] [SIZES] [FRAMES] [ROUNDS] (both probes' command line)."""
    scene = argv[1] if len(argv) > 1 else "final.toml"
    sizes = [tuple(int(v) for v in s.split("x")) for s in (argv[2] if len(argv) > 2 else SIZES).split(",")]
    return Path(argv[0]), scene, sizes, int(argv[3]) if len(argv) > 3 else 200, int(argv[4]) if len(argv) > 4 else 4


def run_rounds(ctx, target, structures: dict, ahead: FramesAhead, frames: int, rounds: int, size: str) -> list[dict]:
    """Each structure ``frames // rounds`` timed frames a round (after WARM untimed ones), the order flipped each
    round; before a round the frame ahead is dropped and the target zeroed, after it the image hashed; a name
    ending in ``_pinned`` runs with the thread pinned to the CPU it is on. One row per structure (rows_for)."""
    from wgpurender.bench.frames import frames_without_gc, settle_garbage

    spans, frame_ms, wait_ms = ({name: [] for name in structures} for _ in range(3))
    hashes = {name: set() for name in structures}
    settle_garbage()
    for k in range(rounds):
        for name in (list(structures) if k % 2 == 0 else list(structures)[::-1]):
            ahead.drop()
            wipe(ctx, target)
            allowed = os.sched_getaffinity(0)
            if name.endswith("_pinned"):
                os.sched_setaffinity(0, {this_cpu()})
            try:
                with frames_without_gc():
                    for i in range(WARM + frames // rounds):
                        start, c_start = time.perf_counter(), time.thread_time()
                        s = structures[name]()
                        if i >= WARM:
                            spans[name].append(s)
                            frame_ms[name].append((time.perf_counter() - start) * 1e3)
                            wait_ms[name].append((time.thread_time() - c_start - s[1] - s[3]) * 1e3)
            finally:
                os.sched_setaffinity(0, allowed)
            hashes[name].add(image_hash(ctx, target))
    ahead.drop()
    rows = [rows_for(name, size, spans[name], frame_ms[name], hashes[name], wait_ms[name]) for name in structures]
    for r in rows:
        print(f"{size} {r['structure']}: cpu {r['cpu_wall_ms']:.3f} ms wall (p99 {r['cpu_wall_p99_ms']:.3f}), "
              f"{r['cpu_thread_ms']:.3f} thread; record {r['record_wall_ms']:.3f}, submit {r['submit_wall_ms']:.3f}; "
              f"wait CPU {r['wait_thread_ms']:.3f}; frame {r['frame_ms']:.3f}; image {r['image_sha256']}", flush=True)
    return rows


def probe_main(argv: list[str], structures_for) -> int:
    """Both probes' run: for each size the scene's renderer and target, ``structures_for(ctx, record, target,
    ahead)`` the structures to compare, :func:`run_rounds`; the rows into OUT.csv."""
    out, scene, sizes, frames, rounds = arguments(argv)

    from wgpurender.bench.scene import SceneRunner
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context()
    rows = []
    for size in sizes:
        runner = SceneRunner(ctx, resolve_scene(scene), size)
        record, target = runner.renderer.record, runner.target
        ahead = FramesAhead(ctx, record, target, label="probe")
        structures = structures_for(ctx, record, target, ahead)
        rows += run_rounds(ctx, target, structures, ahead, frames, rounds, f"{size[0]}x{size[1]}")
    write_rows(out, rows, digits=4)
    return 0


def structures(ctx, record, target, ahead: FramesAhead) -> dict:
    """Today's frame and the frame recorded ahead, each also with the thread pinned."""
    plain = {"after_wait": functools.partial(after_wait, ctx, record, target, 0.0),
             "ahead": functools.partial(ahead_frame, ctx, ahead, 0.0)}
    return {**plain, **{f"{name}_pinned": f for name, f in plain.items()}}


def main() -> int:
    return probe_main(sys.argv[1:], structures)


if __name__ == "__main__":
    raise SystemExit(main())
