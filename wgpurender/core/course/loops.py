"""How long an animated course stage runs before its frame repeats: where a page (wgpurender export) may wrap its
time without a visible jump.

The 3d stage's cubes turn at whole degrees per second: each is back where it started after 360 / speed seconds,
so all of them after the least common multiple of those (24 s for 90, 60 and 45 degrees a second). The textured
stage scrolls its texture; a repeat sampler repeats every tile and a mirror-repeat one every second tile, so the
image repeats after 2 / SCROLL_PER_SECOND seconds (8 s). A stage with no entry is not animated. API-free.
"""

from __future__ import annotations

import math
from fractions import Fraction

from wgpurender.core.course import cubes, textured

MIRROR_TILES = 2  # mirror-repeat: a tile, then its mirror image


def _common(periods: list[Fraction]) -> Fraction:
    """The least common multiple of positive rational periods."""
    num = math.lcm(*(p.numerator * (math.lcm(*(q.denominator for q in periods)) // p.denominator) for p in periods))
    return Fraction(num, math.lcm(*(q.denominator for q in periods)))


def cube_period(specs=cubes.DEFAULT_CUBES) -> Fraction:
    return _common([Fraction(360) / Fraction(spec.speed).limit_denominator(1000) for spec in specs])


def scroll_period() -> Fraction:
    return Fraction(MIRROR_TILES) / Fraction(textured.SCROLL_PER_SECOND).limit_denominator(1000)


LOOP_SECONDS = {"3d": cube_period, "textured": scroll_period}


def loop_seconds(stage: str) -> float | None:
    """Seconds after which ``stage``'s frame repeats; None for a stage that does not move."""
    period = LOOP_SECONDS.get(stage)
    return float(period()) if period else None
