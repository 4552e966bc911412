"""A glTF model's KHR_lights_punctual lights as scene lights, in the scene's light units.

Each node with ``extensions.KHR_lights_punctual.light`` places one of the file's lights at the node's world
position (the model's scene transform applied after the file's node hierarchy), pointing along the node's local
-Z. Types: ``directional``, ``point``, ``spot`` (``innerConeAngle`` default 0, ``outerConeAngle`` default pi/4:
a point light with a cone, ``Light.shape`` in core/scene/model.py); ``range`` (no range: the plain inverse square);
``color`` (linear) and ``intensity``.

Units: the extension gives directional lights in lux (illuminance) and point and spot lights in candela
(E = I / d^2), with a BRDF f reflecting L = f E cos. The scene's lights are such that intensity 1 straight onto
a white Lambertian surface gives 1, L = pi f E cos (shaders_wgsl/pbr.wgsl), so a file light of intensity I
becomes a scene light of intensity I / pi.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.models import gltf_animation, gltf_geometry, gltf_io
from wgpurender.core.scene.model import MAX_LIGHTS, Light, Model

EXTENSION = "KHR_lights_punctual"
KHR_TYPES = ("directional", "point", "spot")


def placed_lights(doc: gltf_io.GltfDocument) -> list[tuple[np.ndarray, int, int]]:
    """(world matrix, light index, node index) for each node that places a KHR_lights_punctual light."""
    out = []
    for world, index, node in gltf_geometry.node_worlds(doc):
        light = _light_of(node)
        if light is not None:
            if not isinstance(light, int) or isinstance(light, bool):
                raise UserError(f"malformed glTF file {doc.path}: node {index}'s {EXTENSION} light is {light!r}, "
                                "not an index; fix the file")
            out.append((world, light, index))
    return out


def _light_of(node: dict):
    """The light index a node's KHR_lights_punctual extension names (None: the node places no light)."""
    ext = node.get("extensions", {}).get(EXTENSION) if isinstance(node.get("extensions"), dict) else None
    return ext.get("light") if isinstance(ext, dict) else None


def model_lights(model: Model, first_index: int) -> list[Light]:
    """The scene lights of a glTF ``model``'s KHR_lights_punctual nodes, numbered from ``first_index``."""
    if model.suffix not in (".gltf", ".glb"):
        return []
    from wgpurender.core.scene.gltf_materials import document

    doc = document(str(model.path))
    defined = doc.json.get("extensions", {}).get(EXTENSION, {})
    defined = defined.get("lights", []) if isinstance(defined, dict) else None
    if not isinstance(defined, list):
        raise UserError(f"malformed glTF file {doc.path}: extensions.{EXTENSION}.lights is not a list; fix the file")
    if not any(_light_of(node) is not None for node in doc.json.get("nodes", []) if isinstance(node, dict)):
        return []  # posing moves nodes, it places no light: the window's every frame need not pose the file here
    doc = gltf_animation.posed(doc, model.pose)  # a light on an animated node: at the time
    out = []
    for world, k, node in placed_lights(doc):
        if not 0 <= k < len(defined):
            raise UserError(f"malformed glTF file {doc.path}: node {node} places {EXTENSION} light {k}, but the "
                            f"file defines {len(defined)}; re-export the file")
        matrix = np.asarray(model.transform.matrix, np.float64) @ world
        out.append(_scene_light(defined[k], matrix, first_index + len(out), f"{model.label} light {k}"
                                + (f" '{defined[k]['name']}'" if defined[k].get("name") else "")))
    return out


def _number(value, what: str, lo: float, hi: float = math.inf, lo_open: bool = False) -> float:
    """A JSON number within [lo, hi] ((lo, hi] with ``lo_open``), else one line naming it and its range."""
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or value < lo or value > hi or (lo_open and value == lo):
        bound = f"{'>' if lo_open else '>='} {lo:g}" + (f" and <= {hi:.4g}" if hi < math.inf else "")
        raise UserError(f"{what} is {value!r}: the extension asks for a number {bound}; fix the file")
    return float(value)


def _scene_light(light: dict, matrix: np.ndarray, index: int, origin: str) -> Light:
    kind = light.get("type") if isinstance(light, dict) else None
    if kind not in KHR_TYPES:
        raise UserError(f"{origin}: {EXTENSION} type {kind!r} is not one of {', '.join(KHR_TYPES)}; fix the file")
    what = f"{origin}: {EXTENSION}"
    color = light.get("color", [1.0, 1.0, 1.0])
    if not isinstance(color, list) or len(color) != 3:
        raise UserError(f"{what} color is {color!r}: the extension asks for [r, g, b]; fix the file")
    color = tuple(_number(c, f"{what} color", 0.0) for c in color)
    intensity = _number(light.get("intensity", 1.0), f"{what} intensity", 0.0) / math.pi  # lux, cd -> scene units
    axis = matrix[:3, :3] @ np.array([0.0, 0.0, -1.0])
    if not np.isfinite(axis).all() or np.linalg.norm(axis) < 1e-12:
        raise UserError(f"{origin}: its node's matrix has no direction (scale 0); fix the file")
    direction = tuple(float(a) for a in axis / np.linalg.norm(axis))
    if kind == "directional":
        return Light(index, "directional", color, intensity, direction=direction, origin=origin)
    cone = None
    if kind == "spot":
        spot = light.get("spot", {})
        spot = spot if isinstance(spot, dict) else {"outerConeAngle": spot}
        outer = _number(spot.get("outerConeAngle", math.pi / 4), f"{what} outerConeAngle", 0.0, math.pi / 2, True)
        cone = (_number(spot.get("innerConeAngle", 0.0), f"{what} innerConeAngle", 0.0, outer), outer)
        if cone[0] == outer:
            raise UserError(f"{what} innerConeAngle equals outerConeAngle ({outer:g}): the extension asks for "
                            "inner < outer; fix the file")
    reach = _number(light["range"], f"{what} range", 0.0, lo_open=True) if "range" in light else 0.0
    position = tuple(float(p) for p in matrix[:3, 3])
    return Light(index, "point", color, intensity, direction=direction if cone else None, position=position,
                 range=reach, cone=cone, origin=origin)


def scene_lights(lights: tuple[Light, ...], models: tuple[Model, ...], where: Path) -> tuple[Light, ...]:
    """The scene's own lights followed by its glTF models' lights; more than MAX_LIGHTS in all is refused."""
    out = list(lights)
    for model in models:
        out += model_lights(model, len(out))
    if len(out) > MAX_LIGHTS:
        raise UserError(f"{where}: {len(out)} lights with the models' {EXTENSION} lights ({len(lights)} in the "
                        f"scene), but at most MAX_LIGHTS = {MAX_LIGHTS} are supported: remove "
                        f"{len(out) - MAX_LIGHTS}")
    return tuple(out)


def light_note(light: Light) -> str:
    """The ``--explain`` line of a model file's light: what it is and its intensity in both units."""
    kind = "spot" if light.cone else light.type
    unit = "lux" if kind == "directional" else "cd"
    text = (f"{light.label}: {EXTENSION} {kind}, intensity {light.intensity * math.pi:g} {unit} -> "
            f"{light.intensity:.4g} in the scene's units (/ pi), colour {tuple(round(c, 4) for c in light.color)}")
    if light.cone:
        text += f", cone {math.degrees(light.cone[0]):.1f}-{math.degrees(light.cone[1]):.1f} deg"
    if light.type == "point":
        text += f", range {light.range:g}" if light.range > 0 else ", no range (inverse square)"
    return text
