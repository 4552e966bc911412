"""The tolerance table (assets/reference/tolerances.toml) is complete and still rejects real changes.

The bounds let lavapipe on another CPU (and a GPU, with its own row) pass; these tests show that
the same bounds reject small but real bugs applied to a fresh raw render of this machine:
a one-pixel shift (a half-pixel/viewport mistake), a colour change of 3/255 in a 24x24 region
(a constant or rounding bug in one material), and a missing triangle (a dropped index).
"""

from __future__ import annotations

import numpy as np
import pytest
from imagecheck import check

from wgpurender.core.files.imageio import load_png, to_uint8
from wgpurender.core.verdict.tolerances import (
    DRIVER_CLASSES,
    TABLE_PATH,
    Metrics,
    calibrate,
    format_table,
    load_table,
    tolerance,
)
from wgpurender.raw_path import reference_stage_names
from wgpurender.raw_path.make_references import (
    REFERENCE_DIR,
    REFERENCE_SIZE,
    SCENE_REFERENCES,
)

# references with content to perturb (the clears are one flat colour: a shift changes nothing)
PERTURBED = ["triangle", "msaa", "msaa-post", "3d", "textured", "scene_final_subpass", "scene_unlit"]


def _fresh(name: str) -> np.ndarray:
    from wgpurender.raw_path.make_references import render_named_reference

    return render_named_reference(name)  # as make_references renders it (scenes: their own anisotropy)


def _busiest_block(image: np.ndarray, size: int) -> tuple[int, int]:
    """Top-left corner of the size x size block with the most non-background pixels (the bug lands on content)."""
    content = (np.abs(image[..., :3].astype(int) - image[0, 0, :3].astype(int)).max(-1) > 8).astype(np.int64)
    sums = np.lib.stride_tricks.sliding_window_view(content, (size, size)).sum(axis=(-1, -2))
    y, x = np.unravel_index(np.argmax(sums), sums.shape)
    return int(y), int(x)


def shift_one_pixel(image: np.ndarray) -> np.ndarray:
    return np.roll(image, 1, axis=1)


def colour_change(image: np.ndarray, amount: int = 3, size: int = 24) -> np.ndarray:
    """+3/255 on the red channel of a size x size block of content (clipped at 255: -3 there)."""
    y, x = _busiest_block(image, size)
    out = image.copy()
    block = out[y:y + size, x:x + size, 0].astype(int)
    out[y:y + size, x:x + size, 0] = np.where(block + amount <= 255, block + amount, block - amount)
    return out


def missing_triangle(image: np.ndarray, legs: int = 12) -> np.ndarray:
    """A right triangle of content (legs x legs pixels) replaced by the background colour."""
    y, x = _busiest_block(image, legs)
    out = image.copy()
    rows, cols = np.mgrid[0:legs, 0:legs]
    mask = cols <= rows
    out[y:y + legs, x:x + legs][mask] = image[0, 0]
    return out


BUGS = {"one-pixel shift": shift_one_pixel, "3/255 colour change": colour_change, "missing triangle": missing_triangle}


@pytest.fixture(scope="module")
def fresh_renders() -> dict[str, np.ndarray]:
    return {name: _fresh(name) for name in PERTURBED}


@pytest.mark.parametrize("name", PERTURBED)
@pytest.mark.parametrize("bug", sorted(BUGS))
def test_lavapipe_bounds_reject_a_real_change(fresh_renders, raw_driver_class, name, bug):
    """Every bug on every reference exceeds the lavapipe row.

    The bug is applied to this machine's fresh raw render on lavapipe (so the CPU spread is in it too),
    and to the committed (lavapipe) image itself on a GPU, whose own render is not lavapipe's.
    """
    expected = load_png(REFERENCE_DIR / f"{name}.png")
    base = fresh_renders[name] if raw_driver_class == "lavapipe" else expected.copy()
    _, _, exceeded = check(name, expected, base, "lavapipe")
    assert not exceeded, f"the unbroken image already fails: {exceeded}"
    broken = BUGS[bug](base)
    assert (broken != base).any(), "the bug changed nothing: not a test"
    metrics, tol, exceeded = check(name, expected, broken, "lavapipe")
    assert exceeded, f"{bug} on {name} passes: {metrics.summary()} within {tol.describe()}"


@pytest.mark.parametrize("name", PERTURBED)
def test_gpu_bounds_reject_a_shift(fresh_renders, name):
    """The looser gpu row still rejects a one-pixel shift of any reference with content.

    (The gpu rows, calibrated on an NVIDIA H100, are too loose to see a 3/255 block or a small missing
    triangle; the lavapipe rows do, and on a GPU the exact wgpu vs raw tier catches a bug in either path.)
    """
    expected = load_png(REFERENCE_DIR / f"{name}.png")
    metrics, tol, exceeded = check(name, expected, shift_one_pixel(fresh_renders[name]), "gpu")
    assert exceeded, f"a one-pixel shift of {name} passes: {metrics.summary()} within {tol.describe()}"


def test_every_reference_has_a_row_for_every_driver_class():
    table = load_table()
    names = {p.stem for p in REFERENCE_DIR.glob("*.png")} | {"tutorial_28", "tutorial_30"}
    assert set(reference_stage_names()) | set(SCENE_REFERENCES) <= names
    for name in sorted(names):
        for cls in DRIVER_CLASSES:
            tol = tolerance(name, cls, table)
            assert 0 <= tol.max_abs <= 255 and 0 <= tol.changed <= 1 and 0 <= tol.flip_mean <= 1
            assert tol.bounded_by and tol.measured, f"{name}/{cls}: no provenance"
        lavapipe = tolerance(name, "lavapipe", table)
        assert not lavapipe.provisional and lavapipe.max_abs <= 2 or name.startswith("tutorial"), name


def test_table_file_round_trips():
    """format_table writes what load_table reads: verify can rewrite the table without losing rows."""
    table = load_table()
    assert format_table(table).count('[references."') == sum(len(rows) for rows in table["references"].values())
    assert TABLE_PATH.read_text() == format_table(table)


def test_calibration_rule():
    """Bounds from spread, written out: lavapipe max + 1 (at least 2), twice the share and FLIP, with floors."""
    spread = [Metrics(1, 591 / 49152, 591, 0.00076, 49152), Metrics(0, 0.0, 0, 0.0, 49152)]
    assert calibrate(spread, "lavapipe") == {"max_abs": 2, "changed": 0.025, "flip_mean": 0.002}
    gpu = calibrate([Metrics(89, 0.12, 9216, 0.013, 76800)], "gpu")
    assert gpu == {"max_abs": 135, "changed": 0.24, "flip_mean": 0.026}


# -- pytest --regenerate-references ---------------------------------------------------------------------------------

def test_regenerate_references_uses_the_raw_path_and_reports_changes(tmp_path, raw_driver_class):
    """`pytest --regenerate-references` in a copy of the repository: the raw path rewrites a spoiled reference
    and prints, per image, the pixels changed and the largest difference; the wgpu path is never imported."""
    import shutil
    import subprocess
    import sys

    repo = REFERENCE_DIR.parent.parent
    copy = tmp_path / "repo"
    for part in ("wgpurender", "tests", "assets", "shaders_glsl", "shaders_wgsl", "pyproject.toml"):
        src = repo / part
        if src.is_dir():
            shutil.copytree(src, copy / part, ignore=shutil.ignore_patterns("__pycache__"))
        elif src.is_file():
            shutil.copy2(src, copy / part)
    spoiled = copy / "assets" / "reference" / "triangle.png"
    pixels = load_png(spoiled).copy()
    pixels[10:20, 10:30, :3] = 255 - pixels[10:20, 10:30, :3]  # 200 pixels inverted
    from wgpurender.core.files.imageio import save_png

    save_png(spoiled, pixels)
    probe = copy / "tests" / "test_probe.py"
    probe.write_text(  # the regeneration made no wgpu device: the wgpu path drew nothing
        "import sys\n\ndef test_probe():\n    gpu = sys.modules.get('wgpurender.wgpu_path.device.context')\n"
        "    assert gpu is None or gpu.get_context.cache_info().currsize == 0\n")
    import os

    # the copy first, then whatever PYTHONPATH already gave this interpreter its packages (wgpu, vulkan, ...)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(copy), os.environ.get("PYTHONPATH")]))}
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--regenerate-references",
                          "tests/test_probe.py"], cwd=copy, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    line = next(ln for ln in run.stdout.splitlines() if ln.strip().startswith("triangle:"))
    changed, max_diff = int(line.split()[1]), int(line.split("max difference ")[1].split("/")[0])
    spread = tolerance("triangle", raw_driver_class).changed * 256 * 192  # this driver vs the committed image
    assert 200 <= changed <= 200 + spread and max_diff > 200, line  # the spoiled block, + the measured spread
    assert "scene_final_subpass:" in run.stdout and "msaa-post:" in run.stdout
    assert np.array_equal(load_png(spoiled), _fresh("triangle"))


# -- diff folders ---------------------------------------------------------------------------------------------------

class _FakeNode:
    def __init__(self, nodeid: str) -> None:
        self.nodeid = nodeid


class _FakeRequest:
    def __init__(self, nodeid: str) -> None:
        self.node = _FakeNode(nodeid)


def test_a_failed_tolerance_check_leaves_a_diff_folder(fresh_renders, monkeypatch, tmp_path):
    """expected.png, actual.png, heatmap.png and metrics.json, and the metrics and folder in the message."""
    import json

    import imagecheck

    monkeypatch.setattr(imagecheck, "DIFF_ROOT", tmp_path / "test-diffs")  # not out/: this failure is on purpose
    request = _FakeRequest("tests/test_reference_tolerances.py::probe[triangle-shifted]")
    folder = imagecheck.diff_folder(request.node.nodeid)
    expected, broken = load_png(REFERENCE_DIR / "triangle.png"), shift_one_pixel(fresh_renders["triangle"])
    with pytest.raises(pytest.fail.Exception) as failure:
        imagecheck.assert_within_tolerance(request, "triangle", expected, broken, "lavapipe")
    message = str(failure.value)
    assert "max diff" in message and "FLIP mean" in message and str(folder) in message
    assert sorted(p.name for p in folder.iterdir()) == ["actual.png", "expected.png", "heatmap.png", "metrics.json"]
    assert np.array_equal(load_png(folder / "actual.png"), broken)
    metrics = json.loads((folder / "metrics.json").read_text())
    assert metrics["reference"] == "triangle" and metrics["max_abs"] > 2 and metrics["exceeded"]
    heat = load_png(folder / "heatmap.png")
    assert heat[..., :3].max() == 255 and heat[..., :3].min() == 0  # bright where they differ, black elsewhere


def test_a_failed_exact_check_leaves_a_diff_folder(monkeypatch, tmp_path):
    """Same-run comparisons (float16 too) fail with the count of differing pixels and a diff folder."""
    import imagecheck

    monkeypatch.setattr(imagecheck, "DIFF_ROOT", tmp_path / "test-diffs")
    request = _FakeRequest("tests/test_reference_tolerances.py::probe[exact]")
    a = np.zeros((8, 8, 4), np.float16)
    b = a.copy()
    b[2, 3, 1] = np.float16(1e-3)
    with pytest.raises(pytest.fail.Exception, match="1 pixels differ; diff folder .*probe_exact"):
        imagecheck.assert_same_render(request, a, b)
    assert (imagecheck.diff_folder(request.node.nodeid) / "metrics.json").is_file()
    imagecheck.assert_same_render(request, a, a.copy())  # equal: passes


# -- real bugs in the raw path, rendered -----------------------------------------------------------------------------

def _shift_first_vertex(monkeypatch) -> str:
    """triangle-buffers with its first vertex 1 pixel to the right (a half-pixel/viewport-style slip)."""
    from wgpurender.raw_path.stages import triangle_buffers

    vertices = triangle_buffers.triangle_vertices

    def moved():
        out = vertices().copy()  # (3, 5): NDC x, y, then colour
        out[0, 0] += 2.0 / REFERENCE_SIZE[0]  # NDC spans 2 over the width
        return out

    monkeypatch.setattr(triangle_buffers, "triangle_vertices", moved)
    return "triangle-buffers"


def _clear_colour_off_by_3(monkeypatch) -> str:
    """clear-pass with its green channel 3/255 too high (a constant typo)."""
    from wgpurender.raw_path.stages import clear_pass

    r, g, b, a = clear_pass.CLEAR_COLOR
    monkeypatch.setattr(clear_pass, "CLEAR_COLOR", (r, g + 3 / 255, b, a))
    return "clear-pass"


def _drop_a_cube_triangle(monkeypatch) -> str:
    """3d with one index triangle of the cube mesh dropped (a lost triangle in an index buffer).

    Triangle 2 is on a face the camera sees (428 of 49,152 pixels change on lavapipe; triangles 0 and 1
    face away and are culled): the smallest visible loss.
    """
    from wgpurender.core.course import cubes

    mesh = cubes.cube_mesh

    def without_triangle_2():
        vertices, indices = mesh()
        return vertices, np.delete(indices, [6, 7, 8])

    monkeypatch.setattr(cubes, "cube_mesh", without_triangle_2)
    return "3d"


RENDER_BUGS = {"vertex moved 1 px": (_shift_first_vertex, {"lavapipe"}),
               "clear colour +3/255": (_clear_colour_off_by_3, {"lavapipe", "gpu"}),
               "missing cube triangle": (_drop_a_cube_triangle, {"lavapipe"})}


@pytest.mark.parametrize("bug", sorted(RENDER_BUGS))
def test_a_real_render_bug_is_caught(monkeypatch, ctx, raw_driver_class, bug):
    """A bug put into the raw path itself, rendered: the committed reference check rejects it with this
    driver class's row. Where that row is (still) too loose for it (a GPU's provisional rows), the
    same-run tier catches it instead: the wgpu path's render differs from the bugged raw render."""
    from wgpurender.wgpu_path.render import render_stage

    make_bug, caught_by = RENDER_BUGS[bug]
    name = make_bug(monkeypatch)
    broken = _fresh(name)
    monkeypatch.undo()
    assert (broken != _fresh(name)).any(), f"{bug} changed nothing in {name}: not a test"
    metrics, tol, exceeded = check(name, load_png(REFERENCE_DIR / f"{name}.png"), broken, raw_driver_class)
    if raw_driver_class in caught_by:
        assert exceeded, f"{bug} passes the {name} reference check: {metrics.summary()} within {tol.describe()}"
    else:
        ours = to_uint8(render_stage(name, REFERENCE_SIZE, None, None, 0.0, ctx, frames=1).pixels)
        assert (ours != broken).any(), f"{bug}: the wgpu render equals the bugged raw render"
