"""w.show and w.record (wgpurender/wgpu_path/notebook.py): the live view in a Jupyter kernel and its still
fallback, and frames written to MP4 or PNG read back and compared with headless renders made here."""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest

import wgpurender as w
from wgpurender.core.files.owned_files import MANIFEST

SIZE = (160, 120)


def _run_notebook(cells: list[str]):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3").execute()
    return nb.cells


def _png(output) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(base64.b64decode(output["data"]["image/png"]))).convert("RGBA"))


def test_show_in_a_kernel_is_the_live_widget_with_a_still_for_frontends_without_widgets():
    """Under nbclient (no widget frontend): the output carries the widget and a PNG equal to the headless render;
    the canvas draws through rendercanvas (a snapshot), and a drag through its events turns the camera."""
    pytest.importorskip("jupyter_rfb")
    cells = _run_notebook([
        "import wgpurender as w\nview = w.show('3d', size=(160, 120))\nview",
        "import asyncio\nimport numpy as np\n"
        "view.canvas.handle_event({'event_type': 'resize', 'width': 160, 'height': 120, 'pixel_ratio': 1.0})\n"
        "view.fixed_time = 0.0\n"
        "view.canvas.get_frame()  # what jupyter_rfb calls to draw; rendercanvas reads the frame back on the loop\n"
        "for _ in range(100):\n"
        "    if view.canvas._last_image is not None:\n"
        "        break\n"
        "    await asyncio.sleep(0.05)\n"
        "live = np.asarray(view.canvas._last_image)\n"
        "before = view.offscreen.frame(0.0)\n"
        "print('live', live.shape, 'same', int(np.abs(live[..., :3].astype(int) - before[..., :3]).max() <= 1))\n"
        "for e in ({'event_type': 'pointer_down', 'x': 0, 'y': 0, 'button': 1},"
        " {'event_type': 'pointer_move', 'x': 80, 'y': 10, 'button': 1},"
        " {'event_type': 'pointer_up', 'x': 80, 'y': 10, 'button': 1}):\n"
        "    view._on_event(e)\n"
        "after = view.offscreen.frame(0.0)\n"
        "print('moved', float((np.abs(after.astype(int) - before.astype(int)).max(axis=2) > 8)"
        ".mean()))\n"
        "view._on_event({'event_type': 'key_down', 'key': 'r'})\n"
        "print('reset', int(np.abs(view.offscreen.frame(0.0).astype(int) - before.astype(int)).max()))",
    ])
    outputs = [o for o in cells[0].outputs if "image/png" in o.get("data", {})]
    assert len(outputs) == 1 and "application/vnd.jupyter.widget-view+json" in outputs[0]["data"]
    want = w.render("3d", size=SIZE).pixels
    assert np.abs(_png(outputs[0]).astype(int) - want.astype(int)).max() <= 1
    text = "".join(o.get("text", "") for o in cells[1].outputs)
    assert "Traceback" not in text and "live (120, 160, 4) same 1" in text, text
    assert float(text.split("moved ")[1].split()[0]) > 0.03
    assert "reset 0" in text


def test_show_outside_a_kernel_without_a_display_is_the_still_image(monkeypatch, capsys):
    """No kernel and no display: one line says why no window opens, and the still frame comes back (a window
    where there is a display: tests/test_window_keys.py)."""
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    img = w.show("triangle", size=SIZE)
    said = capsys.readouterr().err.strip().splitlines()
    assert len(said) == 1 and said[0].startswith("w.show: no window (no display"), said
    assert isinstance(img, w.Image) and img._repr_png_()
    assert np.abs(img.pixels.astype(int) - w.render("triangle", size=SIZE).pixels.astype(int)).max() <= 1


def test_record_mp4_reads_back_as_the_animation(tmp_path):
    """1 s at 10 fps of the rotating cubes: 10 frames of the right size, each close to the headless render at
    t = k / 10 (H.264 is lossy: mean difference under 3/255) and closer to it than to the frame before."""
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    out = w.record("3d", tmp_path / "out.mp4", seconds=1, fps=10, size=(96, 72))
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    frames = [np.frombuffer(f, np.uint8).reshape(72, 96, 3).astype(int) for f in reader]
    assert meta["size"] == (96, 72) and meta["fps"] == pytest.approx(10.0) and len(frames) == 10
    for k in (0, 5, 9):
        want = w.render("3d", size=(96, 72), t=k / 10).pixels[..., :3].astype(int)
        err = np.abs(frames[k] - want).mean()
        assert err < 3.0, f"frame {k}: mean difference {err:.2f}/255"
        if k:
            assert err < np.abs(frames[k - 1] - want).mean()


def test_record_png_frames_are_the_renders(tmp_path):
    from wgpurender.core.files.imageio import load_png

    out = w.record("3d", tmp_path / "frames", seconds=0.3, fps=10, size=(64, 48))
    names = sorted(p.name for p in out.iterdir() if p.name != MANIFEST)  # the folder's manifest of owned files
    assert (out / MANIFEST).is_file()
    assert names == ["frame_00000.png", "frame_00001.png", "frame_00002.png"]
    for k, name in enumerate(names):
        want = w.render("3d", size=(64, 48), t=k / 10).pixels[..., :3]
        assert np.array_equal(load_png(out / name)[..., :3], want)


def test_record_refuses_what_it_cannot_write(tmp_path):
    with pytest.raises(w.UserError, match="give a .mp4 file or a folder"):
        w.record("3d", tmp_path / "out.gif")
    with pytest.raises(w.UserError, match="does not exist"):
        w.record("3d", tmp_path / "no" / "out.mp4")
    with pytest.raises(w.UserError, match="> 0"):
        w.record("3d", tmp_path / "f", seconds=0)
