"""Bounds that hold at any size and catch a dropped post effect (issue 32, item 6).

For every repository scene with a post chain, the browser page is recorded with each ``[[post]]`` entry cut out
of the scene file (tests/dropped_effects.py) and read back in headless Chromium; the matrix's cell (that
recording against wgpu-native's render of the full scene, with the calibrated browser bounds of
assets/reference/implementations.toml) must fail, naming the measure that sees the effect. The unmodified cell
must pass at two sizes (the 160x120 rows and the 320x240 class). One browser for every page, at small sizes.
Skipped only where chromium is not installed.

Which measure sees which effect comes from what the effect does (core/course/effects.py), not from the code under
test: tone mapping, sepia and a vignette move whole rings of the image one way (``radial shift``), sharpening
and FXAA change edge contrast (``detail change``). The output of ``retro`` is ``rgba8unorm``, which does not
encode sRGB, so its plan appends the srgb step whether or not the scene lists it: that drop changes nothing.
"""

from __future__ import annotations

import numpy as np
import pytest
from dropped_effects import without_post

from wgpurender.core.scene import load_scene
from wgpurender.core.verdict.tolerances import Uncalibrated, driver_class, implementation_tolerance, measure
from wgpurender.implementations import render_wgpu, scene_files
from wgpurender.webpage import export
from wgpurender.webpage.chromium import Chromium, find_chromium

SIZES = ((160, 120), (320, 240))
SMALL = SIZES[0]
POST = {name: path for name, path in scene_files().items() if load_scene(path).post}
CATCHES = {"tonemap": "radial shift", "sepia": "radial shift", "vignette": "radial shift",
           "sharpen": "detail change", "fxaa": "detail change"}
DROPS = [(name, k, step.effect) for name, path in POST.items() for k, step in enumerate(load_scene(path).post)]

pytestmark = pytest.mark.skipif(find_chromium() is None, reason="chromium is not installed (apt-get install chromium)")


@pytest.fixture(scope="module")
def calibrated(ctx):
    """The browser bounds apply on this driver class (lavapipe here; a GPU machine skips, as test_export_browser)."""
    try:
        implementation_tolerance("browser", "final", cls=driver_class(ctx.adapter.info["device"]))
    except Uncalibrated as err:
        pytest.skip(str(err))


@pytest.fixture(scope="module")
def recordings(tmp_path_factory, calibrated):
    """{(name, k or None, size): the page's capture}: each scene whole at both sizes, and with each effect cut
    out at the small size; one browser for all pages."""
    root = tmp_path_factory.mktemp("dropped")
    pages = {(name, None, size): export(str(path), root / f"{name}-{size[0]}", size).page
             for name, path in POST.items() for size in SIZES}
    for name, k, effect in DROPS:
        scene = without_post(POST[name], k, root / f"{name}-drop{k}.toml")
        pages[(name, k, SMALL)] = export(str(scene), root / f"{name}-drop{k}-{effect}", SMALL).page
    out = {}
    with Chromium(webgpu=True) as browser:
        for key, page in pages.items():
            tab = browser.open(page)
            out[key] = tab.capture()
            tab.close()
    return out


@pytest.fixture(scope="module")
def native(ctx):
    return {(name, size): render_wgpu(name, size) for name in POST for size in SIZES}


def _cell(tmp_path, name, native_image, browser_image):
    from wgpurender import verify_matrix

    return verify_matrix._compare(tmp_path, name, "wgpu-vulkan", "browser", native_image, browser_image)


def test_every_post_scene_is_covered():
    """The four repository scenes with a chain, and every effect they use but srgb has a measure named."""
    assert sorted(POST) == ["brick", "final", "final_subpass", "retro"]
    assert {effect for _, _, effect in DROPS} == {*CATCHES, "srgb"}


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("name", sorted(POST))
def test_the_unmodified_cell_passes(tmp_path, recordings, native, name, size):
    cell = _cell(tmp_path, name, native[(name, size)], recordings[(name, None, size)])
    assert cell.status == "pass", cell.note
    assert f"({size[0]}x{size[1]} class)" in cell.bound and "radial" in cell.bound


@pytest.mark.parametrize(("name", "k", "effect"), [d for d in DROPS if d[2] != "srgb"],
                         ids=[f"{n}-{e}" for n, _, e in DROPS if e != "srgb"])
def test_dropping_an_effect_fails_its_cell(tmp_path, recordings, native, name, k, effect):
    cell = _cell(tmp_path, name, native[(name, SMALL)], recordings[(name, k, SMALL)])
    assert cell.status == "FAIL" and CATCHES[effect] in cell.note, (effect, cell.status, cell.note)


@pytest.mark.parametrize("name", ["final", "final_subpass"])
def test_a_removed_vignette_passes_the_old_three_bounds(ctx, recordings, native, name):
    """What the issue found: a recording without its vignette stays within max, changed and FLIP; only the
    radial shift catches it."""
    k = next(k for n, k, effect in DROPS if n == name and effect == "vignette")
    tol = implementation_tolerance("browser", name, cls=driver_class(ctx.adapter.info["device"])).at_size(*SMALL)
    assert tol.exceeded(measure(native[(name, SMALL)], recordings[(name, k, SMALL)])) == []


def test_dropping_srgb_from_an_unencoded_output_changes_nothing(recordings):
    assert load_scene(POST["retro"]).render.output_format == "rgba8unorm"
    k = next(k for n, k, effect in DROPS if n == "retro" and effect == "srgb")
    assert np.array_equal(recordings[("retro", k, SMALL)], recordings[("retro", None, SMALL)])
