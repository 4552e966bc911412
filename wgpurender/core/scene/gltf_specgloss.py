"""``KHR_materials_pbrSpecularGlossiness`` converted to metallic-roughness at load, so both paths draw it with
their ordinary PBR shaders.

The conversion is the one of the extension's appendix ("converting between specular-glossiness and
metallic-roughness", as Babylon.js and gltf-transform's ``metalRough()`` do it), in linear light:

- roughness = 1 - glossiness;
- metallic solves ``a m^2 + b m + c = 0`` with a = 0.04 (the dielectric specular), b = D (1 - max S) / (1 - a)
  + P - 2a, c = a - P, where D and P are the perceived brightness sqrt(0.299 r^2 + 0.587 g^2 + 0.114 b^2) of the
  diffuse and specular colours; 0 where P < a;
- base colour = lerp(diffuse (1 - max S) / (1 - a) / (1 - m), (S - a (1 - m)) / m, m^2), clamped to [0, 1];
  alpha = the diffuse alpha.

It is exact for a dielectric (grey specular 0.04) and for a pure metal (black diffuse); other materials are an
approximation (a spec-gloss material can describe colours metallic-roughness cannot), and ``--explain`` says so.
Factors are converted as factors. Textures are converted per texel (the factors folded in) into a base-colour and
a metallic-roughness image of the same size, sampled with the source texture's sampler and coordinates
(``diffuseTexture``'s when both are given: then both must be the same size and sample alike).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import srgb_decode, srgb_encode

EXTENSION = "KHR_materials_pbrSpecularGlossiness"
DIELECTRIC = 0.04
EPSILON = 1e-6
MARK = "#specgloss["  # a converted texture's "path": model.glb#specgloss[material].base / .metalrough
KINDS = ("base", "metalrough")
BAND_ROWS = 64  # rows converted at once (float64 work arrays of 64 x width texels)


def brightness(rgb: np.ndarray) -> np.ndarray:
    """Perceived brightness over the last axis: sqrt(0.299 r^2 + 0.587 g^2 + 0.114 b^2)."""
    rgb = np.asarray(rgb, np.float64)
    return np.sqrt(0.299 * rgb[..., 0] ** 2 + 0.587 * rgb[..., 1] ** 2 + 0.114 * rgb[..., 2] ** 2)


def convert(diffuse: np.ndarray, specular: np.ndarray, glossiness: np.ndarray):
    """(base colour RGBA, metallic, roughness) of linear diffuse RGBA (..., 4), specular RGB (..., 3) and
    glossiness (...): the appendix's formula, elementwise."""
    diffuse, specular = np.asarray(diffuse, np.float64), np.asarray(specular, np.float64)
    one_minus = 1.0 - specular.max(axis=-1)
    d, p = brightness(diffuse[..., :3]), brightness(specular)
    b = d * one_minus / (1.0 - DIELECTRIC) + p - 2.0 * DIELECTRIC
    c = DIELECTRIC - p
    root = np.sqrt(np.maximum(b * b - 4.0 * DIELECTRIC * c, 0.0))
    metallic = np.where(p < DIELECTRIC, 0.0, np.clip((-b + root) / (2.0 * DIELECTRIC), 0.0, 1.0))
    m = metallic[..., None]
    from_diffuse = diffuse[..., :3] * (one_minus / (1.0 - DIELECTRIC))[..., None] / np.maximum(1.0 - m, EPSILON)
    from_specular = (specular - DIELECTRIC * (1.0 - m)) / np.maximum(m, EPSILON)
    base = np.clip(from_diffuse + (from_specular - from_diffuse) * m * m, 0.0, 1.0)
    rgba = np.concatenate([base, diffuse[..., 3:4]], axis=-1)
    return rgba, metallic, 1.0 - np.asarray(glossiness, np.float64)


def factors(ext: dict) -> tuple[np.ndarray, np.ndarray, float]:
    """The extension's factors with the spec's defaults: diffuse RGBA, specular RGB, glossiness."""
    return (np.asarray(ext.get("diffuseFactor", (1.0, 1.0, 1.0, 1.0)), np.float64),
            np.asarray(ext.get("specularFactor", (1.0, 1.0, 1.0)), np.float64),
            float(ext.get("glossinessFactor", 1.0)))


def exact(diffuse: np.ndarray, specular: np.ndarray, base: np.ndarray, metallic: float) -> bool:
    """Whether metallic-roughness draws the same BRDF: the same F0 (specular = lerp(a, base, m)) and the same
    diffuse colour (diffuse (1 - max specular) = base (1 - a) (1 - m))."""
    f0 = DIELECTRIC * (1.0 - metallic) + base[:3] * metallic
    c_diff = base[:3] * (1.0 - DIELECTRIC) * (1.0 - metallic)
    return bool(np.allclose(f0, specular, atol=1e-6)
                and np.allclose(c_diff, diffuse[:3] * (1.0 - specular.max()), atol=1e-6))


def source_info(ext: dict, name: str) -> dict | None:
    """The textureInfo the converted textures sample with (diffuse's, else specular-glossiness's), or None."""
    from wgpurender.core.models.gltf_extensions import texture_uv_choice

    infos = [ext.get(k) for k in ("diffuseTexture", "specularGlossinessTexture") if isinstance(ext.get(k), dict)]
    if len(infos) == 2 and texture_uv_choice(infos[0]) != texture_uv_choice(infos[1]):
        raise UserError(f"{name}: {EXTENSION} diffuseTexture and specularGlossinessTexture sample different "
                        "coordinates (texCoord or KHR_texture_transform): not supported; give both the same")
    return infos[0] if infos else None


def texture_path(model: Path, material: int, kind: str) -> Path:
    return Path(f"{model}{MARK}{material}].{kind}")


def parse_path(path: Path) -> tuple[str, int, int] | None:
    """(model file, material index, which image: 0 base colour, 1 metallic-roughness) of a converted texture's
    ``model#specgloss[k].kind`` path, or None for another path."""
    model, mark, rest = str(path).rpartition(MARK)
    index, _, kind = rest.partition("].")
    if not mark or kind not in KINDS or not index.isdigit() or not os.path.isfile(model):
        return None
    return model, int(index), KINDS.index(kind)


def converted_pngs(ext: dict, texels: dict[str, np.ndarray], name: str) -> tuple[bytes, bytes]:
    """PNG bytes of the base-colour (sRGB) and metallic-roughness (linear: G roughness, B metallic) images of a
    spec-gloss material ``ext`` whose textures decoded to ``texels`` (key -> (H, W, 4) uint8), factors folded in.
    Converted in bands of :data:`BAND_ROWS` rows: float64 work memory stays a few band-sized arrays, whatever
    the image size (the inputs are bounded by the image pixel limit, the outputs are uint8 like them)."""
    from wgpurender.core.files.imageio import encode_png

    shapes = {t.shape for t in texels.values()}
    if len(shapes) != 1:
        raise UserError(f"{name}: {EXTENSION} diffuseTexture and specularGlossinessTexture differ in size: not "
                        "supported; resize one to the other's size")
    height, width = shapes.pop()[:2]
    base, mr = np.empty((height, width, 4), np.uint8), np.empty((height, width, 4), np.uint8)
    for top in range(0, height, BAND_ROWS):
        band = {k: t[top:top + BAND_ROWS] for k, t in texels.items()}
        base[top:top + BAND_ROWS], mr[top:top + BAND_ROWS] = _convert_band(ext, band)
    return encode_png(base), encode_png(mr)


def _convert_band(ext: dict, texels: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Base colour and metallic-roughness RGBA8 of rows of the source texels (see :func:`converted_pngs`)."""
    diffuse, specular, gloss = factors(ext)
    texels = {k: np.asarray(t, np.float64) / 255.0 for k, t in texels.items()}
    if "diffuseTexture" in texels:
        t = texels["diffuseTexture"]
        diffuse = diffuse * np.concatenate([srgb_decode(t[..., :3]), t[..., 3:4]], axis=-1)
    if "specularGlossinessTexture" in texels:
        t = texels["specularGlossinessTexture"]
        specular, gloss = specular * srgb_decode(t[..., :3]), gloss * t[..., 3]
    shape = next(iter(texels.values())).shape[:2]
    base, metallic, roughness = convert(np.broadcast_to(diffuse, (*shape, 4)), np.broadcast_to(specular, (*shape, 3)),
                                        np.broadcast_to(gloss, shape))
    base_rgba = np.concatenate([srgb_encode(base[..., :3]), base[..., 3:4]], axis=-1)
    mr = np.stack([np.zeros(shape), roughness, metallic, np.ones(shape)], axis=-1)
    return tuple(np.round(np.clip(a, 0.0, 1.0) * 255.0).astype(np.uint8) for a in (base_rgba, mr))
