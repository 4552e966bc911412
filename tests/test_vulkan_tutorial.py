"""The Vulkan tutorial's frames (chapters 28 and 30) reproduced by the scene renderer.

The references are the C++ tutorial's own frames on lavapipe (../shared/anchors/vulkan-tutorial,
not ours, never copied into the repository); the test skips when that folder is absent.

Targets (the issue's): mean absolute error <= 1/255 per channel and >= 99% of pixels within
2/255. Reached on lavapipe (Mesa 22.3.6): chapter 28 MAE (1.3e-4, 7.7e-5, 6.3e-5)/255, 99.9998%
within 2/255, 106 pixels differ (105 by 1/255, one by 8/255); chapter 30 MAE (2.0e-4, 1.1e-4,
5.6e-5)/255, 99.9994% within 2/255. The tests assert the issue's targets and, tighter, MAE <=
0.01/255 and >= 99.99% within 2/255 (room for a different LLVM's rounding, still far from any real
regression: an upside-down image, a half-texel shift or a wrong sRGB step each cost > 1/255 MAE).

Why any pixel differs at all, isolated by test_bit_exact_with_the_tutorials_float32_inputs: our
matrices are computed in float64 and rounded once (6 of GLM's float32 elements differ by 1 ulp) and
our OBJ loader computes 1 - v in float64 (tinyobjloader: 1.0f - v in float32; 2003 of 4675
texture coordinates differ by 1 ulp). Given exactly the tutorial's float32 inputs, both frames are
bit-identical, chapter 30's full mip chain included: our gamma-correct box filter equals the
tutorial's linear vkCmdBlitImage chain on this power-of-two (1024^2) sRGB texture.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from wgpurender.compare import compare_images
from wgpurender.imageio import load_png

ROOT = Path(__file__).resolve().parents[1]
ANCHORS = ROOT.parent / "shared" / "anchors" / "vulkan-tutorial"
CHAPTERS = {
    "28": ("vulkan_tutorial_28.toml", "ref_28_model_loading_1x.png"),
    "30": ("vulkan_tutorial_30.toml", "ref_30_multisampling_4xMSAA.png"),
}

pytestmark = pytest.mark.skipif(
    not (ANCHORS / "viking_room.obj").is_file(),
    reason=f"external anchors not found at {ANCHORS} (the tutorial's model, texture and frames live beside the "
           "repository in ../shared/anchors/vulkan-tutorial, never inside it)",
)


def _render(ctx, chapter: str) -> tuple[np.ndarray, np.ndarray]:
    from wgpurender.scene_render import render_scene_file

    scene, ref = CHAPTERS[chapter]
    result = render_scene_file(ROOT / "assets" / "scenes" / scene, ctx=ctx, frames=1)
    return load_png(ANCHORS / ref)[..., :3], result.pixels[..., :3]


def _errors(ref: np.ndarray, ours: np.ndarray) -> tuple[np.ndarray, float]:
    diff = np.abs(ref.astype(np.int32) - ours.astype(np.int32))
    return diff.reshape(-1, 3).mean(axis=0), float(np.mean(diff.max(axis=-1) <= 2))


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_frame_matches_the_tutorial(ctx, chapter, lavapipe_only):
    ref, ours = _render(ctx, chapter)
    assert ours.shape == ref.shape == (600, 800, 3)
    mae, within2 = _errors(ref, ours)
    assert np.all(mae <= 1.0) and within2 >= 0.99  # the targets
    assert np.all(mae <= 0.01), mae
    assert within2 >= 0.9999, within2
    assert compare_images(ref, ours).flip_mean < 1e-3


def test_bit_exact_with_the_tutorials_float32_inputs(ctx, monkeypatch, lavapipe_only):
    """GLM's float32 view/projection (params.json) and tinyobjloader's float32 1 - v: zero difference."""
    from wgpurender.scene_render import resources, scene_pass

    params = json.loads((ANCHORS / "params.json").read_text())["camera"]["matrices_column_major_as_uploaded"]
    glm = {k: np.array(v, dtype=np.float64).T for k, v in params.items()}  # column-major -> m[row, col]
    camera_values, load = scene_pass.camera_values, resources.SceneResources.mesh

    def glm_camera(scene, aspect):
        values = camera_values(scene, aspect)
        values["view"] = glm["view"]
        values["proj"] = scene.camera.clip_correction @ glm["proj"]  # exact: only a sign changes
        return values

    def tinyobj_uvs(self, path):
        mesh = load(self, path)
        v = np.round(1.0 - mesh.uvs[:, 1].astype(np.float64), 6)  # the file's vt (6 decimals), recovered
        mesh.uvs[:, 1] = np.float32(1.0) - v.astype(np.float32)
        return mesh

    monkeypatch.setattr(scene_pass, "camera_values", glm_camera)
    monkeypatch.setattr(resources.SceneResources, "mesh", tinyobj_uvs)
    for chapter in sorted(CHAPTERS):
        ref, ours = _render(ctx, chapter)
        assert np.array_equal(ref, ours), f"chapter {chapter}: {np.count_nonzero((ref != ours).any(-1))} pixels differ"
