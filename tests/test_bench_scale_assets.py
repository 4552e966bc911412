"""bench perf's scene-scale scenes name the bundled brick texture wherever the bundled assets are.

From the wheel the assets are ``wgpurender/_assets``, not the checkout's ``assets/``; scale.py once built the
texture's path from its own file (``parents[2] / "assets"``), which from the wheel named site-packages/assets: the
generated scene then failed with "not found" (and, where a checkout was beside it, would have been refused by the
read rule, which allows the bundled assets as core/files/assets.py finds them). Here the bundled assets are moved
to a temporary folder, as the wheel's are, and the generated scenes must load from there. API-free.
"""

from __future__ import annotations

import shutil

import pytest

from wgpurender.bench import scale
from wgpurender.core.files import assets
from wgpurender.core.scene.load import load_scene


@pytest.mark.parametrize("write", [scale.instanced_scene, scale.batched_scene, scale.distinct_scene])
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
