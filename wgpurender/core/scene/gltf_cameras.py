"""A glTF model's own camera as the scene's camera (``[camera] from_model = M``, ``file_camera = K``).

glTF 2.0, section 3.10 (Cameras): a camera is placed by a node; it looks down the node's local -Z with +Y up, at
the node's global transform (here the model's scene transform applied after the file's hierarchy). Its numbers:
- perspective: ``yfov`` (radians, > 0), ``znear`` (> 0), optional ``zfar`` (> znear; absent: an infinite
  projection) and optional ``aspectRatio`` (> 0; absent: the target's aspect);
- orthographic: ``xmag`` and ``ymag`` (half-extents, != 0; a negative one, which the specification says should
  not be used, would mirror the image and is refused too), ``znear`` (>= 0), ``zfar`` (> znear).
The result is a plain :class:`Camera`: eye at the node's origin, target one step along its -Z (at the model's
distance, so an orbit pivots about there), up its +Y. Scale in the node's matrix does not reach the view.
"""

from __future__ import annotations

import math

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.models import gltf_animation, gltf_geometry
from wgpurender.core.scene.model import Camera, Model

GLTF_SUFFIXES = (".gltf", ".glb")


def placed_cameras(doc) -> list[tuple[np.ndarray, int, int]]:
    """(world matrix, camera index, node index) for each node of the drawn scene that places a camera."""
    return [(world, node["camera"], index) for world, index, node in gltf_geometry.node_worlds(doc)
            if "camera" in node]


def _number(block: dict, name: str, where: str, lo: float, *, lo_open: bool, required: bool = True,
            nonzero: bool = False) -> float | None:
    """``block[name]`` as a finite float >= lo (> lo with ``lo_open``), else one line saying what is wrong."""
    if name not in block and not required:
        return None
    value = block.get(name)
    if not isinstance(value, int | float) or isinstance(value, bool) or not math.isfinite(value):
        raise UserError(f"{where}: {name} is {value!r}, not a finite number; fix the file")
    if value < lo or (lo_open and value == lo) or (nonzero and value == 0):
        bound = "not 0" if nonzero and lo == 0 and not lo_open else f"{'>' if lo_open else '>='} {lo:g}"
        raise UserError(f"{where}: {name} = {value:g}, but the glTF specification asks for {bound}; fix the file "
                        "or view through another camera")
    return float(value)


def _projection(camera: dict, where: str) -> dict:
    """The Camera fields of a file camera's projection, its numbers checked against the specification."""
    kind = camera.get("type")
    block = camera.get(kind) if kind in ("perspective", "orthographic") else None
    if not isinstance(block, dict):
        raise UserError(f"{where}: type {kind!r} with no '{kind}' block: a glTF camera is \"perspective\" or "
                        "\"orthographic\" with the numbers under that name; fix the file")
    where = f"{where} ({kind})"
    if kind == "perspective":
        fields = {"fov_y": math.degrees(_number(block, "yfov", where, 0.0, lo_open=True)),
                  "near": _number(block, "znear", where, 0.0, lo_open=True),
                  "far": _number(block, "zfar", where, 0.0, lo_open=True, required=False) or math.inf,
                  "aspect_ratio": _number(block, "aspectRatio", where, 0.0, lo_open=True, required=False)}
        if fields["fov_y"] >= 180.0:
            raise UserError(f"{where}: yfov = {block['yfov']:g} radians is 180 degrees or more; fix the file")
    else:
        fields = {"xmag": _number(block, "xmag", where, 0.0, lo_open=False, nonzero=True),
                  "ymag": _number(block, "ymag", where, 0.0, lo_open=False, nonzero=True),
                  "near": _number(block, "znear", where, 0.0, lo_open=False),
                  "far": _number(block, "zfar", where, 0.0, lo_open=True)}
    if fields["far"] <= fields["near"]:
        raise UserError(f"{where}: zfar = {fields['far']:g} is not beyond znear = {fields['near']:g}; fix the file")
    return {"projection_type": kind, **fields}


def file_camera(model: Model, index: int, asked: str = "") -> Camera:
    """The scene camera of camera ``index`` of ``model``'s glTF file, at its first node in the drawn scene
    (``asked``: how the index was given, for the refusals; default the scene's ``[camera] file_camera``)."""
    from wgpurender.core.scene.gltf_materials import document

    label = model.label
    asked = asked or f"[camera] file_camera = {index}"
    if model.suffix not in GLTF_SUFFIXES:
        raise UserError(f"[camera] from_model = {model.index}: {label} is not a glTF file, and only glTF files "
                        "carry cameras; set eye and target instead")
    if model.placements is not None:
        raise UserError(f"[camera] from_model = {model.index}: {label} has instances, so its camera would be in "
                        "each copy; view through a model without instances")
    doc = gltf_animation.posed(document(str(model.path)), model.pose)  # an animated camera node: at the time
    cameras = doc.json.get("cameras", [])
    if not cameras:
        raise UserError(f"[camera] from_model = {model.index}: {label} has no cameras; set eye and target instead")
    if not 0 <= index < len(cameras):
        raise UserError(f"{asked}: {label} has {len(cameras)} camera(s), numbered 0.."
                        f"{len(cameras) - 1}")
    placed = [(world, node) for world, k, node in placed_cameras(doc) if k == index]
    if not placed:
        raise UserError(f"{asked}: no node of {label}'s scene places camera {index}, so it "
                        "has no position; choose another or place it in the file")
    world, node = placed[0]
    where = f"{label} camera {index}" + (f" '{cameras[index]['name']}'" if cameras[index].get("name") else "")
    projection = _projection(cameras[index], where)
    world = np.asarray(model.transform.matrix, np.float64) @ world
    forward, up, eye = world[:3, :3] @ (0.0, 0.0, -1.0), world[:3, :3] @ (0.0, 1.0, 0.0), world[:3, 3]
    if min(np.linalg.norm(forward), np.linalg.norm(up), np.linalg.norm(np.cross(forward, up))) < 1e-12:
        raise UserError(f"{where}: its node's matrix is flat (a zero scale), so it has no view direction; fix the "
                        "file")
    distance = float(np.linalg.norm(world[:3, 3] - np.asarray(model.transform.matrix)[:3, 3])) or 1.0
    target = eye + forward / np.linalg.norm(forward) * distance
    more = f", the first of {len(placed)} nodes placing it" if len(placed) > 1 else ""
    return Camera(eye=_vec(eye), target=_vec(target), up=_vec(up / np.linalg.norm(up)),
                  origin=f"{where} at node {node}{more}", file_camera=(model.index, index), **projection)


def with_file_camera(scene, index: int):
    """``scene`` viewed through camera ``index`` of its glTF model (``--camera K``): the model its ``[camera]``
    already takes a camera from, else the first glTF model that has cameras."""
    import dataclasses

    from wgpurender.core.scene.gltf_materials import document

    chosen = [m for m in scene.models if scene.camera.origin.startswith(f"{m.label} camera ")]
    if not chosen:
        chosen = [m for m in scene.models if m.suffix in GLTF_SUFFIXES
                  and document(str(m.path)).json.get("cameras")]
    if not chosen:
        raise UserError(f"--camera {index}: no model of {scene.path.name} is a glTF file with cameras; leave "
                        "--camera out (the scene's [camera] is the view)")
    return dataclasses.replace(scene, camera=file_camera(chosen[0], index, f"--camera {index}"))


def _vec(v) -> tuple[float, float, float]:
    return tuple(float(x) for x in v)


def describe(camera: dict) -> str:
    """One file camera's numbers, as ``--explain`` lists them."""
    kind = camera.get("type")
    block = camera.get(kind, {}) if isinstance(camera.get(kind), dict) else {}
    name = f" '{camera['name']}'" if camera.get("name") else ""
    numbers = ", ".join(f"{k} {v:g}" for k, v in block.items() if isinstance(v, int | float))
    return f"{kind}{name}" + (f" ({numbers})" if numbers else "")


def camera_note(camera: Camera, models: tuple[Model, ...]) -> list[str]:
    """``--explain``'s camera lines: which camera the view is, and every glTF model's cameras, listed."""
    from wgpurender.core.scene.gltf_materials import document

    out = []
    if camera.origin:
        aspect = f"aspect {camera.aspect_ratio:g} (the file's)" if camera.aspect_ratio else "the target's aspect"
        far = "no zfar: infinite projection" if math.isinf(camera.far) else f"far {camera.far:g}"
        shape = f"perspective, fov_y {camera.fov_y:.4g} deg, {aspect}"
        if camera.projection_type == "orthographic":
            shape = f"orthographic, xmag {camera.xmag:g}, ymag {camera.ymag:g}"
        out.append(f"the view is {camera.origin} ({shape}, near {camera.near:g}, {far}); eye "
                   f"{[round(v, 6) for v in camera.eye]}, looking along {[round(float(v), 6) for v in _look(camera)]}")
    for model in models:
        if model.suffix not in GLTF_SUFFIXES:
            continue
        cameras = document(str(model.path)).json.get("cameras", [])
        for k, cam in enumerate(cameras):
            used = camera.origin.startswith(f"{model.label} camera {k} ")
            out.append(f"{model.label} camera {k}: {describe(cam)}"
                       + (" <- the view" if used else f" (not the view: --camera {k}, or [camera] from_model = "
                          f"{model.index}, file_camera = {k}, views through it)"))
    return out


def _look(camera: Camera) -> np.ndarray:
    d = np.asarray(camera.target, np.float64) - np.asarray(camera.eye, np.float64)
    return d / np.linalg.norm(d)
