"""Formats, sample counts and colour-space rules: one home for each fact both paths and the CLI need."""

from __future__ import annotations

from pathlib import PurePath

# MSAA: what WebGPU guarantees without extensions, and all that lavapipe offers.
SAMPLE_COUNTS = (1, 4)

# Colour formats a stage or scene can render into and write to a PNG.
# rgba16float is written after sRGB encoding; the -srgb format stores encoded bytes.
DEFAULT_FORMAT = "rgba8unorm-srgb"
OUTPUT_FORMATS = ("rgba8unorm-srgb", "rgba8unorm", "rgba16float")
HDR_FORMAT = "rgba16float"  # the scene image under a tone-mapping post chain

# Texture colour spaces: colour maps are sRGB-encoded images (the sampler decodes them to linear);
# data maps (normal, roughness) hold values used as stored.
SRGB_TEXTURE_FORMAT = "rgba8unorm-srgb"
LINEAR_TEXTURE_FORMAT = "rgba8unorm"
SRGB_MAPS = frozenset({"albedo_map"})


def is_srgb_map(feature: str) -> bool:
    """Whether a material map holds sRGB-encoded colour (albedo) rather than linear data (normal, roughness)."""
    return feature in SRGB_MAPS


def map_format(feature: str) -> str:
    """The texture format a material map is uploaded as."""
    return SRGB_TEXTURE_FORMAT if is_srgb_map(feature) else LINEAR_TEXTURE_FORMAT


SCENE_SUFFIX = ".toml"


def is_scene_file(target: str | PurePath) -> bool:
    """Whether a render target names a scene file (rather than a stage): it ends in ``.toml``."""
    return str(target).endswith(SCENE_SUFFIX)
