"""Course concept: uniform buffer layout (std140) and alignment, written out by hand.

The raw path packs its uniform blocks itself, with the offsets spelled out, so
that it is an independent check of wgpurender/core/shaders/uniforms.py (which the wgpu path
uses). The std140 rules that matter here:
- a mat4 is 4 columns of vec4: 64 bytes, column-major (transforms.to_gpu);
- a mat3 is 3 columns, each padded to a vec4: 48 bytes, not 36;
- a vec3 is aligned to 16 bytes but only 12 long, so a float after it fills
  the gap (light_dir + ambient share one 16-byte slot);
- a block's size rounds up to a multiple of 16.
Several copies of a block in one buffer, read with dynamic offsets, must start at
multiples of VkPhysicalDeviceLimits::minUniformBufferOffsetAlignment (16 on
lavapipe, 256 on many GPUs): :func:`dynamic_stride`.
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.view.transforms import to_gpu

# layout(std140) uniform Camera { mat4 proj; mat4 view; vec3 light_dir; float ambient; }
CAMERA_SIZE = 64 + 64 + 12 + 4  # proj @0, view @64, light_dir @128, ambient @140
# layout(std140) uniform ObjectData { mat4 world; mat3 normal; }
OBJECT_SIZE = 64 + 48  # world @0, normal @64 (three vec4-padded columns)
# push_constant Draw { vec4 tint; uint object_index; } (std430 for push constants: no tail padding needed)
DRAW_SIZE = 16 + 4


def round_up(value: int, alignment: int) -> int:
    return (value + alignment - 1) // alignment * alignment


def dynamic_stride(size: int, min_offset_alignment: int) -> int:
    """Distance between copies of a block in one buffer, so every dynamic offset is aligned."""
    return round_up(size, max(16, min_offset_alignment))


def pack_camera(proj: np.ndarray, view: np.ndarray, light_dir, ambient: float) -> bytes:
    buf = np.zeros(CAMERA_SIZE // 4, dtype=np.float32)
    buf[0:16] = to_gpu(proj).reshape(-1)
    buf[16:32] = to_gpu(view).reshape(-1)
    buf[32:35] = np.asarray(light_dir, dtype=np.float64)
    buf[35] = ambient
    return buf.tobytes()


def pack_object(world: np.ndarray, normal: np.ndarray) -> bytes:
    buf = np.zeros(OBJECT_SIZE // 4, dtype=np.float32)
    buf[0:16] = to_gpu(world).reshape(-1)
    columns = to_gpu(normal)  # (3 columns, 3 rows)
    for c in range(3):
        buf[16 + 4 * c: 16 + 4 * c + 3] = columns[c]  # column c at 64 + 16 c; the 4th float is padding
    return buf.tobytes()


def pack_draw(tint, object_index: int) -> bytes:
    return np.asarray(tint, dtype=np.float32).tobytes() + np.uint32(object_index).tobytes()


def pack_many(blocks: list[bytes], stride: int) -> bytes:
    out = bytearray(stride * len(blocks))
    for k, block in enumerate(blocks):
        out[k * stride: k * stride + len(block)] = block
    return bytes(out)
