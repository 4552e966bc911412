"""A GPU-culled instanced draw after another draw: are all its copies drawn? (Found by the load engineer on
lavapipe, 2026-11-27, on main too: a 3x2 grid of cubes after a triangle draws 48 of its 72 pixels culled, 72
unculled; the grid first draws all 72 either way.) Prints the grid's pixel count per order and culling knob.

    python benchmarks/cull_order_probe.py
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from wgpurender.core.models import procedural
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.scene import load_renderer
from wgpurender.wgpu_path.scene.frame import render_frame

TRIANGLE = "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0 0.5 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"
GRID = ('[[models]]\npath = "cube.obj"\nmaterial = { albedo_color = [0, 0, 1], unlit = true }\n'
        'instances = { grid = [3, 2, 1], spacing = [1.5, 1.5, 1] }\n\n')
PLAIN = ('[[models]]\npath = "tri.obj"\nmaterial = { albedo_color = [1, 0, 0], unlit = true }\n'
         'transform = { translate = [-3.5, 0, 0] }\n\n')


def main() -> None:
    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "tri.obj").write_text(TRIANGLE)
        procedural.write_obj(folder / "cube.obj", procedural.box(0.5))
        for order, body in (("grid first", GRID + PLAIN), ("grid after a triangle", PLAIN + GRID)):
            path = folder / "s.toml"
            path.write_text('[camera]\neye = [0, 0, 12]\ntarget = [0, 0, 0]\nfov_y = 40\n\n' + body
                            + "[render]\nsize = [128, 64]\nmsaa = 1\n")
            for knob in ("off", "gpu"):
                renderer = load_renderer(path, ctx, knobs={"culling": knob})
                img, _ = render_frame(ctx, renderer, renderer.create_output())
                blue = int(((img[..., 2] > 200) & (img[..., 0] < 50)).sum())
                print(f"{order}, culling {knob}: {blue} grid pixels ({ctx.describe()})")


if __name__ == "__main__":
    main()
