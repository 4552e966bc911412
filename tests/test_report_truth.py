"""The report says the right thing in the right place: each caption over the image it names, each number beside the
label it belongs to (issue 24: PSNR and FLIP under each other's labels, or the wgpu and raw images under each
other's captions, passed every earlier test because the two paths draw these stages identically).

So that the paths differ, the "raw" image here is the wgpu render with a marked block (the test's own pixels): the
figure captioned wgpu must hold a fresh wgpu render, the one captioned raw the marked image, and every metric must
be what core.verdict.compare says about the two images the page shows. The page is read with an HTML parser by the
visible text (captions, row labels), so it does not depend on the report's class names.
"""

from __future__ import annotations

from html.parser import HTMLParser

import numpy as np
import pytest

from wgpurender.core.files.imageio import load_png
from wgpurender.core.verdict.compare import compare_images

MARK = (slice(4, 20), slice(6, 30))  # rows, columns of the block the fake raw path changes
STAGES = ("triangle", "3d")


class _Page(HTMLParser):
    """Sections by id, each with its figures (caption -> image src) and table rows (label -> cell texts)."""

    def __init__(self) -> None:
        super().__init__()
        self.sections: dict[str, dict] = {}
        self._section = self._figure = self._row = None
        self._text: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "section" and "step" in (attrs.get("class") or ""):
            self._section = self.sections.setdefault(attrs["id"], {"figures": [], "rows": []})
        elif self._section is None:
            return
        elif tag == "figure":
            self._figure = {"src": None, "caption": ""}
        elif tag == "img" and self._figure is not None and self._figure["src"] is None:
            self._figure["src"] = attrs.get("src")
        elif tag in ("figcaption", "th", "td"):
            self._text = []
        elif tag == "tr":
            self._row = []

    def handle_data(self, data):
        if self._text is not None:
            self._text.append(data)

    def handle_endtag(self, tag):
        if self._section is None:
            return
        if tag == "figcaption" and self._figure is not None and not self._figure["caption"]:
            self._figure["caption"] = "".join(self._text or []).strip()
        elif tag in ("th", "td") and self._row is not None:
            self._row.append("".join(self._text or []).strip())
        elif tag == "tr" and self._row is not None:
            self._section["rows"].append(self._row)
            self._row = None
        elif tag == "figure" and self._figure is not None:
            self._section["figures"].append(self._figure)
            self._figure = None
        elif tag == "section":
            self._section = None
        if tag in ("figcaption", "th", "td"):
            self._text = None


def _marked(pixels: np.ndarray) -> np.ndarray:
    out = pixels.copy()
    out[MARK] = (255, 0, 255, 255)
    out[MARK[0], 40:60, :3] = np.clip(out[MARK[0], 40:60, :3].astype(int) + 3, 0, 255).astype(np.uint8)
    out[MARK[0], 70:90, :3] = np.clip(out[MARK[0], 70:90, :3].astype(int) + 2, 0, 255).astype(np.uint8)  # over 1 only
    return out


@pytest.fixture(scope="module")
def page(tmp_path_factory, ctx_module):
    import wgpurender.raw_path as raw_path
    from wgpurender.report import build, timings
    from wgpurender.wgpu_path.render import render_stage

    out = tmp_path_factory.mktemp("truth") / "site"
    patch = pytest.MonkeyPatch()
    patch.setattr(raw_path, "render_reference",
                  lambda name, size, **_: _marked(render_stage(name, size, ctx=ctx_module, frames=1).pixels))
    for name in ("stage_wgpu", "stage_raw"):
        patch.setattr(timings, name, lambda *a, **k: None)
    try:
        build.build_report(out, stages=list(STAGES), scenes=[], ctx=ctx_module, log=lambda _: None)
    finally:
        patch.undo()
    parser = _Page()
    parser.feed((out / "index.html").read_text(encoding="utf-8"))
    return out, parser.sections


@pytest.fixture(scope="module")
def ctx_module():
    from wgpurender.wgpu_path.device.context import get_context

    return get_context()


def _figure(section: dict, caption_start: str) -> str:
    found = [f["src"] for f in section["figures"] if f["caption"].startswith(caption_start) and f["src"]]
    assert len(found) == 1, section["figures"]
    return found[0]


def _row(section: dict, label: str) -> str:
    found = [r[1] for r in section["rows"] if r and r[0] == label and len(r) > 1]
    assert len(found) == 1, section["rows"]
    return found[0]


@pytest.mark.parametrize("stage", STAGES)
def test_each_caption_is_over_the_image_it_names(page, ctx_module, stage):
    from wgpurender.wgpu_path.render import render_stage

    site, sections = page
    wgpu_shown = load_png(site / _figure(sections[stage], "wgpu"))
    raw_shown = load_png(site / _figure(sections[stage], "raw Vulkan"))
    fresh = render_stage(stage, wgpu_shown.shape[1::-1], ctx=ctx_module, frames=1).pixels
    assert (wgpu_shown == fresh).all()
    assert (raw_shown[MARK] == (255, 0, 255, 255)).all() and (raw_shown == _marked(fresh)).all()


@pytest.mark.parametrize("stage", STAGES)
def test_each_number_is_beside_its_label(page, stage):
    site, sections = page
    section = sections[stage]
    raw_shown = load_png(site / _figure(section, "raw Vulkan"))
    wgpu_shown = load_png(site / _figure(section, "wgpu"))
    truth = compare_images(raw_shown, wgpu_shown)
    assert np.isfinite(truth.psnr) and truth.flip_mean > 0 and truth.max_abs > 3  # the numbers can tell apart
    assert truth.over_1 > truth.over_2 > 0
    assert _row(section, "PSNR") == f"{truth.psnr:.2f} dB"
    assert _row(section, "FLIP (mean)") == f"{truth.flip_mean:.5f}"
    assert _row(section, "max difference").startswith(f"{truth.max_abs}/255; pixels over 1/255: "
                                                       f"{100 * truth.over_1:.3f}%")


@pytest.mark.parametrize("stage", STAGES)
def test_the_heatmap_lights_exactly_where_the_shown_images_differ(page, stage):
    site, sections = page
    section = sections[stage]
    raw_shown = load_png(site / _figure(section, "raw Vulkan"))
    wgpu_shown = load_png(site / _figure(section, "wgpu"))
    heat_src = [f["src"] for f in section["figures"] if f["src"] and "heat" in f["src"]]
    heat = load_png(site / heat_src[0])
    differs = (raw_shown[..., :3] != wgpu_shown[..., :3]).any(axis=2)
    assert differs[MARK].all()
    assert ((heat[..., :3] > 0).any(axis=2) == differs).all()
    # the page says its heatmap is amplified x32 (a 1/255 difference shows as 32/255) on a black-red-yellow ramp:
    # red = clip(3d), green = clip(3d - 1) with d = 32 * difference / 255
    for columns, step in ((slice(70, 90), 2), (slice(40, 60), 3)):
        d = min(32 * step / 255, 1.0)
        want = [round(min(max(3 * d - k, 0.0), 1.0) * 255) for k in (0, 1, 2)]
        region = heat[MARK[0], columns, :3][differs[MARK[0], columns]]
        assert len(region) and (region == want).all(), (step, want, np.unique(region, axis=0))
