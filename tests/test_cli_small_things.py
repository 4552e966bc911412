"""The small things a user expects from the CLI (issue 14.5).

--version; compare --json and shares printed as %; concepts NAME (and a helpful error); the heatmap's
colour scale; output formats by suffix (an unknown suffix refused before rendering); a broken pipe
ends quietly; no "material library not found" warning when the scene supplies the material.
"""

from __future__ import annotations

import json
import logging
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpurender.cli import main
from wgpurender.core.files.imageio import load_png, save_png

REPO = Path(__file__).resolve().parent.parent


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_version(capsys):
    assert main(["--version"]) == 0
    out = capsys.readouterr().out.strip()
    text = (REPO / "wgpurender" / "__init__.py").read_text()
    assert out.startswith("wgpurender ") and f'__version__ = "{out.split()[1]}"' in text


def _pair(tmp_path: Path) -> tuple[Path, Path]:
    """Two 10x10 images: b has 5 of 100 pixels off by 3 in red, so over_1 = over_2 = 5%."""
    a = np.full((10, 10, 4), 120, np.uint8)
    b = a.copy()
    b[0, :5, 0] += 3
    return save_png(tmp_path / "a.png", a), save_png(tmp_path / "b.png", b)


def test_compare_prints_shares_as_percent(capsys, tmp_path):
    a, b = _pair(tmp_path)
    code, out, _ = _run(capsys, "compare", str(a), str(b), "--threshold", "over_1=10%")
    assert code == 0
    lines = dict(line.split(":", 1) for line in out.splitlines())
    assert lines["    over_1"].strip() == "5%" and lines["    over_2"].strip() == "5%"
    assert lines["   max_abs"].strip() == "3"
    code, out, _ = _run(capsys, "compare", str(a), str(b), "--threshold", "over_1=4%")
    assert code == 1 and "over_1 5% > 4%" in out


def test_compare_json(capsys, tmp_path):
    a, b = _pair(tmp_path)
    heat = tmp_path / "h.png"
    code, out, _ = _run(capsys, "compare", str(a), str(b), "--json", "--heatmap", str(heat),
                        "--threshold", "max_abs=2")
    data = json.loads(out)
    assert code == 1 and data["failed"] == ["max_abs"]
    m = data["metrics"]
    assert m["max_abs"] == 3 and m["over_1"] == pytest.approx(0.05) and m["over_2"] == pytest.approx(0.05)
    mse = 5 * 3**2 / (100 * 3) / 255**2
    assert m["psnr"] == pytest.approx(10 * np.log10(1 / mse))
    assert data["heatmap"] == str(heat) and heat.is_file()
    code, out, _ = _run(capsys, "compare", str(a), str(a), "--json")
    data = json.loads(out)
    assert code == 0 and data["metrics"]["psnr"] is None and data["failed"] == []  # identical: no finite PSNR


def test_heatmap_has_a_colour_scale(capsys, tmp_path):
    """The image is the heatmap on top, then a bar from black (equal) to white (saturated), labelled."""
    from wgpurender.core.verdict.compare import SCALE_BAR, heatmap

    a, b = _pair(tmp_path)
    heat = tmp_path / "h.png"
    assert _run(capsys, "compare", str(a), str(b), "--heatmap", str(heat), "--threshold", "max_abs=3")[0] == 0
    image = np.asarray(Image.open(heat).convert("RGB"))
    bar_h, line_h, margin = SCALE_BAR
    assert image.shape[0] == 10 + margin + bar_h + line_h and image.shape[1] >= 200
    assert np.array_equal(image[:10, :10], heatmap(load_png(a), load_png(b))[..., :3])
    bar = image[10 + margin + bar_h // 2, margin:-margin]
    assert (bar[0] == 0).all() and (bar[-1] == 255).all()
    assert (np.diff(bar.astype(int).sum(axis=1)) >= 0).all()  # brighter left to right
    labels = image[10 + margin + bar_h:]
    assert (labels > 128).sum() > 20  # text is drawn


def test_concepts_name(capsys):
    code, out, _ = _run(capsys, "concepts", "render", "pass")
    assert code == 0 and out.splitlines()[0] == "render pass" and "vkCreateRenderPass" in out
    assert "\nframebuffer\n" not in out  # one concept only
    code, out, _ = _run(capsys, "concepts", "vkCreateSampler")
    assert code == 0 and out.splitlines()[0] == "samplers"


def test_concepts_unknown_name_lists_close_names(capsys):
    code, out, err = _run(capsys, "concepts", "swapchian")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "unknown concept 'swapchian'" in err and "'swapchain'" in err


@pytest.mark.parametrize("suffix, fmt", [(".jpg", "JPEG"), (".bmp", "BMP"), (".png", "PNG")])
def test_render_writes_the_format_its_suffix_names(capsys, tmp_path, suffix, fmt):
    out = tmp_path / f"t{suffix}"
    code, _, _ = _run(capsys, "render", "clear", "-o", str(out), "--size", "16x8")
    assert code == 0
    with Image.open(out) as image:
        assert image.format == fmt and image.size == (16, 8)


def test_unknown_suffix_is_refused_before_rendering(capsys, tmp_path, monkeypatch):
    import wgpurender.api

    monkeypatch.setattr(wgpurender.api, "render", lambda *a, **k: pytest.fail("rendered anyway"))  # the CLI's render
    code, _, err = _run(capsys, "render", "triangle", "-o", str(tmp_path / "t.xyz"))
    assert code == 2 and err.count("\n") == 1 and "'.xyz'" in err and ".png" in err
    assert not list(tmp_path.iterdir())


def test_broken_pipe_prints_no_traceback():
    """The reader closes the pipe at once (like `| head -1` does after one line): no traceback, exit 0."""
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", "concepts"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 0, err
    assert "Traceback" not in err and "BrokenPipeError" not in err, err


def test_no_material_library_warning_when_the_scene_gives_the_material(tmp_path, caplog, ctx):
    """An OBJ whose MTL is missing: reading its material says so (INFO); rendering it from a scene, which names
    the texture, says nothing about it."""
    from wgpurender.core.scene.file_materials import obj_mtl_entry
    from wgpurender.wgpu_path.render import render_any

    obj = tmp_path / "quad.obj"
    obj.write_text("mtllib missing.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "vn 0 0 1\nusemtl m\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    save_png(tmp_path / "tex.png", np.full((4, 4, 4), 200, np.uint8))
    scene = tmp_path / "s.toml"
    scene.write_text('[camera]\neye = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n\n'
                     '[[models]]\npath = "quad.obj"\nmaterial = { albedo_map = "tex.png", unlit = true }\n')
    with caplog.at_level(logging.INFO):
        obj_mtl_entry(obj)
    assert any("material library" in r.getMessage() for r in caplog.records)  # the check below can fail
    caplog.clear()
    with caplog.at_level(logging.INFO):
        pixels = render_any(str(scene), size=(32, 24)).pixels
    assert not [r.getMessage() for r in caplog.records if "material library" in r.getMessage()]
    assert (pixels[12, 16, :3] == 200).all()  # the scene's texture, unlit, in the middle
