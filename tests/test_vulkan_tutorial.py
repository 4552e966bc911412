"""The Vulkan tutorial's frames (chapters 28 and 30) reproduced by the scene renderer.

The references are the C++ tutorial's own frames on lavapipe on an Intel CPU
(../shared/anchors/vulkan-tutorial, not ours, never copied into the repository); the tests skip
when that folder is absent.

Tolerance-based (tests/imagecheck.py, rows tutorial_28 / tutorial_30 of
assets/reference/tolerances.toml, per driver class): llvmpipe's code differs between host CPUs,
and a GPU filters differently. Measured, lavapipe Mesa 22.3.6: on the Intel CPU that made the
frames, chapter 28 differs in 106 pixels (105 by 1/255, one by 8/255); on an AMD EPYC in 2,994
pixels (max 8/255, FLIP 0.0004) and chapter 30 in 3,569 (max 15/255, FLIP 0.0005). The issue's
targets (mean absolute error <= 1/255 per channel, >= 99% of pixels within 2/255) are asserted too,
read from the same rows (mae, within2) per driver class: on a GPU, whose filtering is not lavapipe's,
the rows hold bounds calibrated on an NVIDIA H100 (within 2/255: 95.8% and 98.0% measured there).

Why any pixel differs on the Intel CPU: our matrices are computed in float64 and rounded once (6
of GLM's float32 elements differ by 1 ulp) and our OBJ loader computes 1 - v in float64
(tinyobjloader: 1.0f - v in float32; 2003 of 4675 texture coordinates differ by 1 ulp). Given
exactly the tutorial's float32 inputs, both frames were bit-identical to the C++ frames there.
That equality only holds on the CPU that made them, so test_float32_inputs_same_on_both_paths
keeps the exact check where it is sound: our wgpu render and our raw-Vulkan render, both with the
tutorial's float32 inputs, made in the same run on the same machine.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from imagecheck import assert_same_render, assert_within_tolerance

from wgpurender.core.files.imageio import load_png
from wgpurender.core.verdict.tolerances import load_table

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
    from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
    from wgpurender.wgpu_path.scene import render_scene_file

    scene, ref = CHAPTERS[chapter]
    # the C++ frames filter with the scene's anisotropy 16: so does this render (REFERENCE_ANISOTROPY), where
    # `wgpurender render` on a CPU adapter draws 1 (core/plan/anisotropy.py, reference_difference)
    result = render_scene_file(ROOT / "assets" / "scenes" / scene, ctx=ctx, frames=1, anisotropy=REFERENCE_ANISOTROPY)
    return load_png(ANCHORS / ref)[..., :3], result.pixels[..., :3]


def _errors(ref: np.ndarray, ours: np.ndarray) -> tuple[np.ndarray, float]:
    diff = np.abs(ref.astype(np.int32) - ours.astype(np.int32))
    return diff.reshape(-1, 3).mean(axis=0), float(np.mean(diff.max(axis=-1) <= 2))


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_frame_matches_the_tutorial(request, ctx, chapter, wgpu_driver_class):
    ref, ours = _render(ctx, chapter)
    assert ours.shape == ref.shape == (600, 800, 3)
    mae, within2 = _errors(ref, ours)
    row = load_table()["references"][f"tutorial_{chapter}"][wgpu_driver_class]  # lavapipe: the targets
    assert np.all(mae <= row["mae"]) and within2 >= row["within2"], (
        f"MAE {np.round(mae, 3)}/255 (bound {row['mae']}), {100 * within2:.2f}% within 2/255 (bound "
        f"{100 * row['within2']:.1f}%) on {wgpu_driver_class}; bounds from {row['targets']}")
    assert_within_tolerance(request, f"tutorial_{chapter}", ref, ours, wgpu_driver_class)


def _glm_matrices() -> dict[str, np.ndarray]:
    """GLM's float32 view and projection as the C++ program uploaded them (params.json), m[row, col]."""
    params = json.loads((ANCHORS / "params.json").read_text())["camera"]["matrices_column_major_as_uploaded"]
    return {k: np.array(v, dtype=np.float64).T for k, v in params.items()}  # column-major -> m[row, col]


def _tinyobj_uvs(load):
    """Wrap a mesh loader so that v is tinyobjloader's float32 1.0f - v (the file's vt has 6 decimals)."""
    def mesh(self, path):
        loaded = load(self, path)
        v = np.round(1.0 - loaded.uvs[:, 1].astype(np.float64), 6)
        loaded.uvs[:, 1] = np.float32(1.0) - v.astype(np.float32)
        return loaded
    return mesh


def _use_tutorial_inputs_on_wgpu(monkeypatch, glm) -> None:
    from wgpurender.wgpu_path.scene import scene_pass

    camera_values = scene_pass.camera_values

    def glm_camera(scene, aspect):
        values = camera_values(scene, aspect)
        values["view"] = glm["view"]
        values["proj"] = scene.camera.clip_correction @ glm["proj"]  # exact: only a sign changes
        return values

    monkeypatch.setattr(scene_pass, "camera_values", glm_camera)


def _use_tutorial_inputs_on_raw(monkeypatch, glm) -> None:
    """The raw path uploads the glm-vulkan projection as the tutorial does (Y flip kept, plain viewport)."""
    from wgpurender.raw_path.scene import scene_subpass

    camera_block = scene_subpass.camera_block

    class GlmCamera:
        def __init__(self, cam):
            self._cam = cam

        def __getattr__(self, name):
            return getattr(self._cam, name)

        def source_projection(self, aspect):
            return glm["proj"]

        def view(self):
            return glm["view"]

    class SceneWithGlmCamera:
        def __init__(self, scene):
            self._scene, self.camera = scene, GlmCamera(scene.camera)

        def __getattr__(self, name):
            return getattr(self._scene, name)

    monkeypatch.setattr(scene_subpass, "camera_block", lambda scene, aspect: camera_block(SceneWithGlmCamera(scene),
                                                                                          aspect))


def _use_tutorial_uvs(monkeypatch) -> None:
    """Both paths load their meshes through the core's PlanMeshes: one patch gives both the tutorial's uvs."""
    from wgpurender.core.plan.meshes import PlanMeshes

    monkeypatch.setattr(PlanMeshes, "mesh", _tinyobj_uvs(PlanMeshes.mesh))


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_float32_inputs_same_on_both_paths(request, ctx, monkeypatch, chapter, wgpu_driver_class):
    """GLM's float32 view/projection and tinyobjloader's float32 1 - v on both paths: identical frames.

    Exact because both renders are made here, in this run, on one driver (the two-tier rule); against
    the C++ frame the same render is within the tutorial's tolerance (the C++ frame came from another CPU).
    """
    from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
    from wgpurender.raw_path.scene import render_scene_reference

    glm = _glm_matrices()
    _use_tutorial_inputs_on_wgpu(monkeypatch, glm)
    _use_tutorial_inputs_on_raw(monkeypatch, glm)
    _use_tutorial_uvs(monkeypatch)
    ref, ours = _render(ctx, chapter)
    # the raw render draws the same rule as _render's (the scene's anisotropy 16): the inner render functions'
    # default is "auto" (1 on lavapipe) since da63fa5, so left out it would filter differently from the wgpu render
    raw = render_scene_reference(ROOT / "assets" / "scenes" / CHAPTERS[chapter][0], size=(800, 600),
                                 anisotropy=REFERENCE_ANISOTROPY)
    assert_same_render(request, raw[..., :3], ours, "wgpu and raw renders with the tutorial's float32 inputs")
    assert_within_tolerance(request, f"tutorial_{chapter}", ref, ours, wgpu_driver_class)
