"""Small generated inputs for the reliability and fuzz tests: a glTF triangle, a scene around a model, the CLI.

Everything here is written by the test itself (never by the module under test), so each case states its input.
"""

from __future__ import annotations

import base64
import contextlib
import io
import json
from pathlib import Path

import numpy as np

from wgpurender.cli import main

# A triangle facing +z at the origin, seen by SCENE_CAMERA from z = 3: it covers the image centre.
TRIANGLE = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]], np.float32)
SCENE_CAMERA = 'eye = [0, 0, 3]\ntarget = [0, 0, 0]\nnear = 0.1\nfar = 20.0\n'


def triangle_gltf(normals: bool = True, node: dict | None = None) -> dict:
    """A one-triangle glTF document (positions, optional normals, indices in one data-URI buffer)."""
    blobs = [TRIANGLE.tobytes()]
    attributes = {"POSITION": 0}
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": TRIANGLE.min(0).tolist(), "max": TRIANGLE.max(0).tolist()}]
    if normals:
        blobs.append(np.tile(np.float32([0, 0, 1]), (3, 1)).tobytes())
        attributes["NORMAL"] = len(accessors)
        accessors.append({"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"})
    blobs.append(np.uint16([0, 1, 2, 0]).tobytes())  # padded to 4 bytes
    accessors.append({"bufferView": len(blobs) - 1, "componentType": 5123, "count": 3, "type": "SCALAR"})
    views, offset = [], 0
    for blob in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob)})
        offset += len(blob)
    data = b"".join(blobs)
    return {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, **(node or {})}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": len(accessors) - 1, "mode": 4}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }


def write_gltf(path: Path, doc: dict) -> Path:
    path.write_text(json.dumps(doc))
    return path


def scene_text(model: str | None = "model.gltf", camera: str = SCENE_CAMERA, extra: str = "",
               size: tuple[int, int] = (32, 24)) -> str:
    """A scene: the camera, one unlit white model (if any) and a small render size."""
    text = f"[camera]\n{camera}\n[render]\nsize = [{size[0]}, {size[1]}]\nmsaa = 1\nhdr = false\n"
    if model is not None:
        text += f'\n[[models]]\npath = "{model}"\nmaterial = {{ unlit = true }}\n'
    return text + extra


def run_cli(*argv: str) -> tuple[int, str, str]:
    """``wgpurender ARGV`` in-process: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()
