"""``bench perf``'s scene-scale family: N copies of one lit, textured cube, N distinct meshes, and pygfx beside.

Cases (each a scene file written into a temporary folder, drawn by the scene renderer as any scene is):

- ``instanced/N``: one ``[[models]]`` entry with ``instances = { grid = ... }``: one instanced draw;
- ``batched/N``: N ``[[models]]`` entries of ONE mesh file, each with its own ``transform`` (the grid places of
  ``instanced/N``): what a user writes without knowing about ``instances``; the plan batches them into one
  instanced draw (core/plan/batches.py), so the load pays for N models' TOML and checks, not N meshes; capped at
  :data:`BATCHED_LIMITS`;
- ``distinct/N``: N models of N different mesh files (each cube moved a little in its own file): N draws,
  capped at :data:`DISTINCT_LIMITS` (every mesh file is loaded and uploaded on its own, ~1 ms each here);
- ``pygfx/N`` (path ``pygfx``): pygfx 0.17's ``InstancedMesh`` of the same cube, texture, light and camera, in
  the same process on the same adapter, when pygfx is installed (``pip install 'wgpurender[bench]'``).

Metrics per case: ``frame_ms`` (record + submit + wait), ``cpu_ms`` (record + submit), ``frame_readback_ms``
(with the image read back: the only frame pygfx's offscreen canvas offers, so the ratio uses this row),
``load_ms`` (scene file to the first frame read back, once), ``memory_mb`` (resident memory the load added).
The grid is square in x and y, 1.5 units apart, the camera framing it; at 100k and more copies a cube covers
less than a pixel: the frame is then vertex- and draw-bound, as intended.
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from wgpurender.bench.frames import frames_without_gc, measure
from wgpurender.bench.markdown_scale import SAME_WAIT
from wgpurender.bench.report import Result, size_text
from wgpurender.core.files.assets import assets_dir
from wgpurender.core.models import procedural
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.timing import Stats

COUNTS = (1_000, 10_000, 100_000, 1_000_000)
QUICK_COUNTS = (50, 200)
DISTINCT_LIMITS = {"CPU": 1_000, "GPU": 10_000}  # N mesh files loaded one by one: seconds per thousand
BATCHED_LIMITS = {"CPU": 10_000, "GPU": 100_000}  # N [[models]] tables: ~20 ms of TOML and checks per thousand
PYGFX_LIMIT = 100_000  # pygfx gives every instance a pick id from a 2**20 pool (and sets them in a Python loop)
SPACING = 1.5


def brick_texture() -> Path:
    """The bundled brick texture, wherever the bundled assets are (the checkout's ``assets/`` or the wheel's
    ``wgpurender/_assets``: :func:`~wgpurender.core.files.assets.assets_dir`, the one definition). A path built
    from this file's folder named the checkout's and was not found from the wheel."""
    return assets_dir() / "textures" / "brick_albedo.png"


def grid_side(n: int) -> tuple[int, int]:
    cols = math.ceil(math.sqrt(n))
    return cols, math.ceil(n / cols)


def camera_distance(n: int, fov_y: float = 40.0) -> float:
    cols, rows = grid_side(n)
    return 0.6 * max(cols, rows) * SPACING / math.tan(math.radians(fov_y) / 2) + 2.0


def _head(n: int, size: tuple[int, int], texture: Path) -> str:
    d = camera_distance(n)
    return (f'[camera]\neye = [0.0, 0.0, {d!r}]\ntarget = [0.0, 0.0, 0.0]\nfov_y = 40.0\nfar = {2 * d + 10!r}\n\n'
            f'[materials.brick]\nalbedo_map = "{texture.as_posix()}"\n\n'
            '[[lights]]\ntype = "directional"\ndirection = [-0.5, -0.6, -1.0]\nintensity = 2.0\n\n'
            f'[render]\nsize = [{size[0]}, {size[1]}]\nmsaa = 1\nhdr = false\n')


def instanced_scene(folder: Path, n: int, size: tuple[int, int], texture: Path | None = None) -> Path:
    """N cubes as one model with a grid ``instances`` block (exactly N: the grid is cut to its first N); the
    texture is :func:`brick_texture` unless given."""
    texture = texture or brick_texture()
    cube = folder / "cube.obj"
    if not cube.exists():
        procedural.write_obj(cube, procedural.box(1.0))
    offsets = grid_offsets(n)
    np.save(folder / f"grid_{n}.npy", offsets)
    path = folder / f"instanced_{n}.toml"
    path.write_text(_head(n, size, texture) + f'\n[[models]]\npath = "cube.obj"\nmaterial = "brick"\n'
                    f'instances = {{ file = "grid_{n}.npy" }}\n')
    return path


def batched_scene(folder: Path, n: int, size: tuple[int, int], texture: Path | None = None) -> Path:
    """N models of the one ``cube.obj``, each at its grid place by its own ``transform`` (the places of
    :func:`instanced_scene`'s grid): the plan makes them one draw of N instances; the texture is
    :func:`brick_texture` unless given."""
    texture = texture or brick_texture()
    cube = folder / "cube.obj"
    if not cube.exists():
        procedural.write_obj(cube, procedural.box(1.0))
    lines = [f'[[models]]\npath = "cube.obj"\nmaterial = "brick"\n'
             f'transform = {{ translate = [{x!r}, {y!r}, {z!r}] }}\n' for x, y, z in grid_offsets(n).tolist()]
    path = folder / f"batched_{n}.toml"
    path.write_text(_head(n, size, texture) + "\n" + "\n".join(lines))
    return path


def distinct_scene(folder: Path, n: int, size: tuple[int, int], texture: Path | None = None) -> Path:
    """N models, each its own mesh file (a cube moved to its grid place inside the file): nothing batches; the
    texture is :func:`brick_texture` unless given."""
    texture = texture or brick_texture()
    mesh = procedural.box(1.0)
    lines = []
    for k, offset in enumerate(grid_offsets(n)):
        name = f"m{k}.obj"
        if not (folder / name).exists():
            procedural.write_obj(folder / name, dataclasses.replace(mesh, positions=mesh.positions + offset))
        lines.append(f'[[models]]\npath = "{name}"\nmaterial = "brick"\n')
    path = folder / f"distinct_{n}.toml"
    path.write_text(_head(n, size, texture) + "\n" + "\n".join(lines))
    return path


def grid_offsets(n: int) -> np.ndarray:
    cols, rows = grid_side(n)
    k = np.arange(n)
    return np.stack([(k % cols - (cols - 1) / 2) * SPACING, (k // cols - (rows - 1) / 2) * SPACING,
                     np.zeros(n)], axis=1)


def _rss_mb() -> float:
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
    except (OSError, IndexError, ValueError):
        return float("nan")
    import os

    return pages * os.sysconf("SC_PAGE_SIZE") / 1e6


def _one_off(case: str, path: str, size: str, metric: str, value: float, note: str) -> Result:
    return Result("scene-scale", case, path, size, metric, value, value, value, 1, note)


def bench_case(ctx: GPUContext, scene: Path, case: str, size: tuple[int, int], frames: int) -> list[Result]:
    from wgpurender.bench.scene import SceneRunner

    before, start = _rss_mb(), time.perf_counter()
    runner = SceneRunner(ctx, scene, size)
    runner.frame(readback=True)
    load_ms = (time.perf_counter() - start) * 1e3
    memory = _rss_mb() - before
    s = size_text(size)
    draws = len(runner.renderer.plan.scene_pass.draws)
    samples = measure(runner, frames, readback_frames=max(3, frames // 2))
    out = samples.results("scene-scale", case, "wgpu", size, note=f"{draws} draw(s)")
    out.append(Result.of("scene-scale", case, "wgpu", s, "cpu_thread_ms", thread_cpu(runner, frames),
                         "thread CPU time (time.thread_time) of record + submit: cpu_ms without the waits"))
    same = same_wait_cpu(runner, frames, SAME_WAIT_MS)
    if same is not None:
        out.append(Result.of("scene-scale", case, "wgpu", s, SAME_WAIT, same,
                             f"record + submit, every frame begun {SAME_WAIT_MS:.1f} ms after the one before (the "
                             "GPU waited for, then a sleep): the same wait at every count"))
    out.append(_one_off(case, "wgpu", s, "load_ms", load_ms, "scene file to the first frame read back"))
    out.append(_one_off(case, "wgpu", s, "memory_mb", memory, "resident memory the load added"))
    return out


def thread_cpu(runner, frames: int) -> Stats:
    """The CPU time this thread spends in record + submit per frame (``time.thread_time``), each frame waited for.

    ``cpu_ms`` is wall time: it also counts the thread waiting or running slowly after it slept through the
    previous frame's GPU wait, which grows with the GPU's frame time (benchmarks/cpu_growth_probe.py); this row
    counts only the CPU time spent, to tell the two apart."""
    samples = []
    with frames_without_gc():  # as bench/frames.py's samples ($WGPURENDER_BENCH_GC too)
        for _ in range(frames + 2):
            samples.append(_record_submit(runner, time.thread_time))
            runner.ctx.wait_idle()
    return Stats.of(samples[2:])


SAME_WAIT_MS = 1000 / 30  # a 30 Hz window's frame period: longer than any count's GPU frame on the H100 (1M: ~21 ms)


def same_wait_cpu(runner, frames: int, period_ms: float = SAME_WAIT_MS) -> Stats | None:
    """Record + submit (wall ms, as ``cpu_ms``), each frame begun ``period_ms`` after the one before: the GPU is
    waited for (``ctx.wait_idle``, as ``cpu_ms``'s frames) and the rest of the period slept, so every count's
    record comes after the same time off the CPU and the count is the only variable (issue 31.3's growth question).

    ``cpu_ms`` waits only for its own GPU frame, which grows with the count, and the thread records more slowly
    after a longer sleep (benchmarks/cpu_growth_probe.py): that row is the frame as a window without vsync draws it,
    this one is the controlled comparison. None when a frame takes longer than the period (no same wait exists)."""
    period, samples = period_ms / 1e3, []
    with frames_without_gc():  # as bench/frames.py's samples ($WGPURENDER_BENCH_GC too)
        begin = time.perf_counter()
        for k in range(-2, frames):  # two frames to fall into step, then the samples
            rest = begin - time.perf_counter()
            if rest > 0:
                time.sleep(rest)
            begin = time.perf_counter()
            ms = _record_submit(runner, time.perf_counter)
            runner.ctx.wait_idle()
            if time.perf_counter() - begin > period:
                return None
            if k >= 0:
                samples.append(ms)
            begin += period
    return Stats.of(samples)


def _record_submit(runner, clock: Callable[[], float]) -> float:
    """Record and submit one frame of a scene runner: the milliseconds it took on ``clock``."""
    start = clock()
    encoder = runner.ctx.device.create_command_encoder(label="bench-scale")
    runner.renderer.record(encoder, runner.target, 0.0)
    runner.ctx.queue.submit([encoder.finish()])
    return (clock() - start) * 1e3


def bench_scale(ctx: GPUContext, counts: list[int], frames: int, size: tuple[int, int],
                log: Callable[[str], None] = print, peer=None) -> tuple[list[Result], list[str]]:
    """(results, notes) of every case; ``peer(ctx, n, size, frames)`` (bench/scale_pygfx.py's, or None when pygfx
    is not installed: one line says so) beside each count up to :data:`PYGFX_LIMIT`."""
    kind = "CPU" if ctx.adapter.info["adapter_type"] == "CPU" else "GPU"
    limit, batched = DISTINCT_LIMITS[kind], BATCHED_LIMITS[kind]
    out: list[Result] = []
    notes = [f"scene-scale: distinct meshes stop at {limit} on a {kind} adapter (each mesh file is loaded and "
             "uploaded on its own: seconds per thousand)",
             f"scene-scale: batched (N [[models]] of one mesh file) stops at {batched} on a {kind} adapter (each "
             "model is a TOML table the scene checks: ~20 ms per thousand)"]
    if peer is None:
        notes.append("scene-scale: pygfx is not installed (pip install 'wgpurender[bench]'): no pygfx rows")
    with tempfile.TemporaryDirectory(prefix="wgpurender-scale-") as tmp:
        folder = Path(tmp)
        warm_up(ctx, folder, size)
        notes.append(f"scene-scale: one untimed load of {WARM_UP_COUNT} instances, {WARM_UP_COUNT} batched models "
                     f"and {WARM_UP_COUNT} distinct meshes first, so the process's one-time costs (the driver's "
                     "first pipelines) are not charged to the first case's load_ms")
        for n in counts:
            out += bench_case(ctx, instanced_scene(folder, n, size), f"instanced/{n}", size, frames)
            log(f"  scene-scale: instanced {n}")
            if n <= batched:
                out += bench_case(ctx, batched_scene(folder, n, size), f"batched/{n}", size, frames)
                log(f"  scene-scale: batched {n}")
            if n <= limit:
                out += bench_case(ctx, distinct_scene(folder, n, size), f"distinct/{n}", size, frames)
                log(f"  scene-scale: distinct {n}")
            if peer is not None and n <= PYGFX_LIMIT:
                out += peer(ctx, n, size, frames)
                log(f"  scene-scale: pygfx {n}")
    if peer is not None and max(counts) > PYGFX_LIMIT:
        notes.append(f"scene-scale: pygfx stops at {PYGFX_LIMIT} instances (InstancedMesh claims a pick id per "
                     "instance from a pool of 2**20, in a Python loop)")
    return out, notes


WARM_UP_COUNT = 8


def warm_up(ctx: GPUContext, folder: Path, size: tuple[int, int]) -> None:
    """Load and draw a small scene of each kind once, untimed: the first load in a process also pays for the
    driver's first pipelines and the renderer's first imports (2.4 s on a fresh H100 host, 2026-11-27 evening,
    against 0.04-0.12 s for the same load later in a process), which is not what the count costs."""
    from wgpurender.bench.scene import SceneRunner

    (folder / "warm-up").mkdir()
    for make in (instanced_scene, batched_scene, distinct_scene):
        SceneRunner(ctx, make(folder / "warm-up", WARM_UP_COUNT, size), size).frame(readback=True)


def ratio_rows(results: list[Result]) -> list[Result]:
    """wgpu instanced / pygfx InstancedMesh frame time (with readback, the frame both can time) per count, from
    two medians measured one after the other: reported beside the goal's paired row (bench/scale_paired.py), which
    a change of the GPU's clock between the two cases cannot move (on the H100 one draw read 5.7x apart)."""
    rows = {(r.case, r.path): r for r in results if r.metric == "frame_readback_ms"}
    out = []
    for (case, path), r in rows.items():
        if path == "pygfx" and (f"instanced/{case.split('/')[1]}", "wgpu") in rows:
            mine = rows[(f"instanced/{case.split('/')[1]}", "wgpu")]
            v = mine.median / r.median
            out.append(Result("scene-scale", f"ratio/{case.split('/')[1]}", "wgpu/pygfx", r.size, "frame_ratio",
                              v, v, v, 1, "wgpu instanced frame_readback_ms / pygfx InstancedMesh's, medians "
                              "measured one after the other (reported; the goal is judged on frame_ratio:paired)"))
    return out


__all__ = ["COUNTS", "QUICK_COUNTS", "Stats", "batched_scene", "bench_scale", "distinct_scene", "instanced_scene",
           "ratio_rows"]
