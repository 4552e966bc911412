"""A model's ``instances`` block: "N copies" written compactly, validated into :class:`Placements`.

Three forms (docs/scenes.md), each relative to the model's ``transform`` (the copies' parent)::

    instances = { grid = [nx, ny, nz], spacing = [sx, sy, sz] }   # nx*ny*nz copies, centred on the origin
    instances = { translate = [[x, y, z], ...] }                   # one copy per offset
    instances = { file = "copies.npy" }                            # (N, 3) offsets or (N, 4, 4) matrices

A grid's copy (i, j, k) sits at ``((i, j, k) - (n - 1) / 2) * spacing``, i fastest: the order the plan draws
them in. Counts are bounded by :data:`MAX_INSTANCES` before anything is allocated.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from wgpurender.core.files import read_jail
from wgpurender.core.scene.checker import Checker
from wgpurender.core.scene.model import MAX_INSTANCES, Placements
from wgpurender.core.scene.toml_locator import KeyPath, format_path
from wgpurender.core.view import transforms

INSTANCE_KEYS = ("file", "grid", "spacing", "translate")
_FORMS = ("grid", "translate", "file")


def instances(c: Checker, data: Any, key: KeyPath) -> Placements:
    """The block at ``key`` as placements; one clear line for anything wrong."""
    t = c.table(data, key, INSTANCE_KEYS)
    forms = [f for f in _FORMS if f in t]
    if len(forms) != 1:
        raise c.error(key, f"{format_path(key)}: give exactly one of grid, translate or file "
                           f"(got {', '.join(forms) or 'none'})")
    if "spacing" in t and forms[0] != "grid":
        raise c.error(key + ("spacing",), f"{format_path(key)}.spacing only applies to grid")
    if forms[0] == "grid":
        return _grid(c, t, key)
    if forms[0] == "translate":
        return _translate(c, t["translate"], key + ("translate",))
    return _file(c, t["file"], key + ("file",))


def _bounded(c: Checker, count: int, key: KeyPath) -> None:
    if count > MAX_INSTANCES:
        raise c.error(key, f"{format_path(key)}: {count} copies is more than the {MAX_INSTANCES} allowed "
                           "(split the model into several entries or use fewer copies)")


def _grid(c: Checker, t: dict, key: KeyPath) -> Placements:
    n = t["grid"]
    if not isinstance(n, list) or len(n) != 3:
        raise c.error(key + ("grid",), f"{format_path(key)}.grid must be 3 counts [nx, ny, nz], got {n!r}")
    counts = [c.integer(v, key + ("grid",), lo=1) for v in n]
    _bounded(c, counts[0] * counts[1] * counts[2], key + ("grid",))
    spacing = np.array(c.vector(t.get("spacing", [1, 1, 1]), key + ("spacing",)), dtype=np.float64)
    axes = [(np.arange(k) - (k - 1) / 2.0) * s for k, s in zip(counts, spacing, strict=True)]
    z, y, x = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")  # x varies fastest
    offsets = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    return Placements.of(_translations(offsets), f"grid {counts[0]}x{counts[1]}x{counts[2]}, "
                                                 f"spacing {[float(s) for s in spacing]}")


def _translate(c: Checker, value: Any, key: KeyPath) -> Placements:
    if not isinstance(value, list) or not value:
        raise c.error(key, f"{format_path(key)} must be a non-empty array of [x, y, z] offsets")
    _bounded(c, len(value), key)
    offsets = np.array([c.vector(v, key) for v in value], dtype=np.float64)
    return Placements.of(_translations(offsets), f"{len(value)} offsets")


def _file(c: Checker, value: Any, key: KeyPath) -> Placements:
    path = c.file(value, key, "instances file")
    if path.suffix.lower() != ".npy":
        raise c.error(key, f"{format_path(key)}: '{value}' must be a .npy file of (N, 3) offsets or (N, 4, 4) "
                           "matrices (numpy.save)")
    if path.stat().st_size > MAX_INSTANCES * 16 * 8 + 4096:
        raise c.error(key, f"{format_path(key)}: '{value}' is larger than {MAX_INSTANCES} float64 matrices")
    try:
        with read_jail.open_checked(path) as f:  # the file the scene's check let through
            a = np.load(f, allow_pickle=False)
    except (ValueError, OSError, EOFError) as e:
        raise c.error(key, f"{format_path(key)}: '{value}' is not a readable .npy array ({e})") from None
    if a.dtype.kind not in "fiu" or a.ndim not in (2, 3) or a.shape[1:] not in ((3,), (4, 4)) or not len(a):
        raise c.error(key, f"{format_path(key)}: '{value}' holds a {a.dtype} array of shape {a.shape}: "
                           "need (N, 3) offsets or (N, 4, 4) matrices of numbers")
    if not np.isfinite(a).all():
        raise c.error(key, f"{format_path(key)}: '{value}' contains NaN or infinite values")
    _bounded(c, len(a), key)
    matrices = _translations(a) if a.ndim == 2 else a
    if transforms.flat(matrices).any():
        raise c.error(key, f"{format_path(key)}: '{value}' has a singular matrix (3x3 determinant 0)")
    return Placements.of(matrices, f"{len(a)} {'offsets' if a.ndim == 2 else 'matrices'} from '{value}'")


def _translations(offsets: np.ndarray) -> np.ndarray:
    m = np.broadcast_to(np.eye(4), (len(offsets), 4, 4)).copy()
    m[:, :3, 3] = offsets
    return m
