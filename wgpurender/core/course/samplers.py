"""The sampler description both paths build their samplers from (the VkSamplerCreateInfo analogue)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from wgpurender.core.errors import UserError

FILTERS = ("nearest", "linear")
ADDRESS_MODES = ("repeat", "clamp-to-edge", "mirror-repeat")
MAX_ANISOTROPY = 16


@dataclass(frozen=True)
class SamplerSpec:
    """Everything a sampler is made from; hashable, so equal specs share one GPUSampler.

    The VkSamplerCreateInfo analogue. wgpu (like WebGPU) only allows
    ``max_anisotropy > 1`` when mag, min and mipmap filters are all linear.
    """

    mag_filter: str = "linear"
    min_filter: str = "linear"
    mipmap_filter: str = "linear"
    address_mode_u: str = "repeat"
    address_mode_v: str = "repeat"
    address_mode_w: str = "repeat"
    max_anisotropy: int = 1
    lod_min_clamp: float = 0.0
    lod_max_clamp: float = 32.0

    def __post_init__(self) -> None:
        for name in ("mag_filter", "min_filter", "mipmap_filter"):
            value = getattr(self, name)
            if value not in FILTERS:
                raise UserError(f"sampler {name} {value!r} is not valid: choose one of {', '.join(FILTERS)}")
        for name in ("address_mode_u", "address_mode_v", "address_mode_w"):
            value = getattr(self, name)
            if value not in ADDRESS_MODES:
                raise UserError(f"sampler {name} {value!r} is not valid: choose one of {', '.join(ADDRESS_MODES)}")
        aniso = self.max_anisotropy
        if isinstance(aniso, bool) or not isinstance(aniso, int) or not 1 <= aniso <= MAX_ANISOTROPY:
            raise UserError(f"sampler max_anisotropy {aniso!r} is not valid: give an integer 1..{MAX_ANISOTROPY}")
        if aniso > 1:
            nearest = [n for n in ("mag_filter", "min_filter", "mipmap_filter") if getattr(self, n) != "linear"]
            if nearest:
                raise UserError(
                    f"sampler max_anisotropy {aniso} needs mag_filter, min_filter and mipmap_filter all 'linear' "
                    f"(a wgpu rule), but {', '.join(nearest)} {'is' if len(nearest) == 1 else 'are'} 'nearest': "
                    "use linear filters or max_anisotropy 1"
                )
        clamps = (self.lod_min_clamp, self.lod_max_clamp)
        numbers = all(isinstance(c, (int, float)) and not isinstance(c, bool) and not math.isnan(c) for c in clamps)
        if not numbers or not 0.0 <= self.lod_min_clamp <= self.lod_max_clamp:
            raise UserError(
                f"sampler lod clamps {self.lod_min_clamp}..{self.lod_max_clamp} are not valid: need 0 <= min <= max"
            )

    @classmethod
    def from_dict(cls, spec: dict) -> SamplerSpec:
        """From a scene-file table. Shorthands: ``filter`` sets mag and min, ``address`` sets u, v and w."""
        known = {f.name for f in fields(cls)} | {"filter", "address"}
        unknown = sorted(set(spec) - known)
        if unknown:
            valid = ", ".join(sorted(known))
            raise UserError(f"unknown sampler setting(s) {', '.join(unknown)}: valid ones are {valid}")
        args = {k: v for k, v in spec.items() if k not in ("filter", "address")}
        if "filter" in spec:
            args.setdefault("mag_filter", spec["filter"])
            args.setdefault("min_filter", spec["filter"])
        if "address" in spec:
            for axis in "uvw":
                args.setdefault(f"address_mode_{axis}", spec["address"])
        return cls(**args)


NEAREST = SamplerSpec(mag_filter="nearest", min_filter="nearest", mipmap_filter="nearest")
BILINEAR = SamplerSpec(mipmap_filter="nearest")
TRILINEAR = SamplerSpec()


def anisotropic(n: int = MAX_ANISOTROPY) -> SamplerSpec:
    return SamplerSpec(max_anisotropy=n)
