"""Pixel probes for the samples whose README states a checkable fact, at places computed from the file and the
camera (gltf_view.project). Each returns (passed, what was measured). Samples without one are judged by eye."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from gltf_view import load, local_matrix, mesh_boxes, project


def srgb(linear: float) -> float:
    c = min(max(linear, 0.0), 1.0)
    return 255 * (12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055)


def _node_centres(model: Path) -> dict[str, np.ndarray]:
    doc, _ = load(model)
    return {n.get("name", str(i)): local_matrix(n)[:3, 3] for i, n in enumerate(doc["nodes"]) if "mesh" in n}


def unlit(image, model, cam, size):
    """UnlitTest: each object's visible surface is its sRGB colour: #FF7F00 and #007FFF, within 3/255."""
    want = {"Orange Object": (255, 127, 0), "Blue Object": (0, 127, 255)}
    got = {}
    for name, centre in _node_centres(model).items():
        col, row = project(centre, cam, size)
        got[name] = image[row, col, :3].tolist()
    ok = all(np.abs(np.array(got[k]) - want[k]).max() <= 3 for k in want)
    return ok, f"centres {got} (want {want})"


def emissive_strength(image, model, cam, size):
    """EmissiveStrengthTest: each cube's front face shows emissiveFactor x strength (clamped, sRGB); the red
    channel (0.1 x strength) carries the difference: 89, 124, 170, 231, 255 for strengths 1, 2, 4, 8, 16."""
    doc, _ = load(model)
    rows = []
    for node in doc["nodes"]:
        mat = doc["materials"][doc["meshes"][node["mesh"]]["primitives"][0]["material"]]
        if "emissiveFactor" not in mat:
            continue
        strength = mat.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1)
        acc = doc["accessors"][doc["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
        front = local_matrix(node)[:3, 3] + np.array([0, 0, acc["max"][2]])
        col, row = project(front, cam, size)
        rows.append((strength, srgb(mat["emissiveFactor"][0] * strength), int(image[row, col, 0])))
    rows.sort()
    ok = all(abs(want - got) <= 12 for _, want, got in rows)
    return ok, "strength: want/got red " + ", ".join(f"{s}: {w:.0f}/{g}" for s, w, g in rows)


def instances(image, model, cam, size):
    """SimpleInstancing: every one of the instances (TRANSLATION accessor) covers its projected centre."""
    background = image[0, 0, :3].astype(int)
    boxes = mesh_boxes(model)
    hits = 0
    for box in boxes:
        col, row = project(box.mean(axis=0), cam, size)
        hits += int(np.abs(image[row - 1: row + 2, col - 1: col + 2, :3].astype(int) - background).max() > 12)
    return hits == len(boxes), f"{hits} of {len(boxes)} instance centres covered"


def default_scene(image, model, cam, size):
    """MultipleScenes: scene 1 (the default) is the square: its four corners, 10% inside, are covered (the
    triangle of scene 0 covers at most three)."""
    background = image[0, 0, :3].astype(int)
    (box,) = mesh_boxes(model)
    lo, hi = box.min(axis=0), box.max(axis=0)
    hits = 0
    for fx in (0.1, 0.9):
        for fy in (0.1, 0.9):
            col, row = project(lo + (hi - lo) * np.array([fx, fy, 0.5]), cam, size)
            hits += int(np.abs(image[row, col, :3].astype(int) - background).max() > 12)
    return hits == 4, f"{hits} of 4 square corners covered"


PROBES = {"UnlitTest": unlit, "EmissiveStrengthTest": emissive_strength, "SimpleInstancing": instances,
          "MultipleScenes": default_scene}


def linear_interpolation(image, model, cam, size):
    """TextureLinearInterpolationTest: the sphere lit by the 0.5-green emissive factor and the one sampling its
    emissive from a 2x1 texture show the same green, sRGB(0.5) = 188, within 12/255 (probed 0.4 radius down and
    right of each centre)."""
    doc, _ = load(model)
    got = []
    for node in doc["nodes"][:2]:
        acc = doc["accessors"][doc["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
        radius = (acc["max"][0] - acc["min"][0]) / 2
        at = local_matrix(node)[:3, 3] + np.array([0.4 * radius, -0.4 * radius, 0.0])
        col, row = project(at, cam, size)
        got.append(image[row, col, :3].tolist())
    want = srgb(0.5)
    ok = all(abs(g[1] - want) <= 12 and max(g[0], g[2]) <= 12 for g in got)
    return ok, f"factor sphere {got[0]}, texture sphere {got[1]} (want green {want:.0f})"


PROBES["TextureLinearInterpolationTest"] = linear_interpolation


def draco_morph(image, model, cam, size):
    """MorphPrimitivesTest: weights [0.5] raise the middle of the flat board. Seen edge-on, each primitive's highest
    morphed vertex (Draco-decoded base + 0.5 x its POSITION target, decoded here with DracoPy) is covered at 70% of
    its height, where the unmorphed board (height 0) leaves the background."""
    import DracoPy
    from gltf_view import buffer_bytes, float_vec3

    doc, glb_bin = load(model)
    background = image[0, 0, :3].astype(int)
    weight = doc["meshes"][0]["weights"][0]
    found = []
    for prim in doc["meshes"][0]["primitives"]:
        ext = prim["extensions"]["KHR_draco_mesh_compression"]
        view = doc["bufferViews"][ext["bufferView"]]
        data = buffer_bytes(doc, view["buffer"], model.parent, glb_bin)
        start = view.get("byteOffset", 0)
        decoded = DracoPy.decode(data[start: start + view["byteLength"]])
        morphed = np.asarray(decoded.points, np.float64) + weight * float_vec3(
            doc, prim["targets"][0]["POSITION"], model.parent, glb_bin)
        peak = morphed[int(np.argmax(morphed[:, 1]))] * np.array([1, 0.7, 1])
        col, row = project(peak, cam, size)
        found.append(int(np.abs(image[row, col, :3].astype(int) - background).max() > 12))
    return all(found), f"{sum(found)} of {len(found)} raised peaks covered at 70% height"


PROBES["MorphPrimitivesTest"] = draco_morph
