"""Validation of each part of a scene file (camera, materials, models, lights, render, post) into the dataclasses."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from wgpurender.core.course.formats import POST_PATHS, SAMPLE_COUNTS
from wgpurender.core.course.shading import DEFAULT_ALBEDO_COLOR, DEFAULT_CLEAR_COLOR, DEFAULT_ROUGHNESS
from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import file_suffix
from wgpurender.core.models.gltf_animation import Pose
from wgpurender.core.scene.checker import Checker as _Checker
from wgpurender.core.scene.checker import _type_name
from wgpurender.core.scene.instances import instances
from wgpurender.core.scene.model import (
    ADDRESS_MODES,
    CONVENTIONS,
    DEFAULT_MATERIAL,
    FILTERS,
    IDENTITY,
    LIGHT_TYPES,
    MAX_ANISOTROPY,
    MAX_LIGHTS,
    OUTPUT_FORMATS,
    Camera,
    Light,
    Material,
    Model,
    PostStep,
    RenderSettings,
    SamplerSettings,
    Transform,
    Vec4,
    _rows,
)
from wgpurender.core.scene.toml_locator import KeyPath, format_path
from wgpurender.core.view import transforms

TOP_KEYS = ("camera", "description", "environment", "lights", "materials", "models", "post", "render")
CAMERA_KEYS = ("convention", "eye", "far", "file_camera", "fov_y", "from_model", "near", "target", "up")
FILE_CAMERA_KEYS = ("file_camera", "from_model")  # a model file's camera (core/scene/gltf_cameras.py)
MATERIAL_KEYS = (
    "albedo_color", "albedo_map", "normal_map", "roughness", "roughness_map", "sampler", "unlit", "uv_flip_v"
)
SAMPLER_KEYS = ("address_mode", "anisotropy", "filter", "mipmaps")
MODEL_KEYS = ("animation", "instances", "material", "path", "time", "transform")
TRANSFORM_KEYS = ("matrix", "rotate", "scale", "translate")
LIGHT_KEYS = ("color", "direction", "intensity", "position", "type")
RENDER_KEYS = ("clear_color", "hdr", "msaa", "output_format", "post_fuse", "post_path", "size")


def file_camera_choice(c: _Checker, data: Any) -> tuple[int, int] | None:
    """``[camera] from_model = M`` (and ``file_camera = K``, default 0): view through camera K of model M's file,
    whose node gives eye, direction and up and whose numbers give the projection, so the scene's own camera keys
    are refused beside it. None: the scene's own camera (eye, target, ...)."""
    key = ("camera",)
    t = c.table(data, key, CAMERA_KEYS)
    if "from_model" not in t:
        if "file_camera" in t:
            raise c.error(key + ("file_camera",), "camera.file_camera needs camera.from_model: the index of the "
                                                  "[[models]] entry whose glTF file holds the camera")
        return None
    clash = sorted(set(t) - set(FILE_CAMERA_KEYS))
    if clash:
        raise c.error(key + (clash[0],), f"camera.{clash[0]} cannot be set beside camera.from_model: the file's "
                                         "camera gives the view and the projection; remove one or the other")
    return (c.integer(t["from_model"], key + ("from_model",), lo=0),
            c.integer(t.get("file_camera", 0), key + ("file_camera",), lo=0))


def resolve_file_camera(c: _Checker, choice: tuple[int, int], models: tuple[Model, ...]) -> Camera:
    """The scene camera of ``choice`` (file_camera_choice), checked like a scene's own camera."""
    from wgpurender.core.scene.gltf_cameras import file_camera

    model, index = choice
    key = ("camera", "from_model")
    if model >= len(models):
        raise c.error(key, f"camera.from_model = {model}, but the scene has {len(models)} [[models]] entr"
                           f"{'y' if len(models) == 1 else 'ies'}" + (f", numbered 0..{len(models) - 1}"
                                                                       if models else ""))
    try:
        cam = file_camera(models[model], index)
    except UserError as err:
        raise c.error(key, str(err)) from None
    _check_view(c, cam)
    return cam


def _camera(c: _Checker, data: Any) -> Camera:
    key = ("camera",)
    t = c.table(data, key, CAMERA_KEYS, required=("eye", "target"))
    cam = Camera(
        eye=c.vector(t["eye"], key + ("eye",)),
        target=c.vector(t["target"], key + ("target",)),
        up=c.vector(t.get("up", [0, 1, 0]), key + ("up",), nonzero=True),
        fov_y=c.number(t.get("fov_y", 45.0), key + ("fov_y",), 0.0, 180.0, open_lo=True),
        near=c.number(t.get("near", 0.1), key + ("near",), 0.0, open_lo=True),
        far=c.number(t.get("far", 100.0), key + ("far",), 0.0, open_lo=True),
        convention=c.string(t.get("convention", "wgpu"), key + ("convention",), CONVENTIONS),
    )
    if cam.fov_y >= 180:
        raise c.error(key + ("fov_y",), f"camera.fov_y must be below 180 degrees, got {cam.fov_y}")
    if cam.far <= cam.near:
        raise c.error(key + ("far",), f"camera.far ({cam.far}) must be greater than camera.near ({cam.near})")
    if cam.eye == cam.target:
        raise c.error(key + ("target",), "camera.eye and camera.target are the same point")
    _check_view(c, cam)
    return cam


DEPTH_STEPS_EXPONENT = 20  # near >= distance * 2^-20: the target keeps 16 float32 depth steps below 1.0


def _check_view(c: _Checker, cam: Camera) -> None:
    """The camera's consequences, in the float32 the GPU gets: a view direction and an up vector that are not
    parallel, matrices that stay finite, and a near plane the depth buffer can resolve at the target."""
    key = ("camera",)
    eye, target, up = (np.array(v, np.float64) for v in (cam.eye, cam.target, cam.up))
    forward = (target - eye) / np.abs(target - eye).max()  # scaled first: no overflow in the norm
    forward /= np.linalg.norm(forward)
    up_dir = up / np.abs(up).max()
    up_dir /= np.linalg.norm(up_dir)
    if np.linalg.norm(np.cross(forward, up_dir)) < 1e-6:
        raise c.error(key + ("up",), f"camera.up {list(cam.up)} is parallel to the view direction (eye to target "
                                     f"{list(np.round(forward, 6))}): choose an up vector across it, e.g. [0, 0, 1]")
    try:
        view = cam.view()
        clip = cam.projection(1.0) @ view
    except ValueError as err:
        raise c.error(key + ("up",), f"camera: {err}") from None
    if not (np.all(np.isfinite(view.astype(np.float32))) and np.all(np.isfinite(clip.astype(np.float32)))):
        raise c.error(key + ("eye",), f"camera: eye {list(cam.eye)} and target {list(cam.target)} give a view "
                                      "matrix beyond float32's range; bring them closer to the origin")
    distance = float(np.linalg.norm((target - eye) / 2.0**64)) * 2.0**64
    least = distance * 2.0**-DEPTH_STEPS_EXPONENT
    if cam.near < least and cam.projection_type == "perspective":  # orthographic depth is linear: near 0 is fine
        name, where = ("camera.near", "target") if not cam.origin else (f"{cam.origin}: znear", "model's origin")
        raise c.error(key + ("near",), f"{name} = {cam.near:g} is too small for the depth buffer: at the "
                                       f"{where}'s distance ({distance:.6g}) the depth rounds to 1.0 in float32, "
                                       f"so nothing would be drawn; use near >= {least:.3g}")


def _sampler(c: _Checker, data: Any, key: KeyPath) -> SamplerSettings:
    t = c.table(data, key, SAMPLER_KEYS)
    s = SamplerSettings(
        filter=c.string(t.get("filter", "linear"), key + ("filter",), FILTERS),
        mipmaps=c.boolean(t.get("mipmaps", True), key + ("mipmaps",)),
        anisotropy=c.integer(t.get("anisotropy", 1), key + ("anisotropy",), lo=1, hi=MAX_ANISOTROPY),
        address_mode=c.string(t.get("address_mode", "repeat"), key + ("address_mode",), ADDRESS_MODES),
    )
    if s.anisotropy > 1 and s.filter != "linear":
        raise c.error(
            key + ("anisotropy",),
            f"{format_path(key)}: anisotropy {s.anisotropy} needs filter = \"linear\" "
            "(wgpu allows anisotropic filtering only with linear min, mag and mipmap filters)",
        )
    return s


def _material(c: _Checker, data: Any, key: KeyPath, name: str, origin: str) -> Material:
    t = c.table(data, key, MATERIAL_KEYS)
    written = tuple((k, v if isinstance(v, str) else repr(v)) for k, v in t.items() if k != "sampler")
    maps = {k: c.file(t[k], key + (k,), "texture") for k in ("albedo_map", "normal_map", "roughness_map") if k in t}
    return Material(
        name=name,
        albedo_color=_color(c, t.get("albedo_color", list(DEFAULT_ALBEDO_COLOR)), key + ("albedo_color",)),
        roughness=c.number(t.get("roughness", DEFAULT_ROUGHNESS), key + ("roughness",), 0.0, 1.0),
        unlit=c.boolean(t.get("unlit", False), key + ("unlit",)),
        uv_flip_v=c.boolean(t.get("uv_flip_v", False), key + ("uv_flip_v",)),
        sampler=_sampler(c, t.get("sampler", {}), key + ("sampler",)),
        origin=origin,
        written=written,
        **maps,
    )


def _color(c: _Checker, value: Any, key: KeyPath) -> Vec4:
    v = c.vector(value, key, lengths=(3, 4))
    if min(v) < 0:
        raise c.error(key, f"{format_path(key)} must not be negative, got {list(v)}")
    return v if len(v) == 4 else (*v, 1.0)


def _transform(c: _Checker, data: Any, key: KeyPath) -> Transform:
    t = c.table(data, key, TRANSFORM_KEYS)
    if "matrix" in t:
        others = sorted(set(t) - {"matrix"})
        if others:
            raise c.error(key + (others[0],), f"{format_path(key)}: matrix cannot be combined with {', '.join(others)}")
        rows = t["matrix"]
        if not isinstance(rows, list) or len(rows) != 4:
            raise c.error(key + ("matrix",), f"{format_path(key)}.matrix must be 4 rows of 4 numbers")
        m = np.array([c.vector(r, key + ("matrix",), lengths=(4,)) for r in rows])
        if transforms.flat(m):
            raise c.error(key + ("matrix",), f"{format_path(key)}.matrix is singular (its 3x3 part has determinant 0)")
        return Transform(_rows(m), "matrix")
    if not t:
        return IDENTITY  # most models of a large scene: no matrix to build
    if len(t) == 1 and "translate" in t:  # the next most common (10k placed copies of one mesh): no numpy
        offset = c.vector(t["translate"], key + ("translate",))
        return Transform(_translation_rows(offset), f"translate {list(offset)}")
    parts, m = [], np.eye(4)
    if "translate" in t:
        offset = c.vector(t["translate"], key + ("translate",))
        m = m @ transforms.translate(offset)
        parts.append(f"translate {list(offset)}")
    if "rotate" in t:
        rot, text = _rotation(c, t["rotate"], key + ("rotate",))
        m = m @ rot
        parts.append(text)
    if "scale" in t:
        s = t["scale"]
        factors = (c.number(s, key + ("scale",)),) * 3 if not isinstance(s, list) else c.vector(s, key + ("scale",))
        if not all(factors):
            raise c.error(key + ("scale",), f"{format_path(key)}.scale must not be 0 on any axis")
        m = m @ transforms.scale(factors)
        parts.append(f"scale {list(factors) if isinstance(s, list) else factors[0]}")
    return Transform(_rows(m), ", ".join(parts) or "identity")


def _translation_rows(offset: tuple) -> tuple[tuple[float, ...], ...]:
    """The rows numpy's ``np.eye(4) @ transforms.translate(offset)`` holds, made without numpy (+ 0.0: the
    product's sum turns a -0.0 offset into 0.0)."""
    x, y, z = (float(v) + 0.0 for v in offset)
    return (1.0, 0.0, 0.0, x), (0.0, 1.0, 0.0, y), (0.0, 0.0, 1.0, z), (0.0, 0.0, 0.0, 1.0)


def _rotation(c: _Checker, data: Any, key: KeyPath) -> tuple[np.ndarray, str]:
    """{axis, degrees} (right-hand rule) or {euler = [x, y, z]} in degrees, applied X first: Rz @ Ry @ Rx."""
    t = c.table(data, key, ("axis", "degrees", "euler"))
    if "euler" in t:
        if set(t) != {"euler"}:
            raise c.error(key, f"{format_path(key)}: give either euler, or axis and degrees")
        ex, ey, ez = c.vector(t["euler"], key + ("euler",))
        rot = (transforms.rotate((0, 0, 1), math.radians(ez)) @ transforms.rotate((0, 1, 0), math.radians(ey))
               @ transforms.rotate((1, 0, 0), math.radians(ex)))
        return rot, f"rotate euler XYZ [{ex}, {ey}, {ez}] deg"
    if set(t) != {"axis", "degrees"}:
        raise c.error(key, f"{format_path(key)}: give either euler, or axis and degrees")
    axis = c.vector(t["axis"], key + ("axis",), nonzero=True)
    degrees = c.number(t["degrees"], key + ("degrees",))
    return transforms.rotate(axis, math.radians(degrees)), f"rotate {degrees} deg about {list(axis)}"


def _model_path(c: _Checker, value: Any, key: KeyPath, found: Path | None = None) -> Path:
    """The model file ``value`` names, checked (format, then the file and the read rule); ``found``: what
    Checker.files_ahead already let through for it (None: checked here)."""
    from wgpurender.core.models.mesh import SUPPORTED, UNSUPPORTED

    written = c.string(value, key)
    suffix = file_suffix(written).lower()
    if suffix in UNSUPPORTED:
        raise c.error(key, f"{format_path(key)}: '{written}' is {UNSUPPORTED[suffix]}, which cannot be loaded: "
                           f"convert it to glTF (.glb); supported formats: {', '.join(SUPPORTED)}")
    if suffix not in SUPPORTED:
        raise c.error(key, f"{format_path(key)}: '{written}' has an unknown model format "
                           f"(supported: {', '.join(SUPPORTED)})")
    return found if found is not None else c.file(written, key, "model file")


def _models(c: _Checker, data: Any, materials: dict[str, Material]) -> tuple[Model, ...]:
    if not isinstance(data, list):
        raise c.error(("models",), "models must be an array of tables: write each as [[models]]")
    out = []
    # every plain model path checked in one pass; the loop still checks each model in order, so an error is the
    # same one line, about the same model, as without this pass
    ahead = c.files_ahead([entry.get("path") if isinstance(entry, dict) else None for entry in data])
    for i, entry in enumerate(data):
        key = ("models", i)
        t = c.table(entry, key, MODEL_KEYS, required=("path",))
        material = DEFAULT_MATERIAL
        if "material" in t:
            m = t["material"]
            if isinstance(m, str):
                if m not in materials:
                    valid = ", ".join(sorted(materials)) or "none defined"
                    raise c.error(key + ("material",), f"models[{i}].material: no material '{m}' "
                                                       f"(materials: {valid}; define it as [materials.{m}])")
                material = materials[m]
            else:
                material = _material(c, m, key + ("material",), f"models[{i}]", f"models[{i}].material (inline)")
        out.append(
            Model(
                index=i,
                path=_model_path(c, t["path"], key + ("path",), ahead[i]),
                written_path=t["path"],
                material=material,
                transform=_transform(c, t.get("transform", {}), key + ("transform",)),
                material_from_file="material" not in t,
                placements=instances(c, t["instances"], key + ("instances",)) if "instances" in t else None,
                pose=_pose(c, t, key),
            )
        )
    return tuple(out)


def _pose(c: _Checker, t: dict, key: KeyPath) -> Pose | None:
    """A glTF model's animation pose: ``time`` (seconds, default 0) of ``animation`` (a name or an index, default
    the first); None when neither is given (the nodes as written). Whether the file has that animation is checked
    when it is read (core/models/gltf_animation.choose)."""
    if "time" not in t and "animation" not in t:
        return None
    if not str(t.get("path", "")).lower().endswith((".gltf", ".glb")):
        given = "time" if "time" in t else "animation"
        raise c.error(key + (given,), f"{format_path(key + (given,))}: only a glTF model (.gltf, .glb) has "
                                      "animations to pose; remove it")
    animation = t.get("animation")
    if animation is not None and not isinstance(animation, str):
        animation = c.integer(animation, key + ("animation",), lo=0)
    return Pose(animation, c.number(t.get("time", 0.0), key + ("time",)))


def _lights(c: _Checker, data: Any) -> tuple[Light, ...]:
    if not isinstance(data, list):
        raise c.error(("lights",), "lights must be an array of tables: write each as [[lights]]")
    if len(data) > MAX_LIGHTS:
        raise c.error(("lights", MAX_LIGHTS), f"{len(data)} lights, but at most MAX_LIGHTS = {MAX_LIGHTS} are "
                                              f"supported: remove {len(data) - MAX_LIGHTS}")
    out = []
    for i, entry in enumerate(data):
        key = ("lights", i)
        t = c.table(entry, key, LIGHT_KEYS, required=("type",))
        kind = c.string(t["type"], key + ("type",), LIGHT_TYPES)
        needs, forbids = ("direction", "position") if kind == "directional" else ("position", "direction")
        if needs not in t:
            raise c.error(key, f"lights[{i}]: a {kind} light needs '{needs}'")
        if forbids in t:
            raise c.error(key + (forbids,), f"lights[{i}]: a {kind} light has no '{forbids}' (it has '{needs}')")
        color = _color(c, t.get("color", [1, 1, 1]), key + ("color",))
        out.append(
            Light(
                index=i,
                type=kind,
                color=color[:3],
                intensity=c.number(t.get("intensity", 1.0), key + ("intensity",), 0.0),
                direction=c.vector(t[needs], key + (needs,), nonzero=True) if kind == "directional" else None,
                position=c.vector(t[needs], key + (needs,)) if kind == "point" else None,
            )
        )
    return tuple(out)


def _render(c: _Checker, data: Any) -> RenderSettings:
    key = ("render",)
    t = c.table(data, key, RENDER_KEYS)
    size = t.get("size", [800, 600])
    if not isinstance(size, list) or len(size) != 2:
        raise c.error(key + ("size",), f"render.size must be [width, height], got {size!r}")
    w, h = (c.integer(v, key + ("size",), lo=1, hi=16384) for v in size)
    return RenderSettings(
        size=(w, h),
        msaa=c.integer(t.get("msaa", 4), key + ("msaa",), choices=SAMPLE_COUNTS),
        hdr=c.boolean(t.get("hdr", True), key + ("hdr",)),
        clear_color=_color(c, t.get("clear_color", list(DEFAULT_CLEAR_COLOR)), key + ("clear_color",)),
        output_format=c.string(t.get("output_format", "rgba8unorm-srgb"), key + ("output_format",), OUTPUT_FORMATS),
        post_fuse=c.boolean(t.get("post_fuse", True), key + ("post_fuse",)),
        post_path=c.string(t.get("post_path", "auto"), key + ("post_path",), POST_PATHS),
    )


def _post(c: _Checker, data: Any) -> tuple[PostStep, ...]:
    from wgpurender.core.course.effects import EFFECTS, check_order, effect_names

    if not isinstance(data, list):
        raise c.error(("post",), "post must be an array of tables: write each effect as [[post]]")
    steps = []
    for i, entry in enumerate(data):
        key = ("post", i)
        if not isinstance(entry, dict):
            raise c.error(key, f"post[{i}] must be a table, got {_type_name(entry)}")
        if "effect" not in entry:
            raise c.error(key, f"post[{i}] needs 'effect': one of {', '.join(effect_names())}")
        name = c.string(entry["effect"], key + ("effect",))
        if name not in EFFECTS:
            raise c.error(key + ("effect",), f"post[{i}]: unknown effect '{name}': valid effects are "
                                             f"{', '.join(effect_names())}")
        spec = EFFECTS[name]
        specs = {p.name: p for p in spec.params}
        params = {k: v for k, v in entry.items() if k != "effect"}
        c.table(params, key, ("effect", *specs))
        try:
            values = spec.validate(params)
        except UserError as err:
            bad = _culprit(spec, params)
            raise c.error(key + ((bad,) if bad else ()), f"post[{i}]: {err}") from None
        steps.append(PostStep(index=i, effect=name, params=values, written=tuple(params)))
    try:
        check_order([s.effect for s in steps])
    except UserError as err:
        raise c.error(("post", len(steps) - 1), str(err)) from None
    return tuple(steps)


def _culprit(spec, params: dict) -> str | None:
    """The first parameter that the effect refuses on its own (so the error points at its line)."""
    for name, value in params.items():
        try:
            spec.validate({name: value})
        except UserError:
            return name
    return next(iter(params), None)
