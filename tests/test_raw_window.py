"""The raw-Vulkan window (wgpurender/raw_path/window/__init__.py) under a private Xvfb, on lavapipe, validation on.

Every run here has the validation layer with synchronisation validation on ($WGPURENDER_VALIDATION,
set by conftest.py and passed to the subprocess): any message makes the window raise, so exit code 0
means 0 messages. The screenshot is read back from the presented swapchain image and must equal the
offscreen raw render of the same stage or scene made in this process, bit for bit (threshold 0):
the blit from the stage's rgba8unorm-srgb image to the BGRA sRGB swapchain image (or rgba8unorm to
BGRA UNORM) moves the encoded bytes unchanged on lavapipe (measured: 0 pixels differ).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.files.imageio import load_png
from wgpurender.core.files.owned_files import MANIFEST
from wgpurender.raw_path import render_reference

REPO = Path(__file__).resolve().parent.parent
SIZE = (160, 120)


from xvfb import xvfb_display  # noqa: E402,F401 - the shared Xvfb fixture "display" (skips where Xvfb cannot start)


def raw_demo(display, *args, timeout=180):
    env = dict(os.environ, DISPLAY=display, WGPURENDER_VALIDATION="1")
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", "--raw", *args], env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("target", ["triangle", "offscreen", "clear", "msaa-post", "3d", "assets/scenes/final.toml",
                                    "assets/scenes/retro.toml"])
def test_raw_window_screenshot_equals_offscreen(display, tmp_path, target):
    """3 frames presented through the swapchain, 0 validation messages, screenshot == offscreen raw render."""
    if target.endswith(".toml") and not (REPO / "assets" / "models" / "brick_torus.glb").is_file():
        pytest.skip("scene assets not present")
    shot = tmp_path / "shot.png"
    # both sides draw the one default anisotropy rule ("auto": 1 on lavapipe): render_reference's default was
    # "scene" until da63fa5, which is why the window was once given --anisotropy scene here
    result = raw_demo(display, str(REPO / target) if target.endswith(".toml") else target, "--frames", "3",
                      "--size", f"{SIZE[0]}x{SIZE[1]}", "--screenshot", str(shot), "--time", "0")
    assert result.returncode == 0, result.stderr
    assert "frames: 3" in result.stdout and "present mode fifo" in result.stdout
    assert "fifo" in result.stdout.split("surface offers:")[1].split("\n")[0]  # FIFO is always offered
    want = render_reference(str(REPO / target) if target.endswith(".toml") else target, SIZE)
    got = load_png(shot)
    assert got.shape == want.shape
    assert np.array_equal(got, want), f"{int((got != want).any(-1).sum())} pixels differ"


@pytest.mark.parametrize("mode", ["fifo", "mailbox", "immediate"])
def test_raw_present_modes(display, mode):
    """Each requested present mode is used where offered; otherwise one line naming what is, exit code 2."""
    result = raw_demo(display, "clear-pass", "--frames", "2", "--size", "64x64", "--present-mode", mode)
    if result.returncode == 2 and "not offered" in result.stderr:
        assert "it offers" in result.stderr and "Traceback" not in result.stderr
        pytest.skip(result.stderr.strip())
    assert result.returncode == 0, result.stderr
    assert f"present mode {mode}" in result.stdout


def test_raw_window_resize_and_minimise(display, monkeypatch):
    """In-process: the window is resized to 200x150 after frame 1 and reported minimised for three polls
    after frame 3. The swapchain is re-created, nothing is acquired while minimised, 6 frames are still
    presented, validation stays silent, and the last frame is the 200x150 offscreen render.

    The minimised state is injected (RawWindow.minimised returns True for three polls): Xvfb has no window
    manager, so glfwIconifyWindow has no effect there; the loop's reaction to it is what is tested.
    """
    from wgpurender.raw_path import window as raw_window

    monkeypatch.setenv("DISPLAY", display)
    state = {"calls": 0, "minimised": 0, "acquired_while_minimised": 0}
    real_minimised = raw_window.RawWindow.minimised
    real_frame = raw_window.RawWindow.frame

    def minimised(self):
        if state["minimised"] > 0:
            state["minimised"] -= 1
            return True
        return real_minimised(self)

    def frame(self, *args):
        state["acquired_while_minimised"] += state["minimised"] > 0
        return real_frame(self, *args)

    def on_frame(glfw, window, n):
        state["calls"] += 1
        if n == 1 and "resized" not in state:
            state["resized"] = glfw.set_window_size(window, 200, 150) or True
        if n == 3 and "minimised_once" not in state:
            state["minimised"], state["minimised_once"] = 3, True

    monkeypatch.setattr(raw_window.RawWindow, "minimised", minimised)
    monkeypatch.setattr(raw_window.RawWindow, "frame", frame)
    result = raw_window.run_raw_window("3d", SIZE, frames=6, screenshot=True, fixed_time=0.0, on_frame=on_frame)
    assert result.frames == 6 and state["calls"] >= 6 + 3
    assert result.recreated >= 2  # after the resize, and on restore
    assert "minimised: nothing acquired or drawn" in result.events and state["acquired_while_minimised"] == 0
    assert np.array_equal(result.last_frame, render_reference("3d", (200, 150)))


# -- both windows equal: the same camera, keys, title and benchmark as the wgpu window ----------------------

# A right-drag pan, a left-drag orbit, two scroll steps, an arrow-key orbit and a W: every kind of camera input.
ORBIT_INPUT = ("1:press right; 1:move 0 0; 1:move 30 10; 1:release right; 1:press; 1:move 60 20; 1:release; "
               "1:scroll 2; 1:key LEFT; 1:key W")
# Calibrated on lavapipe (Mesa 22.3.6, 2026-11-24): the two windows give identical images for the 3d stage and
# unlit.toml, and for final.toml differ by 1/255 in 1.5-2.6 % of the pixels (its HDR post chain keeps float16
# between effects on the wgpu path only: docs/verification.md). Bounds: 2/255, 5 % of the pixels.
WINDOW_MAX_ABS, WINDOW_CHANGED = 2, 0.05


def wgpu_demo(display, *args, timeout=180):
    """The wgpu window without its settings overlay (the raw window has none: the same input, the same scene)."""
    env = dict(os.environ, DISPLAY=display)
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", "--no-overlay", *args], env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("target", ["3d", "assets/scenes/unlit.toml", "assets/scenes/final.toml"])
def test_both_windows_move_their_cameras_alike(display, tmp_path, target):
    """The same input script through ``demo`` and ``demo --raw``: equal images before and after the camera moved,
    and the move itself changed the image (so equal images cannot come from ignored input)."""
    if target.endswith(".toml") and not (REPO / "assets" / "models" / "brick_torus.glb").is_file():
        pytest.skip("scene assets not present")
    name = str(REPO / target) if target.endswith(".toml") else target
    shots = {}
    for window, run in (("wgpu", wgpu_demo), ("raw", raw_demo)):
        still, moved = tmp_path / f"{window}-still.png", tmp_path / f"{window}-moved.png"
        script = f"0:shot {still}; {ORBIT_INPUT}; 2:shot {moved}"
        result = run(display, name, "--frames", "3", "--time", "0", "--size", f"{SIZE[0]}x{SIZE[1]}",
                     "--test-input", script)
        assert result.returncode == 0, result.stderr
        shots[window] = (load_png(still).astype(int), load_png(moved).astype(int))
    for k, pose in enumerate(("still", "moved")):
        diff = np.abs(shots["wgpu"][k] - shots["raw"][k])[..., :3].max(axis=2)
        assert diff.max() <= WINDOW_MAX_ABS and (diff > 0).mean() <= WINDOW_CHANGED, \
            f"{pose}: max {diff.max()}/255, {(diff > 0).mean():.2%} of the pixels differ"
    moved = (np.abs(shots["raw"][1] - shots["raw"][0])[..., :3].max(axis=2) > 8).mean()
    assert moved > 0.03, f"the input changed only {moved:.1%} of the raw window's pixels"


def test_raw_window_reset_key_and_escape(display, tmp_path):
    """R restores the start camera (the offscreen render); Esc closes the window before --frames is reached."""
    still, reset = tmp_path / "still.png", tmp_path / "reset.png"
    script = f"0:shot {still}; {ORBIT_INPUT}; 2:key R; 2:shot {reset}; 3:key ESCAPE"
    result = raw_demo(display, "3d", "--frames", "50", "--time", "0", "--size", f"{SIZE[0]}x{SIZE[1]}",
                      "--test-input", script)
    assert result.returncode == 0, result.stderr
    assert "frames: 3," in result.stdout  # frames 0, 1, 2 drawn; Esc before frame 3
    want = render_reference("3d", SIZE)
    assert np.array_equal(load_png(still), want) and np.array_equal(load_png(reset), want)


def test_raw_benchmark_csv_and_fps_title(display, tmp_path, monkeypatch):
    """In-process: --benchmark's CSV has every timed frame, and the title shows an FPS the frame times agree with."""
    import glfw

    from wgpurender.core.view.frame_times import BenchmarkSpec
    from wgpurender.raw_path import window as raw_window

    monkeypatch.setenv("DISPLAY", display)
    titles = []
    real = glfw.set_window_title
    monkeypatch.setattr(glfw, "set_window_title", lambda w, text: titles.append(text) or real(w, text))
    csv_path = tmp_path / "raw.csv"
    result = raw_window.run_raw_window("triangle", (64, 48), present_mode="immediate",
                                       benchmark=BenchmarkSpec(0.3, 1.0, csv_path))
    result.benchmark.write_csv()
    rows = csv_path.read_text().splitlines()
    assert rows[0] == "frame,frame_ms"
    times = [float(r.split(",")[1]) for r in rows[1:]]
    assert [int(r.split(",")[0]) for r in rows[1:]] == list(range(len(times))) and len(times) >= 2
    assert sum(times) >= 1000.0 - 1e-4 * len(times) and sum(times[:-1]) < 1000.0
    assert result.frames > len(times)  # the warm-up frames were drawn and left out
    assert titles, "the title was never updated"
    import re

    match = re.fullmatch(r"wgpurender --raw: triangle  \|  ([0-9.]+) FPS  ([0-9.]+) ms", titles[-1])
    assert match, titles[-1]
    fps, ms = float(match.group(1)), float(match.group(2))
    assert fps == pytest.approx(1e3 / ms, rel=0.01)
    assert min(times) * 0.5 <= ms <= max(times) * 2  # a mean over the last half second of the frames timed


@pytest.mark.parametrize("window", ["wgpu", "raw"])
def test_demo_record_writes_every_presented_frame(display, tmp_path, window):
    """--record FOLDER: one PNG per presented frame, each the frame shown (the offscreen raw render at t=0, within
    the windows' tolerance); --record OUT.mp4 has as many frames, at --record-fps."""
    run = raw_demo if window == "raw" else wgpu_demo
    frames = tmp_path / "frames"
    result = run(display, "3d", "--frames", "3", "--time", "0", "--size", f"{SIZE[0]}x{SIZE[1]}", "--record",
                 str(frames))
    assert result.returncode == 0, result.stderr
    assert f"wrote {frames} (3 frames)" in result.stdout
    want = render_reference("3d", SIZE).astype(int)
    names = sorted(p.name for p in frames.iterdir() if p.name != MANIFEST)  # the folder's manifest of owned files
    assert (frames / MANIFEST).is_file()
    assert names == [f"frame_{k:05d}.png" for k in range(3)]
    for name in names:
        diff = np.abs(load_png(frames / name).astype(int)[..., :3] - want[..., :3]).max(axis=2)
        assert diff.max() <= WINDOW_MAX_ABS and (diff > 0).mean() <= WINDOW_CHANGED
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    video = tmp_path / "demo.mp4"
    result = run(display, "3d", "--frames", "4", "--size", "96x72", "--record", str(video), "--record-fps", "12")
    assert result.returncode == 0, result.stderr
    reader = imageio_ffmpeg.read_frames(str(video))
    meta = next(reader)
    assert meta["size"] == (96, 72) and meta["fps"] == pytest.approx(12.0) and len(list(reader)) == 4


def test_record_fps_without_record_is_refused(display):
    result = wgpu_demo(display, "3d", "--frames", "1", "--record-fps", "10")
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "--record" in result.stderr
