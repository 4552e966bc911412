"""``wgpurender new NAME --from SCENE``: the copy renders from another folder exactly as the bundled scene does."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib

import numpy as np

from wgpurender.core.files.assets import bundled_scene
from wgpurender.core.files.imageio import load_png


def _cli(*args, cwd):
    env = dict(os.environ, XDG_CACHE_HOME=str(cwd / ".cache"))
    return subprocess.run([sys.executable, "-m", "wgpurender", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def _files(scene: dict) -> list[str]:
    """Every path the scene's TOML names (models' path, materials' *_map)."""
    found = [m["path"] for m in scene["models"]]
    for material in scene.get("materials", {}).values():
        found += [v for k, v in material.items() if k.endswith("_map")]
    return found


def test_the_copy_renders_like_the_bundled_scene_from_another_folder(tmp_path):
    made = _cli("new", "mine", "--from", "final", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    copy = tmp_path / "mine" / "mine.toml"
    written = tomllib.loads(copy.read_text())
    original = tomllib.loads(bundled_scene("final").read_text())
    assert len(_files(written)) == len(_files(original)) >= 2
    for path in _files(written):  # every file inside the new folder, byte-equal to the bundled one
        assert (copy.parent / path).resolve().is_relative_to(copy.parent), path
    for new, old in zip(_files(written), _files(original), strict=True):
        if not new.endswith(".glb"):  # a GLB's image uris are rewritten to files beside it
            assert (copy.parent / new).read_bytes() == (bundled_scene("final").parent / old).read_bytes()
    mtl = copy.parent / "models" / "brick_cube.mtl"  # the OBJ's material library and its maps came along
    for line in mtl.read_text().splitlines():
        if line.lower().startswith("map_"):
            assert (mtl.parent / line.split()[-1]).is_file(), line
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    for target, out in ((str(copy), "copy.png"), ("final", "bundled.png")):
        done = _cli("render", target, "--size", "160x120", "-o", out, cwd=elsewhere)
        assert done.returncode == 0, done.stderr
        assert "warn" not in done.stderr.lower(), done.stderr
    copy_png, bundled_png = load_png(elsewhere / "copy.png"), load_png(elsewhere / "bundled.png")
    assert copy_png.shape == (120, 160, 4) and np.array_equal(copy_png, bundled_png)


def test_new_refuses_an_existing_folder_and_an_unknown_scene(tmp_path):
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "keep.txt").write_text("mine")
    done = _cli("new", "taken", cwd=tmp_path)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1 and "already exists" in done.stderr
    assert [p.name for p in (tmp_path / "taken").iterdir()] == ["keep.txt"]
    done = _cli("new", "other", "--from", "no_such_scene", cwd=tmp_path)
    assert done.returncode == 2 and "bundled scenes are" in done.stderr and "final" in done.stderr
    assert not (tmp_path / "other").exists()
