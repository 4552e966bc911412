"""Small glTF 2.0 files written by the tests themselves, independent of wgpurender.core.models.gltf_io.

:class:`GltfWriter` packs numpy arrays into one buffer (accessors, sparse accessors, interleaved views with a
byteStride, normalized integer types), PNG images into buffer views, and writes ``.gltf`` (base64 buffer) or
``.glb``. Every expected value a test compares against is computed from the arrays the test hands in here,
never read back through the loader under test.
"""

from __future__ import annotations

import base64
import io
import json
import struct
from pathlib import Path

import numpy as np

COMPONENT = {np.float32: 5126, np.uint8: 5121, np.uint16: 5123, np.uint32: 5125, np.int8: 5120, np.int16: 5122}
TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}
REPEAT, CLAMP, MIRROR = 10497, 33071, 33648
NEAREST, LINEAR = 9728, 9729


class GltfWriter:
    """A glTF document under construction: add accessors, meshes, nodes, materials; then :meth:`write`."""

    def __init__(self) -> None:
        self.data = bytearray()
        self.doc: dict = {"asset": {"version": "2.0", "generator": "wgpurender tests/gltf_gen.py"},
                          "bufferViews": [], "accessors": [], "meshes": [], "nodes": []}

    # -- raw data -------------------------------------------------------------------------------------------------
    def view(self, raw: bytes, stride: int | None = None) -> int:
        self.data += b"\0" * (-len(self.data) % 4)
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if stride:
            view["byteStride"] = stride
        self.data += raw
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array, *, normalized: bool = False, view: int | None = None, offset: int = 0,
                 count: int | None = None, width: int | None = None, sparse: tuple | None = None) -> int:
        """An accessor of ``array`` (its own tightly packed view unless ``view``/``offset`` are given);
        ``sparse = (indices uint array, values array)`` adds a sparse block; ``array=None`` with count/width and
        a dtype-carrying sparse gives an accessor with no bufferView (zeros + sparse)."""
        if array is not None:
            array = np.asarray(array)
            dtype, width = array.dtype.type, 1 if array.ndim == 1 else array.shape[1]
            count = len(array)
            if view is None:
                view = self.view(np.ascontiguousarray(array).tobytes())
        else:
            dtype = np.asarray(sparse[1]).dtype.type
        acc = {"componentType": COMPONENT[dtype], "count": int(count), "type": TYPES[width]}
        if view is not None:
            acc["bufferView"] = view
            if offset:
                acc["byteOffset"] = offset
        if normalized:
            acc["normalized"] = True
        if sparse is not None:
            idx, values = np.asarray(sparse[0]), np.asarray(sparse[1], dtype)
            indices = {"bufferView": self.view(idx.tobytes()), "componentType": COMPONENT[idx.dtype.type]}
            acc["sparse"] = {"count": len(idx), "indices": indices,
                             "values": {"bufferView": self.view(np.ascontiguousarray(values).tobytes())}}
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def positions(self, array, **kw) -> int:
        array = np.asarray(array, np.float32)
        index = self.accessor(array, **kw)
        self.doc["accessors"][index].update(min=array.min(0).tolist(), max=array.max(0).tolist())
        return index

    # -- structure ------------------------------------------------------------------------------------------------
    def mesh(self, primitives: list[dict]) -> int:
        self.doc["meshes"].append({"primitives": primitives})
        return len(self.doc["meshes"]) - 1

    def node(self, **fields) -> int:
        self.doc["nodes"].append(fields)
        return len(self.doc["nodes"]) - 1

    def material(self, **fields) -> int:
        self.doc.setdefault("materials", []).append(fields)
        return len(self.doc["materials"]) - 1

    def sampler(self, **fields) -> int:
        self.doc.setdefault("samplers", []).append(fields)
        return len(self.doc["samplers"]) - 1

    def texture(self, rgba: np.ndarray, sampler: int | None = None) -> int:
        """A PNG image (embedded in a buffer view) of ``rgba`` (H, W, 4) uint8 and a texture using it."""
        from PIL import Image

        out = io.BytesIO()
        Image.fromarray(np.asarray(rgba, np.uint8), "RGBA").save(out, format="PNG")
        images = self.doc.setdefault("images", [])
        images.append({"bufferView": self.view(out.getvalue()), "mimeType": "image/png"})
        tex = {"source": len(images) - 1}
        if sampler is not None:
            tex["sampler"] = sampler
        self.doc.setdefault("textures", []).append(tex)
        return len(self.doc["textures"]) - 1

    def write(self, path: Path, roots: list[int] | None = None) -> Path:
        doc = dict(self.doc)
        doc["scene"] = 0
        doc["scenes"] = [{"nodes": roots if roots is not None else list(range(len(doc["nodes"])))}]
        return write_container(path, doc, bytes(self.data))


def write_container(path: Path, doc: dict, data: bytes) -> Path:
    """``doc`` with ``data`` as its one buffer: a binary .glb (JSON and BIN chunks, glTF 2.0 section 4.4), else a
    .gltf with the buffer as a base64 data URI. The container is written by hand, never by the loader under test."""
    doc = {**doc}
    data = data + b"\0" * (-len(data) % 4)
    if path.suffix == ".glb":
        doc["buffers"] = [{"byteLength": len(data)}]
        text = json.dumps(doc).encode()
        text += b" " * (-len(text) % 4)
        body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(data), 0x004E4942) + data
        path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
    else:
        doc["buffers"] = [{"byteLength": len(data),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
        path.write_text(json.dumps(doc))
    return path


def quad(x0: float, y0: float, x1: float, y1: float, z: float = 0.0) -> np.ndarray:
    """Four corners of an axis-aligned quad facing +z: (x0,y0) (x1,y0) (x1,y1) (x0,y1), counter-clockwise."""
    return np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], np.float32)


QUAD_INDICES = np.array([0, 1, 2, 0, 2, 3], np.uint16)
QUAD_UVS = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)  # glTF: v = 0 at the top of the image

# A camera at z = 2 looking down -z with fov_y = 90 degrees: a point (x, y, 0) lands at NDC (x / 2 / aspect, y / 2).
CAMERA = "[camera]\neye = [0, 0, 2]\ntarget = [0, 0, 0]\nfov_y = 90\nnear = 0.1\nfar = 10\n"


def pixel_of(x: float, y: float, size: tuple[int, int]) -> tuple[float, float]:
    """(column, row) in pixels of the point (x, y, 0) seen by CAMERA (row 0 at the top)."""
    w, h = size
    return (x / 2 / (w / h) + 1) / 2 * w, (1 - y / 2) / 2 * h


def scene_text(model: str, size: tuple[int, int], material: str | None = None, extra: str = "") -> str:
    """A scene of one model under CAMERA, msaa 1, LDR, black background; ``material``: an inline table or None
    (the model's own materials)."""
    text = f"{CAMERA}\n[render]\nsize = [{size[0]}, {size[1]}]\nmsaa = 1\nhdr = false\n"
    text += "clear_color = [0, 0, 0, 1]\n\n[[models]]\n" + f'path = "{model}"\n'
    if material is not None:
        text += f"material = {material}\n"
    return text + extra
