"""glTF 2.0 accessors read with numpy, and a small GLB writer.

trimesh loads glTF geometry but drops the TANGENT attribute, flips TEXCOORD_0 to its bottom-left convention and
drops TEXCOORD_0 entirely when a primitive has no material. This module reads those attributes straight from the
file, as the file stores them (glTF convention: v = 0 at the top of the image). It also writes GLB files with
TANGENT, which trimesh's exporter cannot.
"""

from __future__ import annotations

import base64
import json
import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.files.input_files import (
    MAX_MODEL_VERTICES,
    MAX_MODEL_VERTICES_ENV,
    check_file_size,
    env_limit,
    input_file,
)
from wgpurender.core.files.safe_write import atomic_write
from wgpurender.core.models import gltf_compression, gltf_extensions, gltf_rules, gltf_schema

GLB_MAGIC = 0x46546C67  # b"glTF"
CHUNK_JSON = 0x4E4F534A
CHUNK_BIN = 0x004E4942

COMPONENT_DTYPES = {
    5120: np.int8,
    5121: np.uint8,
    5122: np.int16,
    5123: np.uint16,
    5125: np.uint32,
    5126: np.float32,
}
TYPE_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
TRIMESH_MODES = (0, 1, 4, 5)  # POINTS, LINES, TRIANGLES, TRIANGLE_STRIP: the modes trimesh makes a geometry of

TEXTURE_ROLES = {
    # role -> (where the textureInfo lives in a material, is the image sRGB-encoded)
    "base_color": (("pbrMetallicRoughness", "baseColorTexture"), True),
    "metallic_roughness": (("pbrMetallicRoughness", "metallicRoughnessTexture"), False),
    "normal": (("normalTexture",), False),
    "occlusion": (("occlusionTexture",), False),
    "emissive": (("emissiveTexture",), True),
}


@dataclass
class GltfDocument:
    """The JSON of a .gltf/.glb file with its buffers loaded as bytes."""

    path: Path
    json: dict
    buffers: list[bytes]


def read_document(path: str | os.PathLike) -> GltfDocument:
    """Parse a .gltf (JSON, buffers as data URIs or files) or .glb (binary container)."""
    path = Path(path)
    raw = read_jail.read_checked(path)  # the file checked, not one swapped in since
    glb_bin = None
    try:
        if raw[:4] == b"glTF":
            doc_json, glb_bin = _split_glb(raw)
        else:
            doc_json = json.loads(raw.decode("utf-8"))
    except GltfVersionError as err:
        raise UserError(f"{path}: {err}") from None
    except (ValueError, UnicodeDecodeError, struct.error, RecursionError) as err:
        raise UserError(f"malformed glTF file {path}: {err}") from None
    check_version(path, doc_json)
    check_required_extensions(path, doc_json)
    try:
        gltf_schema.check(doc_json)
        gltf_rules.check_rules(doc_json)
        gltf_rules.check_budget(doc_json, env_limit(MAX_MODEL_VERTICES_ENV, MAX_MODEL_VERTICES))
    except gltf_rules.BudgetError as err:
        raise UserError(f"glTF file {path}: {err}; simplify the model, or raise the limit with "
                        f"${MAX_MODEL_VERTICES_ENV}=COUNT") from None
    except ValueError as err:
        raise UserError(f"malformed glTF file {path}: {err} (glTF 2.0 schema); fix or re-export the file") from None
    files = {f"$.{kind}[{i}].uri": _uri_file(path, f"$.{kind}[{i}].uri", item["uri"])
             for kind in ("buffers", "images") for i, item in enumerate(doc_json.get(kind, []))
             if "uri" in item and not item["uri"].startswith("data:")}  # every file checked before one is read
    buffers = [_load_buffer(path, i, b, glb_bin, files) for i, b in enumerate(doc_json.get("buffers", []))]
    buffers = gltf_compression.meshopt_buffers(path, doc_json, buffers)
    return GltfDocument(path, doc_json, buffers)


class GltfVersionError(ValueError):
    """A GLB container of another glTF version (its header says so before any JSON is read)."""


# Extensions a file may list in extensionsRequired (each one changes what a correct render is): those implemented.
SUPPORTED_REQUIRED_EXTENSIONS: frozenset[str] = gltf_extensions.SUPPORTED_REQUIRED


def check_version(path: Path, doc_json: object) -> None:
    """glTF 2.x only, checked before the 2.0 schema (a 1.0 file breaks it in ways that would hide the reason)."""
    asset = doc_json.get("asset") if isinstance(doc_json, dict) else None
    version = asset.get("version") if isinstance(asset, dict) else None
    if version is None:
        return  # the schema check names the missing asset / version
    major = str(version).split(".", 1)[0]
    if major != "2":
        raise UserError(f"{path}: glTF {version} is not supported (glTF 2.0 only); convert it to glTF 2.0, e.g. "
                        "with Blender (import, then File > Export > glTF 2.0) or gltf-pipeline")


def check_required_extensions(path: Path, doc_json: object) -> None:
    """An extension in ``extensionsRequired`` changes what the file means: refuse each one we do not implement."""
    required = doc_json.get("extensionsRequired", []) if isinstance(doc_json, dict) else []
    if not isinstance(required, list):
        return
    missing = [str(name) for name in required if name not in SUPPORTED_REQUIRED_EXTENSIONS]
    if missing:
        fixes = "; ".join(dict.fromkeys(REQUIRED_EXTENSION_FIXES.get(name, GENERIC_FIX) for name in missing))
        raise UserError(f"{path}: requires the glTF extension(s) {', '.join(missing)}, which wgpurender does not "
                        f"support; {fixes}")


GENERIC_FIX = "re-export the model without them"
# The fix for the required extensions real files carry most.
REQUIRED_EXTENSION_FIXES = {
    "KHR_texture_basisu": "re-export it with PNG or JPEG textures",
}


def _split_glb(raw: bytes) -> tuple[dict, bytes | None]:
    magic, version, length = struct.unpack_from("<III", raw, 0)
    if magic == GLB_MAGIC and version != 2:
        raise GltfVersionError(f"binary glTF version {version} is not supported (glTF 2.0 only); convert it to "
                               "glTF 2.0, e.g. with Blender or gltf-pipeline")
    if magic != GLB_MAGIC:
        raise ValueError(f"not a glTF 2.0 binary (version {version})")
    offset, doc_json, binary = 12, None, None
    while offset + 8 <= min(length, len(raw)):
        chunk_len, chunk_type = struct.unpack_from("<II", raw, offset)
        chunk = raw[offset + 8 : offset + 8 + chunk_len]
        if len(chunk) != chunk_len:
            raise ValueError("truncated chunk")
        if chunk_type == CHUNK_JSON:
            doc_json = json.loads(chunk.decode("utf-8"))
        elif chunk_type == CHUNK_BIN and binary is None:
            binary = chunk
        offset += 8 + chunk_len
    if doc_json is None:
        raise ValueError("no JSON chunk")
    return doc_json, binary


def _load_buffer(path: Path, index: int, buffer: dict, glb_bin: bytes | None, files: dict[str, Path]) -> bytes:
    uri = buffer.get("uri")
    if uri is None and buffer.get("extensions", {}).get(gltf_compression.MESHOPT, {}).get("fallback"):
        return b""  # EXT_meshopt_compression's placeholder: its views are decoded from the compressed buffer
    if uri is None:
        if glb_bin is None:
            raise UserError(f"malformed glTF file {path}: buffer {index} has no uri and there is no GLB binary chunk")
        return glb_bin
    if uri.startswith("data:"):
        return _data_uri(path, f"$.buffers[{index}].uri", uri)
    file = files[f"$.buffers[{index}].uri"]
    missing = f"glTF file {path}: buffer file {file} not found (keep .bin files next to the .gltf)"
    check_file_size(input_file(file, "glTF buffer file", missing), "glTF buffer file")
    return read_jail.read_checked(file)


def read_accessor(doc: GltfDocument, index: int) -> np.ndarray:
    """An accessor's elements as an (count, width) array; normalized integers become float32 in [0,1]/[-1,1]."""
    try:
        acc = doc.json["accessors"][index]
        dtype = np.dtype(COMPONENT_DTYPES[acc["componentType"]]).newbyteorder("<")
        width, count = TYPE_WIDTHS[acc["type"]], int(acc["count"])
        if "bufferView" not in acc:
            out = np.zeros((count, width), dtype)
        else:
            out = _view_elements(doc, acc["bufferView"], acc.get("byteOffset", 0), dtype, width, count)
        if "sparse" in acc:
            _apply_sparse(doc, acc["sparse"], out, dtype, width)
    except (KeyError, IndexError, TypeError, ValueError, AttributeError) as err:
        raise UserError(f"malformed glTF file {doc.path}: accessor {index}: {err!r}") from None
    if acc.get("normalized") and out.dtype.kind in "iu":
        info = np.iinfo(out.dtype)
        out = np.maximum(out.astype(np.float32) / info.max, -1.0)
    return out


def _view_elements(doc: GltfDocument, view_index: int, offset: int, dtype: np.dtype, width: int,
                   count: int, *, strided: bool = True) -> np.ndarray:
    """``count`` elements of ``width`` components from a bufferView (its byteStride honoured), copied."""
    view = doc.json["bufferViews"][view_index]
    data = doc.buffers[view["buffer"]]
    start = view.get("byteOffset", 0) + offset
    stride = (view.get("byteStride") if strided else None) or dtype.itemsize * width
    end = view.get("byteOffset", 0) + view.get("byteLength", len(data))
    if count and start + stride * (count - 1) + dtype.itemsize * width > min(len(data), end):
        raise ValueError("accessor runs past the end of its buffer view")
    return np.ndarray((count, width), dtype, buffer=data, offset=start, strides=(stride, dtype.itemsize)).copy()


SPARSE_INDEX_DTYPES = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32}


def _apply_sparse(doc: GltfDocument, sparse: dict, out: np.ndarray, dtype: np.dtype, width: int) -> None:
    """Replace the elements a sparse accessor names (glTF 2.0 section 3.6.2.3): ``count`` indices, strictly
    increasing, each below the accessor's count, and as many values, both tightly packed (no byteStride)."""
    n = int(sparse["count"])
    indices_info, values_info = sparse["indices"], sparse["values"]
    index_dtype = np.dtype(SPARSE_INDEX_DTYPES[indices_info["componentType"]]).newbyteorder("<")
    indices = _view_elements(doc, indices_info["bufferView"], indices_info.get("byteOffset", 0), index_dtype, 1, n,
                             strided=False).reshape(-1).astype(np.int64)
    values = _view_elements(doc, values_info["bufferView"], values_info.get("byteOffset", 0), dtype, width, n,
                            strided=False)
    if n and (indices.max() >= len(out) or np.any(np.diff(indices) <= 0)):
        raise ValueError(f"sparse indices must increase strictly and stay below count {len(out)}")
    out[indices] = values


def loaded_primitives(doc: GltfDocument) -> list[tuple[int, int, dict]]:
    """(mesh index, primitive index, primitive) of every primitive trimesh makes a geometry of, in its order."""
    found = []
    for mi, mesh in enumerate(doc.json.get("meshes", [])):
        for pi, prim in enumerate(mesh.get("primitives", [])):
            if prim.get("mode", 4) in TRIMESH_MODES:
                found.append((mi, pi, prim))
    return found


def primitive_attribute(doc: GltfDocument, prim: dict, name: str) -> np.ndarray | None:
    """A vertex attribute of one primitive (e.g. TANGENT, TEXCOORD_0) as float32, or None if absent."""
    index = prim.get("attributes", {}).get(name)
    return None if index is None else read_accessor(doc, index).astype(np.float32)


def image_source(doc: GltfDocument, image: dict) -> dict:
    uri = image.get("uri")
    if uri is None:
        view = doc.json["bufferViews"][image["bufferView"]]
        start = view.get("byteOffset", 0)
        return {"uri": None, "data": doc.buffers[view["buffer"]][start : start + view["byteLength"]]}
    if uri.startswith("data:"):
        return {"uri": None, "data": _data_uri(doc.path, "an image uri", uri)}
    return {"uri": _uri_file(doc.path, "an image uri", uri), "data": None}


def _data_uri(path: Path, where: str, uri: str) -> bytes:
    """The bytes of a base64 data: URI, or UserError."""
    head, comma, payload = uri.partition(",")
    if not comma or ";base64" not in head:
        raise UserError(f"malformed glTF file {path}: {where} is a data: URI without ';base64,'; re-export the file")
    try:
        return base64.b64decode(payload, validate=True)
    except ValueError as err:
        raise UserError(f"malformed glTF file {path}: {where}: bad base64 data ({err})") from None


def _uri_file(path: Path, where: str, uri: str) -> Path:
    """The file a relative URI names in the glTF file's folder (links resolved); UserError for one outside it or
    special (read_jail.py: a model reads only what it ships)."""
    return read_jail.model_file(path, uri, where)


def write_glb(
    path: str | os.PathLike,
    positions: np.ndarray,
    normals: np.ndarray,
    uvs: np.ndarray,
    indices: np.ndarray,
    tangents: np.ndarray | None = None,
    textures: dict[str, str] | None = None,
    name: str = "mesh",
) -> Path:
    """Write one indexed triangle primitive as GLB, atomically.

    uvs are written as given (glTF convention, v = 0 at the top). textures maps a role of TEXTURE_ROLES
    ("base_color", "normal", "metallic_roughness", ...) to an image URI relative to the .glb file.
    """
    attributes = {"POSITION": positions, "NORMAL": normals, "TEXCOORD_0": uvs}
    if tangents is not None:
        attributes["TANGENT"] = tangents
    blobs, accessors, views = [], [], []

    def add(array: np.ndarray, kind: str, target: int, with_bounds: bool = False) -> int:
        data = np.ascontiguousarray(array).tobytes()
        offset = sum(len(b) for b in blobs)
        blobs.append(data + b"\0" * (-len(data) % 4))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data), "target": target})
        component = 5126 if array.dtype == np.float32 else {np.uint16: 5123, np.uint32: 5125}[array.dtype.type]
        count = array.shape[0] if kind != "SCALAR" else array.size
        acc = {"bufferView": len(views) - 1, "componentType": component, "count": int(count), "type": kind}
        if with_bounds:
            acc["min"], acc["max"] = array.min(axis=0).tolist(), array.max(axis=0).tolist()
        accessors.append(acc)
        return len(accessors) - 1

    attr_index = {}
    for key, array in attributes.items():
        array = np.asarray(array, np.float32)
        attr_index[key] = add(array, f"VEC{array.shape[1]}", 34962, with_bounds=key == "POSITION")
    index_dtype = np.uint16 if indices.max() < 65535 else np.uint32
    index_acc = add(np.asarray(indices, index_dtype).reshape(-1), "SCALAR", 34963)

    material, images, gl_textures = {"name": f"{name}_material", "pbrMetallicRoughness": {}}, [], []
    for role, uri in (textures or {}).items():
        keys, _ = TEXTURE_ROLES[role]
        images.append({"uri": uri})
        gl_textures.append({"source": len(images) - 1, "sampler": 0})
        holder = material
        for key in keys[:-1]:
            holder = holder.setdefault(key, {})
        holder[keys[-1]] = {"index": len(gl_textures) - 1}
    material["pbrMetallicRoughness"].setdefault("metallicFactor", 0.0)

    binary = b"".join(blobs)
    doc = {
        "asset": {"version": "2.0", "generator": "wgpurender gltf_io.write_glb"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": name}],
        "meshes": [{"name": name, "primitives": [
            {"attributes": attr_index, "indices": index_acc, "material": 0, "mode": 4}]}],
        "materials": [material],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    if images:
        # 10497 = REPEAT, 9987 = LINEAR_MIPMAP_LINEAR, 9729 = LINEAR
        doc.update(images=images, textures=gl_textures,
                   samplers=[{"wrapS": 10497, "wrapT": 10497, "minFilter": 9987, "magFilter": 9729}])
    text = json.dumps(doc, separators=(",", ":"), sort_keys=True).encode("utf-8")
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    out = struct.pack("<III", GLB_MAGIC, 2, total)
    out += struct.pack("<II", len(text), CHUNK_JSON) + text + struct.pack("<II", len(binary), CHUNK_BIN) + binary
    return atomic_write(Path(path), out)
