"""The raw-Vulkan reference path (wgpurender.raw_path): against the wgpu path, against numpy, and its errors.

Both paths run on the same driver (lavapipe), so where they do the same thing
they must agree to the bit: same formats, same rasterisation rules (top-left
fill rule, pixel centres at .5), the same standard 4x sample positions, the same
sRGB encoding on store, the same flip of the viewport (wgpu's Vulkan backend uses
a negative viewport height too). Shader compilers differ (naga vs glslc) but the
shaders are a pass-through of interpolated colours, which both compile to the
same arithmetic. Every comparison with the wgpu path is therefore exact, and a
difference would be a real divergence (a missed flip, a wrong format, an sRGB
mix-up), not noise. Validation (with synchronisation validation) is on
(tests/conftest.py sets $WGPURENDER_VALIDATION) and any message raises.
"""

from __future__ import annotations

import numpy as np
import pytest
from imagecheck import assert_same_render, assert_within_tolerance

from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import load_png, srgb_decode, srgb_encode, to_uint8
from wgpurender.raw_path import reference_stage_names, render_reference

SIZE = (67, 45)  # small, odd, not square: exposes half-pixel and y-flip mistakes
FORMATS = ("rgba8unorm", "rgba8unorm-srgb", "rgba16float")
MSAA_STAGES = ("triangle", "triangle-buffers")
SINGLE_STAGES = ("clear", "clear-pass", "offscreen", "msaa")
COMPARED = [(s, f, m) for s in MSAA_STAGES for f in FORMATS for m in (1, 4)] + [
    (s, f, None) for s in SINGLE_STAGES for f in FORMATS
]
TRIANGLE = np.array([[-0.8, -0.7], [0.7, -0.5], [-0.1, 0.8]])  # NDC, y up (independent copy)
TRIANGLE_RGB = np.eye(3)


def test_stage_names_mirror_the_wgpu_path():
    """Every compared stage exists under the same name on both paths, msaa-post included (its wgpu twin is two
    render passes: tests/test_msaa_post.py)."""
    from wgpurender.wgpu_path.stages import all_stages

    ref = set(reference_stage_names())
    for name in {s for s, _, _ in COMPARED} | {"3d"}:
        assert name in all_stages() and name in ref
    assert "msaa-post" in ref and "msaa-post" in all_stages()


@pytest.mark.parametrize(("stage", "fmt", "msaa"), COMPARED)
def test_matches_wgpu_path(request, ctx, stage, fmt, msaa):
    """wgpu path == raw-Vulkan path, exactly (threshold 0), for every format and sample count.

    Exact because both run on lavapipe with the same formats, fill rules, sample
    positions and sRGB conversion (see the module docstring). Measured: 0 pixels
    differ in all 24 cases, also at 64x48 and 97x61. 'clear' is zero on both
    paths (WebGPU's clear has no colour); float16 is compared bit for bit.
    """
    from wgpurender.wgpu_path.render import render_stage

    wgpu_pixels = render_stage(stage, SIZE, fmt, msaa, 0.0, ctx, frames=1).pixels
    ref_pixels = render_reference(stage, SIZE, fmt, msaa)
    assert ref_pixels.shape == (SIZE[1], SIZE[0], 4) and ref_pixels.dtype == wgpu_pixels.dtype
    assert_same_render(request, ref_pixels, wgpu_pixels, "raw and wgpu renders")


@pytest.mark.parametrize("t", [0.0, 0.7])
@pytest.mark.parametrize("msaa", [1, 4])
@pytest.mark.parametrize("fmt", FORMATS)
def test_3d_matches_wgpu_path(request, ctx, fmt, msaa, t):
    """Stage '3d' (depth, culling, two UBOs, dynamic offsets, push constants): exact (threshold 0).

    The scene is the course core's (wgpurender/core/course/cubes.py), as on both paths; the
    UBO bytes are packed independently (raw_path/device/ubo.py, hand-written std140
    offsets) from the same float64 matrices, and the shaders come from different
    compilers (naga from WGSL, glslc from GLSL). Measured: bit-identical in all 12
    cases, t = 0 and 0.7: the Lambert term (normalize, dot, max) compiles to the
    same float32 operations on lavapipe. A wrong std140 offset (e.g. a mat3 packed
    as 36 bytes) or a wrong winding after the viewport flip changes whole faces.
    """
    from wgpurender.wgpu_path.render import render_stage

    size = (64, 48)
    wgpu_pixels = render_stage("3d", size, fmt, msaa, t, ctx, frames=1).pixels
    ref_pixels = render_reference("3d", size, fmt, msaa, t)
    assert_same_render(request, ref_pixels, wgpu_pixels, "raw and wgpu renders")


def _barycentric(size: tuple[int, int]) -> np.ndarray:
    """(H, W, 3) barycentric coordinates of each pixel centre, in image rows top to bottom (NDC y up)."""
    width, height = size
    x = (np.arange(width) + 0.5) / width * 2 - 1
    y = 1 - (np.arange(height) + 0.5) / height * 2  # row 0 is NDC y = +1 (top)
    px, py = np.meshgrid(x, y)
    (x0, y0), (x1, y1), (x2, y2) = TRIANGLE
    det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
    b0 = ((y1 - y2) * (px - x2) + (x2 - x1) * (py - y2)) / det
    b1 = ((y2 - y0) * (px - x2) + (x0 - x2) * (py - y2)) / det
    return np.stack([b0, b1, 1 - b0 - b1], axis=-1)


def test_triangle_matches_analytic_raster():
    """The raw path's triangle against float64 numpy: coverage and interpolated colour (rgba8unorm).

    Coverage: a pixel is drawn iff its centre is inside the y-up triangle, except
    pixels whose centre is within 1e-4 (in barycentric units) of an edge, where
    the fill rule decides. Colour: barycentric mix of the vertex colours, within
    1/255 (unorm rounding of the interpolated float). This pins the viewport flip
    independently of the wgpu path: without it the triangle is upside down and
    most pixels fail.
    """
    size = (96, 64)
    pixels = render_reference("triangle", size, "rgba8unorm").astype(np.int32)
    bary = _barycentric(size)
    inside = (bary > 1e-4).all(-1)
    outside = (bary < -1e-4).any(-1)
    drawn = pixels[..., :3].sum(-1) > 0
    assert inside.sum() > 1000
    assert drawn[inside].all() and not drawn[outside].any()
    expected = np.round(np.clip(bary @ TRIANGLE_RGB, 0, 1) * 255)
    assert np.abs(pixels[..., :3][inside] - expected[inside]).max() <= 1
    assert (pixels[..., 3][drawn] == 255).all()


def test_clear_color_image_agrees_with_render_pass_clear(request, ctx, monkeypatch):
    """vkCmdClearColorImage with the clear-pass colour == the wgpu clear-pass stage, exactly, in all formats.

    The colour's components are k/255, exact in unorm; in sRGB both paths encode
    the same float with the same hardware conversion.
    """
    from wgpurender.core.course.triangle import CLEAR_COLOR
    from wgpurender.raw_path.stages.clear import ClearTransfer
    from wgpurender.wgpu_path.render import render_stage

    monkeypatch.setattr(ClearTransfer, "color", CLEAR_COLOR)
    for fmt in FORMATS:
        ref_pixels = render_reference("clear", (16, 8), fmt)
        wgpu_pixels = render_stage("clear-pass", (16, 8), fmt, None, 0.0, ctx, frames=1).pixels
        assert_same_render(request, ref_pixels, wgpu_pixels, f"raw clear and wgpu clear-pass ({fmt})")


@pytest.mark.parametrize("fmt", ["rgba8unorm", "rgba8unorm-srgb"])
def test_msaa_post_is_grey_of_msaa(fmt):
    """msaa-post (two subpasses, input attachment) == Rec. 709 grey of the msaa stage's image, within 1/255.

    Independent reference: numpy float64 on the msaa stage's resolved pixels
    (decoded from sRGB for the -srgb format, since subpassLoad returns linear
    values there and the output store encodes again). 1/255 covers the rounding
    to 8 bits (0.5/255) plus lavapipe's linear -> sRGB encode, which is not
    correctly rounded (Vulkan allows that). Measured max: 0.50/255 for
    rgba8unorm, 0.76/255 for rgba8unorm-srgb.
    """
    size = (64, 48)
    msaa = render_reference("msaa", size, fmt).astype(np.float64) / 255
    post = render_reference("msaa-post", size, fmt).astype(np.float64) / 255
    linear = srgb_decode(msaa[..., :3]) if fmt.endswith("srgb") else msaa[..., :3]
    luma = linear @ np.array([0.2126, 0.7152, 0.0722])
    expected = srgb_encode(luma) if fmt.endswith("srgb") else luma
    assert (msaa[..., :3].max(-1) > 0.1).sum() > 500  # the triangle is there
    assert np.abs(post[..., :3] - expected[..., None]).max() <= 1 / 255 + 1e-9
    assert np.ptp(post[..., :3], axis=-1).max() == 0  # grey: r == g == b
    assert (post[..., 3] == 1).all()


@pytest.mark.parametrize("stage", reference_stage_names())
def test_reference_images_are_current(request, stage, raw_driver_class):
    """assets/reference/<stage>.png against a fresh render by the raw path at 256x192, within the table's bounds.

    The PNGs are written only by the raw path (pytest --regenerate-references, make references); lavapipe's
    output differs between host CPUs and a GPU's more, so the bounds are the driver class's calibrated row
    of assets/reference/tolerances.toml (tests/test_reference_tolerances.py shows they reject real changes).
    """
    from wgpurender.raw_path.make_references import REFERENCE_SIZE, reference_path

    path = reference_path(stage)
    assert path.is_file(), f"{path} missing: run pytest --regenerate-references"
    fresh = to_uint8(render_reference(stage, REFERENCE_SIZE))
    assert_within_tolerance(request, stage, load_png(path), fresh, raw_driver_class)


# -- errors -------------------------------------------------------------------------------------

def test_unknown_stage_names_the_valid_ones():
    with pytest.raises(UserError, match=r"unknown stage 'nope'.*valid stages are clear, clear-pass, triangle"):
        render_reference("nope", (8, 8))


@pytest.mark.parametrize(("stage", "kwargs", "message"), [
    ("clear", {"msaa": 4}, "does not use MSAA"),
    ("triangle", {"msaa": 8}, "MSAA 8x is not supported"),
    ("msaa-post", {"msaa": 1}, "use --msaa 4"),
    ("triangle", {"fmt": "bgra8unorm"}, "unsupported colour format 'bgra8unorm'"),
])
def test_bad_options_are_user_errors(stage, kwargs, message):
    with pytest.raises(UserError, match=message):
        render_reference(stage, (8, 8), **kwargs)


def test_missing_glslc_is_a_user_error(monkeypatch, tmp_path):
    """No glslc on PATH and a cold SPIR-V cache: a UserError naming the apt package, from the full render."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(UserError, match=r"glslc not found on PATH.*apt install glslc"):
        render_reference("triangle", (8, 8))


def test_spirv_cache_spares_glslc(monkeypatch, tmp_path):
    """Once compiled, a shader comes from the cache: glslc is not needed again until the source changes."""
    from wgpurender.raw_path.device.shaders import cache_dir, compile_glsl, glsl_path

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    spirv = compile_glsl(glsl_path("color.frag"))
    assert spirv[:4] == b"\x03\x02\x23\x07"  # SPIR-V magic, little-endian
    assert len(list(cache_dir().glob("*.spv"))) == 1
    monkeypatch.setenv("PATH", str(tmp_path))
    assert compile_glsl(glsl_path("color.frag")) == spirv


def test_glsl_compile_error_names_file_and_line(monkeypatch, tmp_path):
    from wgpurender.raw_path.device.shaders import compile_glsl

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    broken = tmp_path / "broken.frag"
    broken.write_text("#version 450\nlayout(location = 0) out vec4 c;\n\nvoid main() {\n    c = undefined_thing;\n}\n")
    with pytest.raises(UserError, match=rf"{broken} line 5: .*undefined_thing"):
        compile_glsl(broken)
    assert not (tmp_path / "cache").exists()  # failures are not cached


def test_validation_messages_are_caught():
    """The messenger is live: an invalid call (a zero-size buffer) is reported and check_validation raises."""
    import vulkan as vk

    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.device.validation import ValidationFailed

    ctx = get_vulkan()
    assert ctx.log is not None, "tests run with $WGPURENDER_VALIDATION set"
    info = vk.VkBufferCreateInfo(size=0, usage=vk.VK_BUFFER_USAGE_TRANSFER_SRC_BIT)
    buffer = vk.vkCreateBuffer(ctx.device, info, None)
    vk.vkDestroyBuffer(ctx.device, buffer, None)
    with pytest.raises(ValidationFailed, match="VUID-VkBufferCreateInfo-size-00912"):
        ctx.check_validation("a deliberate mistake")


# -- stage 'textured': texture upload, mip chain by render passes, combined vs separate samplers ----------------

@pytest.mark.parametrize(("fmt", "msaa", "t"), [
    ("rgba8unorm-srgb", 1, 0.0),
    ("rgba8unorm-srgb", 4, 0.0),
    ("rgba16float", 4, 0.7),
])
def test_textured_matches_wgpu_path(request, ctx, fmt, msaa, t):
    """Stage 'textured' on both paths, 160x96: exact (threshold 0).

    Same driver, same sampler state (raw_path/device/textures.sampler_info fills VkSamplerCreateInfo
    as wgpu's Vulkan backend does: LOD clamps, anisotropy 16 with samplerAnisotropy enabled),
    and a bit-identical mip chain: the raw path draws each level with the same integer-weight
    box filter in GLSL (textured_mipmap.frag) as mipmap.wgsl, in the same order of float
    operations. The left half reads a COMBINED_IMAGE_SAMPLER, the right half a SAMPLED_IMAGE
    plus four SAMPLER descriptors; lavapipe samples both forms alike. Measured: 0 pixels
    differ in all three cases (and at 161x97 rgba8unorm). The comparison is sensitive: scaling
    the mip weights by 1.0001 in the GLSL changes 2 pixels by 1/255; the raw path without
    anisotropy changes 3686 of 15360 pixels.
    """
    from wgpurender.wgpu_path.render import render_stage

    size = (160, 96)
    wgpu_pixels = render_stage("textured", size, fmt, msaa, t, ctx, frames=1).pixels
    ref_pixels = render_reference("textured", size, fmt, msaa, t)
    assert_same_render(request, ref_pixels, wgpu_pixels, "raw and wgpu renders")


def _box_level(prev: np.ndarray, srgb: bool) -> np.ndarray:
    """Next mip level in float64 (independent of both shaders): area-weighted box filter, linear light for sRGB."""
    def weights(src: int) -> np.ndarray:
        dst = max(1, src >> 1)
        edges_src, edges_dst = np.arange(src + 1) / src, np.arange(dst + 1) / dst
        lo = np.maximum(edges_dst[:-1, None], edges_src[None, :-1])
        hi = np.minimum(edges_dst[1:, None], edges_src[None, 1:])
        w = np.clip(hi - lo, 0, None)
        return w / w.sum(axis=1, keepdims=True)

    f = prev.astype(np.float64) / 255
    if srgb:
        f[..., :3] = srgb_decode(f[..., :3])
    out = np.einsum("yj,xi,jic->yxc", weights(prev.shape[0]), weights(prev.shape[1]), f)
    if srgb:
        out[..., :3] = srgb_encode(np.clip(out[..., :3], 0, 1))
    return out * 255


@pytest.mark.parametrize("srgb", [True, False])
@pytest.mark.parametrize("shape", [(21, 37), (5, 1), (16, 16)])
def test_raw_mip_chain(ctx, srgb, shape):
    """The raw path's mip chain (render pass per level) vs the wgpu path's (exact) and vs numpy float64.

    Odd and degenerate sizes exercise the fractional edge weights. Exact against wgpu: same
    arithmetic on the same driver. Against the unrounded float64 box filter of the previous
    level: below 1.0, one of the two nearest levels, which is what Vulkan requires of a float -> unorm
    store (lavapipe rounds data to nearest, the H200 not always; lavapipe's sRGB encode is not correctly
    rounded either), as in tests/test_textures.py.
    """
    from contextlib import ExitStack

    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.raw_path.device.textures import read_level, upload_texture
    from wgpurender.wgpu_path.device.textures import create_texture, read_mip

    h, w = shape
    pixels = np.random.default_rng(7 * h + w).integers(0, 256, (h, w, 4), dtype=np.uint8)
    vctx = get_vulkan()
    wgpu_texture = create_texture(ctx, pixels, srgb=srgb)
    with ExitStack() as owned:
        texture = upload_texture(vctx, owned, pixels, srgb)
        assert texture.levels == wgpu_texture.mip_level_count == max(h, w).bit_length()
        levels = [read_level(vctx, texture, level) for level in range(texture.levels)]
    vctx.check_validation("the raw mip chain")
    np.testing.assert_array_equal(levels[0], pixels)
    for level in range(1, len(levels)):
        got = levels[level]
        assert got.shape == (max(1, h >> level), max(1, w >> level), 4)
        np.testing.assert_array_equal(got, read_mip(ctx, wgpu_texture.texture, level), err_msg=f"level {level}")
        error = np.abs(got - _box_level(levels[level - 1], srgb))
        assert error.max() < 1.0, f"level {level}: {error.max()}"  # one of the two nearest levels (Vulkan)


def test_sampler_info_mirrors_the_spec():
    """SamplerSpec -> VkSamplerCreateInfo: filters, mipmap mode, address modes, LOD clamps, anisotropy."""
    import vulkan as vk

    from wgpurender.core.course.textured import COMBINED_SAMPLER, SEPARATE_SAMPLERS
    from wgpurender.raw_path.device.textures import sampler_info

    info = sampler_info(COMBINED_SAMPLER)
    assert (info.magFilter, info.minFilter, info.mipmapMode) == (
        vk.VK_FILTER_LINEAR, vk.VK_FILTER_LINEAR, vk.VK_SAMPLER_MIPMAP_MODE_LINEAR)
    assert info.addressModeU == info.addressModeV == vk.VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
    assert info.anisotropyEnable == vk.VK_TRUE and info.maxAnisotropy == 16.0 and info.maxLod == 32.0
    assert sampler_info(COMBINED_SAMPLER, anisotropy_supported=False).anisotropyEnable == vk.VK_FALSE
    nearest = sampler_info(SEPARATE_SAMPLERS[0][1])
    assert (nearest.magFilter, nearest.mipmapMode, nearest.maxLod) == (
        vk.VK_FILTER_NEAREST, vk.VK_SAMPLER_MIPMAP_MODE_NEAREST, 0.0)
    assert nearest.anisotropyEnable == vk.VK_FALSE and nearest.addressModeU == vk.VK_SAMPLER_ADDRESS_MODE_REPEAT
