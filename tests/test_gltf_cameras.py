"""A glTF file's own camera (``[camera] from_model``, ``file_camera``) is the view on both paths, as glTF 2.0
defines cameras (section 3.10 and Appendix on projection matrices).

Each file is built here: an unlit quad of a known size and one or two cameras placed by nodes (a parent
translation and the camera node's own rotation). The expected coverage comes from this file's own float64 ray
casting: for each pixel centre, the ray the camera's numbers give (perspective: through (x tan(yfov/2) aspect,
y tan(yfov/2), -1); orthographic: from (x xmag, y ymag, 0) along -Z, in the camera's frame) meets the quad's
plane inside or outside the quad. Only pixels whose four inner corners agree are compared (no edge pixels).
The lit case checks the orthographic view vector against the float64 BRDF (tests/pbr_reference.py).
"""

from __future__ import annotations

import math

import numpy as np
import pbr_reference as ref
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, quad
from shading_model import course_constant, srgb_encode
from xvfb import xvfb_display  # noqa: F401 - the shared Xvfb fixture "display"

SIZE = (64, 48)
COLOR = (1.0, 0.5, 0.25)
QUAD = (-0.6, -0.4, 0.5, 0.7)  # x0, y0, x1, y1 at z = 0: asymmetric, so a flip or a shift shows
PARENT = (0.3, -0.2, 2.0)  # the camera node's parent translation
TURN = {"axis": (0.3, 1.0, 0.2), "angle": math.radians(12.0)}  # the camera node's own rotation
OWN = (0.1, 0.25, 1.0)  # the camera node's own translation
PERSPECTIVE = {"yfov": 0.9, "znear": 0.05}
ORTHOGRAPHIC = {"xmag": 1.1, "ymag": 0.9, "znear": 0.0, "zfar": 10.0}


def rotation_matrix(axis, angle: float) -> np.ndarray:
    """Rodrigues' formula, float64 (the test's own, not the loader's quaternion code)."""
    a = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def quaternion(axis, angle: float) -> list[float]:
    a = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    return [*(float(v) for v in a * math.sin(angle / 2)), math.cos(angle / 2)]


def write_file(folder, cameras: list[dict], *, unlit: bool = True, rough: float = 0.3, view: int = 0,
               model_transform: str = "", extra_scene: str = "", size=SIZE, quad_corners=QUAD,
               turn=TURN, own=OWN, parent=PARENT) -> None:
    """quad.gltf (the quad, one node per camera: each a child of a translated parent) and scene.toml viewing
    through camera ``view``."""
    g = GltfWriter()
    material = {"pbrMetallicRoughness": {"baseColorFactor": [*COLOR, 1.0], "metallicFactor": 0.0,
                                         "roughnessFactor": rough}}
    if unlit:
        material["extensions"] = {"KHR_materials_unlit": {}}
        g.doc["extensionsUsed"] = ["KHR_materials_unlit"]
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    prim = {"attributes": {"POSITION": g.positions(quad(*quad_corners)), "NORMAL": g.accessor(normals)},
            "indices": g.accessor(QUAD_INDICES), "material": g.material(**material)}
    roots = [g.node(mesh=g.mesh([prim]))]
    for k in range(len(cameras)):
        child = g.node(camera=k, rotation=quaternion(turn["axis"], turn["angle"]), translation=list(own))
        roots.append(g.node(children=[child], translation=list(parent)))
    g.doc["cameras"] = cameras
    g.write(folder / "quad.gltf", roots=roots)
    (folder / "scene.toml").write_text(
        f"[camera]\nfrom_model = 0\nfile_camera = {view}\n\n[render]\nsize = [{size[0]}, {size[1]}]\nmsaa = 1\n"
        f"hdr = false\nclear_color = [0, 0, 0, 1]\n\n{extra_scene}[[models]]\npath = \"quad.gltf\"\n"
        + model_transform)


def camera_frame(turn=TURN, own=OWN, parent=PARENT) -> tuple[np.ndarray, np.ndarray]:
    """The camera's rotation (its columns: right, up, backward) and position in the file's world."""
    rot = rotation_matrix(turn["axis"], turn["angle"])
    return rot, np.asarray(parent, np.float64) + np.asarray(own, np.float64)


def ndc_grid(size, offset=(0.0, 0.0)):
    """NDC x (right) and y (up) of each pixel's centre moved by ``offset`` pixels (row 0 at the top)."""
    w, h = size
    rows, cols = np.mgrid[0:h, 0:w] + 0.5
    return (cols + offset[0]) / w * 2 - 1, 1 - (rows + offset[1]) / h * 2


def rays(camera: dict, size, offset=(0.0, 0.0), frame=None):
    """Each pixel's ray (origin, direction) in the world, from the camera's numbers."""
    rot, eye = frame if frame is not None else camera_frame()
    x, y = ndc_grid(size, offset)
    if camera["type"] == "perspective":
        p = camera["perspective"]
        t = math.tan(p["yfov"] / 2)
        aspect = p.get("aspectRatio", size[0] / size[1])
        local = np.stack([x * t * aspect, y * t, -np.ones_like(x)], axis=-1)
        return np.broadcast_to(eye, local.shape), local @ rot.T
    o = camera["orthographic"]
    local = np.stack([x * o["xmag"], y * o["ymag"], np.zeros_like(x)], axis=-1)
    return eye + local @ rot.T, np.broadcast_to(rot @ (0.0, 0.0, -1.0), local.shape)


def covered(camera: dict, size=SIZE, offset=(0.0, 0.0), corners=QUAD, frame=None):
    """Whether each pixel's ray meets the quad (z = 0) in front of the camera."""
    origin, direction = rays(camera, size, offset, frame)
    t = -origin[..., 2] / direction[..., 2]
    hit = origin + t[..., None] * direction
    x0, y0, x1, y1 = corners
    inside = (hit[..., 0] > x0) & (hit[..., 0] < x1) & (hit[..., 1] > y0) & (hit[..., 1] < y1)
    return inside & (t > 0)


def sure(camera: dict, size=SIZE, **kw):
    """(want, mask): coverage at pixel centres, and where the pixel's four inner points (+-0.45 px) agree."""
    want = covered(camera, size, **kw)
    agree = np.ones_like(want)
    for dx in (-0.45, 0.45):
        for dy in (-0.45, 0.45):
            agree &= covered(camera, size, offset=(dx, dy), **kw) == want
    return want, agree


def render_both(ctx, folder, size=SIZE) -> np.ndarray:
    from wgpurender.raw_path.scene import render_scene_reference
    from wgpurender.wgpu_path.scene import render_scene_file

    path = folder / "scene.toml"
    wgpu = render_scene_file(path, size=size, ctx=ctx, frames=1, knobs={"post_path": "fragment"}).pixels
    raw = render_scene_reference(path, size=size)
    assert np.array_equal(wgpu, raw), "wgpu and raw differ"
    return wgpu[..., :3].astype(np.float64)


def check_coverage(got: np.ndarray, camera: dict, size=SIZE, **kw) -> None:
    want, mask = sure(camera, size, **kw)
    drawn = got.max(axis=-1) > 0
    assert mask.mean() > 0.8 and 0.05 < want[mask].mean() < 0.95  # both sides of the quad's edges are seen
    wrong = (drawn != want) & mask
    assert not wrong.any(), f"{wrong.sum()} pixels differ, first at {np.argwhere(wrong)[:3].tolist()}"
    colour = np.round(srgb_encode(np.asarray(COLOR)) * 255)
    assert np.abs(got[want & mask] - colour).max() <= 1


@pytest.mark.parametrize("aspect", [None, 1.0], ids=["target-aspect", "file-aspect"])
def test_perspective_camera_of_the_file(ctx, tmp_path, aspect):
    """Perspective, no zfar (the infinite projection), the file's aspectRatio or (absent) the target's."""
    camera = {"type": "perspective", "perspective": dict(PERSPECTIVE)}
    if aspect is not None:
        camera["perspective"]["aspectRatio"] = aspect
    write_file(tmp_path, [camera])
    check_coverage(render_both(ctx, tmp_path), camera)


@pytest.mark.parametrize("kind", ["perspective", "orthographic"])
def test_reverse_z_with_a_file_camera(ctx, tmp_path, kind):
    """The wgpu path's reverse_z knob (depth 1 at near; the raw path refuses it) with an infinite perspective and
    with an orthographic camera: the same coverage."""
    from wgpurender.wgpu_path.scene import render_scene_file

    numbers = PERSPECTIVE if kind == "perspective" else ORTHOGRAPHIC
    camera = {"type": kind, kind: dict(numbers)}
    write_file(tmp_path, [camera])
    got = render_scene_file(tmp_path / "scene.toml", size=SIZE, ctx=ctx, frames=1,
                            knobs={"post_path": "fragment", "reverse_z": True})
    assert got.plan.reverse_z
    check_coverage(got.pixels[..., :3].astype(np.float64), camera)


def test_orthographic_camera_of_the_file(ctx, tmp_path):
    """Orthographic: xmag and ymag are the half-extents whatever the target's aspect; znear 0 is allowed."""
    camera = {"type": "orthographic", "orthographic": dict(ORTHOGRAPHIC)}
    write_file(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}, camera], view=1)
    check_coverage(render_both(ctx, tmp_path), camera)


def test_orthographic_size_in_pixels_is_extent_over_twice_xmag(ctx, tmp_path):
    """A camera facing the quad straight on: its width in pixels is exactly extent / (2 xmag) x width, its
    height extent / (2 ymag) x height, at the rows and columns the half-extents put it (edges on pixel
    boundaries: x from -0.5 to 0.5 with xmag 2 covers columns 24..39 of 64; y from -0.25 to 0.5 with ymag 1
    rows 12..29 of 48, row 0 at the top)."""
    camera = {"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0, "znear": 0.5, "zfar": 5.0}}
    write_file(tmp_path, [camera], quad_corners=(-0.5, -0.25, 0.5, 0.5), turn={"axis": (0, 1, 0), "angle": 0.0},
               own=(0.0, 0.0, 1.0), parent=(0.0, 0.0, 1.0))
    drawn = render_both(ctx, tmp_path).max(axis=-1) > 0
    cols, rows = np.flatnonzero(drawn.any(axis=0)), np.flatnonzero(drawn.any(axis=1))
    assert (cols.min(), cols.max() + 1) == (24, 24 + round(1.0 / (2 * 2.0) * SIZE[0]))
    assert (rows.min(), rows.max() + 1) == (12, 12 + round(0.75 / (2 * 1.0) * SIZE[1]))
    assert drawn.sum() == 16 * 18


def test_the_models_transform_moves_its_camera_too(ctx, tmp_path):
    """The model's scene transform applies after the file's hierarchy, to the quad and the camera alike: the
    view is the file's own (a camera left where the file puts it would see the quad moved and turned)."""
    camera = {"type": "perspective", "perspective": dict(PERSPECTIVE)}
    write_file(tmp_path, [camera], model_transform="transform = { translate = [0.7, -0.3, 0.2], "
               "rotate = { axis = [0, 1, 0], degrees = 30 } }\n")
    check_coverage(render_both(ctx, tmp_path), camera)


def test_a_finite_zfar_clips_and_an_absent_one_does_not(ctx, tmp_path):
    """The quad 3 units ahead of a camera facing it: zfar 2 leaves it out; without zfar it is drawn."""
    straight = {"turn": {"axis": (0, 1, 0), "angle": 0.0}, "own": (0.0, 0.0, 1.0), "parent": (0.0, 0.0, 2.0)}
    clipped = {"type": "perspective", "perspective": {**PERSPECTIVE, "zfar": 2.0}}
    write_file(tmp_path, [clipped], **straight)
    assert render_both(ctx, tmp_path).max() == 0
    open_far = {"type": "perspective", "perspective": dict(PERSPECTIVE)}
    write_file(tmp_path, [open_far], **straight)
    frame = camera_frame(**straight)
    check_coverage(render_both(ctx, tmp_path), open_far, frame=frame)


def test_orthographic_view_vector_is_the_cameras_direction(ctx, tmp_path):
    """Lit and glossy under an orthographic camera: every pixel's v is the camera's backward axis (not eye -
    position), so each pixel is the float64 BRDF with that one v, under a point light near the quad."""
    light = (0.2, 0.1, 0.6)
    camera = {"type": "orthographic", "orthographic": {"xmag": 0.45, "ymag": 0.4, "znear": 0.1, "zfar": 10.0}}
    turn = {"axis": (1.0, 0.4, 0.0), "angle": math.radians(25.0)}
    frame_at = {"turn": turn, "own": (0.0, 0.0, 0.0), "parent": tuple(rotation_matrix(turn["axis"], turn["angle"])
                                                                         @ (0.0, 0.0, 1.5))}
    write_file(tmp_path, [camera], unlit=False, rough=0.35, quad_corners=(-4, -4, 4, 4), **frame_at,
               extra_scene=f'[[lights]]\ntype = "point"\nposition = {list(light)}\nintensity = 0.3\n\n')
    got = render_both(ctx, tmp_path)
    rot, eye = camera_frame(**frame_at)
    origin, direction = rays(camera, SIZE, frame=(rot, eye))
    hits = origin - (origin[..., 2] / direction[..., 2])[..., None] * direction
    v = np.broadcast_to(rot @ (0.0, 0.0, 1.0), hits.shape)
    n = np.array([0.0, 0.0, 1.0])
    to_light = np.asarray(light) - hits
    d2 = np.sum(to_light**2, axis=-1)
    l = ref.unit(to_light)  # noqa: E741
    irradiance = math.pi * 0.3 / d2 * np.clip(l @ n, 0, 1)  # scene units: intensity 1 on white Lambert gives 1
    radiance = ref.brdf(n, l, v, COLOR, 0.0, 0.35) * irradiance[..., None]
    want = np.round(srgb_encode(radiance + np.asarray(course_constant("AMBIENT")) * np.asarray(COLOR)) * 255)
    assert np.abs(got - want).max() <= 2
    perspective_v = ref.unit(eye - hits)  # what eye - position would give: visibly different here
    wrong = ref.brdf(n, l, perspective_v, COLOR, 0.0, 0.35) * irradiance[..., None]
    assert np.abs(np.round(srgb_encode(wrong + np.asarray(course_constant("AMBIENT")) * np.asarray(COLOR)) * 255)
                  - want).max() > 8


def test_explain_names_the_view_and_lists_the_other_cameras(tmp_path, capsys):
    from wgpurender.cli import main

    cameras = [{"type": "perspective", "name": "wide", "perspective": dict(PERSPECTIVE)},
               {"type": "orthographic", "orthographic": dict(ORTHOGRAPHIC)}]
    write_file(tmp_path, cameras, view=1)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "camera: the view is models[0] 'quad.gltf' camera 1 at node 3 (orthographic, xmag 1.1, ymag 0.9" in out
    assert "models[0] 'quad.gltf' camera 0: perspective 'wide' (yfov 0.9, znear 0.05) (not the view: --camera 0, " \
           "or [camera] from_model = 0, file_camera = 0, views through it)" in out
    assert "models[0] 'quad.gltf' camera 1: orthographic" in out and "<- the view" in out
    assert "ignored" not in out.split("knobs:")[0]


def test_explain_lists_the_files_cameras_under_the_scenes_own(tmp_path, capsys):
    from wgpurender.cli import main

    write_file(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}])
    text = (tmp_path / "scene.toml").read_text().replace("from_model = 0\nfile_camera = 0\n",
                                                         "eye = [0, 0, 3]\ntarget = [0, 0, 0]\n")
    (tmp_path / "scene.toml").write_text(text)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "camera: the view is the scene's [camera] (eye, target)" in out
    assert "camera 0: perspective (yfov 0.9, znear 0.05) (not the view: --camera 0, or [camera] from_model = 0" in out


BAD = [
    ({"type": "perspective", "perspective": {"yfov": 0.0, "znear": 0.1}}, 0, "yfov = 0, but the glTF "
     "specification asks for > 0"),
    ({"type": "perspective", "perspective": {"yfov": -0.5, "znear": 0.1}}, 0, "yfov = -0.5"),
    ({"type": "perspective", "perspective": {"yfov": 3.2, "znear": 0.1}}, 0, "180 degrees or more"),
    ({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.0}}, 0, "znear = 0, but the glTF "
     "specification asks for > 0"),
    ({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 2.0, "zfar": 2.0}}, 0, "zfar = 2 is not "
     "beyond znear = 2"),
    ({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 0}}, 0, "aspectRatio = 0"),
    ({"type": "perspective", "perspective": {"znear": 0.1}}, 0, "yfov is None, not a finite number"),
    ({"type": "orthographic", "orthographic": {"xmag": 0.0, "ymag": 1.0, "znear": 0.0, "zfar": 1.0}}, 0,
     "xmag = 0, but the glTF specification asks for not 0"),
    ({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": -1.0, "znear": 0.0, "zfar": 1.0}}, 0,
     "ymag = -1"),
    ({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 3.0, "zfar": 1.0}}, 0,
     "zfar = 1 is not beyond znear = 3"),
    ({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.0}}, 0,
     "zfar is None, not a finite number"),
    ({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": -1.0, "zfar": 1.0}}, 0,
     "znear = -1, but the glTF specification asks for >= 0"),
    ({"type": "fisheye"}, 0, "type 'fisheye' with no 'fisheye' block"),
    ({"type": "perspective", "perspective": dict(PERSPECTIVE)}, 1, "file_camera = 1: models[0] 'quad.gltf' has "
     "1 camera(s), numbered 0..0"),
]


@pytest.mark.parametrize("camera, view, needle", BAD, ids=[n for _, _, n in BAD])
def test_a_bad_file_camera_is_one_line(tmp_path, capsys, camera, view, needle):
    from wgpurender.cli import main

    write_file(tmp_path, [camera], view=view)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1, err


SCENE_MISTAKES = [
    ("from_model = 1\n", "camera.from_model = 1, but the scene has 1 [[models]] entry, numbered 0..0"),
    ("from_model = 0\neye = [0, 0, 3]\n", "camera.eye cannot be set beside camera.from_model"),
    ("file_camera = 0\neye = [0, 0, 3]\ntarget = [0, 0, 0]\n", "camera.file_camera needs camera.from_model"),
    ("from_model = -1\n", "camera.from_model must be in 0..None, got -1"),
]


@pytest.mark.parametrize("camera_keys, needle", SCENE_MISTAKES, ids=[n for _, n in SCENE_MISTAKES])
def test_scene_camera_mistakes_are_one_line(tmp_path, capsys, camera_keys, needle):
    from wgpurender.cli import main

    write_file(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}])
    text = (tmp_path / "scene.toml").read_text().replace("from_model = 0\nfile_camera = 0\n", camera_keys)
    (tmp_path / "scene.toml").write_text(text)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1, err


def test_a_file_without_cameras_or_not_gltf_is_one_line(tmp_path, capsys):
    from wgpurender.cli import main

    write_file(tmp_path, [])
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 2
    assert "models[0] 'quad.gltf' has no cameras; set eye and target instead" in capsys.readouterr().err
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "scene.toml").write_text((tmp_path / "scene.toml").read_text().replace('"quad.gltf"', '"tri.obj"'))
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 2
    assert "is not a glTF file" in capsys.readouterr().err


def test_a_camera_no_node_places_is_one_line(tmp_path, capsys):
    from wgpurender.cli import main

    write_file(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}] * 2, view=1)
    gltf = (tmp_path / "quad.gltf").read_text().replace('"camera": 1', '"camera": 0')
    (tmp_path / "quad.gltf").write_text(gltf)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 2
    assert "no node of models[0] 'quad.gltf''s scene places camera 1" in capsys.readouterr().err


@pytest.mark.parametrize("reverse", [False, True], ids=["depth-0-near", "reverse-z"])
def test_culling_planes_of_an_infinite_projection(reverse):
    """Without zfar the far plane is at infinity: the culling planes stay finite, a sphere far ahead is kept,
    one behind the camera or off to the side is culled (a NaN far plane would cull every sphere)."""
    from wgpurender.core.course.shading import REVERSE_Z
    from wgpurender.core.scene import Camera
    from wgpurender.wgpu_path.scene.cpu_culling import visible_mask
    from wgpurender.wgpu_path.scene.culling import frustum_planes

    cam = Camera(eye=(0.0, 0.0, 0.0), target=(0.0, 0.0, -1.0), near=0.1, far=math.inf)
    proj = cam.projection(1.0)
    planes = frustum_planes((REVERSE_Z @ proj if reverse else proj) @ cam.view())
    assert np.isfinite(planes).all()
    centres = np.array([[0.0, 0.0, -1e6], [0.0, 0.0, 5.0], [1e3, 0.0, -1.0], [0.0, 0.0, -2.0]])
    assert visible_mask(planes, centres, np.full(4, 0.5)).tolist() == [True, False, False, True]


def own_camera_scene(folder, cameras: list[dict]) -> None:
    """The file with ``cameras``, and a scene with its own [camera] (eye on +z, looking at the origin)."""
    write_file(folder, cameras)
    text = (folder / "scene.toml").read_text().replace("from_model = 0\nfile_camera = 0\n",
                                                        "eye = [0, 0, 3]\ntarget = [0, 0, 0]\n")
    (folder / "scene.toml").write_text(text)


@pytest.mark.parametrize("command", ["render", "reference"])
def test_cli_camera_flag_views_through_the_files_camera(tmp_path, capsys, command):
    """``--camera 1`` replaces the scene's own [camera] with the file's camera 1, on both paths' commands."""
    from wgpurender.cli import main
    from wgpurender.core.files.imageio import load_png

    ortho = {"type": "orthographic", "orthographic": dict(ORTHOGRAPHIC)}
    own_camera_scene(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}, ortho])
    out = tmp_path / "out.png"
    assert main([command, str(tmp_path / "scene.toml"), "--camera", "1", "-o", str(out)]) == 0
    check_coverage(load_png(out)[..., :3].astype(np.float64), ortho)


@pytest.mark.parametrize("args, needle", [
    (["--camera", "2"], "--camera 2: models[0] 'quad.gltf' has 2 camera(s), numbered 0..1"),
    (["--camera", "-1"], "--camera must be 0..2147483647, got -1"),
])
def test_cli_camera_flag_mistakes_are_one_line(tmp_path, capsys, args, needle):
    from wgpurender.cli import main

    own_camera_scene(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}] * 2)
    assert main(["render", str(tmp_path / "scene.toml"), "--explain", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1, err


def test_cli_camera_flag_needs_a_gltf_with_cameras_and_a_scene(tmp_path, capsys):
    from wgpurender.cli import main

    own_camera_scene(tmp_path, [])
    assert main(["render", str(tmp_path / "scene.toml"), "--explain", "--camera", "0"]) == 2
    assert "--camera 0: no model of scene.toml is a glTF file with cameras" in capsys.readouterr().err
    assert main(["render", "triangle", "-o", str(tmp_path / "t.png"), "--camera", "0"]) == 2
    assert "plan knob 'camera' applies to scene files: stage 'triangle' has no plan" in capsys.readouterr().err
    assert not (tmp_path / "t.png").exists()


def test_browser_page_keeps_the_orthographic_view_vector(tmp_path):
    """The exported page's orbit (player.js) rewrites the camera's view and eye when the wheel zooms: an
    orthographic camera's eye stays its direction with w = 0, so zooming (the eye moves along its direction,
    the projection does not change) leaves the lit, glossy frame as it was; eye - position would move the
    highlights (the lit test above: more than 8/255)."""
    from wgpurender.webpage import export
    from wgpurender.webpage.chromium import Chromium, find_chromium

    if find_chromium() is None:
        pytest.skip("chromium is not installed (apt-get install chromium)")
    camera = {"type": "orthographic", "orthographic": {"xmag": 0.45, "ymag": 0.4, "znear": 0.1, "zfar": 10.0}}
    write_file(tmp_path, [camera], unlit=False, rough=0.35, quad_corners=(-4, -4, 4, 4), own=(0.0, 0.0, 0.0),
               turn={"axis": (1.0, 0.4, 0.0), "angle": math.radians(25.0)},
               parent=tuple(rotation_matrix((1.0, 0.4, 0.0), math.radians(25.0)) @ (0.0, 0.0, 1.5)),
               extra_scene='[[lights]]\ntype = "point"\nposition = [0.2, 0.1, 0.6]\nintensity = 0.3\n\n')
    page = export(str(tmp_path / "scene.toml"), tmp_path / "page", SIZE).page
    with Chromium(webgpu=True) as browser:
        tab = browser.open(page)
        tab.evaluate("window.wgpurender.ready")
        default = tab.capture()
        box = tab.evaluate("(() => { const r = document.getElementById('view').getBoundingClientRect(); "
                           "return [r.left + r.width / 2, r.top + r.height / 2]; })()")
        tab.pipe.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": box[0], "y": box[1], "deltaX": 0,
                                                   "deltaY": -100}, session=tab.session)
        tab.evaluate("new Promise((done) => requestAnimationFrame(() => done(true)))")
        view = np.array(tab.evaluate("window.wgpurender.orbitView()"), np.float64).reshape(4, 4).T
        zoomed = tab.capture("{current: true}")
        assert not tab.errors()
    distance = float(np.linalg.norm(view[:3, 3]))
    assert distance < 1.5 * 0.95  # the wheel moved the eye closer
    assert np.abs(zoomed.astype(int) - default.astype(int)).max() <= 1


@pytest.mark.parametrize("raw", [False, True], ids=["wgpu-window", "raw-window"])
def test_the_windows_view_through_the_files_camera(display, tmp_path, raw):
    """``demo`` (both windows) draws the scene's file camera: the screenshot's coverage is the file's numbers'."""
    import os
    import subprocess
    import sys

    from wgpurender.core.files.imageio import load_png

    camera = {"type": "orthographic", "orthographic": dict(ORTHOGRAPHIC)}
    write_file(tmp_path, [camera])
    shot = tmp_path / "shot.png"
    argv = [sys.executable, "-m", "wgpurender", "demo", *(["--raw"] if raw else ["--no-overlay"]),
            str(tmp_path / "scene.toml"), "--size", f"{SIZE[0]}x{SIZE[1]}", "--frames", "2", "--screenshot", str(shot)]
    result = subprocess.run(argv, env=dict(os.environ, DISPLAY=display), capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    check_coverage(load_png(shot)[..., :3].astype(np.float64), camera)


def test_a_file_camera_too_far_for_its_znear_names_the_file_camera(tmp_path, capsys):
    """The depth check of a scene's camera (near >= distance x 2^-20) applies to a file camera too, at the model's
    origin, naming the file's camera and znear."""
    from wgpurender.cli import main

    write_file(tmp_path, [{"type": "perspective", "perspective": dict(PERSPECTIVE)}], parent=(0.0, 0.0, 1e6))
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 2
    err = capsys.readouterr().err.strip()
    assert "models[0] 'quad.gltf' camera 0 at node 1: znear = 0.05 is too small for the depth buffer: at the " \
           "model's origin's distance" in err and len(err.splitlines()) == 1, err
