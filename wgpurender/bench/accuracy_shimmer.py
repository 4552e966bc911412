"""Shimmer: what mip-maps and MSAA are for, which no still frame can show.

A still frame scores a filter by how close one image is to the truth. A sharp but aliased image (nearest
sampling of a minified texture, edges without anti-aliasing) can score well there: its errors are
scattered, and a blurrier, correctly filtered image pays for its blur everywhere. What aliasing really costs is
*temporal*: under slow motion the aliased samples jump from texel to texel (shimmer, sparkle) and edges crawl
stair-step by stair-step, while the truth changes smoothly. So this measure moves the camera by a sub-pixel
amount per frame and compares the renderer's frame-to-frame change with the truth's own::

    shimmer = mean over frames t and pixels of | (R[t+1] - R[t]) - (T[t+1] - T[t]) |   (linear light)

- **edges**: the flat triangles of the anti-aliasing case (accuracy_analytic.TRIANGLES), the camera sliding
  parallel to their plane by EDGE_STEP_PX pixels per frame: the image translates exactly, and the truth of each
  frame is the exact polygon coverage of the moved triangles.
- **minified plane**: the ground plane to the horizon of the filtering case, the camera moving forward by
  GROUND_STEP world units per frame; the truth of each frame is the float64 footprint integral from the moved
  eye.

Both truths are float64 numpy (accuracy_truth.py) and never see the renderer.
"""

from __future__ import annotations

import csv
import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpurender.bench import accuracy_truth as truth
from wgpurender.bench.accuracy_analytic import (
    BACKGROUND,
    FOV,
    GROUND,
    ground_texture,
    triangle_shapes,
    write_ground_scene,
    write_triangles_scene,
)
from wgpurender.bench.accuracy_downsample import linear_from_srgb8
from wgpurender.bench.accuracy_knobs import Settings

FRAMES = 8
EDGE_STEP_PX = (0.23, 0.17)  # pixels per frame, right and down: every edge orientation crawls
GROUND_STEP = 0.015  # world units per frame along the view: under a pixel per frame at the bottom of the image
EDGE_SETTINGS = {"none": (1, 1, False), "fxaa": (1, 1, True), "msaa4": (4, 1, False), "ssaa2": (1, 2, False)}
PLANE_SETTINGS = ("nearest", "linear", "trilinear", "aniso4")


@dataclass
class ShimmerRow:
    section: str  # "edges" or "minified plane"
    setting: str
    shimmer: float  # mean |renderer's frame-to-frame change - truth's| (linear)
    still_error: float  # mean |R - T| over the frames (linear): what a still frame measures
    truth_change: float  # mean |T[t+1] - T[t]|: how much the truth itself moves per frame


def shimmer(frames: np.ndarray, truths: np.ndarray) -> float:
    """Mean absolute difference between the frame-to-frame changes of ``frames`` and of ``truths`` (T, H, W, C)."""
    frames, truths = np.asarray(frames, np.float64), np.asarray(truths, np.float64)
    if frames.shape != truths.shape or len(frames) < 2:
        raise ValueError(f"need two or more frames of one shape, got {frames.shape} and {truths.shape}")
    return float(np.abs(np.diff(frames, axis=0) - np.diff(truths, axis=0)).mean())


def row(section: str, setting: str, frames: np.ndarray, truths: np.ndarray) -> ShimmerRow:
    truths = np.asarray(truths, np.float64)
    return ShimmerRow(section, setting, shimmer(frames, truths), float(np.abs(frames - truths).mean()),
                      float(np.abs(np.diff(truths, axis=0)).mean()))


def shifted(camera, offset) -> object:
    """The camera moved by ``offset`` (eye and target together: no rotation)."""
    d = np.asarray(offset, np.float64)
    return dataclasses.replace(camera, eye=tuple(map(float, np.asarray(camera.eye) + d)),
                               target=tuple(map(float, np.asarray(camera.target) + d)))


def edge_offset(frame: int, size: tuple[int, int]) -> tuple[float, float, float]:
    """World offset of the camera at ``frame``: one pixel is 2/h world units on the triangles' plane.

    The camera moves right and down, so the image moves left and up, by EDGE_STEP_PX per frame."""
    h = size[1]
    return (frame * EDGE_STEP_PX[0] * 2.0 / h, -frame * EDGE_STEP_PX[1] * 2.0 / h, 0.0)


def edge_truths(size: tuple[int, int], frames: int = FRAMES) -> np.ndarray:
    """(frames, H, W, 3) exact linear images of the moving triangles."""
    shapes = triangle_shapes(size)
    out = []
    for f in range(frames):
        move = np.array([f * EDGE_STEP_PX[0], f * EDGE_STEP_PX[1]])  # pixels: the image moves left and up
        coverages = [truth.polygon_coverage(px - move, size) for _w, px, _c in shapes]
        out.append(truth.composite(coverages, [c for _w, _p, c in shapes], BACKGROUND))
    return np.asarray(out)


def ground_offset(frame: int) -> tuple[float, float, float]:
    eye, target = np.asarray(GROUND["eye"]), np.asarray(GROUND["target"])
    forward = (target - eye) * np.array([1.0, 0.0, 1.0])
    forward /= np.linalg.norm(forward)  # along the ground: the camera keeps its height
    return tuple(map(float, forward * GROUND_STEP * frame))


def ground_truths(size: tuple[int, int], frames: int = FRAMES, n_sub: int = 12) -> np.ndarray:
    """(frames, H, W, 3) footprint integrals of the ground plane seen from the moving eye."""
    texture = linear_from_srgb8(ground_texture(GROUND["tex"]))[..., :3]
    out = []
    for f in range(frames):
        d = np.asarray(ground_offset(f))
        out.append(truth.footprint_average(texture, np.asarray(GROUND["eye"]) + d, np.asarray(GROUND["target"]) + d,
                                           FOV, size, GROUND["uv_per_unit"], n_sub))
    return np.asarray(out)


def render_moving(ctx, scene_path: Path, settings: Settings, size, knobs, offsets) -> np.ndarray:
    """(frames, H, W, 3) linear images, one per camera offset, through the real scene renderer."""
    from wgpurender.bench.accuracy_run import Timed
    from wgpurender.core.scene import load_scene

    scene = load_scene(scene_path)
    t = Timed(ctx, scene, settings, size, knobs)
    out = []
    for offset in offsets:
        t.renderer.move_camera(shifted(scene.camera, offset))
        t.run(1)
        t.read()
        out.append(linear_from_srgb8(t.pixels)[..., :3])
    return np.asarray(out)


def run_shimmer(ctx, work: Path, size: tuple[int, int], frames: int = FRAMES, progress=print,
                edge_settings: tuple[str, ...] = tuple(EDGE_SETTINGS), plane_settings: tuple[str, ...] = PLANE_SETTINGS,
                ) -> list[ShimmerRow]:
    """Both cases, each named setting (default all): the rows in report order."""
    rows: list[ShimmerRow] = []
    plain, _ = write_triangles_scene(work / "shimmer", size, fxaa=False)
    with_fxaa, _ = write_triangles_scene(work / "shimmer", size, fxaa=True)
    truths = edge_truths(size, frames)
    offsets = [edge_offset(f, size) for f in range(frames)]
    for label in edge_settings:
        msaa, ss, fxaa = EDGE_SETTINGS[label]
        images = render_moving(ctx, with_fxaa if fxaa else plain, Settings(msaa=msaa, ss=ss), size,
                               ("msaa", "ss"), offsets)
        rows.append(row("edges", label, images, truths))
        progress(f"shimmer edges {label}: {rows[-1].shimmer:.5f}")
    ground, _ = write_ground_scene(work / "shimmer", size, n_sub=1)
    truths = ground_truths(size, frames)
    offsets = [ground_offset(f) for f in range(frames)]
    for level in plane_settings:
        images = render_moving(ctx, ground, Settings(msaa=1, filter=level), size, ("filter",), offsets)
        rows.append(row("minified plane", level, images, truths))
        progress(f"shimmer minified plane {level}: {rows[-1].shimmer:.5f}")
    return rows


CSV_COLUMNS = ("section", "setting", "shimmer", "still_error", "truth_change")


def write_shimmer_csv(rows: list[ShimmerRow], path: Path) -> Path:
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(CSV_COLUMNS)
        for r in rows:
            writer.writerow([r.section, r.setting, f"{r.shimmer:.5f}", f"{r.still_error:.5f}", f"{r.truth_change:.5f}"])
    return path


def markdown(rows: list[ShimmerRow], frames: int, size: tuple[int, int]) -> list[str]:
    """The shimmer table and what it says, for accuracy_analytic.md."""
    lines = ["", f"## Shimmer under slow motion ({frames} frames, {size[0]}x{size[1]})", "",
             f"The camera moves by a sub-pixel step per frame (edges: {EDGE_STEP_PX[0]}, {EDGE_STEP_PX[1]} px; "
             f"plane: {GROUND_STEP} units forward). Shimmer: mean |renderer's frame-to-frame change - the "
             "truth's| (linear); still error: mean |R - T| per frame, what a still frame measures.", "",
             "| case | setting | shimmer | still error | truth's own change |", "|---|---|---|---|---|"]
    lines += [f"| {r.section} | {r.setting} | {r.shimmer:.5f} | {r.still_error:.5f} | {r.truth_change:.5f} |"
              for r in rows]
    return lines
