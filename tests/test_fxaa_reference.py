"""FXAA on the GPU against an independent numpy implementation of the same algorithm (tests/fxaa_reference.py).

The input is a coloured, non-trivial image (saturated discs, a triangle with diagonal edges, thin lines,
a colour checker whose squares differ in hue more than in brightness), drawn 1:1 onto a quad (unlit,
nearest) into the scene's rgba16float image, followed by the one post effect ``fxaa`` into an rgba16float
output. The test knows the scene image exactly: the sRGB texels decoded, rounded to float16.

The GPU's bilinear filter has limited sub-texel precision (Vulkan requires 4 bits, lavapipe has 8), and a
luma landing on a threshold can flip one pixel's decision, so the comparison is statistical, with stated
bounds: at most 0.1% of pixels off by more than 0.01 (any channel) and a small mean error. A change to
the algorithm (luma weights, thresholds, search steps, the direction test) moves hundreds of pixels by more.
"""

from __future__ import annotations

import numpy as np
from fxaa_reference import fxaa
from shading_model import camera_toml, render_wgpu, srgb_decode, srgb_encode, view_distance

from wgpurender.core.files.imageio import save_png
from wgpurender.core.models import procedural

W, H = 96, 72
# Measured on lavapipe (Mesa 22.3.6, AMD EPYC): 0 pixels off by more than 0.01, max 0.0041, mean 0.00076.
# Rec. 601 luma weights instead of Rec. 709 move 216 pixels by more than 0.01 (up to 0.49); equal weights 189;
# only the blue weight 1.5x, 19. Allowed: 7 pixels (0.1%) for another driver's filter precision.
ALLOWED_OFF = 7


def coloured_image() -> np.ndarray:
    """(H, W, 4) uint8 sRGB: shapes in saturated colours of similar brightness on a dark background."""
    ys, xs = np.mgrid[0:H, 0:W] + 0.5
    img = np.zeros((H, W, 3))
    img[:] = (0.10, 0.12, 0.35)
    img[(xs - 24) ** 2 + (ys - 22) ** 2 < 15**2] = (0.95, 0.15, 0.10)  # red disc
    img[(xs - 70) ** 2 + (ys - 50) ** 2 < 13**2] = (0.10, 0.75, 0.20)  # green disc
    img[(ys > 0.45 * xs + 30) & (ys < 70) & (xs < 60)] = (0.95, 0.85, 0.10)  # yellow wedge, shallow diagonal
    img[(np.abs(ys - 1.7 * xs + 60) < 1.2) & (ys < 40)] = (0.85, 0.20, 0.90)  # a thin magenta steep line
    checker = ((xs // 6 + ys // 6) % 2).astype(bool) & (xs > 50) & (ys < 30)
    img[checker] = (0.20, 0.55, 0.95)  # blue squares
    img[~checker & (xs > 50) & (ys < 30)] = (0.90, 0.45, 0.10)  # orange squares
    # Edges that only the luma weights decide: equal Rec. 709 luminance (red 1.0 | green 0.297, linear) is flat
    # to FXAA, while Rec. 601 weights would see contrast; equal Rec. 601 luminance (red | green 0.509) the reverse.
    img[(ys > 40) & (xs < 40)] = srgb_encode(np.array([1.0, 0.0, 0.0]))
    img[(ys > 40) & (xs < 40) & ((xs - 18) ** 2 + (ys - 56) ** 2 < 10**2)] = srgb_encode(np.array([0.0, 0.297, 0.0]))
    img[(ys > 34) & (xs > 44) & (xs < 60) & (ys < 0.8 * xs)] = srgb_encode(np.array([1.0, 0.0, 0.0]))
    img[(ys > 34) & (xs > 44) & (xs < 60) & (ys >= 0.8 * xs)] = srgb_encode(np.array([0.0, 0.509, 0.0]))
    rgba = np.concatenate([img, np.ones((H, W, 1))], axis=-1)
    return np.round(rgba * 255).astype(np.uint8)


def quad_scene(folder, texels: np.ndarray, output_format: str, post: str) -> str:
    """A scene drawing ``texels`` 1:1 (unlit, nearest) into the rgba16float scene image, then the ``post`` tables."""
    save_png(folder / "coloured.png", texels)
    quad = procedural.write_obj(folder / "quad.obj", procedural.plane(width=2.0 * W / H, height=2.0))
    return camera_toml(view_distance()) + f"""
[[models]]
path = "{quad}"
material = {{ albedo_map = "coloured.png", unlit = true, sampler = {{ filter = "nearest", mipmaps = false }} }}

[render]
size = [{W}, {H}]
msaa = 1
hdr = true
output_format = "{output_format}"

""" + post


def _render_fxaa(ctx, folder, texels: np.ndarray) -> np.ndarray:
    text = quad_scene(folder, texels, "rgba16float", '[[post]]\neffect = "fxaa"\n')
    return render_wgpu(ctx, text, folder).astype(np.float64)


def test_fxaa_matches_the_numpy_reference_on_a_coloured_image(ctx, tmp_path):
    texels = coloured_image()
    scene_image = np.ones((H, W, 4))
    scene_image[..., :3] = srgb_decode(texels[..., :3] / 255.0).astype(np.float16)
    expected = fxaa(scene_image)
    changed = np.abs(expected - scene_image).max(axis=-1) > 0.01
    assert changed.sum() > 300, "the image must give FXAA work: blended pixels in the reference"

    got = _render_fxaa(ctx, tmp_path, texels)
    err = np.abs(got - expected)[..., :3].max(axis=-1)
    off = err > 0.01
    worst = np.unravel_index(np.argmax(err), err.shape)
    assert off.sum() <= ALLOWED_OFF and err.mean() < 2e-3, (
        f"FXAA differs from the numpy reference in {off.sum()} of {W * H} pixels by more than 0.01 "
        f"(allowed: {ALLOWED_OFF}), mean {err.mean():.4f}; worst at (x={worst[1]}, y={worst[0]}): "
        f"GPU {got[worst][:3]}, "
        f"reference {expected[worst][:3]}, input {scene_image[worst][:3]} ({changed.sum()} pixels blended by the "
        "reference)")
