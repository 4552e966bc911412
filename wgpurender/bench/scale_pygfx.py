"""The scene-scale family's peer: pygfx 0.17's ``InstancedMesh`` of the same textured cube grid, same adapter.

pygfx renders into rendercanvas's offscreen canvas, whose ``draw()`` renders, submits and reads the image back:
so its frame is timed with the readback, against wgpurender's ``frame_readback_ms``. ``cpu_ms`` is the time
inside ``renderer.render`` (pygfx's record + submit). Antialiasing off (``ppaa = "none"``, pixel ratio 1), as
the wgpurender scene (msaa 1, no post chain); Phong-lit with an ambient and one directional light. Only the
instance matrices are written directly (``instance_buffer.data["matrix"]``, transposed as pygfx stores them).
"""

from __future__ import annotations

import time

import numpy as np

from wgpurender.bench.frames import frames_without_gc, settle_garbage, warm_up
from wgpurender.bench.report import Result, size_text
from wgpurender.bench.scale import brick_texture, camera_distance, grid_offsets
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.timing import Stats

_selected = False


def _select(ctx: GPUContext) -> None:
    """pygfx's shared device on this context's adapter (once per process, before pygfx makes its device)."""
    global _selected
    if not _selected:
        import pygfx as gfx

        gfx.renderers.wgpu.select_adapter(ctx.adapter)
        _selected = True


def build(n: int, size: tuple[int, int]):
    """(canvas, draw function, timings list): the pygfx scene of ``n`` instanced cubes."""
    import pygfx as gfx
    from rendercanvas.offscreen import RenderCanvas

    from wgpurender.core.files.imageio import load_png

    canvas = RenderCanvas(size=size, pixel_ratio=1)
    renderer = gfx.WgpuRenderer(canvas, pixel_ratio=1, ppaa="none")
    scene = gfx.Scene()
    texels = np.ascontiguousarray(load_png(brick_texture())[..., :4])
    material = gfx.MeshPhongMaterial(map=gfx.Texture(texels, dim=2, colorspace="srgb"))
    mesh = gfx.InstancedMesh(gfx.box_geometry(1, 1, 1), material, n)
    matrices = np.zeros((n, 4, 4), np.float32)
    matrices[:, [0, 1, 2, 3], [0, 1, 2, 3]] = 1.0
    matrices[:, 3, :3] = grid_offsets(n)  # pygfx keeps each matrix transposed: the translation is row 3
    mesh.instance_buffer.data["matrix"] = matrices
    mesh.instance_buffer.update_full()
    light = gfx.DirectionalLight(intensity=2.0)
    light.local.position = (0.5, 0.6, 1.0)
    scene.add(mesh, gfx.AmbientLight(intensity=0.3), light)
    camera = gfx.PerspectiveCamera(40, size[0] / size[1], depth_range=(0.1, 2 * camera_distance(n) + 10))
    camera.local.position = (0.0, 0.0, camera_distance(n))
    camera.look_at((0.0, 0.0, 0.0))
    cpu: list[float] = []

    def draw() -> None:
        start = time.perf_counter()
        renderer.render(scene, camera)
        cpu.append((time.perf_counter() - start) * 1e3)

    canvas.request_draw(draw)
    return canvas, cpu


class _Runner:
    """The runner protocol of bench/frames.warm_up: ``frame()`` draws one frame (with pygfx's readback)."""

    def __init__(self, canvas) -> None:
        self.canvas = canvas

    def frame(self, readback: bool = False) -> tuple[float, None]:
        self.canvas.draw()
        return 0.0, None


def _installed() -> bool:
    try:
        import pygfx  # noqa: F401
    except ImportError:
        return False
    return True


def pygfx_peer():
    """:func:`bench_pygfx`, or None when pygfx is not installed (``pip install 'wgpurender[bench]'``)."""
    return bench_pygfx if _installed() else None


def pygfx_pair():
    """:func:`pygfx_side` (bench/scale_paired.py's peer), or None when pygfx is not installed."""
    return pygfx_side if _installed() else None


def pygfx_side(ctx: GPUContext, n: int, size: tuple[int, int]):
    """pygfx's scene of ``n`` instanced cubes, drawn once: its draw function (render, submit, read back)."""
    _select(ctx)
    canvas, _ = build(n, size)
    canvas.draw()
    return canvas.draw


def bench_pygfx(ctx: GPUContext, n: int, size: tuple[int, int], frames: int) -> list[Result]:
    _select(ctx)
    start = time.perf_counter()
    canvas, cpu = build(n, size)
    canvas.draw()
    load_ms = (time.perf_counter() - start) * 1e3
    settle_garbage()  # before the warm-up, as bench/frames.py's measure: the first timed frame follows warm ones
    warm_up(_Runner(canvas))
    cpu.clear()
    wall = []
    with frames_without_gc():
        for _ in range(frames):
            t = time.perf_counter()
            canvas.draw()
            wall.append((time.perf_counter() - t) * 1e3)
    case, s, note = f"pygfx/{n}", size_text(size), "pygfx 0.17 InstancedMesh, offscreen canvas draw() (reads back)"
    return [Result.of("scene-scale", case, "pygfx", s, "frame_readback_ms", Stats.of(wall), note),
            Result.of("scene-scale", case, "pygfx", s, "cpu_ms", Stats.of(cpu), "time inside renderer.render"),
            Result("scene-scale", case, "pygfx", s, "load_ms", load_ms, load_ms, load_ms, 1,
                   "scene built to the first frame read back")]
