"""The scene's uniform blocks and push constants, packed by hand with the std140 offsets written out.

Independent of wgpurender/core/shaders/uniforms.py (the wgpu path's generated layouts), so that comparing the
two paths' images also checks that packer. The GLSL declarations are in shaders_glsl/scene.vert,
scene.frag and post_chain.frag; each offset below is the one written beside its member there.

std140 rules used: vec4/uvec4 and mat4 columns on 16 bytes; a mat3 is three vec4-padded columns
(48 bytes); an array of structs has a stride of the struct size rounded up to 16; a block's size
rounds up to 16. Push constants use std430 (no rounding of the block's size).
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.view.transforms import normal_matrix, to_gpu

MAX_LIGHTS = 8  # array sizes in the camera block; scene.MAX_LIGHTS bounds what a scene may have

# layout(std140) uniform Camera: proj @0, view @64, eye @128, ambient @144, light_counts @160,
# directional[MAX_LIGHTS] @176 (direction, radiance: 32 bytes each), point[MAX_LIGHTS] after them (position with
# the range in w, radiance with the spot cone offset in w, spot axis with the cone scale in w: 48 bytes each).
CAMERA_DIRECTIONAL = 176
LIGHT_STRIDE = 32
POINT_STRIDE = 48
CAMERA_POINT = CAMERA_DIRECTIONAL + LIGHT_STRIDE * MAX_LIGHTS  # 432
CAMERA_SIZE = CAMERA_POINT + POINT_STRIDE * MAX_LIGHTS  # 816
# layout(std140) uniform Object: world @0, normal (mat3) @64, mirror @112; 116 bytes, rounded up to 128.
OBJECT_SIZE = 128
# push_constant Material: base_color @0, roughness @16, normal_strength @20, specular (PBR: metallic) @24 (lit);
# 16 bytes unlit.
MATERIAL_SIZE_LIT, MATERIAL_SIZE_UNLIT = 28, 16  # + 4 (alpha_cutoff) in alpha-masked variants
# layout(std140) uniform Chain: size (vec2) @0, count @8, steps[MAX_POST_STEPS] @16 (kind, p0, p1, p2: 16 bytes).
MAX_POST_STEPS = 8
CHAIN_STEPS = 16
CHAIN_SIZE = CHAIN_STEPS + 16 * MAX_POST_STEPS


def _put(buf: bytearray, offset: int, values, dtype=np.float32) -> None:
    data = np.asarray(values, dtype=dtype).tobytes()
    buf[offset: offset + len(data)] = data


def pack_camera(proj: np.ndarray, view: np.ndarray, eye, ambient, directional: list[tuple],
                point: list[tuple]) -> bytes:
    """``directional``: (unit direction, radiance) pairs; ``point``: (position, radiance, (spot axis, cone scale,
    cone offset, range)) triples (core.scene.Light.shape)."""
    buf = bytearray(CAMERA_SIZE)
    _put(buf, 0, to_gpu(proj).reshape(-1))
    _put(buf, 64, to_gpu(view).reshape(-1))
    _put(buf, 128, list(eye))  # (x, y, z, 1), or an orthographic camera's direction with w = 0
    _put(buf, 144, [*ambient, 0.0])
    _put(buf, 160, [len(directional), len(point), 0, 0], np.uint32)
    for k, (direction, radiance) in enumerate(directional):
        _put(buf, CAMERA_DIRECTIONAL + LIGHT_STRIDE * k, [*direction, 0.0, *radiance, 0.0])
    for k, (position, radiance, (axis, scale, offset, reach)) in enumerate(point):
        _put(buf, CAMERA_POINT + POINT_STRIDE * k, [*position, reach, *radiance, offset, *axis, scale])
    return bytes(buf)


def pack_object(world: np.ndarray) -> bytes:
    """One Object block packed by hand, field by field: the independent check of core/plan/batches.py's
    vectorised instance_blocks, which both paths upload (tests/test_instancing.py compares them)."""
    buf = bytearray(OBJECT_SIZE)
    _put(buf, 0, to_gpu(world).reshape(-1))
    columns = to_gpu(normal_matrix(world))  # (3 columns, 3 rows)
    for c in range(3):
        _put(buf, 64 + 16 * c, columns[c])  # column c at 64 + 16 c; its 4th float is padding
    _put(buf, 112, [1.0 if np.linalg.det(world[:3, :3]) >= 0 else -1.0])
    return bytes(buf)


def pack_material(base_color, lit: bool, roughness: float = 0.0, normal_strength: float = 0.0,
                  specular: float = 0.0, alpha_cutoff: float | None = None, occlusion_strength: float | None = None,
                  clearcoat=None, emissive=None) -> bytes:
    """The push constant block (std430); a PBR variant's metallic factor goes where ``specular`` is. Model-file
    variants append, in scene.frag's order: alpha_cutoff and occlusion_strength (floats, each right after the
    last), clearcoat (three floats: factor, roughness, normal scale), emissive (a vec4 on the next 16-byte
    boundary)."""
    values = [*base_color, roughness, normal_strength, specular] if lit else list(base_color)
    values += [v for v in (alpha_cutoff, occlusion_strength) if v is not None]
    values += list(clearcoat) if clearcoat is not None else []
    if emissive is not None:
        values += [0.0] * (-len(values) % 4) + [*emissive[:3], 0.0]
    return np.asarray(values, dtype=np.float32).tobytes()


def pack_chain(size: tuple[int, int], steps: list[tuple[int, tuple[float, ...]]]) -> bytes:
    """``steps``: (kind, up to three parameters) in chain order."""
    buf = bytearray(CHAIN_SIZE)
    _put(buf, 0, [float(size[0]), float(size[1])])
    _put(buf, 8, [len(steps)], np.int32)
    for k, (kind, params) in enumerate(steps):
        offset = CHAIN_STEPS + 16 * k
        _put(buf, offset, [kind], np.int32)
        _put(buf, offset + 4, [*params, *([0.0] * (3 - len(params)))])
    return bytes(buf)
