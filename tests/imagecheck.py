"""The one image-comparison helper of the test suite: checks, and a diff folder on every failure.

Two tiers (issue 12):

- :func:`assert_same_render`: two renders made in this run on this machine (wgpu vs raw
  Vulkan): exact, byte for byte (float16 included).
- :func:`assert_within_tolerance`: a fresh render against a committed reference (or the C++
  tutorial's frame), within the bounds of ``assets/reference/tolerances.toml`` for this
  driver class (wgpurender.core.verdict.tolerances).

A failing comparison writes ``out/test-diffs/<test-id>/`` with expected.png, actual.png,
heatmap.png and metrics.json, and the failure message gives the metrics and that folder.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.files.imageio import save_png, to_uint8
from wgpurender.core.verdict.compare import heatmap
from wgpurender.core.verdict.structure import structure
from wgpurender.core.verdict.tolerances import Metrics, Tolerance, measure, tolerance

REPO = Path(__file__).resolve().parent.parent
DIFF_ROOT = REPO / "out" / "test-diffs"


def diff_folder(test_id: str) -> Path:
    """out/test-diffs/<test id with path separators and brackets made safe>."""
    return DIFF_ROOT / re.sub(r"[^A-Za-z0-9._-]+", "_", test_id.replace("tests/", "")).strip("_")


def write_diff(folder: Path, expected: np.ndarray, actual: np.ndarray, metrics: dict) -> Path:
    """expected.png, actual.png, heatmap.png (where they differ) and metrics.json into ``folder``."""
    if folder.is_dir():
        shutil.rmtree(folder)  # only this comparison's files, never a stale mix
    folder.mkdir(parents=True)
    exp8, act8 = _rgba8(expected), _rgba8(actual)
    save_png(folder / "expected.png", exp8)
    save_png(folder / "actual.png", act8)
    if exp8.shape == act8.shape:
        save_png(folder / "heatmap.png", heatmap(exp8, act8))
    (folder / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    return folder


def _rgba8(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    return image if image.dtype == np.uint8 else to_uint8(image)


def _test_id(request) -> str:
    return request.node.nodeid if hasattr(request, "node") else str(request)


def assert_same_render(request, expected: np.ndarray, actual: np.ndarray, what: str = "renders") -> None:
    """Two renders of this run on this machine: identical bytes (dtype, shape and every value)."""
    same = (expected.shape == actual.shape and expected.dtype == actual.dtype
            and np.array_equal(expected.view(np.uint8), actual.view(np.uint8)))
    if same:
        return
    metrics: dict = {"check": "exact", "expected_shape": list(expected.shape), "actual_shape": list(actual.shape),
                     "expected_dtype": str(expected.dtype), "actual_dtype": str(actual.dtype)}
    if expected.shape == actual.shape:
        bytes_e = expected.view(np.uint8).reshape(*expected.shape[:2], -1)
        bytes_a = actual.view(np.uint8).reshape(*actual.shape[:2], -1)
        metrics["pixels_differing"] = int((bytes_e != bytes_a).any(-1).sum())
        metrics["pixels"] = int(expected.shape[0] * expected.shape[1])
    folder = write_diff(diff_folder(_test_id(request)), expected, actual, metrics)
    pytest.fail(f"{what} differ (exact comparison, same machine and run): "
                f"{metrics.get('pixels_differing', 'shape/dtype')} pixels differ; diff folder {folder}", pytrace=False)


def check(name: str, expected: np.ndarray, actual: np.ndarray, cls: str) -> tuple[Metrics, Tolerance, list[str]]:
    """The metrics, the table's tolerance and the exceeded bounds (empty: passes), without pytest."""
    metrics = measure(_rgba8(expected), _rgba8(actual))
    tol = tolerance(name, cls)
    return metrics, tol, tol.exceeded(metrics)


def assert_within_tolerance(request, name: str, expected: np.ndarray, actual: np.ndarray, cls: str) -> Metrics:
    """``actual`` (a fresh render) against ``expected`` (a committed reference), with the table's bounds
    for reference ``name`` on driver class ``cls``; on failure a diff folder and the metrics."""
    return _assert_within(request, expected, actual, tolerance(name, cls))


def assert_close(request, expected: np.ndarray, actual: np.ndarray, *, max_abs: int, changed: float = 1.0,
                 flip_mean: float = 1.0, what: str = "renders") -> Metrics:
    """Two renders of this run that may differ by an explained amount (bounds stated in the test)."""
    tol = Tolerance(what, "same machine", max_abs, changed, flip_mean, "see the test's docstring",
                    "this test's bounds", False)
    return _assert_within(request, expected, actual, tol)


def _assert_within(request, expected: np.ndarray, actual: np.ndarray, tol: Tolerance) -> Metrics:
    metrics = measure(_rgba8(expected), _rgba8(actual))
    exceeded = tol.exceeded(metrics)
    if tol.radial is not None or tol.detail is not None:  # the implementation rows' size-free bounds
        exceeded += tol.structure_exceeded(structure(_rgba8(expected), _rgba8(actual)))
    if exceeded:
        data = {"check": "tolerance", "reference": tol.name, "driver_class": tol.driver_class, **metrics.as_dict(),
                "tolerance": {"max_abs": tol.max_abs, "changed": tol.changed, "flip_mean": tol.flip_mean,
                              "provisional": tol.provisional, "bounded_by": tol.bounded_by},
                "exceeded": exceeded}
        folder = write_diff(diff_folder(_test_id(request)), expected, actual, data)
        pytest.fail(f"{tol.name}: {'; '.join(exceeded)}\n  measured: {metrics.summary()}\n  {tol.describe()}\n"
                    f"  diff folder: {folder}", pytrace=False)
    return metrics
