"""glTF animations sampled at a scene's time and skins posed on the CPU (core/models/gltf_animation.py,
core/models/gltf_skin.py), on both paths.

Every file is built here (tests/gltf_gen.py) with known keyframes and a known skin; every expectation is computed
in this file in float64 from those numbers (the specification's formulas: slerp, the cubic Hermite form with
tangents scaled by the key interval, joint matrix = global(joint) x inverseBindMatrix) and the camera of
gltf_gen.CAMERA, never read back through the loader under test.
"""

from __future__ import annotations

import json
import math
import re
import struct

import numpy as np
import pytest
from gltf_gen import GltfWriter, scene_text
from test_gltf_render import PATHS, SIZE, UNLIT, render, write_scene
from xvfb import xvfb_display  # noqa: F401 - the shared Xvfb fixture "display"

from wgpurender.core.errors import UserError
from wgpurender.core.models.gltf_animation import Pose
from wgpurender.core.models.mesh import load_mesh

TRIANGLE = np.array([[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 1.5, 0.0]])
COLOUR = [0.9, 0.6, 0.2, 1.0]


def _quat_z(degrees: float) -> list[float]:
    half = math.radians(degrees) / 2
    return [0.0, 0.0, math.sin(half), math.cos(half)]


def _rot_z(degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def _translate(x: float, y: float, z: float = 0.0) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def _animated_file(tmp_path, path: str, times, values, interpolation="LINEAR", name="move", extra=None,
                   suffix=".gltf"):
    """One triangle on node 0, whose ``path`` (translation / rotation / scale) one channel animates."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": COLOUR}, **UNLIT)
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(TRIANGLE)}, "material": mat}]))
    values = np.asarray(values, np.float32)
    sampler = {"input": g.accessor(np.asarray(times, np.float32)), "output": g.accessor(values),
               "interpolation": interpolation}
    g.doc["animations"] = [{"name": name, "channels": [{"sampler": 0, "target": {"node": 0, "path": path}}],
                            "samplers": [sampler]}] + (extra(g) if extra else [])
    return g.write(tmp_path / f"anim{suffix}")


def _positions_at(path, t, animation=None) -> np.ndarray:
    """The loaded triangle's three vertices (flat-shaded: one per corner, in file order)."""
    return load_mesh(path, generate_tangents=False, pose=Pose(animation, t)).positions.astype(np.float64)


# -- interpolation: hand-computed values ------------------------------------------------------------------------

STEP_TIMES, STEP_X = [0.0, 1.0, 2.0], [0.0, 10.0, 20.0]


@pytest.mark.parametrize(("t", "x"), [(0.5, 0.0), (1.0, 10.0), (1.99, 10.0), (2.0, 20.0), (-3.0, 0.0), (9.0, 20.0)])
def test_step_holds_the_last_key_and_clamps(tmp_path, t, x):
    path = _animated_file(tmp_path, "translation", STEP_TIMES, [[v, 0, 0] for v in STEP_X], "STEP")
    np.testing.assert_allclose(_positions_at(path, t), TRIANGLE + [x, 0, 0], atol=1e-5)


@pytest.mark.parametrize(("t", "x"), [(0.25, 2.5), (1.5, 15.0), (-1.0, 0.0), (4.0, 20.0)])
def test_linear_translation_and_clamping(tmp_path, t, x):
    path = _animated_file(tmp_path, "translation", STEP_TIMES, [[v, 0, 0] for v in STEP_X])
    np.testing.assert_allclose(_positions_at(path, t), TRIANGLE + [x, 0, 0], atol=1e-5)


def test_linear_scale_per_component(tmp_path):
    path = _animated_file(tmp_path, "scale", [0.0, 2.0], [[1, 1, 1], [3, 0.5, 1]])
    np.testing.assert_allclose(_positions_at(path, 0.5), TRIANGLE * [1.5, 0.875, 1], atol=1e-5)


@pytest.mark.parametrize("negate_end", [False, True])
def test_rotation_is_slerp_along_the_shorter_arc(tmp_path, negate_end):
    """0 -> 120 degrees about z at s = 0.25: 30 degrees (a per-component lerp then normalize gives 28.2). The end
    key stored as -q (the same rotation) must still take the short way."""
    end = np.array(_quat_z(120.0)) * (-1 if negate_end else 1)
    path = _animated_file(tmp_path, "rotation", [0.0, 1.0], [_quat_z(0.0), end])
    want = TRIANGLE @ _rot_z(30.0)[:3, :3].T
    np.testing.assert_allclose(_positions_at(path, 0.25), want, atol=1e-5)


def test_cubicspline_uses_tangents_scaled_by_the_key_interval(tmp_path):
    """Keys at t = 1 and 3 (interval d = 2): v0 = 0, out-tangent b0 = 0.5; v1 = 1, in-tangent a1 = -1. At t = 2
    (s = 0.5): p = 0.5 v0 + d 0.125 b0 + 0.5 v1 + d (-0.125) a1 = 0.125 + 0.5 + 0.25 = 0.875 (unscaled tangents
    would give 0.6875)."""
    # per key: in-tangent, value, out-tangent
    values = [[9, 0, 0], [0, 0, 0], [0.5, 0, 0], [-1, 0, 0], [1, 0, 0], [7, 0, 0]]
    path = _animated_file(tmp_path, "translation", [1.0, 3.0], values, "CUBICSPLINE")
    np.testing.assert_allclose(_positions_at(path, 2.0), TRIANGLE + [0.875, 0, 0], atol=1e-5)
    np.testing.assert_allclose(_positions_at(path, 3.5), TRIANGLE + [1.0, 0, 0], atol=1e-5)  # clamped: v1
    np.testing.assert_allclose(_positions_at(path, 0.0), TRIANGLE, atol=1e-5)  # clamped: v0


@pytest.mark.parametrize(("mode", "values"), [("LINEAR", [[1, 0, 0]]), ("STEP", [[1, 0, 0]]),
                                               ("CUBICSPLINE", [[9, 0, 0], [1, 0, 0], [7, 0, 0]])])
def test_a_single_key_holds_at_every_time(tmp_path, mode, values):
    """One key: its value at any time (a CUBICSPLINE key's value is the middle of in-tangent, value, out-tangent)."""
    path = _animated_file(tmp_path, "translation", [0.5], values, mode)
    for t in (0.0, 0.5, 3.0):
        np.testing.assert_allclose(_positions_at(path, t), TRIANGLE + [1, 0, 0], atol=1e-5)


def test_cubicspline_rotation_is_normalized(tmp_path):
    """Zero tangents between 0 and 90 degrees about z: at s = 0.5 the Hermite blend is the mean of the two
    quaternions (0, 0, 0.3827, 0.9619), normalized: a rotation by 2 atan2(0.3827, 0.9619) = 43.4 degrees."""
    zero = [0.0, 0.0, 0.0, 0.0]
    path = _animated_file(tmp_path, "rotation", [0.0, 1.0], [zero, _quat_z(0), zero, zero, _quat_z(90), zero],
                          "CUBICSPLINE")
    q = (np.array(_quat_z(0)) + np.array(_quat_z(90))) / 2
    angle = math.degrees(2 * math.atan2(q[2], q[3]))
    np.testing.assert_allclose(_positions_at(path, 0.5), TRIANGLE @ _rot_z(angle)[:3, :3].T, atol=1e-5)


def test_animation_chosen_by_name_and_index(tmp_path):
    def lift(g: GltfWriter) -> list[dict]:  # a second animation: up by 4 over the first's key times
        output = g.accessor(np.float32([[0, 0, 0], [0, 4, 0]]))
        return [{"name": "lift", "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
                 "samplers": [{"input": 1, "output": output}]}]

    path = _animated_file(tmp_path, "translation", [0.0, 1.0], [[0, 0, 0], [4, 0, 0]], extra=lift)
    for choice, shift in (("lift", [0, 2, 0]), (1, [0, 2, 0]), (None, [2, 0, 0]), (0, [2, 0, 0]),
                          ("move", [2, 0, 0])):
        np.testing.assert_allclose(_positions_at(path, 0.5, choice), TRIANGLE + shift, atol=1e-5)
    with pytest.raises(UserError, match=r"no animation 'walk' \(its animations: 0 'move', 1 'lift'\)"):
        _positions_at(path, 0.5, "walk")
    with pytest.raises(UserError, match="no animation 2"):
        _positions_at(path, 0.5, 2)


def test_morph_weights_channel(tmp_path):
    """A weights channel 0 -> 1 over one second: at t = 0.25 the target's lift applies a quarter."""
    g = GltfWriter()
    lift = np.array([[0, 0, 0], [0, 0, 0], [0, 2.0, 0]], np.float32)
    prim = {"attributes": {"POSITION": g.positions(TRIANGLE)}, "targets": [{"POSITION": g.accessor(lift)}]}
    g.node(mesh=g.mesh([prim]), weights=[0.0])
    g.doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
                            "samplers": [{"input": g.accessor(np.float32([0, 1])),
                                          "output": g.accessor(np.float32([0, 1]))}]}]
    path = g.write(tmp_path / "morph.gltf")
    np.testing.assert_allclose(_positions_at(path, 0.25), TRIANGLE + 0.25 * lift, atol=1e-5)
    np.testing.assert_allclose(load_mesh(path, generate_tangents=False).positions, TRIANGLE, atol=1e-6)  # at rest


# -- skins --------------------------------------------------------------------------------------------------------

STRIP_X, STRIP_Y = (-0.25, 0.25), (0.0, 0.5, 1.0, 1.5, 2.0)
ARMATURE = _translate(0.0, -1.0)  # the joints' parent node
BEND = 90.0


def _strip():
    """A strip along +y (two columns, five rows), rows 0-1 on joint 0, row 2 half and half, rows 3-4 on joint 1
    (at (0, 1) in the armature's bind pose)."""
    positions = np.array([[x, y, 0.0] for y in STRIP_Y for x in STRIP_X])
    faces = np.array([[2 * r, 2 * r + 1, 2 * r + 3, 2 * r, 2 * r + 3, 2 * r + 2] for r in range(4)]).reshape(-1, 3)
    weight1 = np.repeat([0.0, 0.0, 0.5, 1.0, 1.0], 2)
    return positions, faces, np.stack([1 - weight1, weight1], axis=1)


def _skinned_file(tmp_path, *, joints=None, inverse_bind=None, weights=None, mesh_node_translation=(5.0, 0, 0),
                  with_weights=True, normal=(0.0, 0.0, 1.0), tangent=None, split_sets=False, with_joints=True):
    """The strip bound to joints 1 (armature child, at its origin) and 2 (child of 1, at y = 1); joint 2's
    rotation animated from 0 to BEND degrees about z over one second. The mesh node's own translation must be
    ignored (glTF: a skinned mesh is placed by its joints)."""
    positions, faces, w = _strip()
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": COLOUR}, doubleSided=True, **UNLIT)
    attrs = {"POSITION": g.positions(positions)}
    if normal is not None:
        attrs["NORMAL"] = g.accessor(np.tile(np.float32(normal), (10, 1)))
    if tangent is not None:
        attrs["TANGENT"] = g.accessor(np.tile(np.float32(tangent), (10, 1)))
    if joints is None:
        joint_index = np.zeros((10, 4), np.uint8)
        joint_index[:, 1] = 1
    else:
        joint_index = np.asarray(joints, np.uint8)
    w4 = np.zeros((10, 4), np.float32)
    w4[:, :2] = w if weights is None else weights
    if split_sets:  # joint 0 in set 0, joint 1 in set 1 (JOINTS_1 / WEIGHTS_1), as real files with 8 influences
        attrs["JOINTS_1"] = g.accessor(np.tile(np.uint8([1, 0, 0, 0]), (10, 1)))
        attrs["WEIGHTS_1"] = g.accessor(np.ascontiguousarray(np.pad(w4[:, 1:2], ((0, 0), (0, 3)))))
        joint_index, w4 = np.zeros((10, 4), np.uint8), np.pad(w4[:, :1], ((0, 0), (0, 3)))
    if with_joints:
        attrs["JOINTS_0"] = g.accessor(joint_index)
    if with_weights and with_joints:
        attrs["WEIGHTS_0"] = g.accessor(np.ascontiguousarray(w4, np.float32))
    prim = {"attributes": attrs, "indices": g.accessor(faces.astype(np.uint16).ravel()), "material": mat}
    g.node(mesh=g.mesh([prim]), skin=0, translation=list(mesh_node_translation))  # node 0
    g.node(children=[2], translation=[0.0, -1.0, 0.0])  # node 1: armature
    g.node(children=[3])  # node 2: joint 0 at the armature's origin
    g.node(translation=[0.0, 1.0, 0.0])  # node 3: joint 1
    bind = [ARMATURE, ARMATURE @ _translate(0, 1)]  # the joints' globals as written (the bind pose)
    ibm = np.array([np.linalg.inv(m) for m in bind]) if inverse_bind is None else inverse_bind
    columns = np.ascontiguousarray(ibm.transpose(0, 2, 1).reshape(-1, 4), np.float32)  # MAT4 is column-major
    g.doc["skins"] = [{"joints": [2, 3], "inverseBindMatrices": g.accessor(columns)}]
    g.doc["accessors"][-1].update(type="MAT4", count=len(ibm))
    g.doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 3, "path": "rotation"}}],
                            "samplers": [{"input": g.accessor(np.float32([0, 1])),
                                          "output": g.accessor(np.float32([_quat_z(0), _quat_z(BEND)]))}]}]
    return g.write(tmp_path / "skin.glb", roots=[0, 1])


def _posed_strip(t: float) -> np.ndarray:
    """The strip's vertices at ``t``, by this test's own float64 skinning: sum_j w_j global_j(t) IBM_j v."""
    positions, _, w = _strip()
    globals_ = [ARMATURE, ARMATURE @ _translate(0, 1) @ _rot_z(BEND * min(max(t, 0.0), 1.0))]
    ibm = [np.linalg.inv(ARMATURE), np.linalg.inv(ARMATURE @ _translate(0, 1))]
    homogeneous = np.concatenate([positions, np.ones((len(positions), 1))], axis=1)
    out = sum(w[:, j, None] * (homogeneous @ (globals_[j] @ ibm[j]).T) for j in range(2))
    return out[:, :3]


def test_skin_poses_vertices_by_joint_matrices(tmp_path):
    path = _skinned_file(tmp_path)
    for t in (0.0, 0.5, 1.0, 2.0):
        mesh = load_mesh(path, generate_tangents=False, pose=Pose(None, t))
        np.testing.assert_allclose(mesh.positions, _posed_strip(t), atol=1e-5, err_msg=f"t = {t}")
    at_rest = load_mesh(path, generate_tangents=False)  # no pose: skinned in the nodes as written
    np.testing.assert_allclose(at_rest.positions, _posed_strip(0.0), atol=1e-5)


def _blend3(t: float) -> np.ndarray:
    """(10, 3, 3): each strip vertex's blended joint matrix (upper 3x3), from this test's own globals."""
    _, _, w = _strip()
    bent = _rot_z(BEND * min(max(t, 0.0), 1.0))[:3, :3]
    return w[:, 0, None, None] * np.eye(3) + w[:, 1, None, None] * bent


@pytest.mark.parametrize("t", [0.4, 1.0])
def test_skin_turns_normals_by_the_inverse_transpose_and_tangents_by_the_matrix(tmp_path, t):
    """An in-plane normal (1, 0, 0) and tangent (0, 1, 0): on the half-and-half row the blend 0.5 (I + R) is not a
    rotation, so the normal (inverse transpose) and the tangent (the matrix) turn differently."""
    path = _skinned_file(tmp_path, normal=(1.0, 0.0, 0.0), tangent=(0.0, 1.0, 0.0, 1.0))
    mesh = load_mesh(path, generate_tangents=False, pose=Pose(None, t))
    m = _blend3(t)
    normals = np.einsum("vij,j->vi", np.linalg.inv(m).transpose(0, 2, 1), [1.0, 0, 0])
    tangents = np.einsum("vij,j->vi", m, [0, 1.0, 0])
    unit = lambda v: v / np.linalg.norm(v, axis=1, keepdims=True)  # noqa: E731
    np.testing.assert_allclose(mesh.normals, unit(normals), atol=1e-5)
    np.testing.assert_allclose(mesh.tangents[:, :3], unit(tangents), atol=1e-5)
    np.testing.assert_allclose(mesh.tangents[:, 3], 1.0)


def test_weights_are_normalized_and_second_sets_count(tmp_path):
    """Weights summing to 2 pose as their halves; joints split over JOINTS_0/JOINTS_1 pose as one set."""
    _, _, w = _strip()
    doubled = _skinned_file(tmp_path, weights=2 * w)
    np.testing.assert_allclose(load_mesh(doubled, generate_tangents=False, pose=Pose(None, 0.6)).positions,
                               _posed_strip(0.6), atol=1e-5)
    split = _skinned_file(tmp_path, split_sets=True)
    np.testing.assert_allclose(load_mesh(split, generate_tangents=False, pose=Pose(None, 0.6)).positions,
                               _posed_strip(0.6), atol=1e-5)


def test_a_skinned_mesh_without_normals_is_flat_shaded_then_posed(tmp_path):
    """No NORMAL: glTF asks for flat normals, so every triangle gets its own corners; each corner keeps its
    vertex's joints and weights."""
    path = _skinned_file(tmp_path, normal=None)
    _, faces, _ = _strip()
    mesh = load_mesh(path, generate_tangents=False, pose=Pose(None, 0.8))
    np.testing.assert_allclose(mesh.positions, _posed_strip(0.8)[faces].reshape(-1, 3), atol=1e-5)


def _coverage(triangles: np.ndarray, size) -> tuple[np.ndarray, np.ndarray]:
    """(inside, far from every edge) per pixel centre, for 2-D ``triangles`` (T, 3, 2) seen by CAMERA."""
    w, h = size
    cols, rows = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    x = ((cols / w) * 2 - 1) * 2 * (w / h)  # CAMERA: eye z = 2, fov_y 90: the z = 0 plane spans +-2
    y = (1 - (rows / h) * 2) * 2
    inside = np.zeros((h, w), bool)
    margin = np.full((h, w), np.inf)
    pixel = 4.0 / h
    for tri in triangles:
        signs = []
        for k in range(3):
            a, b = tri[k], tri[(k + 1) % 3]
            edge = b - a
            cross = edge[0] * (y - a[1]) - edge[1] * (x - a[0])
            signs.append(cross)
            length = np.hypot(*edge)
            s = np.clip(((x - a[0]) * edge[0] + (y - a[1]) * edge[1]) / length ** 2, 0, 1)
            margin = np.minimum(margin, np.hypot(x - a[0] - s * edge[0], y - a[1] - s * edge[1]) / pixel)
        signs = np.array(signs)
        inside |= np.all(signs >= 0, axis=0) | np.all(signs <= 0, axis=0)
    return inside, margin > 1.5


@pytest.mark.parametrize("which", PATHS)
def test_bent_strip_covers_the_posed_place_not_the_rest_one(ctx, tmp_path, which):
    """At t = 1 the strip's upper half is bent 90 degrees to the left: the image covers exactly the triangles of
    this test's own posed vertices (pixels further than 1.5 px from an edge), and not the rest pose's top."""
    _skinned_file(tmp_path)
    image = render(ctx, write_scene(tmp_path, "skin.glb", extra="time = 1.0\n"), which)
    covered = image[..., :3].max(axis=2) > 20
    _, faces, _ = _strip()
    inside, sure = _coverage(_posed_strip(1.0)[:, :2][faces], SIZE)
    assert inside.sum() > 200 and sure.sum() > 0.8 * covered.size
    assert np.array_equal(covered[sure], inside[sure]), (which, np.argwhere(sure & (covered != inside))[:5])
    rest_top, _ = _coverage(_strip()[0][:, :2][faces[4:]], SIZE)  # rows 2-4 where the rest pose has them
    assert not np.any(covered & rest_top & ~inside & sure)
    assert np.any(rest_top & ~inside & sure)  # the probe is not empty: the bend moved something


@pytest.mark.parametrize("raw", [False, True], ids=["wgpu-window", "raw-window"])
def test_the_windows_draw_the_posed_strip(display, tmp_path, raw):
    """``demo`` (both windows) plays the animation; ``--time 0.8`` freezes it there (over the block's 1.0): the
    screenshot covers the strip's float64 triangles at 0.8, as the headless image does."""
    import os
    import subprocess
    import sys

    from wgpurender.core.files.imageio import load_png

    _skinned_file(tmp_path)
    scene = write_scene(tmp_path, "skin.glb", extra="time = 1.0\n")
    shot = tmp_path / "shot.png"
    argv = [sys.executable, "-m", "wgpurender", "demo", *(["--raw"] if raw else ["--no-overlay"]), str(scene),
            "--size", f"{SIZE[0]}x{SIZE[1]}", "--frames", "2", "--time", "0.8", "--screenshot", str(shot)]
    result = subprocess.run(argv, env=dict(os.environ, DISPLAY=display), capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    covered = load_png(shot)[..., :3].max(axis=2) > 20
    _, faces, _ = _strip()
    inside, sure = _coverage(_posed_strip(0.8)[:, :2][faces], SIZE)
    assert np.array_equal(covered[sure], inside[sure])


@pytest.mark.parametrize("which", PATHS)
def test_rotated_triangle_lands_at_the_analytic_place(ctx, tmp_path, which):
    """AnimatedTriangle's case: a rotation channel 0 -> 180 degrees; at t = 0.25 (45 degrees) the triangle covers
    its rotated place and its rest corner (1.4, 0.05) is bare."""
    _animated_file(tmp_path, "rotation", [0.0, 1.0], [_quat_z(0), _quat_z(180)], suffix=".glb")
    image = render(ctx, write_scene(tmp_path, "anim.glb", extra="time = 0.25\n"), which)
    covered = image[..., :3].max(axis=2) > 20
    posed = (TRIANGLE @ _rot_z(45)[:3, :3].T)[:, :2]
    inside, sure = _coverage(posed[None], SIZE)
    assert np.array_equal(covered[sure], inside[sure]), which
    rest, _ = _coverage(TRIANGLE[None, :, :2], SIZE)
    assert np.any(rest & ~inside & sure) and not np.any(covered & rest & ~inside & sure)


@pytest.mark.parametrize("which", PATHS)
def test_two_models_of_one_file_at_two_times(ctx, tmp_path, which):
    """The plan keys meshes by file and pose: one file posed at t = 0 and t = 1 draws twice, not once."""
    _animated_file(tmp_path, "translation", [0.0, 1.0], [[-1.6, -1.0, 0], [0.2, -1.0, 0]], suffix=".glb")
    scene = tmp_path / "two.toml"
    scene.write_text(scene_text("anim.glb", SIZE, extra="time = 0.0\n")
                     + '\n[[models]]\npath = "anim.glb"\ntime = 1.0\n')
    covered = render(ctx, scene, which)[..., :3].max(axis=2) > 20
    want = np.zeros_like(covered)
    sure = np.ones_like(covered)
    for dx in (-1.6, 0.2):
        inside, far = _coverage((TRIANGLE + [dx, -1.0, 0])[None, :, :2], SIZE)
        want |= inside
        sure &= far
    assert np.array_equal(covered[sure], want[sure])


@pytest.mark.parametrize("which", PATHS)
def test_time_flag_poses_like_the_model_block_and_overrides_it(tmp_path, which):
    """``--time T`` (the API's ``t``) is resolved into the one plan: the same image as ``time = T`` in the model
    block, on both paths, and it overrides a block's own time."""
    from wgpurender import api

    draw = api.render if which == "wgpu" else api.reference
    _skinned_file(tmp_path)
    for name, extra in (("block", "time = 0.7\n"), ("plain", ""), ("other", "time = 0.2\n")):
        (tmp_path / f"{name}.toml").write_text(scene_text("skin.glb", SIZE, extra=extra))
    block = draw(str(tmp_path / "block.toml")).pixels
    assert np.array_equal(draw(str(tmp_path / "plain.toml"), t=0.7).pixels, block)
    assert np.array_equal(draw(str(tmp_path / "other.toml"), t=0.7).pixels, block)
    assert not np.array_equal(draw(str(tmp_path / "other.toml")).pixels, block)  # the block's 0.2 differs
    plan = draw(str(tmp_path / "plain.toml"), t=0.7).plan
    assert "sampled at t = 0.7 s" in plan.explain()


def test_time_flag_on_a_static_scene_is_one_line(tmp_path, capsys):
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(TRIANGLE)}}]))
    g.write(tmp_path / "still.glb")
    from helpers import one_line_refusal

    from wgpurender.cli import main

    scene = tmp_path / "still.toml"
    scene.write_text(scene_text("still.glb", SIZE))
    code = main(["render", str(scene), "-o", str(tmp_path / "out.png"), "--time", "2"])
    one_line_refusal(code, capsys.readouterr().err.strip(), "is static", "--time", "glTF file with an animation")
    assert not (tmp_path / "out.png").exists()


# -- --explain and refusals ---------------------------------------------------------------------------------------

def _explain(tmp_path, capsys, model: str, extra: str, *flags: str) -> str:
    from wgpurender.cli import main

    scene = tmp_path / "explain.toml"
    scene.write_text(scene_text(model, SIZE, extra=extra))
    assert main(["render", str(scene), "-o", str(tmp_path / "e.png"), "--explain", *flags]) == 0
    return capsys.readouterr().out


def test_explain_names_the_animation_time_and_skin(tmp_path, capsys):
    _skinned_file(tmp_path)
    out = _explain(tmp_path, capsys, "skin.glb", "time = 0.5\n")
    assert "animation 0 sampled at t = 0.5 s (keys 0..1 s, 1 channel(s))" in out
    assert "skin 0 (2 joints): posed on the CPU at t = 0.5 s" in out
    assert "ignored" not in "".join(line for line in out.splitlines() if "skin" in line or "animation" in line)
    assert "JOINTS_0, WEIGHTS_0 ignored" not in out  # used by the skin, not ignored
    out = _explain(tmp_path, capsys, "skin.glb", "time = 3\n")
    assert "t is outside the keys, so each channel is clamped to its last key" in out
    out = _explain(tmp_path, capsys, "skin.glb", "")
    assert "1 animation(s) not applied: drawn at rest" in out and "posed on the CPU at rest" in out
    out = _explain(tmp_path, capsys, "skin.glb", "time = 0.2\n", "--time", "0.9")  # the flag wins
    assert "sampled at t = 0.9 s" in out and "t = 0.2" not in out


def test_an_animation_without_node_targets_is_listed_as_ignored(tmp_path, capsys):
    """A channel without target.node (an extension's target, e.g. KHR_animation_pointer) poses nothing: said."""
    path = _animated_file(tmp_path, "translation", [0.0, 1.0], [[0, 0, 0], [1, 0, 0]])
    doc = json.loads(path.read_text())
    del doc["animations"][0]["channels"][0]["target"]["node"]
    path.write_text(json.dumps(doc))
    np.testing.assert_allclose(_positions_at(path, 0.5), TRIANGLE, atol=1e-6)
    out = _explain(tmp_path, capsys, "anim.gltf", "time = 0.5\n")
    assert "animation 0 'move': no channel targets a node" in out and "ignored, drawn at rest" in out


def _refused(tmp_path, capsys, model: str, extra: str, *needles: str) -> None:
    from helpers import one_line_refusal

    from wgpurender.cli import main

    scene = tmp_path / "refused.toml"
    scene.write_text(scene_text(model, SIZE, extra=extra))
    code = main(["render", str(scene), "-o", str(tmp_path / "out.png")])
    err = "\n".join(line for line in capsys.readouterr().err.splitlines() if line.strip())
    one_line_refusal(code, err, *needles)
    assert not (tmp_path / "out.png").exists()


def test_unknown_animation_is_one_line(tmp_path, capsys):
    _skinned_file(tmp_path)
    _refused(tmp_path, capsys, "skin.glb", 'animation = "walk"\n', "no animation 'walk'", "its animations: 0")
    _refused(tmp_path, capsys, "skin.glb", "animation = 3\ntime = 1\n", "no animation 3")


def test_time_for_a_file_without_animations_or_not_gltf_is_one_line(tmp_path, capsys):
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(TRIANGLE)}}]))
    g.write(tmp_path / "still.glb")
    _refused(tmp_path, capsys, "still.glb", "time = 1\n", "has no animations to pose")
    (tmp_path / "t.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    _refused(tmp_path, capsys, "t.obj", "time = 1\n", "only a glTF model", "has animations to pose")
    _refused(tmp_path, capsys, "still.glb", 'time = "soon"\n', "time must be a number")


@pytest.mark.parametrize(("kwargs", "needle"), [
    ({"joints": np.tile([0, 2, 0, 0], (10, 1))}, "names joint 2, but its skin has 2 joints"),
    ({"with_weights": False}, "1 JOINTS_n and 0 WEIGHTS_n"),
    ({"weights": np.zeros((10, 2))}, "negative, not finite or all 0"),
    ({"inverse_bind": np.array([np.eye(4), np.diag([1.0, 0.0, 1.0, 1.0])])}, "inverse bind matrix of joint 1"),
    ({"inverse_bind": np.array([np.eye(4)])}, "needs one MAT4 per joint (2), got 1"),
    ({"with_joints": False}, "is skinned (its node has a skin) but has no JOINTS_0/WEIGHTS_0"),
])
def test_malformed_skins_are_one_line(tmp_path, kwargs, needle):
    path = _skinned_file(tmp_path, **kwargs)
    with pytest.raises(UserError, match=re.escape(needle)):
        load_mesh(path, generate_tangents=False, pose=Pose(None, 0.5))


def test_a_weights_count_unlike_the_vertex_count_is_one_line(tmp_path):
    """WEIGHTS_0 with 9 elements for 10 vertices (the GLB's JSON chunk edited here): refused when the file is read."""
    path = _skinned_file(tmp_path)
    raw = path.read_bytes()
    length = struct.unpack_from("<I", raw, 12)[0]
    doc = json.loads(raw[20:20 + length])
    doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"]]["count"] = 9
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + raw[20 + length:]
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
    with pytest.raises(UserError, match="WEIGHTS_0 has 9 elements, POSITION 10"):
        load_mesh(path, generate_tangents=False, pose=Pose(None, 0.5))


def test_malformed_samplers_are_one_line(tmp_path):
    path = _animated_file(tmp_path, "translation", [0.0, 1.0, 0.5], [[0, 0, 0]] * 3)
    with pytest.raises(UserError, match="strictly increasing finite key times"):
        _positions_at(path, 0.5)
    path = _animated_file(tmp_path, "translation", [0.0, 1.0], [[0, 0, 0]] * 3, "CUBICSPLINE")
    with pytest.raises(UserError, match=r"3 output\(s\) per key and target \(got CUBICSPLINE, 2 keys, 3 outputs"):
        _positions_at(path, 0.5)
    path = _animated_file(tmp_path, "rotation", [0.0, 1.0], [[0, 0, 0], [0, 0, 0]])
    with pytest.raises(UserError, match="rotation needs 4 components per value"):
        _positions_at(path, 0.5)
    path = _animated_file(tmp_path, "translation", [0.0, 1.0], [[0, 0, 0]] * 2, "SMOOTH")
    with pytest.raises(UserError, match="got SMOOTH"):
        _positions_at(path, 0.5)


def test_key_times_must_be_scalar_floats(tmp_path):
    path = _animated_file(tmp_path, "translation", [[0.0, 0.0], [1.0, 1.0]], [[0, 0, 0]] * 4)
    with pytest.raises(UserError, match="input \\(key times\\) must be a SCALAR FLOAT accessor, got VEC2"):
        _positions_at(path, 0.5)


def test_an_animated_node_with_a_matrix_is_one_line(tmp_path):
    """glTF animates translation/rotation/scale nodes only; a matrix node as a channel's target is malformed."""
    path = _animated_file(tmp_path, "translation", [0.0, 1.0], [[0, 0, 0], [1, 0, 0]])
    doc = json.loads(path.read_text())
    doc["nodes"][0]["matrix"] = np.eye(4).ravel().tolist()
    path.write_text(json.dumps(doc))
    with pytest.raises(UserError, match="targets node 0, which has a matrix"):
        _positions_at(path, 0.5)



# -- what the file's animated nodes place: its camera and its lights follow the time ------------------------------

CAMERA_KEYS = ([0.0, 1.0], [[0.0, 0.0, 2.0], [0.0, 0.0, 6.0]])  # the camera node slides back along +z
LIGHT_KEYS = ([0.0, 1.0], [[1.0, 0.0, 1.0], [3.0, 0.0, 1.0]])  # the lamp slides along +x


def _camera_and_lamp_file(tmp_path):
    """A triangle, a perspective camera and a KHR point light, the camera's and the lamp's nodes animated by one
    animation (LINEAR translation channels with CAMERA_KEYS and LIGHT_KEYS)."""
    g = GltfWriter()
    g.node(mesh=g.mesh([{"attributes": {"POSITION": g.positions(TRIANGLE)}}]))
    g.node(camera=0, translation=CAMERA_KEYS[1][0])
    g.node(extensions={"KHR_lights_punctual": {"light": 0}}, translation=LIGHT_KEYS[1][0])
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 50.0}}]
    g.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 3.0}]}}
    samplers = [{"input": g.accessor(np.asarray(times, np.float32)), "output": g.accessor(np.asarray(v, np.float32))}
                for times, v in (CAMERA_KEYS, LIGHT_KEYS)]
    g.doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}},
                                         {"sampler": 1, "target": {"node": 2, "path": "translation"}}],
                            "samplers": samplers}]
    g.write(tmp_path / "rig.gltf")
    scene = tmp_path / "rig.toml"
    scene.write_text("[camera]\nfrom_model = 0\n\n[render]\nsize = [32, 32]\n\n"
                     '[[lights]]\ntype = "point"\nposition = [0, 5, 0]\n\n[[models]]\npath = "rig.gltf"\ntime = 0.5\n')
    return scene


def _lerp(keys, t: float) -> np.ndarray:
    (t0, t1), (a, b) = keys
    s = min(max((t - t0) / (t1 - t0), 0.0), 1.0)
    return (1 - s) * np.asarray(a) + s * np.asarray(b)


@pytest.mark.parametrize("t", [None, 0.25, 2.0])
def test_a_file_camera_and_lights_on_animated_nodes_are_placed_at_the_time(tmp_path, t):
    """The block's time (0.5), and --time overriding it (0.25; 2.0 clamps to the last key): the view's eye and the
    file lamp's position are the nodes' translations at that time; the scene's own light stays where it is."""
    from wgpurender.core.plan.resolve import resolve_plan

    plan = resolve_plan(_camera_and_lamp_file(tmp_path), None, time=t)
    at = 0.5 if t is None else t
    np.testing.assert_allclose(plan.scene.camera.eye, _lerp(CAMERA_KEYS, at), atol=1e-6)
    own, lamp = plan.scene.lights
    np.testing.assert_allclose(own.position, (0.0, 5.0, 0.0))
    np.testing.assert_allclose(lamp.position, _lerp(LIGHT_KEYS, at), atol=1e-6)


def test_camera_flag_views_from_the_animated_node_at_the_time(tmp_path):
    from wgpurender.core.plan.resolve import resolve_plan

    scene = _camera_and_lamp_file(tmp_path)
    scene.write_text(scene.read_text().replace("from_model = 0\n", "eye = [0, 0, 9]\ntarget = [0, 0, 0]\n"))
    plan = resolve_plan(scene, None, time=0.75, camera=0)
    np.testing.assert_allclose(plan.scene.camera.eye, _lerp(CAMERA_KEYS, 0.75), atol=1e-6)


# -- playback's per-frame cost: what is read once -----------------------------------------------------------------

def test_a_documents_channels_are_read_once_and_kept_read_only(tmp_path, monkeypatch):
    """The window poses the same parsed document every frame: its keys are read from the buffers once per document
    object and animation (a new document reads them again), the positions it gives are those of a fresh read, and
    the kept arrays refuse in-place changes."""
    from wgpurender.core.models import gltf_animation, gltf_io

    path = _animated_file(tmp_path, "translation", [0.0, 2.0], [[0, 0, 0], [8, 0, 0]])
    reads = []
    real = gltf_animation.read_accessor
    monkeypatch.setattr(gltf_animation, "read_accessor", lambda doc, i: reads.append(i) or real(doc, i))
    doc = gltf_io.read_document(path)
    first = gltf_animation.posed(doc, Pose(None, 0.5))
    once = len(reads)
    second = gltf_animation.posed(doc, Pose(None, 1.5))
    assert once == 2 and len(reads) == once  # times and values, then nothing more for the same document
    assert first.json["nodes"][0]["translation"][0] == pytest.approx(2.0)  # 8 * 0.5 / 2
    assert second.json["nodes"][0]["translation"][0] == pytest.approx(6.0)
    gltf_animation.posed(gltf_io.read_document(path), Pose(None, 0.5))
    assert len(reads) == 2 * once  # another document object: read again
    (_, _, times, values, _), = gltf_animation.read_channels(doc, 0)
    with pytest.raises(ValueError):
        values[0, 0] = 99.0


def test_a_file_without_light_nodes_is_not_posed_for_its_lights(tmp_path, monkeypatch):
    """The window places a file's KHR lights again every frame (model_motion.placed_again): a file whose nodes
    place no light gives none without being posed (posing moves nodes, it adds no light)."""
    from wgpurender.core.models import gltf_animation
    from wgpurender.core.scene import gltf_lights
    from wgpurender.core.scene.load import load_scene

    path = _animated_file(tmp_path, "translation", [0.0, 2.0], [[0, 0, 0], [8, 0, 0]])
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text(path.name, (16, 12), extra="time = 1.0\n"))
    model = load_scene(scene).models[0]
    monkeypatch.setattr(gltf_animation, "posed", lambda doc, pose: (_ for _ in ()).throw(AssertionError("posed")))
    assert gltf_lights.model_lights(model, 0) == []
