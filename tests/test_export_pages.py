"""Exported pages, light and loud: PNG textures and reference frame (decoded to their exact bytes in the page),
the size printed is the size on disk, a WebGPU error or a lost device is said on the page, the animation's loop
wraps where the stage repeats, and the plan names the adapter type."""

from __future__ import annotations

import base64
import io
import json
import os
import re
import subprocess
import sys
import time
import zlib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpurender.core.course.loops import loop_seconds
from wgpurender.core.files.assets import assets_dir
from wgpurender.webpage import FPS
from wgpurender.webpage.chromium import Chromium, find_chromium
from wgpurender.wgpu_path.render import render_stage

SIZE = ("--size", "160x120")
needs_chromium = pytest.mark.skipif(find_chromium() is None, reason="chromium is not installed")


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """brick (textured scene) and 3d (animated stage), exported by the CLI as a user does: (folder, printed line)."""
    root = tmp_path_factory.mktemp("pages")
    out = {}
    for target in ("brick", "3d"):
        done = subprocess.run([sys.executable, "-m", "wgpurender", "export", target, "-o", str(root / target), *SIZE],
                              capture_output=True, text=True, timeout=600, env=dict(os.environ))
        assert done.returncode == 0, done.stderr
        out[target] = (root / target, done.stdout.strip())
    return out


def _data(folder: Path) -> dict:
    text = (folder / "data.js").read_text()
    return json.loads(text[text.index("{"):text.rstrip().rindex("}") + 1])


def _png(entry: dict) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(entry["png"]))))


def test_textures_and_the_reference_travel_as_png_and_the_size_printed_is_the_size_on_disk(exported):
    folder, line = exported["brick"]
    data = _data(folder)
    uploads = {c["a"][1]["#"] for c in [*data["setup"], *data["frame"]] if c.get("m") == "writeTexture"}
    assert uploads and all(isinstance(data["blobs"][i], dict) for i in uploads)  # no raw RGBA base64
    albedo = np.asarray(Image.open(assets_dir() / "textures" / "brick_albedo.png").convert("RGBA"))
    assert any(np.array_equal(_png(data["blobs"][i]), albedo) for i in uploads), "the albedo's texels, exactly"
    assert _png(data["reference"]).shape == (120, 160, 4)
    textures = sum((assets_dir() / "textures" / f"brick_{m}.png").stat().st_size for m in ("albedo", "normal",
                                                                                           "roughness"))
    on_disk = sum((folder / name).stat().st_size for name in ("index.html", "data.js", "player.js"))  # the page
    assert on_disk < 4 * textures, (on_disk, textures)  # base64 of the raw texels was 4.2 MB
    said = float(re.search(r"([\d.]+) MB on disk", line).group(1))
    assert said == round(on_disk / 1e6, 2), (line, on_disk)


def test_the_loop_wraps_where_the_stage_repeats(exported):
    period = loop_seconds("3d")
    data = _data(exported["3d"][0])
    assert len(data["samples"]) == round(FPS * period)  # the page's time wraps at exactly one period
    size = (160, 120)
    start, wrapped = (render_stage("3d", size, t=t, frames=1).pixels.astype(int) for t in (0.0, period))
    half = render_stage("3d", size, t=period / 2, frames=1).pixels.astype(int)
    assert np.abs(start - wrapped).max() <= 1  # t = period draws t = 0: no jump at the wrap
    assert np.abs(start - half).max() > 50  # while in between the cubes have turned


def test_the_textured_stage_repeats_after_its_period():
    """Its mirror-repeat lane repeats every second tile: 8 s at a quarter tile a second; half of it is a mirror."""
    period, size = loop_seconds("textured"), (96, 72)
    start, wrapped, half = (render_stage("textured", size, t=t, frames=1).pixels.astype(int)
                            for t in (0.0, period, period / 2))
    assert period == 8.0 and np.abs(start - wrapped).max() <= 2 and np.abs(start - half).max() > 50


def _png_with_every_filter(pixels: np.ndarray, first: int = 0) -> bytes:
    """An 8-bit RGBA PNG whose row y uses filter (first + y) % 5 (None, Sub, Up, Average, Paeth: the PNG
    specification's definitions, written here independently of any decoder)."""
    h, w, _ = pixels.shape
    stride, data = w * 4, pixels.astype(np.int32).reshape(h, w * 4)
    out = bytearray()
    for y in range(h):
        kind, row = (first + y) % 5, data[y]
        up = data[y - 1] if y else np.zeros(stride, np.int32)
        left = np.concatenate([np.zeros(4, np.int32), row[:-4]])
        upleft = np.concatenate([np.zeros(4, np.int32), up[:-4]])
        p = left + up - upleft
        pa, pb, pc = np.abs(p - left), np.abs(p - up), np.abs(p - upleft)
        paeth = np.where((pa <= pb) & (pa <= pc), left, np.where(pb <= pc, up, upleft))
        predict = [np.zeros(stride, np.int32), left, up, (left + up) // 2, paeth][kind]
        out += bytes([kind]) + ((row - predict) % 256).astype(np.uint8).tobytes()

    def chunk(kind: bytes, body: bytes) -> bytes:
        return len(body).to_bytes(4, "big") + kind + body + zlib.crc32(kind + body).to_bytes(4, "big")

    header = w.to_bytes(4, "big") + h.to_bytes(4, "big") + bytes([8, 6, 0, 0, 0])
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(out))) + \
        chunk(b"IEND", b"")


@needs_chromium
def test_the_page_decodes_every_png_row_filter_exactly(exported):
    """Each filter on the first row too (where the row above counts as zeros) and on later rows."""
    pixels = np.random.default_rng(7).integers(0, 256, (10, 7, 4), dtype=np.uint8)
    with Chromium() as browser:
        tab = browser.open(exported["brick"][0] / "index.html")
        for first in range(5):
            png = _png_with_every_filter(pixels, first)
            assert np.array_equal(np.asarray(Image.open(io.BytesIO(png))), pixels)  # valid: PIL reads it back
            text = base64.b64encode(png).decode("ascii")
            got = base64.b64decode(tab.evaluate(f"window.wgpurender.decodePng({json.dumps(text)})"))
            assert got == pixels.tobytes(), first


@needs_chromium
def test_the_page_decodes_its_pngs_to_the_exact_bytes(exported):
    """player.js's PNG decoder (all five row filters) against PIL's, on every PNG of the brick page."""
    data = _data(exported["brick"][0])
    pngs = [b for b in data["blobs"] if isinstance(b, dict)] + [data["reference"]]
    with Chromium() as browser:
        tab = browser.open(exported["brick"][0] / "index.html")
        for entry in pngs:
            got = base64.b64decode(tab.evaluate(f"window.wgpurender.decodePng({json.dumps(entry['png'])})"))
            assert got == _png(entry).tobytes()
    filters = set()
    for entry in pngs:  # which row filters the encoder chose: the test reaches the decoder's branches
        png = base64.b64decode(entry["png"])
        pos, idat, width = 8, b"", 0
        while pos < len(png):
            length, kind = int.from_bytes(png[pos:pos + 4], "big"), png[pos + 4:pos + 8]
            width = int.from_bytes(png[pos + 8:pos + 12], "big") if kind == b"IHDR" else width
            idat += png[pos + 8:pos + 8 + length] if kind == b"IDAT" else b""
            pos += 12 + length
        rows = zlib.decompress(idat)
        filters |= set(rows[::width * 4 + 1])
    assert len(pngs) >= 4 and len(filters) >= 3, filters


def test_the_plan_names_the_adapter_type(exported):
    from wgpurender import api

    plan = _data(exported["brick"][0])["meta"]["plan"]
    assert " a  adapter" not in plan and "adapter type is not known here" in plan
    native = api.explain("brick")
    assert re.search(r"fragment on a (CPU|IntegratedGPU|VirtualGPU|Other) adapter|compute on a discrete GPU", native)


def _wait_for_message(tab, seconds: float = 20.0) -> dict:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        shown = tab.evaluate("({message: document.getElementById('message').textContent, stopped: "
                             "!!window.wgpurender.stopped, frametime: document.getElementById('frametime')"
                             ".textContent, frames: window.wgpurender.frames, difference: document."
                             "getElementById('difference').textContent})")
        if shown["message"]:
            return shown
        time.sleep(0.2)
    raise AssertionError("the page said nothing")


@needs_chromium
def test_a_webgpu_error_and_a_lost_device_are_said_on_the_page(exported):
    with Chromium() as browser:
        tab = browser.open(exported["brick"][0] / "index.html")
        tab.evaluate("window.wgpurender.ready")
        assert tab.evaluate("document.getElementById('message').textContent") == ""
        tab.evaluate("(window.wgpurender.device.createShaderModule({code: 'fn broken( {'}), 1)")  # a bad shader
        shown = _wait_for_message(tab)
        assert shown["message"].startswith("WebGPU error:") and "broken" in shown["message"]
        assert shown["stopped"] and shown["frametime"] == "stopped" and "within the spec" not in shown["difference"]
        frames = shown["frames"]
        time.sleep(0.5)
        assert tab.evaluate("window.wgpurender.frames") == frames  # the loop stopped
        tab = browser.open(exported["3d"][0] / "index.html")
        tab.evaluate("window.wgpurender.ready")
        tab.evaluate("(window.wgpurender.device.destroy(), 1)")
        shown = _wait_for_message(tab)
        assert "device was lost" in shown["message"] and "Reload" in shown["message"] and shown["stopped"]
