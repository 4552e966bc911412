"""The plan's textures and samplers: each texture file once per upload format, each sampler once per spec,
with every material that uses it."""

from __future__ import annotations

from pathlib import Path

from wgpurender.core.course.formats import map_format
from wgpurender.core.plan.anisotropy import resolve_anisotropy
from wgpurender.core.plan.model import Knobs, SamplerUse, TextureUse
from wgpurender.core.scene import Material
from wgpurender.core.scene.texture_pixels import image_size, mip_level_count


class TextureTable:
    """Collects :class:`TextureUse` and :class:`SamplerUse` entries as draws ask for them, in first-use order."""

    def __init__(self) -> None:
        self.textures: dict[tuple[Path, str], TextureUse] = {}
        self.samplers: dict[object, SamplerUse] = {}

    def add_textures(self, label: str, sampled: tuple[tuple[str, Path], ...], mipmaps: bool) -> None:
        """Albedo is uploaded as sRGB (decoded by the sampler), normal and roughness maps as stored values."""
        for feature, path in sampled:
            fmt = map_format(feature)
            who = f"{label} {feature}"
            old = self.textures.get((path, fmt))
            if old is None:
                self.textures[(path, fmt)] = _texture_use(path, fmt, mipmaps, (who,))
            elif who not in old.used_by:
                self.textures[(path, fmt)] = _texture_use(path, fmt, old.mipmaps or mipmaps, old.used_by + (who,),
                                                          old.size)

    def add_sampler(self, spec: object, label: str) -> None:
        who = f"{label} sampler"
        old = self.samplers.get(spec)
        if old is None:
            self.samplers[spec] = SamplerUse(spec, (who,))
        elif who not in old.used_by:
            self.samplers[spec] = SamplerUse(spec, old.used_by + (who,))


def _texture_use(path: Path, fmt: str, mipmaps: bool, used_by: tuple[str, ...],
                 size: tuple[int, int] | None = None) -> TextureUse:
    """The use with the image's size (its header only) and the mip levels the upload fills."""
    size = size or image_size(path)
    levels = (mip_level_count(*size) if size else None) if mipmaps else 1
    return TextureUse(path, fmt, mipmaps, used_by, size, levels)


def material_sampler(material: Material, label: str, knobs: Knobs, adapter_type: str | None,
                     notes: list[str] | None, spec: object | None = None) -> object:
    """The material's sampler (or ``spec``: a model file texture's own) after the anisotropy rule; a change is
    noted in ``notes`` (None: already noted)."""
    spec, why = resolve_anisotropy(spec or material.sampler.spec(), knobs.anisotropy, adapter_type)
    if why and notes is not None:
        notes.append(f"{label} sampler: {why}")
    return spec
