"""Does the driver honour an index buffer's bind offset in an indexed indirect draw? (cullfix, 2026-11-27)

The cause of a GPU-culled draw after another draw losing triangles on lavapipe (benchmarks/cull_order_probe.py):
its mesh's indices were bound at their byte offset in the shared index buffer and the indirect block said first
index 0. A 16x1 target; the index buffer holds 6 indices of an off-screen vertex, then a one-pixel quad's 6; each
instance i draws its quad at column i. Each row names how the quad's indices are reached and prints the columns
drawn: three instances from first instance 2 should light columns 2-4 every time.

    python benchmarks/indirect_index_offset_probe.py
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgpurender.wgpu_path.device.context import get_context

WIDTH = 16
SHADER = """
@vertex fn vs(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> @builtin(position) vec4f {
    let corners = array<vec2f, 6>(vec2f(0.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
                                  vec2f(0.0, -1.0), vec2f(1.0, 1.0), vec2f(0.0, 1.0));
    if (v >= 6u) { return vec4f(9.0, 9.0, 0.0, 1.0); }
    return vec4f((f32(i) + corners[v].x) / 8.0 - 1.0, corners[v].y, 0.0, 1.0);
}
@fragment fn fs() -> @location(0) vec4f { return vec4f(1.0); }
"""


def columns(dev, pipeline, index, offset: int, args: list[int] | None) -> str:
    """The lit columns after one draw (indirect with ``args``, else direct) of the index buffer bound at ``offset``."""
    tex = dev.create_texture(size=(WIDTH, 1, 1), format="rgba8unorm",
                             usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC)
    encoder = dev.create_command_encoder()
    rpass = encoder.begin_render_pass(color_attachments=[{
        "view": tex.create_view(), "load_op": "clear", "store_op": "store", "clear_value": (0, 0, 0, 0)}])
    rpass.set_pipeline(pipeline)
    rpass.set_index_buffer(index, "uint32", offset)
    if args is None:
        rpass.draw_indexed(6, 3, (24 - offset) // 4, 0, 2)
    else:
        rpass.draw_indexed_indirect(dev.create_buffer_with_data(data=np.array(args, np.uint32).tobytes(),
                                                                usage=wgpu.BufferUsage.INDIRECT), 0)
    rpass.end()
    dev.queue.submit([encoder.finish()])
    row = np.frombuffer(dev.queue.read_texture({"texture": tex}, {"bytes_per_row": 256}, (WIDTH, 1, 1)), np.uint8)
    return "".join("#" if r else "." for r in row[: WIDTH * 4: 4])


def main() -> None:
    ctx = get_context()
    dev = ctx.device
    module = dev.create_shader_module(code=SHADER)
    pipeline = dev.create_render_pipeline(layout="auto", vertex={"module": module, "entry_point": "vs"}, fragment={
        "module": module, "entry_point": "fs", "targets": [{"format": "rgba8unorm"}]})
    index = dev.create_buffer_with_data(data=np.array([7] * 6 + list(range(6)), np.uint32).tobytes(),
                                        usage=wgpu.BufferUsage.INDEX)
    print(ctx.describe())
    print("direct,   bound at 24 bytes, first index 0:", columns(dev, pipeline, index, 24, None))
    print("direct,   bound at 0,        first index 6:", columns(dev, pipeline, index, 0, None))
    print("indirect, bound at 24 bytes, first index 0:", columns(dev, pipeline, index, 24, [6, 3, 0, 0, 2]))
    print("indirect, bound at 0,        first index 6:", columns(dev, pipeline, index, 0, [6, 3, 6, 0, 2]))


if __name__ == "__main__":
    main()
