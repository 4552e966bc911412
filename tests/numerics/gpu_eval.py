"""Evaluate a small compute shader over storage buffers and read the result back: the hard cases' GPU probe.

The numerics tests want to see exactly what float32 arithmetic on the GPU produces (a transformed vertex, a
normalised vector), without rasterisation in the way. Inputs are read-only storage buffers at bindings 0..k-1,
the output is ``array<vec4f>`` at binding k; one invocation per output element, workgroup size 64.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import wgpu

from numerics.wgsl import load_wgsl
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.device.shaders import create_shader_module

WORKGROUP_SIZE = 64  # the @workgroup_size of every numerics_*.wgsl compute entry point


def run_compute(
    ctx: GPUContext,
    shader: str,
    inputs: Sequence[np.ndarray],
    out_count: int,
    *,
    constants: Mapping[str, float] | None = None,
    entry_point: str = "main",
    prelude: Sequence[str] = (),
) -> np.ndarray:
    """Run ``shaders_wgsl/<shader>`` over float32 ``inputs``; returns the (out_count, 4) float32 output.

    ``prelude``: shader files whose text goes before the shader's own (shared functions).
    """
    device = ctx.device
    stage = wgpu.ShaderStage.COMPUTE
    entries = [{"binding": i, "visibility": stage, "buffer": {"type": "read-only-storage"}} for i in range(len(inputs))]
    entries.append({"binding": len(inputs), "visibility": stage, "buffer": {"type": "storage"}})
    bgl = device.create_bind_group_layout(label=shader, entries=entries)
    pipeline = device.create_compute_pipeline(
        label=shader,
        layout=device.create_pipeline_layout(bind_group_layouts=[bgl]),
        compute={
            "module": create_shader_module(device, shader, "\n".join(load_wgsl(n) for n in [*prelude, shader])),
            "entry_point": entry_point,
            "constants": dict(constants or {}),
        },
    )
    buffers = [
        device.create_buffer_with_data(
            label=f"{shader}-in{i}", data=np.ascontiguousarray(a, dtype=np.float32), usage=wgpu.BufferUsage.STORAGE
        )
        for i, a in enumerate(inputs)
    ]
    out = device.create_buffer(
        label=f"{shader}-out", size=16 * out_count, usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC
    )
    bind_group = device.create_bind_group(
        layout=bgl,
        entries=[{"binding": i, "resource": {"buffer": b, "offset": 0, "size": b.size}} for i, b in enumerate(buffers)]
        + [{"binding": len(buffers), "resource": {"buffer": out, "offset": 0, "size": out.size}}],
    )
    encoder = device.create_command_encoder(label=shader)
    compute_pass = encoder.begin_compute_pass()
    compute_pass.set_pipeline(pipeline)
    compute_pass.set_bind_group(0, bind_group)
    compute_pass.dispatch_workgroups((out_count + WORKGROUP_SIZE - 1) // WORKGROUP_SIZE)
    compute_pass.end()
    ctx.queue.submit([encoder.finish()])
    result = np.frombuffer(ctx.read_buffer(out), dtype=np.float32).reshape(out_count, 4).copy()
    for b in [*buffers, out]:
        b.destroy()
    return result
