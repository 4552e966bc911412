"""The report owns only what it wrote in its folder, checks the folder before rendering, and sweeps what a killed
build left (issue 28.4, 28.5).

Before: rebuilding a report into a folder that held the user's own files deleted them (the old site was removed
whole and the new one renamed into place); the destination was checked for writing only after every step was
rendered; a build killed mid-way left its ``.DIR.*`` temp folder for good.
"""

from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path

import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.files.owned_files import MANIFEST
from wgpurender.report import build

SMALL = dict(size=(32, 24), stages=["triangle"], scenes=[], accuracy=False)


def _build(out: Path, ctx, steps: list | None = None, **extra) -> Path:
    log = steps.append if steps is not None else (lambda _: None)
    return build.build_report(out, ctx=ctx, log=log, **SMALL, **extra)


def test_a_rebuild_keeps_the_users_files_byte_for_byte(tmp_path, ctx):
    site = tmp_path / "site"
    _build(site, ctx)
    (site / "notes.txt").write_bytes(b"my notes \x00\xff")
    (site / "img").mkdir()
    (site / "img" / "mine.png").write_bytes(b"\x89PNG not really")
    owned = set(build_manifest(site))
    assert "index.html" in owned and "triangle_wgpu.png" in owned and "notes.txt" not in owned
    index = _build(site, ctx)
    assert index == site / "index.html" and index.is_file()
    assert (site / "notes.txt").read_bytes() == b"my notes \x00\xff"
    assert (site / "img" / "mine.png").read_bytes() == b"\x89PNG not really"
    assert set(build_manifest(site)) == owned


def build_manifest(site: Path) -> list[str]:
    import json

    return json.loads((site / MANIFEST).read_text())["files"]


def test_a_file_the_last_build_wrote_and_this_one_does_not_is_removed(tmp_path, ctx):
    site = tmp_path / "site"
    _build(site, ctx)
    import json

    data = json.loads((site / MANIFEST).read_text())
    (site / "old_step_wgpu.png").write_bytes(b"stale")  # as if an earlier build had a step this one has not
    data["files"].append("old_step_wgpu.png")
    (site / MANIFEST).write_text(json.dumps(data))
    _build(site, ctx)
    assert not (site / "old_step_wgpu.png").exists()


def test_a_folder_without_a_manifest_is_refused_before_rendering_unless_forced(tmp_path, ctx):
    (tmp_path / "notes.txt").write_text("mine")
    steps: list[str] = []
    with pytest.raises(UserError) as caught:
        _build(tmp_path, ctx, steps)
    assert "not empty" in str(caught.value) and steps == []  # nothing rendered
    _build(tmp_path, ctx, force=True)
    assert (tmp_path / "notes.txt").read_text() == "mine" and (tmp_path / "index.html").is_file()


def test_a_read_only_destination_is_refused_before_rendering():
    folder = Path(tempfile.mkdtemp(prefix="wgpurender-ro-"))
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=16k", "tmpfs", str(folder)]).returncode != 0:
        folder.rmdir()
        pytest.skip("cannot mount a tmpfs here (needs root)")
    try:
        steps: list[str] = []
        with pytest.raises(UserError) as caught:
            _build(folder / "site", None, steps)
        assert "Read-only file system" in str(caught.value) and steps == []
    finally:
        subprocess.run(["umount", str(folder)], check=False)
        folder.rmdir()


def _dead_pid() -> int:
    proc = subprocess.Popen(["true"])
    proc.wait()
    return proc.pid


def test_a_killed_builds_staging_folder_is_swept_and_only_ours(tmp_path, ctx):
    stale = tmp_path / f".site.wgpurender-{_dead_pid()}.build"
    (stale / "live").mkdir(parents=True)
    (stale / "index.html").write_text("half a site")
    alive = tmp_path / f".site.wgpurender-{os.getppid()}.build"  # a build still running (its process lives)
    alive.mkdir()
    users = tmp_path / ".site.mine.build"  # not our pattern
    users.mkdir()
    _build(tmp_path / "site", ctx)
    assert not stale.exists() and alive.is_dir() and users.is_dir()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([alive.name, users.name, "site"])


def test_a_symlinked_site_folder_is_one_line(tmp_path, ctx, monkeypatch):
    monkeypatch.delenv("WGPURENDER_FOLLOW_SYMLINKS", raising=False)
    (tmp_path / "real").mkdir()
    (tmp_path / "site").symlink_to(tmp_path / "real")
    with pytest.raises(UserError) as caught:
        _build(tmp_path / "site", ctx)
    assert "symbolic link" in str(caught.value) and "\n" not in str(caught.value)
    assert os.listdir(tmp_path / "real") == []


def test_a_report_built_before_manifests_is_rebuilt_beside_its_files(tmp_path, ctx):
    from wgpurender.report import page

    site = tmp_path / "site"
    site.mkdir()
    (site / "index.html").write_text(f"<html><head>{page.GENERATOR_MARK}</head></html>")
    (site / "old_step_wgpu.png").write_bytes(b"an old image")
    _build(site, ctx)
    assert (site / "old_step_wgpu.png").read_bytes() == b"an old image"  # unknown owner: kept
    assert "triangle_wgpu.png" in build_manifest(site)
