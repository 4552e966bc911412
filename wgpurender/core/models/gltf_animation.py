"""glTF 2.0 animations sampled at one time: a still of the file's pose at ``t`` seconds (glTF 2.0, 3.11).

A channel drives one node's ``translation``, ``rotation``, ``scale`` or morph ``weights`` from a sampler's
keyframes (input: times in seconds, increasing; output: values). :func:`posed` returns the document with those
node properties replaced by their values at ``t``, so the node graph, skins and morph targets that follow read a
posed file like any other. Interpolation as the specification's Appendix C defines it:

- STEP: the value of the last key at or before ``t``;
- LINEAR: per component, except rotations: spherical linear interpolation along the shorter arc, normalized;
- CUBICSPLINE: each key holds (in-tangent, value, out-tangent); between keys k and k+1, with s in [0, 1] and
  the interval d = t(k+1) - t(k): p = (2s^3 - 3s^2 + 1) v_k + d (s^3 - 2s^2 + s) b_k + (-2s^3 + 3s^2) v_k+1
  + d (s^3 - s^2) a_k+1 (b: out-tangent, a: in-tangent); rotations normalized after.

A time outside a sampler's keys is clamped to its first or last key (the specification: "clamped"), and
:func:`describe` says so for ``--explain``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.models.gltf_io import GltfDocument, read_accessor

INTERPOLATIONS = ("LINEAR", "STEP", "CUBICSPLINE")
PATH_WIDTHS = {"translation": 3, "rotation": 4, "scale": 3, "weights": 1}
FLOAT = 5126


@dataclass(frozen=True)
class Pose:
    """Which of a file's animations to sample (its index, its name, or None: the first) at ``time`` seconds."""

    animation: int | str | None = None
    time: float = 0.0


def choose(doc: GltfDocument, animation: int | str | None) -> int:
    """The index of the animation a pose names; UserError (one line) for a file without any or an unknown one."""
    found = doc.json.get("animations", [])
    names = [a.get("name", "") for a in found]
    listed = ", ".join(f"{i}" + (f" '{n}'" if n else "") for i, n in enumerate(names)) or "none"
    if not found:
        raise UserError(f"{doc.path}: has no animations to pose (time/animation given); remove 'time' and "
                        "'animation' from its [[models]] block")
    if animation is None:
        return 0
    if isinstance(animation, int) and 0 <= animation < len(found):
        return animation
    if isinstance(animation, str) and animation in names:
        return names.index(animation)
    raise UserError(f"{doc.path}: no animation {animation!r} (its animations: {listed}); name one of them or give "
                    "its index")


def interpolate(times: np.ndarray, values: np.ndarray, t: float, mode: str, rotation: bool = False) -> np.ndarray:
    """The value at ``t`` of keys ``times`` (K,) with ``values`` (K, W), or (3K, W) for CUBICSPLINE."""
    if mode == "CUBICSPLINE":
        values = values.reshape(len(times), 3, -1)  # (in-tangent, value, out-tangent) per key
    t = min(max(t, times[0]), times[-1])
    k = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, max(len(times) - 2, 0)))
    if len(times) == 1:
        return _unit(values[0, 1] if mode == "CUBICSPLINE" else values[0], rotation)
    d = times[k + 1] - times[k]
    s = (t - times[k]) / d
    if mode == "STEP":
        return values[k + 1] if s >= 1.0 else values[k]
    if mode == "CUBICSPLINE":
        s2, s3 = s * s, s * s * s
        p = ((2 * s3 - 3 * s2 + 1) * values[k, 1] + d * (s3 - 2 * s2 + s) * values[k, 2]
             + (-2 * s3 + 3 * s2) * values[k + 1, 1] + d * (s3 - s2) * values[k + 1, 0])
        return _unit(p, rotation)
    if rotation:
        return slerp(values[k], values[k + 1], s)
    return (1 - s) * values[k] + s * values[k + 1]


def slerp(a: np.ndarray, b: np.ndarray, s: float) -> np.ndarray:
    """Spherical linear interpolation of unit quaternions along the shorter arc, normalized."""
    a, b = _unit(a, True), _unit(b, True)
    dot = float(np.dot(a, b))
    if dot < 0.0:
        b, dot = -b, -dot
    if dot > 0.9995:  # nearly equal: linear, then normalized (sin(theta) ~ 0)
        return _unit(a + s * (b - a), True)
    theta = np.arccos(dot)
    return (np.sin((1 - s) * theta) * a + np.sin(s * theta) * b) / np.sin(theta)


def _unit(q: np.ndarray, rotation: bool) -> np.ndarray:
    if not rotation:
        return q
    norm = np.linalg.norm(q)
    return q / norm if norm > 0 else np.array([0.0, 0.0, 0.0, 1.0])


_READ: dict[tuple[int, int], tuple[GltfDocument, tuple]] = {}  # (id(doc), animation) -> (that doc, its channels)
READ_KEEP = 16  # documents x animations kept


def read_channels(doc: GltfDocument, index: int) -> tuple:
    """:func:`channels` as a tuple, read once per document object and animation: the window poses the same
    parsed document every frame (core/scene/playback.py) and its keys do not change. The arrays are read-only, so
    a caller that would change them in place fails instead of changing every later frame."""
    hit = _READ.get((id(doc), index))
    if hit is not None and hit[0] is doc:  # the document itself held: its id is not another's
        return hit[1]
    found = tuple(channels(doc, index))
    for _, _, times, values, _ in found:
        times.setflags(write=False)
        values.setflags(write=False)
    if len(_READ) >= READ_KEEP:
        _READ.pop(next(iter(_READ)))
    _READ[(id(doc), index)] = (doc, found)
    return found


def channels(doc: GltfDocument, index: int):
    """(node, path, times, values, interpolation) of each channel of animation ``index`` that targets a node,
    its keys checked (one line naming what is wrong)."""
    anim = doc.json["animations"][index]
    where = f"malformed glTF file {doc.path}: animation {index}"
    for c, channel in enumerate(anim["channels"]):
        target, sampler_index = channel["target"], channel["sampler"]
        if "node" not in target:
            continue  # no node: an extension's target (e.g. KHR_animation_pointer), not drawn
        path = target["path"]
        if path not in PATH_WIDTHS or sampler_index >= len(anim["samplers"]):
            raise UserError(f"{where} channel {c}: path {path!r} / sampler {sampler_index} is not one of "
                            f"{', '.join(PATH_WIDTHS)} / 0..{len(anim['samplers']) - 1}; fix or re-export the file")
        sampler = anim["samplers"][sampler_index]
        mode = sampler.get("interpolation", "LINEAR")
        keys = doc.json["accessors"][sampler["input"]]
        if (keys.get("type"), keys.get("componentType")) != ("SCALAR", FLOAT):
            raise UserError(f"{where} sampler {sampler_index}: its input (key times) must be a SCALAR FLOAT accessor, "
                            f"got {keys.get('type')} of component type {keys.get('componentType')}; fix or re-export "
                            "the file")
        times = read_accessor(doc, sampler["input"]).reshape(-1).astype(np.float64)
        values = read_accessor(doc, sampler["output"]).astype(np.float64)
        per_key = 3 if mode == "CUBICSPLINE" else 1
        if mode not in INTERPOLATIONS or not len(times) or np.any(np.diff(times) <= 0) \
                or not np.all(np.isfinite(times)) or len(values) % (per_key * len(times)):
            raise UserError(f"{where} sampler {sampler_index}: needs interpolation in {', '.join(INTERPOLATIONS)}, "
                            f"strictly increasing finite key times and {per_key} output(s) per key and target "
                            f"(got {mode}, {len(times)} keys, {len(values)} outputs); fix or re-export the file")
        if path == "weights":
            values = values.reshape(len(times) * per_key, -1)
        elif values.shape[1] != PATH_WIDTHS[path]:
            raise UserError(f"{where} sampler {sampler_index}: {path} needs {PATH_WIDTHS[path]} components per "
                            f"value, the output accessor has {values.shape[1]}; fix or re-export the file")
        yield target["node"], path, times, values, mode


def posed(doc: GltfDocument, pose: Pose | None) -> GltfDocument:
    """The document with each animated node property replaced by its value at ``pose.time`` (None: as written)."""
    if pose is None:
        return doc
    index = choose(doc, pose.animation)
    nodes = [dict(node) for node in doc.json.get("nodes", [])]
    for node, path, times, values, mode in read_channels(doc, index):
        if "matrix" in nodes[node]:
            raise UserError(f"malformed glTF file {doc.path}: animation {index} targets node {node}, which has a "
                            "matrix (glTF animates translation/rotation/scale nodes only); fix or re-export the file")
        value = interpolate(times, values, float(pose.time), mode, rotation=path == "rotation")
        nodes[node][path] = [float(v) for v in np.ravel(value)]
    return GltfDocument(doc.path, {**doc.json, "nodes": nodes}, doc.buffers)


def describe(doc: GltfDocument, pose: Pose | None) -> str | None:
    """``--explain``'s line for the animation drawn (None: the file has none)."""
    found = doc.json.get("animations", [])
    if pose is None:
        return (f"{len(found)} animation(s) not applied: drawn at rest (the nodes as written); pose one with "
                "time = T (and animation = NAME or INDEX) in the model's [[models]] block") if found else None
    index = choose(doc, pose.animation)
    keys = [times for _, _, times, _, _ in read_channels(doc, index)]
    name = found[index].get("name", "")
    if not keys:
        return (f"animation {index}" + (f" '{name}'" if name else "") + ": no channel targets a node (its targets "
                "are an extension's, e.g. KHR_animation_pointer): ignored, drawn at rest")
    start, end = min(k[0] for k in keys), max(k[-1] for k in keys)
    line = f"animation {index}" + (f" '{name}'" if name else "") + f" sampled at t = {pose.time:g} s (keys " \
        f"{start:g}..{end:g} s, {len(keys)} channel(s))"
    if not start <= pose.time <= end:
        side = "first" if pose.time < start else "last"
        line += f"; t is outside the keys, so each channel is clamped to its {side} key (glTF 2.0)"
    return line


def pose_notes(doc: GltfDocument, pose: Pose | None) -> list[str]:
    """``--explain``'s lines for what moves the file's vertices: the animation sampled, and each skin placed."""
    lines = [line for line in (describe(doc, pose),) if line]
    when = f"at t = {pose.time:g} s" if pose is not None else "at rest (its joints' nodes as written)"
    skins = doc.json.get("skins", [])
    used = sorted({node["skin"] for node in doc.json.get("nodes", []) if "skin" in node and "mesh" in node})
    lines += [f"skin {k} ({len(skins[k]['joints'])} joints): posed on the CPU {when} (linear blend skinning of "
              "positions, normals and tangents; both paths draw the same vertices)" for k in used]
    return lines
