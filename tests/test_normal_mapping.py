"""Normal mapping on the GPU against analytic values: a constant-slope map, mirrored UVs, degenerate UVs.

Rendered into rgba16float with no post chain (linear values, read back as float16), so the
only rounding beyond the reference's float64 is float32 shading and the float16 store
(relative 2^-11): the analytic comparison allows 2e-3 absolute on values around 0.1..0.5.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wgpurender.core.course.shading import AMBIENT, SPECULAR
from wgpurender.core.files.imageio import save_png
from wgpurender.core.models import procedural
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import parse_scene
from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

ROOT = Path(__file__).resolve().parents[1]
ASSETS = ROOT / "assets"
W, H = 96, 72
FOV = 45.0
ALBEDO = 0.6
ROUGHNESS = 0.3


def _render(ctx, text: str, folder: Path) -> np.ndarray:
    scene = parse_scene(text, folder / "scene.toml")
    renderer = SceneRenderer(ctx, scene, resolve_plan(scene, None))
    target = renderer.create_output()
    return render_frame(ctx, renderer, target)[0].astype(np.float64)


def _quad_scene(quad: Path, normal_map: str, light_direction, distance: float) -> str:
    return f"""
[camera]
eye = [0.0, 0.0, {float(distance)!r}]
target = [0.0, 0.0, 0.0]
fov_y = {FOV}

[[models]]
path = "{quad}"
material = {{ albedo_color = [{ALBEDO}, {ALBEDO}, {ALBEDO}], roughness = {ROUGHNESS}, normal_map = "{normal_map}" }}

[[lights]]
type = "directional"
direction = {list(map(float, light_direction))}

[render]
size = [{W}, {H}]
msaa = 1
hdr = false
output_format = "rgba16float"
"""


def _blinn_phong(n, to_light, v, albedo: float, roughness: float) -> np.ndarray:
    """scene.wgsl's shading for one directional light of intensity 1, float64, per pixel."""
    n_dot_l = np.maximum(np.sum(n * to_light, axis=-1), 0.0)
    h = to_light + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    s = np.clip(2.0 / roughness**4 - 2.0, 1.0, 4096.0)
    spec = SPECULAR * (s + 8.0) / 8.0 * np.maximum(np.sum(n * h, axis=-1), 0.0) ** s
    return n_dot_l * (albedo + spec)


def test_constant_slope_normal_map_lights_to_the_analytic_value(ctx, tmp_path):
    """Every texel encodes m = normalize(0.3, 0, 1); the quad (tangent +X, bitangent +Y, normal +Z)
    exactly fills the view. Expected per pixel: albedo * ambient + Blinn-Phong with n' = normalize(m_q)
    (m_q = the 8-bit texel decoded), light l = normalize(-0.5, 0.5, 0.707), view from the pixel's point
    to the eye. The specular term there is below 1e-12 (n'.h ~ 0.8, exponent 245), so this checks the
    Lambert part; the flat normal would give a value 0.05 higher, far outside the 2e-3 tolerance.
    Measured on lavapipe: max error 2.2e-4 (the float16 store)."""
    m = np.array([0.3, 0.0, 1.0]) / np.linalg.norm([0.3, 0.0, 1.0])
    texel = np.round((m * 0.5 + 0.5) * 255.0)
    pixels = np.zeros((16, 16, 4), np.uint8)
    pixels[..., :3], pixels[..., 3] = texel, 255
    save_png(tmp_path / "slope.png", pixels)
    quad = procedural.write_obj(tmp_path / "quad.obj", procedural.plane(width=2.0 * W / H, height=2.0))
    distance = 1.0 / np.tan(np.radians(FOV) / 2.0)
    to_light = np.array([-0.5, 0.5, 0.707])
    to_light /= np.linalg.norm(to_light)
    image = _render(ctx, _quad_scene(quad, "slope.png", -to_light, distance), tmp_path)[..., :3]

    m_q = texel / 255.0 * 2.0 - 1.0
    n = m_q / np.linalg.norm(m_q)  # tangent frame = world axes on this quad
    ys, xs = np.mgrid[0:H, 0:W] + 0.5
    points = np.stack([(xs / W * 2 - 1) * W / H, 1 - ys / H * 2, np.zeros_like(xs)], axis=-1)
    v = np.array([0.0, 0.0, distance]) - points
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    ambient = ALBEDO * np.array(AMBIENT)
    expected = ambient + _blinn_phong(n, to_light, v, ALBEDO, ROUGHNESS)[..., None]
    flat = ambient + _blinn_phong(np.array([0.0, 0.0, 1.0]), to_light, v, ALBEDO, ROUGHNESS)[..., None]
    assert np.min(np.abs(flat - expected)) > 0.05  # the map matters: ignoring it fails the test
    inner = (slice(1, -1), slice(1, -1))  # skip the outermost pixels, where the quad's edge runs
    assert np.max(np.abs(image[inner] - expected[inner])) < 2e-3


def test_mirrored_uvs_light_both_halves_the_same(ctx, tmp_path):
    """mirrored_quad.glb: the left half's u runs 1 -> 0 (tangent -X, w = -1), the right half's 0 -> 1,
    both sampling the dome normal map. Under a light symmetric about x = 0 (and a centred camera,
    even width) the image must be its own mirror image: |left - mirrored right| < 2e-3 everywhere
    (the same texels are sampled at mirrored pixels; only float rounding of interpolation differs).
    A wrong bitangent sign on the mirrored half would turn its domes' shading upside down: the
    domes make the two halves differ by up to ~0.2 then (checked: the image has that much variation).
    Measured on lavapipe: the halves are bit-identical mirror images (max difference 0)."""
    quad = ASSETS / "models" / "mirrored_quad.glb"
    dome = ASSETS / "textures" / "dome_normal.png"
    image = _render(ctx, _quad_scene(quad, str(dome), [0.0, -0.6, -0.8], 2.6), tmp_path)[..., 0]
    mirrored = image[:, ::-1]
    assert np.max(np.abs(image - mirrored)) < 2e-3
    covered = image > 0.0
    assert covered.mean() > 0.3
    assert np.ptp(image[covered]) > 0.2  # the domes shade visibly, so symmetry is not trivial


def test_degenerate_uv_triangles_give_no_nan_on_the_gpu(ctx, tmp_path):
    """A 4x4 grid whose UVs collapse in places (triangles with identical or collinear UVs): tangents
    are whatever tangents.py makes of them; the shader's guarded normalisations must keep every
    output value finite, and the grid must still be drawn."""
    mesh = procedural.plane(width=2.0 * W / H, height=2.0, cols=4, rows=4)
    mesh.uvs[:6] = 0.25  # first row and one more vertex: zero-area UV triangles
    mesh.uvs[10:15, 1] = mesh.uvs[10, 1]  # a row of vertices on one v: collinear UVs
    quad = procedural.write_obj(tmp_path / "degenerate.obj", mesh)
    dome = ASSETS / "textures" / "dome_normal.png"
    distance = 1.0 / np.tan(np.radians(FOV) / 2.0)
    image = _render(ctx, _quad_scene(quad, str(dome), [0.3, -0.4, -1.0], distance), tmp_path)
    assert np.all(np.isfinite(image))
    assert (image[..., :3].max(axis=-1) > 0.01).mean() > 0.9
