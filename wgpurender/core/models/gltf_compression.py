"""Compressed glTF geometry: EXT_meshopt_compression buffer views and KHR_draco_mesh_compression primitives.

Both decoders are optional packages (``pip install wgpurender[compressed]``): ``meshoptimizer`` (zeux's
meshoptimizer codecs and filters) and ``DracoPy`` (Google's Draco decoder). They are imported only when a file
uses the extension; without them the file is refused in one line naming the extension and the pip command.

meshopt: every compressed view is decoded when the document is read and stands in for the view from then on
(its bytes become a buffer of their own), so accessors read it as any other view. Draco: a primitive's
attributes are decoded when its geometry is read (gltf_geometry), matched to the primitive's accessors by the
extension's unique ids.
"""

from __future__ import annotations

import importlib.util

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import MAX_MODEL_BYTES, MAX_MODEL_BYTES_ENV, env_limit

MESHOPT = "EXT_meshopt_compression"
DRACO = "KHR_draco_mesh_compression"
PACKAGES = {MESHOPT: ("meshoptimizer", "meshoptimizer"), DRACO: ("DracoPy", "DracoPy")}


def _decoder(path, extension: str):
    """The decoder module for ``extension``, or the one-line refusal saying how to install it."""
    module, pip_name = PACKAGES[extension]
    try:
        return __import__(module)
    except ImportError:
        raise UserError(f"{path}: uses {extension}, whose decoder is not installed; `pip install {pip_name}` (or "
                        "`pip install wgpurender[compressed]`), or re-export the model without compression") from None


def uses_draco(doc, prim: dict) -> bool:
    """Whether a primitive is read from its Draco data: it has some, and either DracoPy is installed or the
    primitive has no uncompressed fallback (an attribute accessor without a bufferView)."""
    if DRACO not in prim.get("extensions", {}):
        return False
    accessors = doc.json.get("accessors", [])
    fallback = all("bufferView" in accessors[i] for i in prim.get("attributes", {}).values())
    return not fallback or importlib.util.find_spec(PACKAGES[DRACO][0]) is not None


def meshopt_buffers(path, doc_json: dict, buffers: list[bytes]) -> list[bytes]:
    """Decode every EXT_meshopt_compression buffer view in place: the view then names a new buffer holding its
    decoded bytes (byteOffset 0). Returns the buffers, extended."""
    views = [v for v in doc_json.get("bufferViews", []) if MESHOPT in v.get("extensions", {})]
    if not views:
        return buffers
    codec = _decoder(path, MESHOPT)
    buffers = list(buffers)
    limit = env_limit(MAX_MODEL_BYTES_ENV, MAX_MODEL_BYTES)
    total = sum(int(v["extensions"][MESHOPT].get("count", 0)) * int(v["extensions"][MESHOPT].get("byteStride", 0))
                for v in views)
    if total > limit:  # a few compressed bytes can claim gigabytes: refused before anything is allocated
        raise UserError(f"{path}: its {MESHOPT} views decode to {total / 2**20:.0f} MiB, over the model limit of "
                        f"{limit / 2**20:.0f} MiB; raise it with ${MAX_MODEL_BYTES_ENV}=BYTES if the model is real")
    for view in views:
        ext = view["extensions"][MESHOPT]
        source = buffers[ext["buffer"]]
        start = int(ext.get("byteOffset", 0))
        data = source[start: start + int(ext["byteLength"])]
        count, stride = int(ext["count"]), int(ext["byteStride"])
        try:
            raw = _meshopt_decode(codec, ext.get("mode"), ext.get("filter", "NONE"), data, count, stride)
        except (ValueError, RuntimeError, KeyError) as err:
            raise UserError(f"malformed glTF file {path}: an {MESHOPT} buffer view does not decode ({err}); "
                            "re-export the model") from None
        buffers.append(raw)
        view.update(buffer=len(buffers) - 1, byteOffset=0, byteLength=len(raw))
        view.pop("extensions")
    return buffers


FILTERS = {"OCTAHEDRAL": ("decode_filter_oct", (4, 8)), "QUATERNION": ("decode_filter_quat", (8,)),
           "EXPONENTIAL": ("decode_filter_exp", tuple(range(4, 257, 4)))}


def _meshopt_decode(codec, mode: str, filter_name: str, data: bytes, count: int, stride: int) -> bytes:
    """One view's bytes. Strides are checked before the decoder runs: it trusts them (and writes past a buffer
    sized from a bad one)."""
    if mode == "ATTRIBUTES":
        if stride % 4 or not 0 < stride <= 256:
            raise ValueError(f"byteStride {stride} of an ATTRIBUTES view must be a multiple of 4 up to 256")
        out = codec.decode_vertex_buffer(count, stride, data)  # float32 (count, stride / 4); its dtype= under-allocates
    elif mode in ("TRIANGLES", "INDICES"):
        if stride not in (2, 4):
            raise ValueError(f"byteStride {stride} of an index view must be 2 or 4")
        decode = codec.decode_index_buffer if mode == "TRIANGLES" else codec.decode_index_sequence
        out = decode(count, stride, data)
    else:
        raise ValueError(f"unknown mode {mode!r}")
    raw = np.ascontiguousarray(out).tobytes()[: count * stride]  # index decoders return whole uint32 words
    if filter_name in FILTERS:
        name, strides = FILTERS[filter_name]
        if mode != "ATTRIBUTES" or stride not in strides:
            raise ValueError(f"filter {filter_name} needs an ATTRIBUTES view of byteStride {strides[0]}"
                             + (f" or {strides[-1]}" if len(strides) > 1 else ""))
        raw = getattr(codec, name)(np.frombuffer(raw, np.uint8).copy(), count, stride).tobytes()
    elif filter_name != "NONE":
        raise ValueError(f"unknown filter {filter_name!r}")
    if len(raw) != count * stride:
        raise ValueError(f"decoded {len(raw)} bytes, expected {count} x {stride}")
    return raw


_DECODED: dict[tuple[int, int], tuple[object, dict, tuple]] = {}  # (id(buffer), id(prim)) -> (both, the decode)
DECODED_KEEP = 64  # primitives kept


def draco_attributes(doc, prim: dict, where: str) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The attributes (by semantic, float64; normalized integer accessors scaled to [0,1]/[-1,1]) and the
    triangle indices (F, 3) of a Draco-compressed primitive, as fresh arrays.

    A primitive is decoded once per buffer and primitive object: the window re-poses an animated model from the
    same parsed document every frame (core/scene/playback.py), whose compressed bytes do not change."""
    buffer = doc.buffers[doc.json["bufferViews"][prim["extensions"][DRACO]["bufferView"]]["buffer"]]
    hit = _DECODED.get((id(buffer), id(prim)))
    if hit is None or hit[0] is not buffer or hit[1] is not prim:  # the objects held: their ids are not others'
        hit = (buffer, prim, _decode(doc, prim, where))
        if len(_DECODED) >= DECODED_KEEP:
            _DECODED.pop(next(iter(_DECODED)))
        _DECODED[(id(buffer), id(prim))] = hit
    arrays, faces = hit[2]
    return {k: v.copy() for k, v in arrays.items()}, faces.copy()


def _decode(doc, prim: dict, where: str) -> tuple[dict[str, np.ndarray], np.ndarray]:
    ext = prim["extensions"][DRACO]
    codec = _decoder(doc.path, DRACO)
    view = doc.json["bufferViews"][ext["bufferView"]]
    start = view.get("byteOffset", 0)
    data = doc.buffers[view["buffer"]][start: start + view["byteLength"]]
    try:
        mesh = codec.decode(data)
    except Exception as err:  # DracoPy raises its own types for corrupt data
        raise UserError(f"malformed glTF file {doc.path}: {where}: its {DRACO} data does not decode "
                        f"({type(err).__name__}); re-export the model") from None
    arrays = {}
    for semantic, unique_id in ext.get("attributes", {}).items():
        found = mesh.get_attribute_by_unique_id(int(unique_id))
        if found is None:
            raise UserError(f"malformed glTF file {doc.path}: {where}: {DRACO} has no attribute id {unique_id} "
                            f"for {semantic}")
        values = np.asarray(found["data"])
        accessor = doc.json["accessors"][prim["attributes"][semantic]]
        values = values.reshape(len(values), -1).astype(np.float64)
        if accessor.get("normalized") and np.asarray(found["data"]).dtype.kind in "iu":
            values = np.maximum(values / np.iinfo(np.asarray(found["data"]).dtype).max, -1.0)
        arrays[semantic] = values
    faces = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), np.int64).reshape(-1, 3)
    return arrays, faces
