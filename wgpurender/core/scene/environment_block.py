"""A scene's ``[environment]`` table: the equirectangular environment that lights its PBR materials (image-based
lighting), either a Radiance .hdr file or the procedural sky (core/course/environment.py)::

    [environment]
    hdr = "sky.hdr"          # relative to the scene file's folder; or:
    procedural = "sky"
    intensity = 1.0          # scales the environment's radiance
    samples = 256            # GGX samples per prefiltered texel and table cell (16, 64, 256 or 1024)

Exactly one of ``hdr`` and ``procedural``. The maps are made only when a glTF metallic-roughness material is lit
in the scene (core/plan/shading_models.py says so in ``--explain``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from wgpurender.core.course.ibl_maps import SAMPLE_CHOICES, SAMPLES
from wgpurender.core.scene.checker import Checker
from wgpurender.core.scene.toml_locator import format_path

ENVIRONMENT_KEYS = ("hdr", "intensity", "procedural", "samples")
PROCEDURAL = ("sky",)


@dataclass(frozen=True)
class Environment:
    hdr: Path | None = None
    procedural: str | None = None
    intensity: float = 1.0
    samples: int = SAMPLES

    @property
    def label(self) -> str:
        return f"hdr '{self.hdr.name}'" if self.hdr is not None else f"procedural '{self.procedural}'"

    def radiance(self) -> np.ndarray:
        """(h, w, 3) linear radiance, times ``intensity``."""
        if self.hdr is not None:
            from wgpurender.core.files.hdr_io import load_hdr

            image = load_hdr(self.hdr)
        else:
            from wgpurender.core.course.environment import sky

            image = sky()
        return image.astype(np.float64) * self.intensity


def parse_environment(c: Checker, data: Any) -> Environment | None:
    if data is None:
        return None
    key = ("environment",)
    t = c.table(data, key, ENVIRONMENT_KEYS)
    if ("hdr" in t) == ("procedural" in t):
        raise c.error(key, f"{format_path(key)}: give exactly one of hdr = \"FILE.hdr\" or procedural = \"sky\"")
    hdr = procedural = None
    if "hdr" in t:
        hdr = c.file(t["hdr"], key + ("hdr",), "environment image")
    else:
        procedural = c.string(t["procedural"], key + ("procedural",), PROCEDURAL)
    return Environment(hdr=hdr, procedural=procedural,
                       intensity=c.number(t.get("intensity", 1.0), key + ("intensity",), lo=0.0, hi=1e6),
                       samples=c.integer(t.get("samples", SAMPLES), key + ("samples",), choices=SAMPLE_CHOICES))
