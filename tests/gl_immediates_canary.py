"""The cut-down case of wgpu's GL immediates bug (docs/backends.md, "Immediates on OpenGL"), run in its own
process by tests/test_backends.py: a fragment shader reads a var<immediate> Material; ``python
gl_immediates_canary.py first|after`` declares another struct before Material (``first``: Material first) and
prints the pixel the draw wrote, pushed colour (1, 0, 0, 1)."""

import sys

import numpy as np
import wgpu

from wgpurender.wgpu_path.device.context import get_context

OTHER = "struct Camera { proj: mat4x4f, view: mat4x4f, eye: vec4f, }\n"
MATERIAL = "struct Material { base_color: vec4f, }\n"
BODY = """var<immediate> material: Material;
struct VertexOut { @builtin(position) clip: vec4f, };
@vertex fn vs_main(@builtin(vertex_index) i: u32) -> VertexOut {
    var xy = array<vec2f, 3>(vec2f(-1.0, -1.0), vec2f(3.0, -1.0), vec2f(-1.0, 3.0));
    var out: VertexOut;
    out.clip = vec4f(xy[i], 0.5, 1.0);
    return out;
}
@fragment fn fs_main(in: VertexOut) -> @location(0) vec4f { return material.base_color; }
"""


def main(order: str) -> None:
    ctx = get_context("opengl")
    dev = ctx.device
    code = (MATERIAL + OTHER if order == "first" else OTHER + MATERIAL) + BODY
    module = dev.create_shader_module(code=code)
    layout = dev.create_pipeline_layout(bind_group_layouts=[], immediate_size=16)
    pipeline = dev.create_render_pipeline(layout=layout, vertex={"module": module, "entry_point": "vs_main"},
                                          fragment={"module": module, "entry_point": "fs_main",
                                                    "targets": [{"format": "rgba8unorm"}]}, primitive={})
    texture = dev.create_texture(size=(4, 1, 1), format="rgba8unorm",
                                 usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC)
    encoder = dev.create_command_encoder()
    render_pass = encoder.begin_render_pass(color_attachments=[{"view": texture.create_view(), "load_op": "clear",
                                                                "store_op": "store", "clear_value": (0, 0, 1, 1)}])
    render_pass.set_pipeline(pipeline)
    render_pass.set_immediates(0, np.array([1, 0, 0, 1], np.float32).tobytes(), 0, 16)
    render_pass.draw(3)
    render_pass.end()
    dev.queue.submit([encoder.finish()])
    pixels = np.frombuffer(dev.queue.read_texture({"texture": texture}, {"bytes_per_row": 256}, (4, 1, 1)), np.uint8)
    print(pixels[:4].tolist())


if __name__ == "__main__":
    main(sys.argv[1])
