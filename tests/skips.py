"""The skips the suite expects, and the check that fails a run whose skips grew (conftest's sessionfinish).

A skip is expected only when its reason names something the environment lacks (a tool, a package, a display,
an adapter feature, the course's shared files): :data:`ENVIRONMENT` lists them. An uncalibrated bound may skip
only where the machine's driver class really differs from the one the bounds were measured on (the reason names
both); a reason naming the same class twice is a broken comparison, not an environment. And however good the
reasons, more than :data:`DEFAULT_MAX_SKIPS` skips fail the run: one inverted comparison once turned 34 tests
into skips. A machine that lacks more (no anchors, no browser, no display: the GPU machine skips ~90) sets
``WGPURENDER_MAX_SKIPS=N``.
"""

from __future__ import annotations

import os
import re

DEFAULT_MAX_SKIPS = 40  # this project's CI machine (lavapipe, every optional tool installed) skips far fewer
ENVIRONMENT = (  # (pattern of a skip reason, what the environment lacks)
    (r"glslc", "the shader compiler of the raw path"),
    (r"chromium", "a browser for the exported page"),
    (r"OpenGL adapter", "an OpenGL adapter"),
    (r"Xvfb|xdotool|display", "a virtual display"),
    (r"anchors|shared/course|course texts", "the course's shared files beside the checkout"),
    (r"timestamp", "timestamp queries on this adapter"),
    (r"has no immediates", "immediates on this adapter"),
    (r"not offered", "a present mode on this surface"),
    (r"storage binding holds \d+ copies, more than a model", "a storage binding small enough to overflow in a test"),
    (r"could not import|not installed|No module named", "an optional Python package"),
    (r"root \(CAP_MKNOD\)|/proc", "an operating-system facility"),
    (r"assets not present|scene assets|brick_torus", "assets of a source checkout (an installed wheel has none)"),
)
_UNCALIBRATED = re.compile(r"calibrated on (\S+), not (\S+?):")


def expected(reason: str) -> bool:
    """Whether a skip with this reason is an environment lack (see the module doc)."""
    uncalibrated = _UNCALIBRATED.search(reason)
    if uncalibrated:
        return uncalibrated.group(1) != uncalibrated.group(2)
    return any(re.search(pattern, reason) for pattern, _ in ENVIRONMENT)


def max_skips() -> int:
    return int(os.environ.get("WGPURENDER_MAX_SKIPS") or DEFAULT_MAX_SKIPS)


def skip_problems(reasons: list[str], collected: int = 0) -> list[str]:
    """One line per unexpected skip reason, and one if there are more skips than allowed; [] when all is well."""
    out = [f"unexpected skip: {reason}" for reason in reasons if not expected(reason)]
    if len(reasons) > max_skips():
        out.append(f"{len(reasons)} of {collected} tests skipped, more than the {max_skips()} expected "
                   "(tests/skips.py; set WGPURENDER_MAX_SKIPS where the environment lacks more)")
    return out
