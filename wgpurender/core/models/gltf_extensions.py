"""glTF extensions that change geometry, applied while the file is read (no shader knows about them).

- ``KHR_texture_transform`` (offset, rotation, scale, texCoord override): an affine map of the texture
  coordinates, so it is applied to the primitive's TEXCOORD values once at load (interpolating transformed
  coordinates equals transforming interpolated ones): both paths draw it with their ordinary shaders.
- ``EXT_mesh_gpu_instancing``: a node's TRANSLATION / ROTATION / SCALE accessors place its mesh N times.
- default morph target weights (``node.weights``, else ``mesh.weights``) added to POSITION, NORMAL and TANGENT.
- ``KHR_mesh_quantization``: integer attribute types for POSITION, NORMAL, TANGENT and TEXCOORD (its table).

Which extensions a file may require is listed here too (:data:`SUPPORTED_REQUIRED`), each with its one-line
refusal when it cannot apply.
"""

from __future__ import annotations

import math

import numpy as np

from wgpurender.core.errors import UserError

TEXTURE_TRANSFORM = "KHR_texture_transform"
INSTANCING = "EXT_mesh_gpu_instancing"
QUANTIZATION = "KHR_mesh_quantization"
DRACO = "KHR_draco_mesh_compression"
MESHOPT = "EXT_meshopt_compression"
CLEARCOAT = "KHR_materials_clearcoat"

# extensionsRequired a file may list: each is implemented (Draco and meshopt need their decoder package)
SUPPORTED_REQUIRED = frozenset({"KHR_materials_unlit", "KHR_materials_emissive_strength", TEXTURE_TRANSFORM,
                                "KHR_materials_pbrSpecularGlossiness",  # converted: core/scene/gltf_specgloss.py
                                CLEARCOAT,  # shaders_wgsl/clearcoat.wgsl
                                QUANTIZATION, INSTANCING, DRACO, MESHOPT})

BYTE, UBYTE, SHORT, USHORT, FLOAT = 5120, 5121, 5122, 5123, 5126
# KHR_mesh_quantization's table: semantic -> component types (normalized or not, as listed there)
QUANTIZED = {"POSITION": (FLOAT, BYTE, UBYTE, SHORT, USHORT), "NORMAL": (FLOAT, BYTE, SHORT),
             "TANGENT": (FLOAT, BYTE, SHORT), "TEXCOORD": (FLOAT, BYTE, UBYTE, SHORT, USHORT)}
MUST_NORMALIZE = {"NORMAL", "TANGENT"}  # the table lists only their normalized integer forms


def quantized_components(semantic: str) -> tuple[int, ...] | None:
    """Component types KHR_mesh_quantization allows for an attribute semantic, or None (not one it widens)."""
    return QUANTIZED.get(semantic.split("_", 1)[0] if semantic.startswith("TEXCOORD_") else semantic)


def uses(doc_json: dict, name: str) -> bool:
    used = doc_json.get("extensionsUsed", [])
    return isinstance(used, list) and name in used


def texture_transform_matrix(transform: dict) -> np.ndarray:
    """The 3x3 matrix KHR_texture_transform defines: T(offset) @ R(rotation) @ S(scale), applied to (u, v, 1).
    Its rotation matrix is [[cos, sin], [-sin, cos]]: counter-clockwise in UV space, whose v axis points down."""
    ox, oy = (float(v) for v in transform.get("offset", (0.0, 0.0)))
    sx, sy = (float(v) for v in transform.get("scale", (1.0, 1.0)))
    angle = float(transform.get("rotation", 0.0))
    c, s = math.cos(angle), math.sin(angle)
    translation = np.array([[1, 0, ox], [0, 1, oy], [0, 0, 1]], np.float64)
    rotation = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]], np.float64)
    scale = np.array([[sx, 0, 0], [0, sy, 0], [0, 0, 1]], np.float64)
    return translation @ rotation @ scale


def transform_uvs(uvs: np.ndarray, transform: dict) -> np.ndarray:
    """Texture coordinates (N, 2) under a KHR_texture_transform object."""
    m = texture_transform_matrix(transform)
    return uvs @ m[:2, :2].T + m[:2, 2]


def texture_uv_choice(info: dict) -> tuple[int, tuple]:
    """(TEXCOORD set, transform key) a textureInfo samples with: its texCoord, overridden by the transform's
    ``texCoord``; the key is hashable so that two textures sampling alike compare equal."""
    ext = info.get("extensions", {}).get(TEXTURE_TRANSFORM) if isinstance(info.get("extensions"), dict) else None
    texcoord = int(info.get("texCoord", 0))
    if not isinstance(ext, dict):
        return texcoord, ()
    check_texture_transform(ext)
    texcoord = int(ext.get("texCoord", texcoord))
    key = tuple(sorted((k, tuple(v) if isinstance(v, list) else v) for k, v in ext.items() if k != "texCoord"))
    return texcoord, key


def _finite(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def check_texture_transform(ext: dict) -> None:
    """UserError in one line for a KHR_texture_transform object its schema does not allow (a traceback before)."""
    def bad(field: str, want: str) -> UserError:
        return UserError(f"{TEXTURE_TRANSFORM}.{field} is {ext[field]!r}: it must be {want} (fix the file's "
                         "material, or re-export it)")

    if "texCoord" in ext and not (isinstance(ext["texCoord"], int) and not isinstance(ext["texCoord"], bool)
                                  and ext["texCoord"] >= 0):
        raise bad("texCoord", "a non-negative integer")
    for field in ("offset", "scale"):
        value = ext.get(field, (0.0, 0.0))
        if not (isinstance(value, (list, tuple)) and len(value) == 2 and all(_finite(v) for v in value)):
            raise bad(field, "two finite numbers")
    if "rotation" in ext and not _finite(ext["rotation"]):
        raise bad("rotation", "a finite number (radians)")


def instance_matrices(translation: np.ndarray | None, rotation: np.ndarray | None,
                      scale: np.ndarray | None) -> np.ndarray:
    """(N, 4, 4) matrices T @ R @ S of EXT_mesh_gpu_instancing's per-instance attributes (any may be absent)."""
    count = next(len(a) for a in (translation, rotation, scale) if a is not None)
    out = np.tile(np.eye(4), (count, 1, 1))
    if rotation is not None:
        q = np.asarray(rotation, np.float64)
        q = q / np.maximum(np.linalg.norm(q, axis=1, keepdims=True), 1e-30)
        x, y, z, w = q.T
        out[:, 0, :3] = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], 1)
        out[:, 1, :3] = np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], 1)
        out[:, 2, :3] = np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], 1)
    if scale is not None:
        out[:, :3, :3] *= np.asarray(scale, np.float64)[:, None, :]
    if translation is not None:
        out[:, :3, 3] = translation
    return out


def morphed(base: np.ndarray | None, deltas: list[np.ndarray | None], weights: list[float]) -> np.ndarray | None:
    """base + sum(weight_i * delta_i) over the targets that carry this attribute (glTF 2.0, 3.7.2.2)."""
    if base is None:
        return None
    out = np.array(base, np.float64)
    width = min(out.shape[1], 3)  # TANGENT targets move xyz; w (handedness) stays
    for delta, weight in zip(deltas, weights, strict=False):
        if delta is not None and weight:
            out[:, :width] += float(weight) * delta[:, :width]
    return out
