"""Bind group layouts and bind groups for one uniform buffer: the pattern every wgpu pass repeats.

The VkDescriptorSetLayout with one UNIFORM_BUFFER (or UNIFORM_BUFFER_DYNAMIC) binding, and
the VkDescriptorSet that points it at a buffer. With a dynamic offset the binding is a window of
one struct's size sliding over a buffer that holds several.
"""

from __future__ import annotations

import wgpu

from wgpurender.core.shaders.uniforms import Struct


def uniform_layout(device: wgpu.GPUDevice, struct: Struct, visibility: int, dynamic: bool) -> wgpu.GPUBindGroupLayout:
    """A layout with one uniform buffer at binding 0, at least one ``struct`` large."""
    return device.create_bind_group_layout(
        label=f"{struct.name}-layout",
        entries=[
            {
                "binding": 0,
                "visibility": visibility,
                "buffer": {"type": "uniform", "has_dynamic_offset": dynamic, "min_binding_size": struct.size},
            }
        ],
    )


def uniform_group(device: wgpu.GPUDevice, layout: wgpu.GPUBindGroupLayout, buffer: wgpu.GPUBuffer, struct: Struct,
                  offset: int = 0) -> wgpu.GPUBindGroup:
    """Binding 0 = one ``struct`` of ``buffer`` at ``offset`` (not the whole buffer: see the module docstring)."""
    return device.create_bind_group(
        layout=layout, entries=[{"binding": 0, "resource": {"buffer": buffer, "offset": offset, "size": struct.size}}]
    )
