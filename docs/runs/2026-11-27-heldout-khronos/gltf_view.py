"""Where a glTF file's meshes lie, read from the file alone (accessor min/max, node transforms, instance
translations), and the camera that frames them. Independent of wgpurender's loader and of pygfx."""

from __future__ import annotations

import base64
import json
import math
import struct
from pathlib import Path

import numpy as np


def load(path: Path) -> tuple[dict, bytes | None]:
    """The JSON of a .gltf or .glb and, for a .glb, its BIN chunk."""
    data = path.read_bytes()
    if data[:4] != b"glTF":
        return json.loads(data), None
    length = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + length])
    rest = 20 + length
    binary = data[rest + 8: rest + 8 + struct.unpack_from("<I", data, rest)[0]] if rest < len(data) else None
    return doc, binary


def buffer_bytes(doc: dict, index: int, folder: Path, glb_bin: bytes | None) -> bytes:
    uri = doc["buffers"][index].get("uri")
    if uri is None:
        return glb_bin or b""
    if uri.startswith("data:"):
        return base64.b64decode(uri.split(",", 1)[1])
    return (folder / uri).read_bytes()


def float_vec3(doc: dict, accessor: int, folder: Path, glb_bin: bytes | None) -> np.ndarray:
    acc = doc["accessors"][accessor]
    view = doc["bufferViews"][acc["bufferView"]]
    data = buffer_bytes(doc, view["buffer"], folder, glb_bin)
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", 12)
    return np.array([np.frombuffer(data, "<f4", 3, start + i * stride) for i in range(acc["count"])], np.float64)


def local_matrix(node: dict) -> np.ndarray:
    if "matrix" in node:
        return np.array(node["matrix"], np.float64).reshape(4, 4).T
    x, y, z, w = node.get("rotation", (0, 0, 0, 1))
    rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = rot * np.array(node.get("scale", (1, 1, 1)))
    m[:3, 3] = node.get("translation", (0, 0, 0))
    return m


def mesh_boxes(path: Path) -> list[np.ndarray]:
    """World-space corner sets (8 x 3) of every drawn mesh (each instance of an instanced node) in the default
    scene, from the POSITION accessors' min/max."""
    doc, glb_bin = load(path)
    scenes = doc.get("scenes") or [{"nodes": list(range(len(doc.get("nodes", []))))}]
    boxes: list[np.ndarray] = []

    def walk(index: int, parent: np.ndarray) -> None:
        node = doc["nodes"][index]
        world = parent @ local_matrix(node)
        if "mesh" in node:
            offsets = [np.zeros(3)]
            inst = node.get("extensions", {}).get("EXT_mesh_gpu_instancing", {}).get("attributes", {})
            if "TRANSLATION" in inst:
                offsets = list(float_vec3(doc, inst["TRANSLATION"], path.parent, glb_bin))
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                acc = doc["accessors"][prim["attributes"]["POSITION"]]
                lo, hi = np.array(acc["min"], np.float64), np.array(acc["max"], np.float64)
                corners = np.array([[(lo, hi)[(k >> a) & 1][a] for a in range(3)] for k in range(8)])
                for off in offsets:
                    placed = corners + off
                    boxes.append((world @ np.c_[placed, np.ones(8)].T).T[:, :3])
        for child in node.get("children", []):
            walk(child, world)

    for root in scenes[doc.get("scene", 0)]["nodes"]:
        walk(root, np.eye(4))
    return boxes


def frame(boxes: list[np.ndarray], view=(0.0, 0.0, 1.0), fov_y: float = 45.0, zoom: float = 1.0) -> dict:
    """A camera that sees every box: target the centre, eye along ``view`` at the distance where the bounding
    sphere fits the vertical field of view."""
    points = np.concatenate(boxes)
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, radius = (lo + hi) / 2, max(float(np.linalg.norm(hi - lo)) / 2, 1e-3)
    direction = np.array(view, np.float64) / np.linalg.norm(view)
    dist = radius / math.sin(math.radians(fov_y) / 2) * 1.02 / zoom
    return {"eye": (centre + direction * dist).tolist(), "target": centre.tolist(), "fov_y": fov_y,
            "near": max(dist - radius * 1.5, dist * 0.01), "far": dist + radius * 1.5}


def project(point: np.ndarray, cam: dict, size: int) -> tuple[int, int]:
    """(column, row) of a world point in a square image of ``size`` seen by ``cam`` (up = +y)."""
    eye, target = np.array(cam["eye"]), np.array(cam["target"])
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, (0, 1, 0))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = point - eye
    depth = rel @ forward
    f = 1 / math.tan(math.radians(cam["fov_y"]) / 2)
    x, y = f * (rel @ right) / depth, f * (rel @ up) / depth
    return int((x + 1) / 2 * size), int((1 - y) / 2 * size)
