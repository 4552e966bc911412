"""Formats, sample counts, post paths and colour-space rules: the one home of each fact the paths, the plan,
the scene validator, the CLI and the benches need (they import it from here; the plan re-exports it)."""

from __future__ import annotations

from pathlib import PurePath

from wgpurender.core.course.steps import course_step
from wgpurender.core.files.assets import bundled_scene

# MSAA: what WebGPU guarantees without extensions, and all that lavapipe offers.
SAMPLE_COUNTS = (1, 4)

# Colour formats a stage or scene can render into and write to a PNG.
# rgba16float is written after sRGB encoding; the -srgb format stores encoded bytes.
DEFAULT_FORMAT = "rgba8unorm-srgb"
OUTPUT_FORMATS = ("rgba8unorm-srgb", "rgba8unorm", "rgba16float")
HDR_FORMAT = "rgba16float"  # the scene image under a tone-mapping post chain

# Where a scene's post chain runs: render-pipeline (fragment) passes or compute passes; auto asks the plan.
POST_PATHS = ("auto", "fragment", "compute")

# Bytes per texel of every format the plan and the benches count traffic for.
BYTES_PER_PIXEL = {"rgba8unorm": 4, "rgba8unorm-srgb": 4, "bgra8unorm": 4, "bgra8unorm-srgb": 4, "rgba16float": 8,
                   "rgba32float": 16, "depth16unorm": 2, "depth24plus": 4, "depth24plus-stencil8": 4,
                   "depth32float": 4}

# Texture colour spaces: colour maps are sRGB-encoded images (the sampler decodes them to linear);
# data maps (normal, roughness) hold values used as stored.
SRGB_TEXTURE_FORMAT = "rgba8unorm-srgb"
LINEAR_TEXTURE_FORMAT = "rgba8unorm"
SRGB_MAPS = frozenset({"albedo_map", "emissive_map"})  # colour; normal, roughness, occlusion are data


def is_srgb_map(feature: str) -> bool:
    """Whether a material map holds sRGB-encoded colour (albedo) rather than linear data (normal, roughness)."""
    return feature in SRGB_MAPS


def map_format(feature: str) -> str:
    """The texture format a material map is uploaded as."""
    return SRGB_TEXTURE_FORMAT if is_srgb_map(feature) else LINEAR_TEXTURE_FORMAT


SCENE_SUFFIX = ".toml"


def is_scene_file(target: str | PurePath) -> bool:
    """Whether a render target names a scene file (rather than a stage): it ends in ``.toml``, or it is a
    bundled scene's name (``final``: :func:`wgpurender.core.files.assets.bundled_scene`) that no stage step has."""
    if str(target).endswith(SCENE_SUFFIX):
        return True
    step = course_step(str(target))
    return (step is None or step.scene is not None) and bundled_scene(target) is not None
