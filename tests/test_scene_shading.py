"""The scene shader against the documented shading model, evaluated in float64 numpy in the test.

What no other test renders: the output encoding when the scene draws straight into the output
(no post chain), ``uv_flip_v``, the roughness map's channel, a specular lobe that dominates the
image, the ambient term, and normal mapping under mirrored and non-uniformly scaled world matrices.
Every expected value comes from :mod:`shading_model` (the documented formulas and constants, typed
in again), from the texture written by the test, and from the scene geometry, never from the
renderer. Each scene is a quad facing the camera; most run on both the wgpu and the raw-Vulkan path.

Images are 64x48; float results are read from rgba16float targets (relative rounding 2^-11).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from shading_model import (
    blinn_phong,
    camera_toml,
    course_constant,
    normalize,
    pixel_points_on_plane,
    render_raw,
    render_wgpu,
    srgb_decode,
    srgb_encode,
    view_distance,
)

from wgpurender.core.files.imageio import save_png
from wgpurender.core.models import procedural

W, H = 64, 48
PATHS = ("wgpu", "raw")


def _render(path: str, ctx, text: str, folder: Path) -> np.ndarray:
    if path == "wgpu":
        return render_wgpu(ctx, text, folder)
    return render_raw(text, folder)


def _quad(folder: Path, scale: float = 1.0) -> Path:
    """A quad that exactly fills the view at view_distance() (times ``scale``): u along +X, v = 0 at the top."""
    mesh = procedural.plane(width=2.0 * W / H * scale, height=2.0 * scale)
    return procedural.write_obj(folder / "quad.obj", mesh)


def _pattern_texture() -> np.ndarray:
    """(H, W, 4) uint8, every code value 0..255 in each channel, channels unlike each other."""
    code = (np.arange(W * H) * 7 % 256).reshape(H, W)
    rgba = np.stack([code, 255 - code, (code * 3 + 40) % 256, np.full_like(code, 255)], axis=-1)
    return rgba.astype(np.uint8)


def _textured_unlit_scene(folder: Path, fmt: str, flip_v: bool = False) -> tuple[str, np.ndarray]:
    texels = _pattern_texture()
    save_png(folder / "pattern.png", texels)
    quad = _quad(folder)
    flip = str(flip_v).lower()
    material = (f'{{ albedo_map = "pattern.png", unlit = true, uv_flip_v = {flip}, '
                'sampler = { filter = "nearest", mipmaps = false } }')
    text = camera_toml(view_distance()) + f"""
[[models]]
path = "{quad}"
material = {material}

[render]
size = [{W}, {H}]
msaa = 1
hdr = false
output_format = "{fmt}"
"""
    return text, texels


# -- output encoding with no post chain -----------------------------------------------------------


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("fmt", ["rgba8unorm-srgb", "rgba8unorm", "rgba16float"])
def test_output_encoding_without_post_chain(ctx, tmp_path, path, fmt):
    """An unlit quad textured 1:1 (nearest, one texel per pixel) with every sRGB code value, drawn straight
    into the output. The texture decodes to linear L = srgb_decode(t / 255); the output must hold
    - rgba8unorm-srgb: the hardware encode of L, i.e. t again (within 1/255);
    - rgba8unorm: the shader's own encode of L, also t (within 1/255): a missing encode gives
      t = 128 -> 55, a double encode (on an -srgb target) t = 55 -> 128;
    - rgba16float: L itself, linear (within 5e-3).

    Why 5e-3 for rgba16float: the value comes straight from the hardware's sRGB decode of the texture.
    The Vulkan spec defines that decode only by reference ("Texel Decode": the "sRGB EOTF" section of
    the Khronos Data Format Specification) and states no precision for it, so it need not be correctly
    rounded. lavapipe is within 2e-3; NVIDIA's H100 (driver 580.159.04, 2026-11-23) was 3.75e-3 off
    (texel 251 -> 0.9609 for 0.9647), 0.43 of the gap to the next code's value there (8.9e-3 at the top).
    A missing, double or extra sRGB conversion is off by up to 0.287, 57x the bound.
    """
    text, texels = _textured_unlit_scene(tmp_path, fmt)
    image = _render(path, ctx, text, tmp_path)
    linear = srgb_decode(texels[..., :3] / 255.0)
    if fmt == "rgba16float":
        got, expected, tol, unit = image[..., :3].astype(np.float64), linear, 5e-3, ""
    else:
        got = image[..., :3].astype(np.float64)
        expected, tol, unit = np.round(srgb_encode(linear) * 255.0), 1.0, "/255"
    err = np.abs(got - expected)
    worst = np.unravel_index(np.argmax(err), err.shape)
    assert err.max() <= tol, (
        f"{path} path, {fmt} output without a post chain: pixel (x={worst[1]}, y={worst[0]}) channel {worst[2]} "
        f"is {got[worst]:.4f}, expected {expected[worst]:.4f}{unit} for texel {texels[worst]} "
        f"({(err > tol).sum()} values off by more than {tol}{unit}); is the output encoded once, and only once?")


# -- uv_flip_v ------------------------------------------------------------------------------------


@pytest.mark.parametrize("path", PATHS)
def test_uv_flip_v_turns_the_texture_upside_down(ctx, tmp_path, path):
    """uv_flip_v = true samples v -> 1 - v: the 1:1 textured quad shows the texture's rows in reverse
    order (within 1/255); with false it shows them in order (the encoding test above)."""
    text, texels = _textured_unlit_scene(tmp_path, "rgba8unorm-srgb", flip_v=True)
    image = _render(path, ctx, text, tmp_path)[..., :3].astype(int)
    flipped, unflipped = texels[::-1, :, :3].astype(int), texels[..., :3].astype(int)
    assert np.abs(image - unflipped).max() > 100, f"{path} path: uv_flip_v = true left the texture upright"
    assert np.abs(image - flipped).max() <= 1, (
        f"{path} path: uv_flip_v = true should show row y of the image as texture row {H - 1} - y; "
        f"{(np.abs(image - flipped) > 1).any(axis=-1).sum()} of {W * H} pixels differ")


# -- lit quads: roughness channel, specular lobe, ambient -----------------------------------------


def _lit_scene(folder: Path, material: str, light_direction, fmt: str = "rgba16float") -> str:
    quad = _quad(folder)
    return camera_toml(view_distance()) + f"""
[[models]]
path = "{quad}"
material = {material}

[[lights]]
type = "directional"
direction = {[float(x) for x in light_direction]}

[render]
size = [{W}, {H}]
msaa = 1
hdr = false
output_format = "{fmt}"
"""


def _expected_flat_quad(albedo, roughness, to_light) -> np.ndarray:
    """Ambient + one unit directional light on the z = 0 quad (normal +Z), viewed from each pixel's point."""
    distance = view_distance()
    points = pixel_points_on_plane((W, H), distance)
    v = np.array([0.0, 0.0, distance]) - points
    lit = blinn_phong(np.array([0.0, 0.0, 1.0]), to_light, v, albedo, roughness)
    return np.asarray(course_constant("AMBIENT")) * np.asarray(albedo) + lit


def _assert_close(image: np.ndarray, expected: np.ndarray, what: str, atol: float = 2e-3, rtol: float = 4e-3):
    got = image[..., :3].astype(np.float64)
    err = np.abs(got - expected) - rtol * np.abs(expected)
    worst = np.unravel_index(np.argmax(err), err.shape)
    assert err.max() <= atol, (
        f"{what}: pixel (x={worst[1]}, y={worst[0]}) channel {worst[2]} is {got[worst]:.5f}, the analytic value is "
        f"{expected[worst]:.5f}; {(err > atol).sum()} values outside {atol} + {rtol} * expected")


@pytest.mark.parametrize("path", PATHS)
def test_roughness_map_is_read_from_its_green_channel(ctx, tmp_path, path):
    """A roughness map whose channels differ: G = 90/255 (s ~ 96), R = B = 220/255 (s ~ 1.4). Black albedo,
    so the image is the specular lobe alone, lit head-on from the camera's direction. Expected: the
    normalized Blinn-Phong lobe with roughness = G. Reading R or B instead flattens the peak from ~0.5 to ~0.04."""
    texture = np.zeros((8, 8, 4), np.uint8)
    texture[...] = (220, 90, 220, 255)
    save_png(tmp_path / "rough.png", texture)
    material = '{ albedo_color = [0.0, 0.0, 0.0], roughness_map = "rough.png" }'
    to_light = np.array([0.0, 0.0, 1.0])
    image = _render(path, ctx, _lit_scene(tmp_path, material, -to_light), tmp_path)
    expected = _expected_flat_quad([0.0, 0.0, 0.0], 90 / 255, to_light)
    wrong_channel = _expected_flat_quad([0.0, 0.0, 0.0], 220 / 255, to_light)
    assert np.abs(expected - wrong_channel).max() > 0.3  # the test can tell the channels apart
    _assert_close(image, expected, f"{path} path, roughness from the map's G channel (90/255; R and B are 220/255)")


@pytest.mark.parametrize("path", PATHS)
def test_specular_lobe_dominates_and_matches_normalized_blinn_phong(ctx, tmp_path, path):
    """Roughness 0.3 (s = 2 / 0.3^4 - 2 ~ 245), albedo 0.02, a light from the upper left: the highlight's peak
    (~0.04 * 253 / 8 ~ 1.3) is ~60x the diffuse term. Every pixel against the analytic value: a wrong
    normalisation ((s + 2) / 2pi, or none), a wrong exponent mapping or h computed from the wrong vectors
    all move the peak by far more than the tolerance."""
    albedo = [0.02, 0.02, 0.02]
    material = "{ albedo_color = [0.02, 0.02, 0.02], roughness = 0.3 }"
    to_light = normalize(np.array([-0.25, 0.2, 1.0]))
    image = _render(path, ctx, _lit_scene(tmp_path, material, -to_light), tmp_path)
    expected = _expected_flat_quad(albedo, 0.3, to_light)
    diffuse_only = np.asarray(course_constant("AMBIENT")) * 0.02 + 0.02 * to_light[2]
    assert expected.max() > 30 * diffuse_only.max()  # the lobe dominates somewhere in the frame
    _assert_close(image, expected, f"{path} path, specular lobe (roughness 0.3)")


@pytest.mark.parametrize("path", PATHS)
def test_ambient_only_colour_is_the_course_ambient_times_albedo(ctx, tmp_path, path):
    """The only light shines on the quad's back (n.l < 0), so each pixel is ambient * albedo: the course's
    ambient radiance (0.03, 0.03, 0.035) times albedo (0.9, 0.5, 0.2). A path that keeps its own,
    changed ambient constant fails (0.03 -> 0.04 moves red by 0.009, 4x the tolerance)."""
    albedo = np.array([0.9, 0.5, 0.2])
    material = "{ albedo_color = [0.9, 0.5, 0.2], roughness = 0.5 }"
    image = _render(path, ctx, _lit_scene(tmp_path, material, [0.0, 0.0, 1.0]), tmp_path)
    expected = np.broadcast_to(np.asarray(course_constant("AMBIENT")) * albedo, (H, W, 3))
    _assert_close(image, expected, f"{path} path, ambient-only colour", atol=2e-4, rtol=2e-3)


# -- normal mapping under mirrored and non-uniformly scaled world matrices --------------------------

SLOPE = normalize(np.array([0.35, -0.45, 1.0]))  # a tangent-space normal with both x and y tilt


def _rotation_y(degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


WORLDS = {
    "mirrored": np.diag([-1.0, 1.0, 1.0]),
    "non-uniform": np.diag([1.7, 0.8, 0.45]) @ _rotation_y(35.0),
    "mirrored-non-uniform": np.diag([1.0, -1.3, 0.6]) @ _rotation_y(-25.0),
}


def _expected_normal_mapped(world3: np.ndarray, texel: np.ndarray, to_light, albedo, roughness) -> np.ndarray:
    """Per pixel, from the geometry alone: the world quad's tangent frame, the ray hit under each pixel centre.

    Object space: u runs along +X, "up" in the texture (+Y, decreasing v) along +Y, the face normal is +Z.
    World: T_geo = M x, U_geo = M y, N = sign(det M) * normalize(T_geo x U_geo) (how a normal transforms,
    written as the cofactor identity), T = T_geo made orthogonal to N, B = the unit vector orthogonal to
    N and T on U_geo's side. The shaded normal is normalize(T m.x + B m.y + N m.z).
    """
    t_geo, u_geo = world3 @ [1.0, 0.0, 0.0], world3 @ [0.0, 1.0, 0.0]
    n = np.sign(np.linalg.det(world3)) * normalize(np.cross(t_geo, u_geo))
    t = normalize(t_geo - n * (n @ t_geo))
    b = np.cross(n, t)
    b = b if b @ u_geo > 0 else -b
    m = texel / 255.0 * 2.0 - 1.0
    shaded = normalize(t * m[0] + b * m[1] + n * m[2])

    distance = view_distance()
    eye = np.array([0.0, 0.0, distance])
    rays = pixel_points_on_plane((W, H), distance) - eye
    hit = eye + rays * (-(n @ eye) / (rays @ n))[..., None]
    lit = blinn_phong(shaded, to_light, eye - hit, albedo, roughness)
    return np.asarray(course_constant("AMBIENT")) * np.asarray(albedo) + lit, n


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("world", list(WORLDS))
def test_normal_mapping_under_mirrored_and_non_uniform_world(ctx, tmp_path, path, world):
    """A constant-slope normal map (m = normalize(0.35, -0.45, 1)) on a large quad under a mirrored and/or
    non-uniformly scaled world matrix, lit by one directional light from the upper right. Expected per
    pixel from the geometry (see _expected_normal_mapped). Dropping the mirror sign of the bitangent
    flips m.y's contribution; transforming the normal by M instead of its inverse transpose tilts it:
    both move most pixels by more than 0.03, fifteen times the tolerance."""
    m = SLOPE
    texel = np.round((m * 0.5 + 0.5) * 255.0)
    pixels = np.zeros((8, 8, 4), np.uint8)
    pixels[..., :3], pixels[..., 3] = texel, 255
    save_png(tmp_path / "slope.png", pixels)
    world3 = WORLDS[world]
    quad = procedural.write_obj(tmp_path / "quad.obj", procedural.plane(width=8.0, height=8.0))
    matrix = np.eye(4)
    matrix[:3, :3] = world3
    albedo, roughness = [0.6, 0.6, 0.6], 0.6
    to_light = normalize(np.array([0.3, 0.6, 0.75]))
    material = f'{{ albedo_color = {albedo}, roughness = {roughness}, normal_map = "slope.png" }}'
    text = camera_toml(view_distance()) + f"""
[[models]]
path = "{quad}"
material = {material}
transform = {{ matrix = {matrix.tolist()} }}

[[lights]]
type = "directional"
direction = {(-to_light).tolist()}

[render]
size = [{W}, {H}]
msaa = 1
hdr = false
output_format = "rgba16float"
"""
    expected, n = _expected_normal_mapped(world3, texel, to_light, albedo, roughness)
    assert n[2] > 0.2  # the quad faces the camera
    wrong_b = _expected_normal_mapped(world3 @ np.diag([1.0, -1.0, 1.0]), texel, to_light, albedo, roughness)[0]
    assert np.abs(wrong_b - expected).max() > 0.03  # the bitangent's sign is visible
    image = _render(path, ctx, text, tmp_path)
    _assert_close(image, expected, f"{path} path, normal map under the {world} world matrix")
