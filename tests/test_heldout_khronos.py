"""Fixes found by the held-out Khronos run (docs/runs/2026-11-27-heldout-khronos): each case is built here at run
time after the sample that showed it, with expectations from the numbers written into the file.

- Avocado (glTF-Quantized) was refused as "singular": its node scale 3.839089e-6 (positions quantized to uint16)
  gives det 5.7e-17, under the old absolute bound 1e-12. A transform is flat when its 3x3 maps the unit cube to a
  sliver of the box its column lengths span (core/view/transforms.flat), whatever the model's units.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, pixel_of
from test_gltf_render import PATHS, SIZE, UNLIT, assert_colour, render, write_scene

from wgpurender.core.errors import UserError
from wgpurender.core.models.mesh import load_mesh
from wgpurender.core.view import transforms

AVOCADO_SCALE = 3.839089e-06  # the node scale of Khronos' Avocado/glTF-Quantized
COLOUR = (0.8, 0.3, 0.1)
X0, Y0, X1, Y1 = -1.2, -1.0, 1.4, 1.3  # the quad's world extent after both scales


def _quantized_quad(tmp_path, node_scale: float, units: float, axes=(1.0, 1.0, 1.0)) -> str:
    """An int16 quad whose integers times ``units`` are (X0..X1, Y0..Y1), placed by a node scale ``node_scale``;
    the scene's model transform scales by ``units / node_scale`` so the world extent stays the same."""
    g = GltfWriter()
    ints = np.round(np.array([[X0, Y0, 0], [X1, Y0, 0], [X1, Y1, 0], [X0, Y1, 0]]) / units).astype(np.int16)
    pos = g.accessor(ints)
    g.doc["accessors"][pos].update(min=ints.min(0).tolist(), max=ints.max(0).tolist())
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [*COLOUR, 1]}, **UNLIT)
    g.node(mesh=g.mesh([{"attributes": {"POSITION": pos}, "indices": g.accessor(QUAD_INDICES), "material": mat}]),
           scale=[node_scale * a for a in axes])
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_mesh_quantization", "KHR_materials_unlit"]
    g.write(tmp_path / "q.glb")
    return f"[models.transform]\nscale = {units / node_scale!r}\n"


@pytest.mark.parametrize("which", PATHS)
def test_a_micrometre_node_scale_is_drawn_not_refused(ctx, tmp_path, which):
    """Avocado's case: the quad's edges land where integer x node scale x scene scale puts them, on both paths."""
    extra = _quantized_quad(tmp_path, AVOCADO_SCALE, units=1e-4)
    assert abs(np.linalg.det(np.eye(3) * AVOCADO_SCALE)) < 1e-12  # the old bound refused this
    image = render(ctx, write_scene(tmp_path, "q.glb", extra=extra), which)
    covered = image[..., :3].max(axis=2) > 20
    for x, y, inside in ((X0 + 0.05, 0, True), (X0 - 0.08, 0, False), (X1 - 0.05, 0, True), (X1 + 0.08, 0, False),
                         (0, Y1 - 0.05, True), (0, Y1 + 0.08, False), (0, Y0 + 0.05, True), (0, Y0 - 0.08, False)):
        col, row = pixel_of(x, y, SIZE)
        assert covered[int(row), int(col)] == inside, (which, x, y, inside)
    assert_colour(image, 0.1, 0.1, COLOUR, f"{which} unlit colour")


def test_a_node_that_flattens_an_axis_is_still_refused(tmp_path):
    """Scale 0 on one axis: one line naming the node, whatever the other axes' size."""
    _quantized_quad(tmp_path, AVOCADO_SCALE, units=1e-4, axes=(1.0, 1.0, 0.0))
    path = tmp_path / "q.glb"
    with pytest.raises(UserError, match="singular transform"):
        load_mesh(path)


def _rotation(degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


@pytest.mark.parametrize("matrix, flat", [
    (np.eye(3) * AVOCADO_SCALE, False),                         # tiny uniform scale: a whole cube, small
    (np.diag([1e-6, 1.0, 1e6]), False),                         # extreme non-uniform scale: still a box
    (_rotation(30) @ np.diag([2.0, 0.5, 3.0]), False),          # rotation x scale
    (np.diag([1.0, 1.0, -1.0]), False),                         # a mirror is not flat
    (np.diag([1.0, 0.0, 1.0]), True),                           # scale 0 on one axis
    (np.array([[1.0, 1.0, 0], [0, 0, 0], [0, 0, 1.0]]).T, True),  # a zero column (y to nothing)
    (np.array([[1.0, 0, 0], [1.0, 1e-12, 0], [0, 0, 1.0]]).T, True),  # two columns parallel to 1e-12
    (np.array([[1.0, 0, 0], [1.0, 1e-3, 0], [0, 0, 1.0]]).T, False),  # a strong shear, 1e-3 of a right angle
])
def test_flat_is_scale_free(matrix, flat):
    """Expected from geometry: volume over the product of the edge lengths is |sin| of the angles between them."""
    assert bool(transforms.flat(matrix)) is flat
    for k in (1e-6, 1.0, 1e6):  # the same shape at any size
        assert bool(transforms.flat(matrix * k)) is flat
    padded = np.eye(4)
    padded[:3, :3] = matrix
    assert bool(transforms.flat(padded)) is flat  # a 4x4 is judged by its 3x3


def test_flat_judges_each_of_a_stack():
    stack = np.stack([np.eye(3), np.diag([1.0, 0.0, 1.0]), np.eye(3) * 1e-7])
    assert transforms.flat(stack).tolist() == [False, True, False]


def test_a_scene_matrix_of_tiny_scale_is_accepted(tmp_path):
    """validate.py's [models.transform] matrix used the same absolute bound: a 1e-5 scale (det 1e-15) was
    refused as singular; a matrix with a zero row still is."""
    from wgpurender.core.scene import load_scene

    g = GltfWriter()
    big = np.array([[X0, Y0, 0], [X1, Y0, 0], [X1, Y1, 0], [X0, Y1, 0]], np.float32) * 1e5
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(big)}, "indices": g.accessor(QUAD_INDICES)}]))
    g.write(tmp_path / "big.glb")
    rows = "[[1e-5, 0, 0, 0], [0, 1e-5, 0, 0], [0, 0, 1e-5, 0], [0, 0, 0, 1]]"
    load_scene(write_scene(tmp_path, "big.glb", extra=f"[models.transform]\nmatrix = {rows}\n"))
    flat_rows = "[[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"
    with pytest.raises(UserError, match="singular"):
        load_scene(write_scene(tmp_path, "big.glb", extra=f"[models.transform]\nmatrix = {flat_rows}\n"))


# --- MorphPrimitivesTest/glTF-Draco: a Draco primitive's morph targets ----------------------------------------------

MORPH_LIFT = 0.8  # the target moves the two top vertices up by this; weight 0.5 lifts them by half


def _draco_morph_quad(tmp_path, target_count: int = 4) -> None:
    """A Draco quad (order preserved, as the extension's generators write it) with one plain POSITION target
    lifting its top edge, mesh weights [0.5]."""
    DracoPy = pytest.importorskip("DracoPy")
    positions = np.array([[X0, Y0, 0], [X1, Y0, 0], [X1, Y1, 0], [X0, Y1, 0]], np.float64)
    faces = QUAD_INDICES.reshape(-1, 3).astype(np.uint32)
    blob = DracoPy.encode(positions, faces, quantization_bits=14, preserve_order=True)
    decoded = DracoPy.decode(blob)
    order = [int(np.argmin(np.linalg.norm(positions - p, axis=1))) for p in np.asarray(decoded.points)]
    delta = np.zeros((target_count, 3), np.float32)
    lifted = [k for k in range(min(4, target_count)) if positions[order[k], 1] == Y1]
    delta[lifted, 1] = MORPH_LIFT  # in the decoded order: the data the accessors describe
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [*COLOUR, 1]}, **UNLIT)
    view = g.view(blob)
    first = len(g.doc["accessors"])
    g.doc["accessors"] += [{"componentType": 5126, "count": 4, "type": "VEC3", "min": [X0, Y0, 0],
                            "max": [X1, Y1, 0]}, {"componentType": 5123, "count": 6, "type": "SCALAR"}]
    target = g.positions(delta)
    ext = {"bufferView": view, "attributes": {"POSITION": decoded.attributes[0]["unique_id"]}}
    g.node(mesh=g.mesh([{"attributes": {"POSITION": first}, "indices": first + 1, "material": mat,
                         "targets": [{"POSITION": target}], "extensions": {"KHR_draco_mesh_compression": ext}}]))
    g.doc["meshes"][0]["weights"] = [0.5]
    g.doc["extensionsUsed"] = ["KHR_draco_mesh_compression", "KHR_materials_unlit"]
    g.doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    g.write(tmp_path / "dm.glb")


@pytest.mark.parametrize("which", PATHS)
def test_draco_primitive_morph_targets_apply(ctx, tmp_path, which):
    """The top edge moves from Y1 to Y1 + 0.5 x lift: covered just under the morphed edge, bare just above it
    (MorphPrimitivesTest/glTF-Draco drew flat: its targets were ignored)."""
    _draco_morph_quad(tmp_path)
    image = render(ctx, write_scene(tmp_path, "dm.glb"), which, size=(128, 128))
    covered = image[..., :3].max(axis=2) > 20
    top = Y1 + 0.5 * MORPH_LIFT
    for x, y, inside in ((0.1, top - 0.08, True), (0.1, top + 0.08, False), (0.1, Y0 + 0.05, True),
                         (0.1, Y0 - 0.08, False)):
        col, row = pixel_of(x, y, (128, 128))
        assert covered[int(row), int(col)] == inside, (which, x, y, inside)


def test_a_draco_morph_target_of_the_wrong_count_is_one_line(tmp_path):
    _draco_morph_quad(tmp_path, target_count=3)
    with pytest.raises(UserError, match=r"morph target 0 POSITION has 3 elements, the primitive 4 vertices"):
        load_mesh(tmp_path / "dm.glb")


def test_instance_matrices_of_tiny_scale_are_accepted_and_one_flat_one_is_not(tmp_path):
    """instances.py used the absolute bound too: a stack of 1e-5-scale matrices (det 1e-15) is a valid placement;
    one flat matrix among good ones is still refused."""
    from wgpurender.core.scene import parse_scene

    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]))},
                         "indices": g.accessor(np.uint16([0, 1, 2]))}]))
    g.write(tmp_path / "t.glb")
    tiny = np.tile(np.diag([1e-5, 1e-5, 1e-5, 1.0]), (3, 1, 1))
    np.save(tmp_path / "tiny.npy", tiny)
    mixed = tiny.copy()
    mixed[1, 1, 1] = 0.0
    np.save(tmp_path / "mixed.npy", mixed)
    head = "[camera]\neye = [0, 0, 2]\ntarget = [0, 0, 0]\n"
    scene = parse_scene(f'{head}[[models]]\npath = "t.glb"\ninstances = {{ file = "tiny.npy" }}\n', tmp_path / "s.toml")
    assert scene.models[0].placements.count == 3
    with pytest.raises(UserError, match="singular"):
        parse_scene(f'{head}[[models]]\npath = "t.glb"\ninstances = {{ file = "mixed.npy" }}\n', tmp_path / "s.toml")


def test_a_plain_morph_target_of_the_wrong_count_is_one_line(tmp_path):
    """The same check for an uncompressed primitive: 3 target elements for 4 vertices was a numpy broadcast
    traceback before."""
    from gltf_gen import quad

    g = GltfWriter()
    target = g.positions(np.zeros((3, 3), np.float32))
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(quad(-1, -1, 1, 1))},
                         "indices": g.accessor(QUAD_INDICES), "targets": [{"POSITION": target}]}]))
    g.doc["meshes"][0]["weights"] = [0.5]
    with pytest.raises(UserError, match=r"morph target 0 POSITION has 3 elements, the primitive 4 vertices"):
        load_mesh(g.write(tmp_path / "t.glb"))


@pytest.mark.parametrize("required, fix", [
    (["KHR_texture_basisu"], "re-export it with PNG or JPEG textures"),
    (["EXT_made_up"], "re-export the model without them"),
    (["KHR_texture_basisu", "EXT_made_up"], "PNG or JPEG textures; re-export the model without them"),
    (["EXT_made_up", "EXT_also_made_up"], "re-export the model without them"),  # said once
])
def test_a_required_extension_is_refused_with_its_own_fix(tmp_path, capsys, required, fix):
    """A required extension wgpurender lacks: the one line names it and the way to a file wgpurender draws (the
    old line suggested dropping KHR_texture_basisu, whatever was missing). SpecGlossVsMetalRough's
    KHR_materials_pbrSpecularGlossiness, refused here before, is now converted (test_gltf_specgloss.py)."""
    from wgpurender.cli import main

    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]))},
                         "indices": g.accessor(np.uint16([0, 1, 2]))}]))
    g.doc["extensionsRequired"] = g.doc["extensionsUsed"] = required
    g.write(tmp_path / "r.glb")
    code = main(["render", str(write_scene(tmp_path, "r.glb")), "-o", str(tmp_path / "out.png")])
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 2 and len(err) == 1, err
    assert ", ".join(required) in err[0] and err[0].count(fix) == 1, err
    assert not (tmp_path / "out.png").exists()
