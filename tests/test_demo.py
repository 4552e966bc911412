"""The interactive demo under a private Xvfb: orbit camera input, live reload of shaders, the benchmark CSV.

Input goes in through the demo's test hook (``--test-input``), which calls the same handlers
as the window's GLFW callbacks; ``shot PATH`` saves the frame drawn at that point and
``wait-reload`` blocks until a watched file changed and its rebuild was tried. Expected
images are headless renders made in the same run, or formulas written here.
"""

from __future__ import annotations

import csv
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from xvfb import xvfb_display  # noqa: F401  (the fixture "display": a private Xvfb)

from wgpurender.core.files.imageio import load_png
from wgpurender.core.view.orbit import Orbit
from wgpurender.wgpu_path.render import render_stage

REPO = Path(__file__).resolve().parent.parent
SIZE = "160x120"
# The 3d stage's clear colour (linear 0.02, 0.02, 0.03) in sRGB bytes: sRGB(0.02) = 1.055 * 0.02^(1/2.4) - 0.055.
_SRGB = [round(255 * (1.055 * c ** (1 / 2.4) - 0.055)) for c in (0.02, 0.02, 0.03)]


def _demo(display, *args, env=None, timeout=180):
    env = dict(os.environ, DISPLAY=display, **(env or {}))
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", *args], env=env, capture_output=True,
                          text=True, timeout=timeout)


def _covered(image: np.ndarray) -> int:
    """Pixels of the 3d stage that are not its clear colour (cubes), counted with a 2/255 margin."""
    return int((np.abs(image[..., :3].astype(int) - _SRGB).max(axis=2) > 2).sum())


# -- the orbit camera itself (no window) ---------------------------------------------------------


def test_orbit_starts_at_the_look_at_eye_and_turns_on_a_sphere():
    eye, target, up = (0.0, 1.9, 4.6), (0.1, 0.15, 0.0), (0.0, 1.0, 0.0)
    orbit = Orbit.from_look_at(eye, target, up)
    assert np.allclose(orbit.eye(), eye, atol=1e-12)
    radius = math.dist(eye, target)
    orbit.rotate(math.radians(90.0) / math.radians(0.4), 0.0)  # a quarter turn about +y through the target
    turned = np.array(orbit.eye())
    assert math.dist(turned, target) == pytest.approx(radius, rel=1e-12)
    assert turned[1] == pytest.approx(eye[1], abs=1e-12)  # height along up unchanged
    before, after = np.array(eye) - target, turned - target
    assert np.dot(before[[0, 2]], after[[0, 2]]) == pytest.approx(0.0, abs=1e-9)  # 90 degrees apart
    orbit.zoom(1)
    assert math.dist(orbit.eye(), target) == pytest.approx(0.9 * radius, rel=1e-12)
    orbit.rotate(0.0, 1e6)  # pitch clamps short of the pole
    assert orbit.pitch == pytest.approx(math.radians(89.0))
    orbit.reset()
    assert np.allclose(orbit.eye(), eye, atol=1e-12)


def test_orbit_respects_a_z_up_camera():
    """The Vulkan tutorial's camera looks from (2, 2, 2) with +z up: turning keeps z."""
    orbit = Orbit.from_look_at((2.0, 2.0, 2.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    orbit.rotate(100.0, 0.0)
    assert orbit.eye()[2] == pytest.approx(2.0, abs=1e-12)
    assert math.dist(orbit.eye(), (0, 0, 0)) == pytest.approx(math.sqrt(12.0), rel=1e-12)


# -- camera input in the window --------------------------------------------------------------------


def test_camera_input_changes_the_image_and_reset_restores_it(ctx, display, tmp_path):
    """3d stage at t=0: no input = the headless render; a drag moves the cubes; scroll brings them closer; R resets."""
    shots = {name: tmp_path / f"{name}.png" for name in ("still", "dragged", "zoomed", "reset")}
    script = (f"0:shot {shots['still']}; 1:press; 1:move 0 0; 1:move 80 10; 1:release; 2:shot {shots['dragged']}; "
              f"3:key R; 3:scroll 4; 4:shot {shots['zoomed']}; 5:key R; 6:shot {shots['reset']}")
    result = _demo(display, "3d", "--frames", "7", "--time", "0", "--size", SIZE, "--validation", "--no-overlay",
                   "--test-input", script)
    assert result.returncode == 0, result.stderr
    assert "validation messages: 0" in result.stdout
    img = {name: load_png(path).astype(int) for name, path in shots.items()}
    want = render_stage("3d", (160, 120), "rgba8unorm-srgb", ctx=ctx, frames=1).pixels.astype(int)
    assert np.abs(img["still"][..., :3] - want[..., :3]).max() <= 1
    moved = (np.abs(img["dragged"] - img["still"])[..., :3].max(axis=2) > 8).mean()
    assert moved > 0.03, f"a drag of 80 pixels changed only {moved:.1%} of the pixels"
    assert _covered(img["zoomed"]) > 1.3 * _covered(img["still"])  # 0.9**4 = 0.66 of the distance
    assert np.abs(img["reset"] - img["still"]).max() <= 1


def test_scene_camera_comes_from_the_scene_file_and_moves(display, tmp_path):
    scene = str(REPO / "assets" / "scenes" / "unlit.toml")
    still, moved = tmp_path / "still.png", tmp_path / "moved.png"
    script = f"0:shot {still}; " + "1:key LEFT; " * 6 + f"1:key UP; 2:shot {moved}"  # 30 degrees round, 5 up
    result = _demo(display, scene, "--frames", "3", "--size", SIZE, "--no-overlay", "--test-input", script)
    assert result.returncode == 0, result.stderr
    from wgpurender.wgpu_path.scene import render_scene_file

    want = render_scene_file(scene, size=(160, 120)).pixels.astype(int)
    a, b = load_png(still).astype(int), load_png(moved).astype(int)
    assert np.abs(a[..., :3] - want[..., :3]).max() <= 1
    assert (np.abs(b - a)[..., :3].max(axis=2) > 8).mean() > 0.01  # a flat-coloured cube: its outline moves


# -- live reload -------------------------------------------------------------------------------------


def _wait_for(path: Path, proc: subprocess.Popen, seconds: float = 120.0) -> None:
    deadline = time.monotonic() + seconds
    while not path.exists():
        if proc.poll() is not None:
            pytest.fail(f"the demo ended before writing {path.name}: {proc.stderr.read()}")
        if time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"no {path.name} after {seconds:.0f} s")
        time.sleep(0.1)


def _save(path: Path, text: str) -> None:
    """Replace the file in one step, as editors do (the watcher never sees it half written)."""
    tmp = path.with_suffix(".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def test_editing_a_shader_changes_the_next_frame_and_a_broken_one_keeps_the_last(display, tmp_path):
    """Edit triangle.wgsl to a flat magenta, then break it: magenta shows, then stays; the process lives on."""
    shaders = tmp_path / "shaders"
    shutil.copytree(REPO / "shaders_wgsl", shaders)
    wgsl = shaders / "triangle.wgsl"
    original = wgsl.read_text()
    assert original.count("return vec4f(in.color, 1.0);") == 1
    s = {k: tmp_path / f"{k}.png" for k in ("before", "edited", "broken", "fixed")}
    script = (f"0:shot {s['before']}; 1:wait-reload; 1:shot {s['edited']}; 2:wait-reload; 3:shot {s['broken']}; "
              f"4:wait-reload; 5:shot {s['fixed']}")
    env = dict(os.environ, DISPLAY=display, WGPURENDER_SHADERS=str(shaders))
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", "demo", "triangle", "--frames", "7", "--size",
                             SIZE, "--test-input", script], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        _wait_for(s["before"], proc)
        _save(wgsl, original.replace("return vec4f(in.color, 1.0);", "return vec4f(1.0, 0.0, 1.0, 1.0);"))
        _wait_for(s["edited"], proc)
        broken = original.replace("return vec4f(in.color, 1.0);", "retur n vec4f(in.color, 1.0);")
        _save(wgsl, broken)
        _wait_for(s["broken"], proc)
        _save(wgsl, original)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    before, edited, still, fixed = (load_png(s[k]).astype(int) for k in ("before", "edited", "broken", "fixed"))
    triangle = np.abs(before[..., :3] - before[0, 0, :3]).max(axis=2) > 0  # not the clear colour
    assert triangle.mean() > 0.1
    assert (edited[triangle][:, :3] == [255, 0, 255]).all()  # every triangle pixel is the new flat colour
    assert (edited[~triangle] == before[~triangle]).all()
    assert (still == edited).all()  # the broken shader left the last good frame on screen
    assert np.abs(fixed - before).max() <= 1  # and the fixed file is picked up again
    line = 1 + broken.splitlines().index(next(x for x in broken.splitlines() if "retur n" in x))
    assert err.count(f"{wgsl}:{line}:") == 1, err  # the error, with file:line, printed once
    assert out.count("reloaded after a change to triangle.wgsl") == 2


# -- benchmark -------------------------------------------------------------------------------------


def test_benchmark_writes_every_timed_frame_to_csv(display, tmp_path):
    out = tmp_path / "frames.csv"
    result = _demo(display, "triangle", "--size", "64x48", "--present-mode", "immediate", "--benchmark",
                   "--benchmark-warmup", "0.3", "--benchmark-runtime", "1", "--benchmark-result-file", str(out))
    assert result.returncode == 0, result.stderr
    with out.open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["frame", "frame_ms"]
    frames = [int(r[0]) for r in rows[1:]]
    times = [float(r[1]) for r in rows[1:]]
    assert frames == list(range(len(frames))) and len(frames) >= 2
    assert all(t > 0 for t in times)
    assert sum(times) >= 1000.0 - 1e-4 * len(times)  # at least the asked run time (rows are rounded to 0.1 us)
    assert sum(times[:-1]) < 1000.0
    assert f"benchmark: {len(frames)} frames" in result.stdout
    shown = int(result.stdout.split("frames: ")[1].split(",")[0])
    assert shown > len(frames)  # warm-up frames were drawn and left out


def test_bad_test_input_is_one_line(display):
    result = _demo(display, "triangle", "--frames", "1", "--test-input", "x:key R")
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "frame number" in result.stderr


def test_editing_the_scene_file_rebuilds_the_scene(display, tmp_path):
    """unlit.toml (flat colour, no lighting, no MSAA, sRGB output) gets a new albedo: the cube's pixels take it."""
    shutil.copytree(REPO / "assets" / "models", tmp_path / "models")
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    scene = scenes / "unlit.toml"
    text = (REPO / "assets" / "scenes" / "unlit.toml").read_text()
    assert text.count("albedo_color = [0.8, 0.3, 0.1]") == 1
    scene.write_text(text)
    before, after = tmp_path / "before.png", tmp_path / "after.png"
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", "demo", str(scene), "--frames", "3", "--size", SIZE,
                             "--test-input", f"0:shot {before}; 1:wait-reload; 1:shot {after}"],
                            env=dict(os.environ, DISPLAY=display), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        _wait_for(before, proc)
        _save(scene, text.replace("albedo_color = [0.8, 0.3, 0.1]", "albedo_color = [0.0, 1.0, 0.0]"))
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "reloaded after a change to unlit.toml" in out
    a, b = load_png(before).astype(int), load_png(after).astype(int)
    # sRGB bytes of the linear albedo, unlit: round(255 * srgb(c)) for c = 0.8, 0.3, 0.1 and then 0, 1, 0.
    srgb = [round(255 * (1.055 * c ** (1 / 2.4) - 0.055)) if c > 0.0031308 else round(255 * 12.92 * c)
            for c in (0.8, 0.3, 0.1)]
    cube = (np.abs(a[..., :3] - srgb).max(axis=2) <= 1)
    assert cube.mean() > 0.05
    assert (np.abs(b[cube][:, :3] - [0, 255, 0]).max(axis=1) <= 1).mean() > 0.95  # the cube is green now
