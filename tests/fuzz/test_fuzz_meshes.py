"""Fuzzed OBJ, glTF, GLB, PLY and STL files rendered through a fixed scene: a clean render or one clean error."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from harness import check, render_argv, reset_folder, run_case
from hypothesis import given
from hypothesis import strategies as st
from reliab_gen import scene_text, triangle_gltf
from strategies import ASSETS, EDGE_NUMBERS, fuzz_settings, mutated_bytes, mutated_json, mutated_text, number_text


@pytest.fixture
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("mesh")


def _case(folder, name: str, data: bytes, label: str) -> None:
    reset_folder(folder)
    (folder / "out").mkdir()
    (folder / name).write_bytes(data)
    scene = folder / "scene.toml"
    scene.write_text(scene_text(name))
    output = folder / "out" / "out.png"
    outcome = run_case(render_argv(scene, output), output, scene, label)
    check(outcome, f"{outcome}: {label}")


def _box(file_type: str) -> bytes:
    import trimesh

    return trimesh.creation.box().export(file_type=file_type)


@st.composite
def obj_text(draw) -> str:
    """OBJ records with edge numbers, too few or too many coordinates, and faces with any indices."""
    lines = []
    for _ in range(draw(st.integers(1, 8))):
        kind = draw(st.sampled_from(["v", "v", "v", "vt", "vn", "f", "f", "mtllib", "usemtl", "o", "#"]))
        if kind in ("v", "vt", "vn"):
            count = draw(st.integers(0, 4))
            lines.append(" ".join([kind] + [draw(number_text) for _ in range(count)]))
        elif kind == "f":
            corner = st.one_of(st.integers(-4, 9).map(str), st.sampled_from(["1/1", "2/2/2", "1//1", "x", "0"]))
            lines.append("f " + " ".join(draw(corner) for _ in range(draw(st.integers(1, 5)))))
        else:
            lines.append(f"{kind} {draw(st.sampled_from(['a.mtl', 'm', '', 'x y']))}")
    return "\n".join(["v -1 -1 0", "v 1 -1 0", "v 0 1 0"] * draw(st.integers(0, 1)) + lines) + "\n"


@fuzz_settings(ci=8, long=900)
@given(text=obj_text())
def test_generated_obj(folder, text):
    _case(folder, "model.obj", text.encode(), f"generated obj\n{text}")


@fuzz_settings(ci=5, long=600)
@given(data=st.data())
def test_mutated_obj(folder, data):
    text = data.draw(mutated_text((ASSETS / "models" / "brick_cube.obj").read_text()))
    _case(folder, "model.obj", text.encode(), "mutated brick_cube.obj")


@fuzz_settings(ci=8, long=1000)
@given(data=st.data())
def test_mutated_gltf_json(folder, data):
    doc = triangle_gltf(normals=data.draw(st.booleans()))
    doc = data.draw(mutated_json(doc))
    _case(folder, "model.gltf", json.dumps(doc).encode(), f"gltf {json.dumps(doc)[:1500]}")


@fuzz_settings(ci=6, long=800)
@given(data=st.data())
def test_mutated_glb(folder, data):
    source = data.draw(st.sampled_from(["mirrored_quad.glb", "brick_torus.glb"]))
    raw = (ASSETS / "models" / source).read_bytes()
    if data.draw(st.booleans()):  # edit the JSON chunk as JSON, keeping the container valid
        raw = _with_json(raw, data.draw(mutated_json(_json_of(raw))))
    else:
        raw = data.draw(mutated_bytes(raw))
    _case(folder, "model.glb", raw, f"mutated {source}")


def _json_of(glb: bytes) -> dict:
    length = int.from_bytes(glb[12:16], "little")
    return json.loads(glb[20:20 + length])


def _with_json(glb: bytes, doc: dict) -> bytes:
    length = int.from_bytes(glb[12:16], "little")
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    rest = glb[20 + length:]
    body = len(text).to_bytes(4, "little") + b"JSON" + text + rest
    return glb[:8] + (12 + len(body)).to_bytes(4, "little") + body


@st.composite
def ply_text(draw) -> str:
    vertices = draw(st.integers(0, 5))
    faces = draw(st.integers(0, 3))
    head = ["ply", "format ascii 1.0", f"element vertex {draw(st.sampled_from([vertices, vertices + 1, 99]))}",
            "property float x", "property float y", "property float z",
            f"element face {faces}", "property list uchar int vertex_indices", "end_header"]
    body = [" ".join(draw(number_text) for _ in range(3)) for _ in range(vertices)]
    body += [f"3 {draw(st.integers(-1, 6))} {draw(st.integers(0, 6))} {draw(st.integers(0, 6))}" for _ in range(faces)]
    return "\n".join(head + body) + "\n"


@fuzz_settings(ci=5, long=700)
@given(data=st.data())
def test_ply(folder, data):
    if data.draw(st.booleans()):
        raw = data.draw(ply_text()).encode()
    else:
        raw = data.draw(mutated_bytes(_box("ply")))
    _case(folder, "model.ply", raw, "ply")


@fuzz_settings(ci=5, long=600)
@given(data=st.data())
def test_stl(folder, data):
    if data.draw(st.booleans()):
        raw = data.draw(mutated_bytes(_box("stl")))
    else:
        values = [data.draw(st.sampled_from(EDGE_NUMBERS + ["0.5", "1", "-1"])) for _ in range(9)]
        raw = ("solid t\nfacet normal 0 0 1\nouter loop\n" + "".join(
            f"vertex {' '.join(values[i:i + 3])}\n" for i in range(0, 9, 3)) + "endloop\nendfacet\nendsolid t\n"
        ).encode()
    _case(folder, "model.stl", raw, "stl")


def test_box_exports_are_meshes():
    """The generators' seeds are what they claim (so a mutation starts from a valid file)."""
    import trimesh

    for kind in ("ply", "stl"):
        mesh = trimesh.load(io.BytesIO(_box(kind)), file_type=kind)
        assert len(mesh.faces) == 12 and np.allclose(np.abs(mesh.vertices), 0.5)
