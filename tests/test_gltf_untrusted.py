"""Issue 28, items 6, 7, 10 and 11: a glTF file is untrusted input. Each case is built here at run time (by
tests/gltf_gen.py, never by the loader under test) and must end as the right image, or one line with exit 2:

- 6: a primitive without NORMAL is flat-shaded (glTF 2.0, 3.7.2.1), as the same cube with per-face normals;
- 7: a file with nothing to draw (points or lines only, a scene that places no mesh) is refused, not blank;
- 10: declared counts are bounded before anything is allocated; the node graph is checked in linear time;
- 11: a field of the wrong JSON type or value is one line naming its JSON path, never a traceback.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from gltf_gen import GltfWriter, quad, write_container
from helpers import one_line_refusal
from PIL import Image
from reliab_gen import run_cli

SIZE = (64, 48)
CUBE_CAMERA = "[camera]\neye = [1.5, 1.2, 2.0]\ntarget = [0, 0, 0]\nfov_y = 45\nnear = 0.1\nfar = 20\n"
LIGHT = '[[lights]]\ntype = "directional"\ndirection = [-0.4, -1.0, -0.7]\ncolor = [1, 1, 1]\nintensity = 0.8\n'



GREY = "{ albedo_color = [0.5, 0.5, 0.5, 1], roughness = 0.9 }"


def _scene(folder: Path, model: str, material: str | None = GREY) -> Path:
    text = CUBE_CAMERA + f"\n[render]\nsize = [{SIZE[0]}, {SIZE[1]}]\nmsaa = 1\nhdr = false\n"
    text += "clear_color = [0, 0, 0, 1]\n\n" + LIGHT + f'\n[[models]]\npath = "{model}"\n'
    if material is not None:
        text += f"material = {material}\n"
    scene = folder / f"{Path(model).stem}.toml"
    scene.write_text(text)
    return scene


def _render(scene: Path) -> np.ndarray:
    out = scene.with_suffix(".png")
    code, _, err = run_cli("render", scene, "-o", out)
    assert code == 0, err
    with Image.open(out) as im:
        return np.asarray(im.convert("RGB")).astype(int)


# --- 6: flat normals ----------------------------------------------------------------------------------------

CORNERS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)], np.float32)
FACES = {  # outward normal -> its 4 corners (indices into CORNERS), counter-clockwise seen from outside
    (1, 0, 0): (4, 6, 7, 5), (-1, 0, 0): (0, 1, 3, 2), (0, 1, 0): (2, 3, 7, 6),
    (0, -1, 0): (0, 4, 5, 1), (0, 0, 1): (1, 5, 7, 3), (0, 0, -1): (0, 2, 6, 4),
}


def _shared_cube(g: GltfWriter) -> dict:
    """8 shared corners, 36 indices, no NORMAL: the file asks for flat normals."""
    indices = np.array([[a, b, c, a, c, d] for a, b, c, d in FACES.values()], np.uint16).ravel()
    return {"attributes": {"POSITION": g.positions(CORNERS)}, "indices": g.accessor(indices)}


def _faceted_cube(g: GltfWriter) -> dict:
    """24 vertices, each face its own 4 with the face's normal written out: the reference."""
    positions = np.concatenate([CORNERS[list(c)] for c in FACES.values()])
    normals = np.repeat(np.array(list(FACES), np.float32), 4, axis=0)
    indices = np.array([[k, k + 1, k + 2, k, k + 2, k + 3] for k in range(0, 24, 4)], np.uint16).ravel()
    return {"attributes": {"POSITION": g.positions(positions), "NORMAL": g.accessor(normals)},
            "indices": g.accessor(indices)}


def test_faces_are_counter_clockwise_from_outside():
    """The test's own cube: each face's corners turn counter-clockwise around its outward normal."""
    for normal, (a, b, c, _) in FACES.items():
        n = np.cross(CORNERS[b] - CORNERS[a], CORNERS[c] - CORNERS[a])
        np.testing.assert_allclose(n / np.linalg.norm(n), normal, atol=1e-6)


def test_a_cube_without_normals_renders_as_the_cube_with_face_normals(tmp_path):
    shapes = {}
    for name, build in (("shared", _shared_cube), ("faceted", _faceted_cube)):
        g = GltfWriter()
        g.node(mesh=g.mesh([build(g)]))
        g.write(tmp_path / f"{name}.glb")
        shapes[name] = _render(_scene(tmp_path, f"{name}.glb"))
    shared, faceted = shapes["shared"], shapes["faceted"]
    lit = faceted.max(axis=2) > 0
    assert lit.mean() > 0.15  # the cube covers the image's middle
    assert len(np.unique(faceted[lit].sum(axis=1) // 24)) >= 3  # three faces seen, each its own brightness
    assert np.abs(shared - faceted).max() <= 8, np.abs(shared - faceted).max()


def test_flat_normals_split_each_triangle_and_ignore_the_files_tangents(tmp_path):
    """Loader level: 12 triangles -> 36 vertices, each with its face's normal; a TANGENT without NORMAL is
    ignored (3.7.2.1), so tangents are generated."""
    from wgpurender.core.models.mesh import load_mesh

    g = GltfWriter()
    prim = _shared_cube(g)
    prim["attributes"]["TANGENT"] = g.accessor(np.tile(np.float32([0, 0, 1, 1]), (8, 1)))
    g.node(mesh=g.mesh([prim]))
    mesh = load_mesh(g.write(tmp_path / "cube.gltf"))
    assert mesh.triangle_count == 12 and mesh.vertex_count >= 36
    p = mesh.positions[mesh.indices.astype(int)]
    face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    for k in range(3):
        np.testing.assert_allclose(mesh.normals[mesh.indices[:, k].astype(int)], face, atol=1e-6)
    assert mesh.tangents_source == "generated"


# --- 7: nothing to draw -------------------------------------------------------------------------------------

def _nothing_file(g: GltfWriter, kind: str) -> list[int] | None:
    """Fill ``g`` with a file that has nothing to draw; returns the scene's roots."""
    positions = g.positions(quad(-1, -1, 1, 1))
    if kind in ("points", "lines", "line-strip"):
        mode = {"points": 0, "lines": 1, "line-strip": 3}[kind]
        g.node(mesh=g.mesh([{"attributes": {"POSITION": positions}, "mode": mode}]))
        return None
    g.node(mesh=g.mesh([{"attributes": {"POSITION": positions}}]))  # a good triangle mesh ...
    if kind == "no-roots":
        return []  # ... that the scene does not place
    g.doc["nodes"][0].pop("mesh")  # ... that no node places
    return None


@pytest.mark.parametrize("material", [None, "{ unlit = true }"])
@pytest.mark.parametrize("kind", ["points", "lines", "line-strip", "no-roots", "no-mesh-node"])
def test_a_file_with_nothing_to_draw_is_refused(tmp_path, kind, material):
    g = GltfWriter()
    g.write(tmp_path / "model.gltf", roots=_nothing_file(g, kind))
    code, _, err = run_cli("render", _scene(tmp_path, "model.gltf", material), "-o", tmp_path / "out.png")
    why = "places no mesh" if kind.startswith("no-") else "only"
    one_line_refusal(code, err, "model.gltf", "nothing to draw", why)
    assert not (tmp_path / "out.png").exists()


def test_triangles_beside_lines_still_draw(tmp_path):
    g = GltfWriter()
    positions = g.positions(quad(-1, -1, 1, 1))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": positions}, "mode": 1}, {"attributes": {"POSITION": positions},
                                                                              "mode": 6}]))
    g.write(tmp_path / "model.gltf")
    assert _render(_scene(tmp_path, "model.gltf", None)).max() > 0


# --- 10: bounded before allocation --------------------------------------------------------------------------

# The child reports its own peak: VmHWM of /proc/self/status is the high-water mark of the mm that exec gave it.
# getrusage(RUSAGE_SELF).ru_maxrss is not: on Linux exec folds the replaced mm's peak into it, and that mm is
# the forked (or vfork-shared) parent's, so under a grown pytest-xdist worker it read 447-453 MiB for a child
# that peaked near 53.
PROBE = textwrap.dedent("""
    import sys
    from wgpurender.core.errors import UserError
    from wgpurender.core.models.mesh import load_mesh
    from wgpurender.core.scene.gltf_materials import model_materials
    try:
        model_materials(__import__("pathlib").Path(sys.argv[1]), "m")
        load_mesh(sys.argv[1], generate_tangents=False)
        result = "loaded"
    except UserError as err:
        result = "error: " + str(err)
    with open("/proc/self/status") as status:
        hwm_kb = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
    print("PEAK_RSS_MIB", hwm_kb // 1024)
    print(result)
""")


def _probe(path: Path) -> tuple[int, str]:
    """(peak RSS in MiB, "loaded" or "error: MESSAGE") of loading ``path`` in a fresh process; a run past the
    generous bound is a hang (quadratic or unbounded work), not a slow machine."""
    run = subprocess.run([sys.executable, "-c", PROBE, str(path)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    head, _, result = run.stdout.rpartition("PEAK_RSS_MIB ")[2].partition("\n")
    assert head.isdigit(), run.stdout[-2000:]
    return int(head), result.strip()


BASE_RSS_MB = 400  # a few hundred MB (issue 28); the loader refusing these peaked at 53 MiB here (2026-11-27)


@pytest.mark.parametrize("count", [10**9, 10**12])
def test_an_accessor_without_a_buffer_view_declaring_huge_counts_is_refused_from_the_count(tmp_path, count):
    g = GltfWriter()
    g.doc["accessors"].append({"componentType": 5126, "count": count, "type": "VEC3"})
    g.node(mesh=g.mesh([{"attributes": {"POSITION": 0}}]))
    rss, result = _probe(g.write(tmp_path / "huge.gltf"))
    assert result.startswith("error: ") and f"{count:,}" in result and "WGPURENDER_MAX_MODEL_VERTICES" in result
    assert rss < BASE_RSS_MB, rss


@pytest.mark.parametrize("by", ["nodes", "primitives"])
def test_instancing_past_the_vertex_budget_is_refused(tmp_path, by):
    """40,000 declared vertices placed 300 times (by 300 nodes, or as 300 primitives of one mesh naming the same
    accessor): 12 M vertices, over the 8 M budget."""
    g = GltfWriter()
    g.doc["accessors"].append({"componentType": 5126, "count": 40_000, "type": "VEC3"})
    copies = 300 if by == "primitives" else 1
    mesh = g.mesh([{"attributes": {"POSITION": 0}}] * copies)
    for k in range(300 // copies):
        g.node(mesh=mesh, translation=[k, 0, 0])
    rss, result = _probe(g.write(tmp_path / "many.glb"))
    assert result.startswith("error: ") and "12,000,000" in result, result
    assert rss < BASE_RSS_MB, rss


def test_the_vertex_budget_is_an_environment_setting(tmp_path, monkeypatch):
    from wgpurender.core.errors import UserError
    from wgpurender.core.models.gltf_io import read_document

    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(0, 0, 1, 1))}}]))
    path = g.write(tmp_path / "quad.gltf")
    monkeypatch.setenv("WGPURENDER_MAX_MODEL_VERTICES", "4")
    read_document(path)  # 4 vertices: at the limit
    monkeypatch.setenv("WGPURENDER_MAX_MODEL_VERTICES", "3")
    with pytest.raises(UserError, match="declares 4 vertices"):
        read_document(path)


def _chain(n: int) -> dict:
    """n nodes, each the child of the one before, the last placing a one-triangle mesh (no buffers needed)."""
    nodes = [{"children": [i + 1]} for i in range(n - 1)] + [{"mesh": 0}]
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3"}]}


def test_a_20000_node_chain_is_checked_in_linear_time(tmp_path):
    path = tmp_path / "chain.gltf"
    path.write_text(json.dumps(_chain(20_000)))
    assert 400_000 < path.stat().st_size < 600_000  # the 449 KB case
    rss, result = _probe(path)
    assert result == "loaded", result  # the leaf's mesh is reached through 20,000 levels
    assert rss < BASE_RSS_MB, rss


def _traced_lines(path: Path) -> int:
    """Python lines run in gltf_rules.py and gltf_geometry.py while the file is read and its nodes placed: a
    count of work that does not depend on the machine's speed."""
    from wgpurender.core.models.gltf_geometry import placed_meshes
    from wgpurender.core.models.gltf_io import read_document

    lines = 0

    def local(frame, event, arg):
        nonlocal lines
        lines += event == "line"
        return local

    def tracer(frame, event, arg):
        return local if frame.f_code.co_filename.endswith(("gltf_rules.py", "gltf_geometry.py")) else None

    sys.settrace(tracer)
    try:
        placed_meshes(read_document(path))
    finally:
        sys.settrace(None)
    return lines


def test_the_node_graph_work_grows_linearly_with_the_chain(tmp_path):
    """Doubling a chain's length doubles the checks' work (a walk from every node up to the root made it 4x)."""
    work = {}
    for n in (1000, 2000):
        (tmp_path / f"c{n}.gltf").write_text(json.dumps(_chain(n)))
        work[n] = _traced_lines(tmp_path / f"c{n}.gltf")
    assert work[2000] < 2.5 * work[1000], work


def test_a_root_listed_twice_or_a_child_listed_as_a_root_is_refused(tmp_path):
    from wgpurender.core.errors import UserError
    from wgpurender.core.models.gltf_io import read_document

    for roots, why in (([0, 0], "listed twice"), ([0, 5], "child of another node")):
        doc = _chain(10)
        doc["scenes"][0]["nodes"] = roots
        (tmp_path / "c.gltf").write_text(json.dumps(doc))
        with pytest.raises(UserError, match=f"scenes\\[0\\].nodes\\[1\\] = {roots[1]} .*{why}"):
            read_document(tmp_path / "c.gltf")


# --- 11: one line naming the JSON path ----------------------------------------------------------------------

def _rich() -> GltfWriter:
    """A file using every field the cases below break: a textured material with emissive strength, a sparse
    accessor, a strided view. It renders (test_the_rich_file_renders)."""
    g = GltfWriter()
    rgba = np.full((2, 2, 4), 200, np.uint8)
    tex = g.texture(rgba)
    mat = g.material(pbrMetallicRoughness={"baseColorTexture": {"index": tex}}, emissiveFactor=[0.1, 0, 0],
                     extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}})
    pos = quad(-1, -1, 1, 1)
    interleaved = np.concatenate([pos, np.tile(np.float32([0, 0, 1]), (4, 1))], axis=1)
    view = g.view(interleaved.tobytes(), stride=24)
    position = g.accessor(pos, view=view)
    g.doc["accessors"][position].update(min=pos.min(0).tolist(), max=pos.max(0).tolist())
    normal = g.accessor(np.tile(np.float32([0, 0, 1]), (4, 1)), view=view, offset=12)
    uv = g.accessor(np.float32([[0, 1], [1, 1], [1, 0], [0, 0]]),
                    sparse=(np.array([2], np.uint8), np.float32([[0.9, 0.1]])))
    indices = g.accessor(np.array([0, 1, 2, 0, 2, 3], np.uint16))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv},
                         "indices": indices, "material": mat}]))
    g.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    return g


def _set(doc: dict, path: str, value) -> None:
    keys = [int(k) if k.isdigit() else k for k in path.replace("[", ".").replace("]", "").split(".")]
    holder = doc
    for k in keys[:-1]:
        holder = holder[k]
    if value is DELETE:
        del holder[keys[-1]]
    else:
        holder[keys[-1]] = value


class _Delete:
    def __repr__(self) -> str:
        return "DELETE"


DELETE = _Delete()  # a field to remove
UV_SPARSE = "accessors.2.sparse"  # the TEXCOORD_0 accessor of _rich (0 and 1: position and normal, interleaved)
BAD_FIELDS = [  # (where, value, what the message must name)
    ("extensions", 5, "$.extensions must be an object"),
    ("extensions", {"EXT_x": 3}, "$.extensions.EXT_x must be an object"),
    ("extensionsUsed", "KHR_materials_emissive_strength", "$.extensionsUsed must be an array"),
    ("extensionsUsed", [7], "$.extensionsUsed[0] must be a string"),
    ("extensionsRequired", {"a": 1}, "$.extensionsRequired must be an array"),
    ("materials.0.extensions", [], "$.materials[0].extensions must be an object"),
    ("materials.0.extensions.KHR_materials_emissive_strength", 2.0,
     "$.materials[0].extensions.KHR_materials_emissive_strength must be an object"),
    ("materials.0.extensions.KHR_materials_emissive_strength.emissiveStrength", "2",
     "emissiveStrength must be a finite number"),
    ("materials.0.extensions.KHR_materials_emissive_strength.emissiveStrength", -1,
     "emissiveStrength must not be negative"),
    ("materials.0.pbrMetallicRoughness.baseColorTexture.extensions", 3,
     "$.materials[0].pbrMetallicRoughness.baseColorTexture.extensions must be an object"),
    ("materials.0.alphaCutoff", -0.5, "$.materials[0].alphaCutoff must not be negative"),
    ("images.0.bufferView", DELETE, "$.images[0] needs exactly one of 'uri' and 'bufferView', got neither"),
    ("images.0.uri", "a.png", "$.images[0] needs exactly one of 'uri' and 'bufferView', got both"),
    (UV_SPARSE + ".count", 1.5, ".sparse.count must be a non-negative integer"),
    (UV_SPARSE + ".count", float("inf"), ".sparse.count must be a non-negative integer"),
    (UV_SPARSE + ".count", -1, ".sparse.count must be a non-negative integer"),
    (UV_SPARSE + ".count", 0, ".sparse.count must be in 1..4"),
    (UV_SPARSE + ".count", 5, ".sparse.count must be in 1..4"),
    (UV_SPARSE + ".indices.byteOffset", -4, ".sparse.indices.byteOffset must be a non-negative integer"),
    (UV_SPARSE + ".indices.componentType", 5126, ".sparse.indices.componentType must be 5121, 5123 or 5125"),
    (UV_SPARSE + ".indices.bufferView", 99, ".sparse.indices.bufferView = 99 points past the end"),
    (UV_SPARSE + ".values", DELETE, ".sparse needs the property 'values'"),
    ("bufferViews.1.byteStride", 6, "$.bufferViews[1].byteStride must be a multiple of 4 in 4..252, got 6"),
    ("bufferViews.1.byteStride", 256, "$.bufferViews[1].byteStride must be a multiple of 4 in 4..252, got 256"),
    ("bufferViews.1.byteStride", 2, "$.bufferViews[1].byteStride must be a multiple of 4 in 4..252, got 2"),
    ("bufferViews.1.byteStride", 8, "$.bufferViews[1].byteStride 8 is below the 12-byte element"),
    ("bufferViews.1.byteStride", 1e400, "$.bufferViews[1].byteStride must be a non-negative integer"),
]


def test_the_rich_file_renders(tmp_path):
    _rich().write(tmp_path / "rich.gltf")
    assert _render(_scene(tmp_path, "rich.gltf", None)).max() > 0


@pytest.mark.parametrize(("where", "value", "needle"), BAD_FIELDS, ids=[f"{w}={v!r}" for w, v, _ in BAD_FIELDS])
def test_a_field_of_the_wrong_type_or_value_is_one_line_naming_its_json_path(tmp_path, where, value, needle):
    g = _rich()
    doc = {**g.doc, "scene": 0, "scenes": [{"nodes": [0]}]}
    _set(doc, where, value)
    write_container(tmp_path / "bad.gltf", doc, bytes(g.data))
    code, _, err = run_cli("render", _scene(tmp_path, "bad.gltf", None), "-o", tmp_path / "out.png")
    one_line_refusal(code, err, "bad.gltf", needle)
    assert not (tmp_path / "out.png").exists()
