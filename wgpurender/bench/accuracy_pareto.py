"""The Pareto front of (time, error) points: the settings no other setting beats on both."""

from __future__ import annotations

import math
from collections.abc import Sequence


def dominates(a: tuple[float, float], b: tuple[float, float]) -> bool:
    """a is no slower and no less accurate than b, and strictly better in one of the two."""
    return a[0] <= b[0] and a[1] <= b[1] and (a[0] < b[0] or a[1] < b[1])


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the non-dominated points (minimising both coordinates), sorted by time.

    Points with a NaN coordinate take no part (neither on the front nor dominating). Equal points are all kept:
    neither dominates the other. O(n^2), which is nothing for a few dozen settings.
    """
    valid = [i for i, p in enumerate(points) if not (math.isnan(p[0]) or math.isnan(p[1]))]
    front = [i for i in valid if not any(dominates(points[j], points[i]) for j in valid if j != i)]
    return sorted(front, key=lambda i: (points[i][0], points[i][1]))
