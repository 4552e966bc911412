"""Generators for issue 28's model classes: references out of a model's folder, declared counts and node graphs,
fields of the wrong JSON shape, files with nothing to draw, and primitives without normals. Each case runs through
the CLI (harness.run_case) and must be a clean render or one clean error; beyond that:

- a reference out of the model's folder must be an error naming it: its target is a FIFO where the OS allows, so
  a read hangs (counted as "hang"), and a render that read it counts as "escaped";
- a file whose scene places no triangle must be an error ("blank" otherwise);
- a process whose peak memory passes 2 GB counts as "memory";
- a cube without normals must render as the faceted cube within 8/255 ("wrong" otherwise);
- a scene naming a model outside its project folder, the assets and $WGPURENDER_ALLOW_PATHS must be an error
  ("escaped" otherwise), one inside them must render ("wrong" otherwise).
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
from harness import _count, check, render_argv, reset_folder, run_case
from hypothesis import given
from hypothesis import strategies as st
from peak_memory import peak_mib
from reliab_gen import SCENE_CAMERA, TRIANGLE, triangle_gltf, write_gltf
from strategies import fuzz_settings

MAX_RSS_MB = 2048


@pytest.fixture
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("models")


def _scene(folder, model: str, material: bool = True) -> os.PathLike:
    text = f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\nmsaa = 1\nhdr = false\n\n[[models]]\n"
    text += f'path = "{model}"\n' + ("material = { unlit = true }\n" if material else "")
    (folder / "model" / "scene.toml").write_text(text)
    return folder / "model" / "scene.toml"


def _memory(outcome: str, label: str) -> str:
    rss = peak_mib()  # this worker's own peak (ru_maxrss would add the parent's: tests/peak_memory.py)
    return _count("memory", label, f"peak RSS {rss} MiB") if rss > MAX_RSS_MB else outcome


# --- references out of the folder ---------------------------------------------------------------------------

OUT_KINDS = ("absolute", "file-url", "dotdot", "percent", "link-out", "link-dir-out", "proc", "device",
             "fifo-inside")
IN_KINDS = ("inside", "inside-dotdot", "data")
ROLES = ("buffer", "image", "mtllib", "map_Kd")


def _reference(folder, kind: str, name: str) -> str:
    """A reference of ``kind`` to a file called ``name``; files outside are FIFOs: opening one blocks."""
    outside = folder / "outside"
    if not (outside / name).exists():
        os.mkfifo(outside / name)
    return {
        "absolute": str(outside / name), "file-url": (outside / name).as_uri(), "dotdot": f"../outside/{name}",
        "percent": f"%2e%2e/outside/{name}", "link-out": f"l-{name}", "link-dir-out": f"sub/{name}",
        "proc": "/proc/self/environ", "device": "/dev/zero", "fifo-inside": f"f-{name}",
        "inside": f"real-{name}", "inside-dotdot": f"sub2/../real-{name}",
    }[kind]


def _prepare(folder, name: str, data: bytes) -> None:
    outside, inside = folder / "outside", folder / "model"
    (inside / f"real-{name}").write_bytes(data)
    (inside / f"l-{name}").symlink_to(outside / name)
    os.mkfifo(inside / f"f-{name}")
    if not (inside / "sub").exists():
        (inside / "sub").symlink_to(outside)
        (inside / "sub2").mkdir()


def _png() -> bytes:
    import io

    from PIL import Image

    out = io.BytesIO()
    Image.new("RGBA", (2, 2), (200, 100, 50, 255)).save(out, format="PNG")
    return out.getvalue()


def _model(folder, role: str, kind: str) -> tuple[str, str]:
    """Write the model whose ``role`` reference is of ``kind``; (the model's file name, the reference)."""
    import base64

    doc = triangle_gltf()
    if role in ("buffer", "image"):
        name, mime = ("x.bin", "application/octet-stream") if role == "buffer" else ("x.png", "image/png")
        raw = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1]) if role == "buffer" else _png()
        _prepare(folder, name, raw)
        ref = f"data:{mime};base64,{base64.b64encode(raw).decode()}" if kind == "data" else \
            _reference(folder, kind, name)
        if role == "buffer":
            doc["buffers"][0]["uri"] = ref
        else:
            doc.update(images=[{"uri": ref}], textures=[{"source": 0}],
                       materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}])
            doc["meshes"][0]["primitives"][0]["material"] = 0
        write_gltf(folder / "model" / "model.gltf", doc)
        return "model.gltf", ref
    png_name = "t.png"
    _prepare(folder, png_name, _png())
    _prepare(folder, "m.mtl", f"newmtl m\nmap_Kd real-{png_name}\n".encode())
    kind = "inside" if kind == "data" else kind
    if role == "mtllib":
        ref, lib = _reference(folder, kind, "m.mtl"), None
    else:
        ref = _reference(folder, kind, png_name)
        lib = "own.mtl"
        (folder / "model" / lib).write_text(f"newmtl m\nmap_Kd {ref}\n")
    v = "\n".join(f"v {x} {y} {z}" for x, y, z in TRIANGLE)
    (folder / "model" / "model.obj").write_text(f"mtllib {lib or ref}\n{v}\nvt 0 0\nvt 1 0\nvt 0.5 1\nusemtl m\n"
                                                "f 1/1 2/2 3/3\n")
    return "model.obj", ref


@fuzz_settings(ci=10, long=1500)
@given(role=st.sampled_from(ROLES), kind=st.sampled_from(OUT_KINDS + IN_KINDS))
def test_a_model_reads_only_its_folder(folder, role, kind):
    reset_folder(folder)
    for sub in ("model", "outside", "out"):
        (folder / sub).mkdir()
    model, ref = _model(folder, role, kind)
    output = folder / "out" / "out.png"
    label = f"reference {role} {kind} {ref[:60]!r}"
    scene = _scene(folder, model, material=False)
    outcome = run_case(render_argv(scene, output), output, None, label)
    literal = role in ("mtllib", "map_Kd") and kind == "percent"  # OBJ names are not percent-encoded: a folder
    if kind in OUT_KINDS and not literal and outcome == "render":  # named "%2e%2e" inside, not found
        outcome = _count("escaped", label, "rendered")
    check(outcome, f"{outcome}: {label}")


# --- declared counts and node graphs ------------------------------------------------------------------------

@st.composite
def graph_case(draw):
    return {"count": draw(st.sampled_from([3, 10**6, 10**9, 10**12, 2**53])),
            "placements": draw(st.sampled_from([1, 2, 300, 5000])),
            "chain": draw(st.sampled_from([1, 2, 1000, 20_000])),
            "repeat_root": draw(st.booleans()), "view": draw(st.booleans())}


def _graph_doc(case: dict) -> dict:
    """A chain of ``chain`` nodes whose last node has ``placements`` children, each placing one mesh whose
    POSITION declares ``count`` elements (with a bufferView too short for it, or none)."""
    doc = triangle_gltf()
    acc = doc["accessors"][0]
    acc["count"] = case["count"]
    if not case["view"]:
        acc.pop("bufferView")
    n = case["chain"]
    nodes = [{"children": [i + 1]} for i in range(n - 1)] + [{}]
    first = len(nodes)
    nodes[-1]["children"] = list(range(first, first + case["placements"]))
    nodes += [{"mesh": 0, "translation": [k * 0.01, 0, 0]} for k in range(case["placements"])]
    doc["nodes"], doc["scenes"] = nodes, [{"nodes": [0, 0] if case["repeat_root"] else [0]}]
    prim = doc["meshes"][0]["primitives"][0]
    prim.pop("indices")
    prim["attributes"] = {"POSITION": 0}
    return doc


@fuzz_settings(ci=6, long=800)
@given(case=graph_case())
def test_declared_counts_and_graphs_are_bounded(folder, case):
    reset_folder(folder)
    (folder / "model").mkdir()
    (folder / "out").mkdir()
    write_gltf(folder / "model" / "model.gltf", _graph_doc(case))
    output = folder / "out" / "out.png"
    label = f"graph {case}"
    outcome = _memory(run_case(render_argv(_scene(folder, "model.gltf"), output), output, None, label), label)
    check(outcome, f"{outcome}: {label}")


# --- fields of the wrong JSON shape -------------------------------------------------------------------------

EDGE_VALUES = [5, -1, 1.5, float("inf"), "x", "", [], [7], {}, {"a": 3}, None, True, 2**40, 6, 256]


def _paths(value, prefix=()):
    """Every JSON path in ``value`` (a dict/list tree)."""
    yield prefix
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _paths(v, prefix + (i,))


def _rich_doc() -> dict:
    doc = triangle_gltf()
    doc.update(extensionsUsed=["KHR_materials_emissive_strength"], extensions={},
               materials=[{"emissiveFactor": [0.1, 0, 0], "alphaCutoff": 0.5,
                           "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}}}])
    doc["meshes"][0]["primitives"][0]["material"] = 0
    doc["bufferViews"][0]["byteStride"] = 12
    doc["accessors"][0]["sparse"] = {"count": 1, "indices": {"bufferView": 2, "componentType": 5123},
                                     "values": {"bufferView": 0}}
    return doc


@fuzz_settings(ci=12, long=2000)
@given(data=st.data())
def test_a_field_of_the_wrong_shape_is_one_line(folder, data):
    reset_folder(folder)
    (folder / "model").mkdir()
    (folder / "out").mkdir()
    doc = _rich_doc()
    paths = [p for p in _paths(doc) if p and p != ("buffers", 0, "uri")]
    path = data.draw(st.sampled_from(paths))
    value = data.draw(st.sampled_from(EDGE_VALUES + ["DELETE"]))
    holder = doc
    for key in path[:-1]:
        holder = holder[key]
    if value == "DELETE":
        del holder[path[-1]]
    else:
        holder[path[-1]] = value
    write_gltf(folder / "model" / "model.gltf", doc)
    output = folder / "out" / "out.png"
    label = f"shape {'.'.join(map(str, path))} = {value!r}"
    outcome = run_case(render_argv(_scene(folder, "model.gltf", material=False), output), output, None, label)
    check(outcome, f"{outcome}: {label}")


# --- nothing to draw ----------------------------------------------------------------------------------------

@fuzz_settings(ci=6, long=600)
@given(modes=st.lists(st.integers(0, 6), min_size=1, max_size=3), placed=st.booleans(),
       material=st.booleans())
def test_nothing_to_draw_is_never_a_blank_image(folder, modes, placed, material):
    reset_folder(folder)
    (folder / "model").mkdir()
    (folder / "out").mkdir()
    doc = triangle_gltf()
    prim = doc["meshes"][0]["primitives"][0]
    doc["meshes"][0]["primitives"] = [{**prim, "mode": m} for m in modes]
    if not placed:
        doc["scenes"] = [{"nodes": []}]
    write_gltf(folder / "model" / "model.gltf", doc)
    output = folder / "out" / "out.png"
    label = f"modes {modes} placed={placed} material={material}"
    outcome = run_case(render_argv(_scene(folder, "model.gltf", material), output), output, None, label)
    if outcome == "render" and not (placed and set(modes) & {4, 5, 6}):
        outcome = _count("blank", label, "rendered a file with nothing to draw")
    check(outcome, f"{outcome}: {label}")


# --- flat normals -------------------------------------------------------------------------------------------

CORNERS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)], np.float32)
FACES = {(1, 0, 0): (4, 6, 7, 5), (-1, 0, 0): (0, 1, 3, 2), (0, 1, 0): (2, 3, 7, 6),
         (0, -1, 0): (0, 4, 5, 1), (0, 0, 1): (1, 5, 7, 3), (0, 0, -1): (0, 2, 6, 4)}


def _cube(faceted: bool, rotation: list[float]):
    from gltf_gen import GltfWriter

    g = GltfWriter()
    if faceted:
        pos = np.concatenate([CORNERS[list(c)] for c in FACES.values()])
        idx = np.array([[k, k + 1, k + 2, k, k + 2, k + 3] for k in range(0, 24, 4)], np.uint16).ravel()
        attrs = {"POSITION": g.positions(pos),
                 "NORMAL": g.accessor(np.repeat(np.array(list(FACES), np.float32), 4, axis=0))}
    else:
        idx = np.array([[a, b, c, a, c, d] for a, b, c, d in FACES.values()], np.uint16).ravel()
        attrs = {"POSITION": g.positions(CORNERS)}
    g.node(mesh=g.mesh([{"attributes": attrs, "indices": g.accessor(idx)}]), rotation=rotation)
    return g


@fuzz_settings(ci=2, long=200)
@given(q=st.lists(st.floats(-1, 1, allow_nan=False), min_size=4, max_size=4).filter(
    lambda q: np.linalg.norm(q) > 0.1))
def test_a_cube_without_normals_is_flat_shaded(folder, q):
    from PIL import Image

    reset_folder(folder)
    (folder / "model").mkdir()
    (folder / "out").mkdir()
    rotation = (np.array(q) / np.linalg.norm(q)).tolist()
    images = {}
    for faceted in (False, True):
        name = f"cube{int(faceted)}.glb"
        _cube(faceted, rotation).write(folder / "model" / name)
        (folder / "model" / "scene.toml").write_text(
            "[camera]\neye = [1.5, 1.2, 2.0]\ntarget = [0, 0, 0]\nfov_y = 45\n\n[render]\nsize = [40, 30]\n"
            "msaa = 1\nhdr = false\n\n[[lights]]\ntype = \"directional\"\ndirection = [-0.4, -1, -0.7]\n"
            f"intensity = 0.8\n\n[[models]]\npath = \"{name}\"\nmaterial = {{ albedo_color = [0.5, 0.5, 0.5, 1] }}\n")
        output = folder / "out" / f"{name}.png"
        outcome = run_case(render_argv(folder / "model" / "scene.toml", output), output, None, f"cube {q}")
        check(outcome, f"{outcome}: cube {q}")
        if outcome != "render":
            return
        with Image.open(output) as im:
            images[faceted] = np.asarray(im.convert("RGB")).astype(int)
    diff = int(np.abs(images[False] - images[True]).max())
    outcome = "render" if diff <= 8 else _count("wrong", f"cube {q}", f"max diff {diff}")
    check(outcome, f"{outcome}: flat cube differs by {diff}")


def test_the_rich_document_is_valid(folder):
    """The shape generator's base file renders: every mutation starts from a good file."""
    reset_folder(folder)
    (folder / "model").mkdir()
    (folder / "out").mkdir()
    write_gltf(folder / "model" / "model.gltf", _rich_doc())
    output = folder / "out" / "out.png"
    assert run_case(render_argv(_scene(folder, "model.gltf", material=False), output), output, None, "rich") \
        == "render"
    assert json.loads((folder / "model" / "model.gltf").read_text())["accessors"][0]["sparse"]["count"] == 1


# --- a scene's own paths ------------------------------------------------------------------------------------

SCENE_KINDS = {  # kind -> (where the model is, how the scene names it, may the scene read it)
    "same-folder": ("project/scenes/m.gltf", "m.gltf", True),
    "project": ("project/models/m.gltf", "../models/m.gltf", True),
    "above-project": ("m.gltf", "../../m.gltf", False),
    "absolute-outside": ("outside/m.gltf", "{folder}/outside/m.gltf", False),
    "link-out": ("outside/m.gltf", "link.gltf", False),
    "allowed": ("outside/m.gltf", "{folder}/outside/m.gltf", True),
    "assets": (None, "{assets}/models/brick_torus.glb", True),
}


@fuzz_settings(ci=7, long=300)
@given(kind=st.sampled_from(sorted(SCENE_KINDS)), flat=st.booleans())
def test_a_scene_reads_only_its_project(folder, kind, flat):
    """``flat``: the scene sits in project/ itself (no scenes/ folder), so ../models is outside too."""
    from strategies import ASSETS

    reset_folder(folder)
    where, named, allowed = SCENE_KINDS[kind]
    scene_dir = folder / "project" / ("" if flat else "scenes")
    for sub in (scene_dir, folder / "project" / "models", folder / "outside", folder / "out"):
        sub.mkdir(parents=True, exist_ok=True)
    if where is not None:
        target = folder / where.replace("project/scenes", str(scene_dir.relative_to(folder)))
        write_gltf(target, triangle_gltf())
    if kind == "link-out":
        (scene_dir / "link.gltf").symlink_to(folder / "outside" / "m.gltf")
    if flat and kind == "project":
        allowed = False  # project/../models is beside the project, not in it
    named = named.format(folder=folder, assets=ASSETS)
    (scene_dir / "s.toml").write_text(f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\nmsaa = 1\n\n"
                                      f'[[models]]\npath = "{named}"\nmaterial = {{ unlit = true }}\n')
    os.environ.pop("WGPURENDER_ALLOW_PATHS", None)
    if kind == "allowed":
        os.environ["WGPURENDER_ALLOW_PATHS"] = str(folder / "outside")
    output = folder / "out" / "out.png"
    label = f"scene path {kind} flat={flat}"
    try:
        outcome = run_case(render_argv(scene_dir / "s.toml", output), output, None, label)
    finally:
        os.environ.pop("WGPURENDER_ALLOW_PATHS", None)
    if outcome == "render" and not allowed:
        outcome = _count("escaped", label, "rendered a model outside the scene's folders")
    elif outcome == "error" and allowed:
        outcome = _count("wrong", label, "refused an allowed path")
    check(outcome, f"{outcome}: {label}")
