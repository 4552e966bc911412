"""Course step 4 (stage "3d"): cubes through camera/object UBOs, dynamic offsets, depth, immediates.

References are computed here in float64 numpy from the stage's inputs (cube specs,
camera spec, face colours, light): projection with transforms.perspective/look_at,
normals rotated by the world matrix's 3x3 (not by the normal matrix the stage
uploads), Lambert + ambient shading. Images are rgba8unorm (no sRGB), so a pixel
is round(255 * linear value).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from helpers import inside, ndc_to_pixels, pixel_centres

from wgpurender.core.course.cubes import (
    AMBIENT,
    DEFAULT_CUBES,
    FACE_COLORS,
    FACE_NORMALS,
    LIGHT_DIR,
    CameraSpec,
    CubeSpec,
    permute_channels,
)
from wgpurender.core.errors import UserError
from wgpurender.wgpu_path.device.targets import create_target, read_texture
from wgpurender.wgpu_path.render import render_stage
from wgpurender.wgpu_path.stages.cube3d import Cube3D

FMT = "rgba8unorm"
COLOR_TOL = 2  # /255: float32 GPU maths vs float64 here, plus 8-bit rounding (0.5)


def render(ctx, size, t=0.0, msaa=1, **kwargs) -> np.ndarray:
    stage = Cube3D(ctx, FMT, msaa, **kwargs)
    stage.resize(size)
    target = create_target(ctx, size, FMT)
    encoder = ctx.device.create_command_encoder()
    stage.record(encoder, target, t)
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, target)


def to_pixels(points, camera: CameraSpec, size) -> np.ndarray:
    """World points (N, 3) to pixel coordinates (N, 2), float64."""
    proj, view = camera.matrices(size[0] / size[1])
    clip = (proj @ view @ np.c_[points, np.ones(len(points))].T).T
    return ndc_to_pixels(clip[:, :2] / clip[:, 3:4], size)


def transform(world: np.ndarray, points) -> np.ndarray:
    points = np.asarray(points, dtype=np.float64)
    return (world @ np.c_[points, np.ones(len(points))].T).T[:, :3]


def face_quad(normal) -> np.ndarray:
    """The 4 corners of a unit cube face (half-size 1), in order around the face."""
    n = np.asarray(normal, dtype=np.float64)
    u, v = np.roll(n, 1), np.cross(n, np.roll(n, 1))
    return np.array([n + su * u + sv * v for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


def polygon_edge_distance(polygon: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Distance from each point (N, 2) to the nearest line through an edge of a convex polygon."""
    points = np.atleast_2d(points)
    d = np.full(len(points), np.inf)
    for p, q in zip(polygon, np.roll(polygon, -1, axis=0), strict=True):
        n = np.array([q[1] - p[1], p[0] - q[0]])
        d = np.minimum(d, np.abs((points - p) @ n) / np.linalg.norm(n))
    return d


def expected_faces(cube: CubeSpec, k: int, t: float, camera: CameraSpec, size, min_facing=0.2):
    """(pixel (x, y), expected rgb 0..255, face index) for each face of cube k that clearly faces the camera.

    The pixel is the one holding the projected face centre, kept only when its
    centre is more than 1.5 px from the face's projected edges.
    """
    world = cube.world(t)
    rot = world[:3, :3] / cube.half_size  # rotation only: normals by hand, not via normal_matrix
    out = []
    for f, n in enumerate(FACE_NORMALS):
        centre = transform(world, [n])[0]
        normal = rot @ n
        to_eye = np.asarray(camera.eye) - centre
        if normal @ to_eye / np.linalg.norm(to_eye) < min_facing:
            continue
        px = to_pixels(np.array([centre]), camera, size)[0]
        pixel = np.floor(px).astype(int)
        quad_px = to_pixels(transform(world, face_quad(n)), camera, size)
        if polygon_edge_distance(quad_px, pixel + 0.5)[0] < 1.5:
            continue
        light = AMBIENT + (1 - AMBIENT) * max(normal @ LIGHT_DIR, 0.0)
        rgb = permute_channels(FACE_COLORS[f], k) * np.asarray(cube.tint[:3]) * light
        out.append((pixel, rgb * 255, f))
    return out


@pytest.mark.parametrize("msaa, t", [(1, 0.7), (1, 3.1), (4, 0.7)])
def test_face_colours_and_lambert_shading(ctx, msaa, t):
    """Every clearly visible face of the 3 default cubes: colour = face colour (channel order by object
    index) * tint * (ambient + (1 - ambient) * max(n.l, 0)), within 2/255 per channel.

    This also checks the camera and object matrices (the pixel is where float64 projection puts the
    face centre) and back-face culling (a culled front face would show the cube's far side)."""
    size = (192, 128)
    image = render(ctx, size, t, msaa)
    camera = CameraSpec()
    checked = 0
    for k, cube in enumerate(DEFAULT_CUBES):
        faces = expected_faces(cube, k, t, camera, size)
        assert faces, f"cube {k}: no clearly visible face"
        for (x, y), rgb, f in faces:
            got = image[y, x, :3].astype(float)
            assert np.abs(got - rgb).max() <= COLOR_TOL, f"cube {k} face {f} at ({x}, {y}): {got} != {rgb.round(1)}"
            checked += 1
    assert checked >= 6


def _dominant(image: np.ndarray) -> np.ndarray:
    """Which channels are nonzero at each pixel, as a 3-bit code (r=4, g=2, b=1)."""
    rgb = image[..., :3] > 0
    return rgb[..., 0] * 4 + rgb[..., 1] * 2 + rgb[..., 2] * 1


@pytest.mark.parametrize("near_first", [True, False])
def test_nearer_cube_occludes_farther(ctx, near_first):
    """Two cubes on the camera's line of sight: the near one (red tint) covers the middle of the far one
    (blue tint) whichever is drawn first; the far one shows around it. Background is nonzero in all channels."""
    camera = CameraSpec()
    eye = np.asarray(camera.eye)
    towards = -eye / np.linalg.norm(eye)
    near = CubeSpec(tuple(eye + 4.0 * towards), speed=0.0, half_size=0.3, tint=(1, 0, 0, 1))
    far = CubeSpec((0.0, 0.0, 0.0), speed=0.0, half_size=1.2, tint=(0, 0, 1, 1))
    size = (96, 96)
    cubes = (near, far) if near_first else (far, near)
    image = render(ctx, size, cubes=cubes)
    code = _dominant(image)
    cx, cy = np.floor(to_pixels(np.array([near.position]), camera, size)[0]).astype(int)
    assert code[cy, cx] == 4, f"centre pixel {image[cy, cx]} is not the near (red) cube"
    red, blue = (code == 4).sum(), (code == 1).sum()
    assert red > 30 and blue > 300, (red, blue)


def _cross2(a, b) -> float:
    return a[0] * b[1] - a[1] * b[0]


def _hull(points: np.ndarray) -> np.ndarray:
    """Convex hull (counter-clockwise in a y-up frame), Andrew's monotone chain."""
    pts = sorted(map(tuple, points))

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and _cross2(np.subtract(out[-1], out[-2]), np.subtract(p, out[-2])) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def test_dynamic_offsets_put_each_cube_at_its_projected_place(ctx):
    """Five cubes from one object buffer (dynamic offsets) and five tints whose zero channels identify
    them: each cube's pixels are exactly the pixel centres inside the convex hull of its 8 projected
    corners (pixels within 0.01 px of a hull edge are not judged), on a non-square target."""
    tints = [(1, 0, 0, 1), (0, 1, 0, 1), (0, 0, 1, 1), (1, 1, 0, 1), (0, 1, 1, 1)]
    codes = [4, 2, 1, 6, 3]
    positions = [(-2.2, 1.0, 0.0), (0.0, 1.0, 0.0), (2.2, 1.0, 0.0), (-1.1, -1.0, 0.5), (1.1, -1.0, 0.5)]
    cubes = [
        CubeSpec(p, axis=(1, 2, 3), speed=40.0 * (i + 1), half_size=0.45, tint=tint)
        for i, (p, tint) in enumerate(zip(positions, tints, strict=True))
    ]
    size, t, camera = (160, 112), 0.4, CameraSpec()
    image = render(ctx, size, t, cubes=cubes)
    code = _dominant(image).reshape(-1)
    centres = pixel_centres(size)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
    for cube, want in zip(cubes, codes, strict=True):
        hull = _hull(to_pixels(transform(cube.world(t), corners), camera, size))
        tris = [np.array([hull[0], hull[i], hull[i + 1]]) for i in range(1, len(hull) - 1)]
        expected = np.any([inside(tri, centres) for tri in tris], axis=0)
        decided = polygon_edge_distance(hull, centres) > 0.01
        got = code == want
        wrong = decided & (got != expected)
        assert expected.sum() > 100
        assert not wrong.any(), f"cube {cube.position}: {wrong.sum()} pixels differ from its projected hull"


def test_immediates_and_uniform_fallback_give_identical_images(ctx):
    """Push constants (var<immediate>) and the group-2 dynamic-offset UBO carry the same Draw data:
    bit-identical images, with and without MSAA."""
    if not ctx.has("immediates"):
        pytest.skip("this adapter has no immediates: only the fallback can run")
    for msaa in (1, 4):
        a = render(ctx, (96, 64), 1.3, msaa, use_immediates=True)
        b = render(ctx, (96, 64), 1.3, msaa, use_immediates=False)
        assert (a[..., :3] > 20).any()  # something drawn
        assert np.array_equal(a, b)


def test_fallback_chosen_without_the_feature(ctx):
    """On a device without immediates, auto picks the UBO path and forcing immediates is a UserError."""
    without = dataclasses.replace(ctx, features=ctx.features - {"immediates"})
    assert not Cube3D(without, FMT, 1).uses_immediates
    assert Cube3D(without, FMT, 1).draw_group is not None
    with pytest.raises(UserError, match="immediates"):
        Cube3D(without, FMT, 1, use_immediates=True)
    if ctx.has("immediates"):
        assert Cube3D(ctx, FMT, 1).uses_immediates


def test_time_is_deterministic_and_animates(ctx):
    """Same t: identical frames (through the stage registry, name "3d"); different t: the cubes moved."""
    a = render_stage("3d", (64, 64), FMT, t=0.25, ctx=ctx, frames=1).pixels
    b = render_stage("3d", (64, 64), FMT, t=0.25, ctx=ctx, frames=1).pixels
    c = render_stage("3d", (64, 64), FMT, t=0.75, ctx=ctx, frames=1).pixels
    assert np.array_equal(a, b)
    assert (np.abs(a.astype(int) - c.astype(int)).max(axis=-1) > 10).sum() > 50
