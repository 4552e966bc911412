"""bench perf's scene-scale scenes name the bundled brick texture wherever the bundled assets are.

From the wheel the assets are ``wgpurender/_assets``, not the checkout's ``assets/``; scale.py once built the
texture's path from its own file (``parents[2] / "assets"``), which from the wheel named site-packages/assets: the
generated scene then failed with "not found" (and, where a checkout was beside it, would have been refused by the
read rule, which allows the bundled assets as core/files/assets.py finds them). Here the bundled assets are moved
to a temporary folder, as the wheel's are, and the generated scenes must load from there. API-free.
"""

from __future__ import annotations

import shutil
import time

import pytest

from wgpurender.bench import scale
from wgpurender.core.files import assets
from wgpurender.core.scene.load import load_scene


@pytest.mark.parametrize("write", [scale.instanced_scene, scale.distinct_scene])
def test_scale_scenes_read_the_brick_texture_from_the_bundled_assets_wherever_they_are(write, tmp_path,
                                                                                       monkeypatch):
    bundled = assets.assets_dir() / "textures" / "brick_albedo.png"
    elsewhere = tmp_path / "elsewhere"  # another layout: assets_dir() is elsewhere/assets
    (elsewhere / "assets" / "textures").mkdir(parents=True)
    shutil.copy(bundled, elsewhere / "assets" / "textures")
    monkeypatch.setattr(assets, "CHECKOUT", elsewhere)
    monkeypatch.setattr(assets, "PACKAGED", {**assets.PACKAGED, "assets": "_no_such_folder"})
    assert assets.assets_dir() == elsewhere / "assets"

    folder = tmp_path / "scene"
    folder.mkdir()
    scene = load_scene(write(folder, 4, (32, 32)))  # UserError before: the checkout's texture, outside the jail
    assert scale.brick_texture() == elsewhere / "assets" / "textures" / "brick_albedo.png"
    assert scale.brick_texture().resolve() in {m.albedo_map for m in scene.materials.values()}


def test_scale_case_reports_thread_cpu_beside_wall_cpu(ctx, tmp_path):
    """bench_case adds a cpu_thread_ms row (record + submit in thread CPU time) with one sample per timed frame,
    each a positive part of the thread's CPU time."""
    size = (32, 24)
    rows = scale.bench_case(ctx, scale.instanced_scene(tmp_path, 8, size), "instanced/8", size, frames=6)
    by_metric = {r.metric: r for r in rows}
    thread = by_metric["cpu_thread_ms"]
    assert (thread.family, thread.case, thread.path, thread.size, thread.n) == ("scene-scale", "instanced/8", "wgpu",
                                                                              "32x24", 6)
    assert 0 < thread.p10 <= thread.median <= thread.p90
    assert thread.n * thread.p10 <= time.thread_time() * 1e3  # per frame: no sample holds the thread's whole CPU time


@pytest.mark.parametrize(("kind", "family", "config", "want"), [
    ("DiscreteGPU", "scene", {}, 100), ("DiscreteGPU", "frames", {}, 100), ("DiscreteGPU", "scene-scale", {}, 100),
    ("DiscreteGPU", "objects", {}, 20), ("CPU", "scene", {}, 20), ("DiscreteGPU", "scene", {"frames": 7}, 7),
    ("DiscreteGPU", "scene", {"quick": True}, 4)])
def test_judged_tail_rows_get_enough_frames_for_a_p99_on_a_gpu(kind, family, config, want):
    """The p99 of 20 samples is their largest: the families whose p99 is judged time 100 frames a case on a GPU
    (--frames and --quick still decide when given)."""
    from types import SimpleNamespace

    from wgpurender.bench.perf import PerfConfig

    ctx = SimpleNamespace(adapter=SimpleNamespace(info={"adapter_type": kind}))
    assert PerfConfig(**config).timed_frames(ctx, family) == want
