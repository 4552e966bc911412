"""KHR_lights_punctual lights from a glTF file light the scene on both paths, as the extension defines them.

Each file holds a large quad facing the camera (a rough dielectric glTF material) and one light placed by a node
hierarchy, the model moved by the scene's transform. The expected radiance is the extension's physics, written
here independently of the renderer's light units: L = f(l, v) E cos, with E = intensity (lux) for a directional
light and E = intensity (candela) / d^2 x clamp(1 - (d / range)^4, 0, 1) x clamp((cos a - cos outer) /
(cos inner - cos outer), 0, 1)^2 for a spot (the extension's recommended range window and cone), f the float64
BRDF of tests/pbr_reference.py, plus the ambient term (ambient x base colour).
"""

from __future__ import annotations

import numpy as np
import pbr_reference as ref
import pytest
from gltf_gen import QUAD_INDICES, GltfWriter, quad, scene_text
from helpers import render_both_paths
from shading_model import course_constant, srgb_encode

SIZE = (64, 64)
SHIFT = (0.1, -0.05, 0.0)  # the scene's transform of the model: it moves the file's lights too
EYE = np.array([0.0, 0.0, 2.0])
BASE = (0.8, 0.7, 0.6)
ROUGHNESS = 0.7
SCENE = scene_text("lit.glb", SIZE, extra=f"transform = {{ translate = {list(SHIFT)} }}\n")  # eye (0, 0, 2), fov 90
SPOT = {"position": (0.2, -0.1, 1.0), "inner": 0.35, "outer": 0.6, "range": 1.6, "intensity": 3.0}
SUN = {"turn": np.radians(30), "intensity": 2.5}


def write_file(folder, light: dict, node: dict) -> None:
    """The quad and one light placed by a parent node (translation (0, 0, 0.5)) and ``node``'s own transform."""
    g = GltfWriter()
    mat = g.material(pbrMetallicRoughness={"baseColorFactor": [*BASE, 1.0], "metallicFactor": 0.0,
                                           "roughnessFactor": ROUGHNESS})
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    prim = {"attributes": {"POSITION": g.positions(quad(-4, -4, 4, 4)), "NORMAL": g.accessor(normals)},
            "indices": g.accessor(QUAD_INDICES), "material": mat}
    g.node(mesh=g.mesh([prim]))
    child = g.node(extensions={"KHR_lights_punctual": {"light": 0}}, **node)
    g.node(children=[child], translation=[0.0, 0.0, 0.5])
    g.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [light]}}
    g.write(folder / "lit.glb", roots=[0, 2])
    (folder / "scene.toml").write_text(SCENE)


def surface():
    """The world point under each pixel centre, its v, and the quad's normal."""
    rays = ref.pixel_rays(SIZE, 90.0)
    normal = np.array([0.0, 0.0, 1.0])
    hits = ref.plane_hits(EYE, rays, normal)
    return hits, ref.unit(EYE - hits), normal


def expected_bytes(light_radiance) -> np.ndarray:
    linear = light_radiance + np.asarray(course_constant("AMBIENT")) * np.asarray(BASE)
    return np.round(srgb_encode(linear) * 255)


def render_both(ctx, folder):
    return render_both_paths(ctx, folder, SIZE)


def test_spot_light_with_cone_and_range(ctx, tmp_path):
    """A spot at SPOT's position (0.5 from the parent, the rest from its node), pointing down -z: full inside the
    inner cone, nothing beyond the outer cone or the range, the cone and window in between."""
    light = {"type": "spot", "intensity": SPOT["intensity"], "range": SPOT["range"], "color": [1, 1, 1],
             "spot": {"innerConeAngle": SPOT["inner"], "outerConeAngle": SPOT["outer"]}}
    x, y, z = SPOT["position"]
    write_file(tmp_path, light, {"translation": [x, y, z - 0.5]})
    got = render_both(ctx, tmp_path)
    hits, v, n = surface()
    to_light = np.asarray(SPOT["position"]) + SHIFT - hits
    d = np.linalg.norm(to_light, axis=-1)
    l = to_light / d[..., None]  # noqa: E741
    cos_axis = -l @ np.array([0.0, 0.0, -1.0])
    cone = np.clip((cos_axis - np.cos(SPOT["outer"])) / (np.cos(SPOT["inner"]) - np.cos(SPOT["outer"])), 0, 1) ** 2
    window = np.clip(1 - (d / SPOT["range"]) ** 4, 0, 1)
    irradiance = SPOT["intensity"] / d**2 * window * cone * np.clip(l @ n, 0, 1)
    want = expected_bytes(ref.brdf(n, l, v, BASE, 0.0, ROUGHNESS) * irradiance[..., None])
    assert np.abs(got - want).max() <= 2
    lit = cone * window > 0.05
    assert 0.05 < lit.mean() < 0.6  # the cone's edge is in view: the test sees inside and outside


@pytest.mark.parametrize("kind", ["directional", "point"])
def test_directional_and_point_lights_from_the_file(ctx, tmp_path, kind):
    """A directional light (lux) whose node turns -Z by 30 degrees about x, or a point light (candela, no range)
    at (0, 0, 1), after a scene light that cannot reach the quad's front: each lights the quad as L = f E cos."""
    turn = SUN["turn"]
    rotation = [float(np.sin(turn / 2)), 0.0, 0.0, float(np.cos(turn / 2))]
    light = {"type": kind, "intensity": SUN["intensity"]}
    write_file(tmp_path, light, {"rotation": rotation, "translation": [0.0, 0.0, 0.5]})
    with open(tmp_path / "scene.toml", "a") as scene:  # a scene light first, behind the quad (n.l < 0: no light):
        scene.write('[[lights]]\ntype = "point"\nposition = [0, 0, -5]\n')  # the file's comes second in its list
    got = render_both(ctx, tmp_path)
    hits, v, n = surface()
    if kind == "directional":
        travel = np.array([0.0, np.sin(turn), -np.cos(turn)])  # local -Z turned about x
        l = np.broadcast_to(-travel, hits.shape)  # noqa: E741
        irradiance = SUN["intensity"] * np.clip(l @ n, 0, 1)
    else:
        to_light = np.array([0.0, 0.0, 1.0]) + SHIFT - hits
        d2 = np.sum(to_light**2, axis=-1)
        l = ref.unit(to_light)  # noqa: E741
        irradiance = SUN["intensity"] / d2 * np.clip(l @ n, 0, 1)
    want = expected_bytes(ref.brdf(n, l, v, BASE, 0.0, ROUGHNESS) * irradiance[..., None])
    assert np.abs(got - want).max() <= 2


def test_explain_names_the_file_lights(tmp_path, capsys):
    from wgpurender.cli import main

    write_file(tmp_path, {"type": "spot", "name": "lamp", "intensity": 1.0}, {})
    assert main(["render", str(tmp_path / "scene.toml"), "--explain"]) == 0
    out = capsys.readouterr().out
    assert "models[0] 'lit.glb' light 0 'lamp': KHR_lights_punctual spot, intensity 1 cd -> 0.3183" in out
    assert "cone 0.0-45.0 deg, no range" in out and "KHR_lights_punctual: ignored" not in out


BAD_LIGHTS = [
    ({"type": "spot", "intensity": -1.0}, "intensity is -1.0"),
    ({"type": "point", "range": 0}, "range is 0"),
    ({"type": "point", "color": [1, 1]}, "color is [1, 1]"),
    ({"type": "point", "color": "red"}, "color is 'red'"),
    ({"type": "spot", "spot": {"innerConeAngle": 0.8, "outerConeAngle": 0.5}}, "innerConeAngle is 0.8"),
    ({"type": "spot", "spot": {"outerConeAngle": 2.0}}, "outerConeAngle is 2.0"),
    ({"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.5}}, "innerConeAngle equals"),
    ({"type": "area"}, "type 'area' is not one of"),
]


@pytest.mark.parametrize("light, needle", BAD_LIGHTS, ids=[n for _, n in BAD_LIGHTS])
def test_a_malformed_file_light_is_refused_in_one_line(tmp_path, capsys, light, needle):
    """Values the extension forbids: exit 2, one line naming the light, the value and the allowed range."""
    from wgpurender.cli import main

    write_file(tmp_path, light, {})
    code = main(["render", str(tmp_path / "scene.toml"), "-o", str(tmp_path / "out.png")])
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 2 and len(err) == 1 and needle in err[0] and "light 0" in err[0], err
    assert not (tmp_path / "out.png").exists()
