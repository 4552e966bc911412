"""The many-objects benchmark's objects: what both the CPU-animated and the GPU-animated renderers draw."""

from __future__ import annotations

import numpy as np

FORMAT = "rgba8unorm"
BACKGROUND = (0.0, 0.0, 0.0, 1.0)
HALF_SIZE = (0.005, 0.0067)  # NDC: quads of about 4x4 pixels at 800x600


def object_params(count: int, seed: int = 7) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(centres (count, 2), phases (count,), colours (count, 3)): what does not change with time."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-0.98, 0.98, size=(count, 2))
    phase = rng.uniform(0.0, 2.0 * np.pi, size=count)
    return centres, phase, rng.uniform(0.2, 1.0, size=(count, 3))
