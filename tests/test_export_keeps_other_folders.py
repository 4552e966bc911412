"""export owns only the files it wrote in its folder (issue 28.3, 28.4).

``wgpurender export triangle -o out/report`` overwrote the course report's index.html with the triangle's page
(exit 0); later it refused any folder holding more than its three files, and wrote through a symlinked
``index.html`` / ``data.js`` / ``player.js`` (or into a dangling symlinked folder), not atomically. Now the folder
carries a manifest (core/files/owned_files.py): an earlier export is replaced, the user's files beside it are kept
byte for byte, a folder of other files without a manifest is refused unless ``--force`` (which writes beside
them and deletes nothing), and symlinks are refused as ``render`` refuses them.
"""

from __future__ import annotations

import json
import os

import pytest

from wgpurender.cli import main
from wgpurender.core.files.owned_files import MANIFEST

EXPORT_FILES = {"index.html", "data.js", "player.js"}
ARGS = ["--size", "32x24"]


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_a_folder_of_other_files_is_refused(capsys, tmp_path):
    site = tmp_path / "site"
    site.mkdir()
    (site / "index.html").write_text("<p>my page</p>")
    (site / "photo.png").write_bytes(b"x")
    assert main(["export", "triangle", "-o", str(site), *ARGS]) == 2
    assert str(site) in _one_line(capsys)
    assert (site / "index.html").read_text() == "<p>my page</p>"
    assert {p.name for p in site.iterdir()} == {"index.html", "photo.png"}


def test_a_lone_foreign_index_is_refused(capsys, tmp_path):
    (tmp_path / "index.html").write_text("mine")
    assert main(["export", "triangle", "-o", str(tmp_path), *ARGS]) == 2
    assert (tmp_path / "index.html").read_text() == "mine"


def test_an_earlier_export_is_replaced_and_the_users_files_beside_it_kept(capsys, tmp_path):
    out = tmp_path / "e"
    out.mkdir()
    assert main(["export", "triangle", "-o", str(out), *ARGS]) == 0
    assert {p.name for p in out.iterdir()} == EXPORT_FILES | {MANIFEST}
    assert set(json.loads((out / MANIFEST).read_text())["files"]) == EXPORT_FILES
    (out / "notes.txt").write_bytes(b"my notes\x00\xff")
    (out / "img").mkdir()
    (out / "img" / "mine.png").write_bytes(b"\x89PNG mine")
    assert main(["export", "clear-pass", "-o", str(out), *ARGS]) == 0
    assert "clear-pass" in (out / "index.html").read_text()
    assert (out / "notes.txt").read_bytes() == b"my notes\x00\xff"
    assert (out / "img" / "mine.png").read_bytes() == b"\x89PNG mine"
    assert not [p for p in out.iterdir() if p.name.endswith((".tmp", ".build"))]


def test_force_writes_beside_the_users_files_and_deletes_none(capsys, tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    assert main(["export", "triangle", "-o", str(tmp_path), *ARGS, "--force"]) == 0
    assert (tmp_path / "notes.txt").read_text() == "mine"
    assert set(json.loads((tmp_path / MANIFEST).read_text())["files"]) == EXPORT_FILES  # notes.txt is not ours
    assert main(["export", "clear-pass", "-o", str(tmp_path), *ARGS]) == 0  # the manifest makes it ours now
    assert (tmp_path / "notes.txt").read_text() == "mine"


@pytest.mark.parametrize("name", sorted(EXPORT_FILES))
def test_a_symlinked_page_file_is_refused_and_its_target_untouched(capsys, tmp_path, monkeypatch, name):
    monkeypatch.delenv("WGPURENDER_FOLLOW_SYMLINKS", raising=False)
    out = tmp_path / "e"
    assert main(["export", "triangle", "-o", str(out), *ARGS]) == 0
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    (out / name).unlink()
    (out / name).symlink_to(victim)
    assert main(["export", "triangle", "-o", str(out), *ARGS]) == 2
    assert "symbolic link" in _one_line(capsys)
    assert victim.read_text() == "keep me" and (out / name).is_symlink()


def test_a_dangling_symlinked_folder_is_refused_even_when_links_are_followed(capsys, tmp_path, monkeypatch):
    link = tmp_path / "page"
    link.symlink_to(tmp_path / "nowhere")
    for follow in ("0", "1"):
        monkeypatch.setenv("WGPURENDER_FOLLOW_SYMLINKS", follow)
        assert main(["export", "triangle", "-o", str(link), *ARGS]) == 2
        assert "symbolic link" in _one_line(capsys)
        assert not (tmp_path / "nowhere").exists()


def test_a_symlinked_folder_is_written_only_when_asked(capsys, tmp_path, monkeypatch):
    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "page"
    link.symlink_to(real)
    monkeypatch.delenv("WGPURENDER_FOLLOW_SYMLINKS", raising=False)
    assert main(["export", "triangle", "-o", str(link), *ARGS]) == 2
    assert "symbolic link" in _one_line(capsys) and not os.listdir(real)
    monkeypatch.setenv("WGPURENDER_FOLLOW_SYMLINKS", "1")
    assert main(["export", "triangle", "-o", str(link), *ARGS]) == 0
    assert {p.name for p in real.iterdir()} == EXPORT_FILES | {MANIFEST}


def test_a_manifest_entry_outside_the_folder_is_never_deleted(capsys, tmp_path):
    """The manifest is input too: entries that climb out, are absolute or pass a symlink are ignored."""
    out = tmp_path / "e"
    assert main(["export", "triangle", "-o", str(out), *ARGS]) == 0
    outside = tmp_path / "outside.txt"
    outside.write_text("keep")
    (out / "lnk").symlink_to(tmp_path)
    data = json.loads((out / MANIFEST).read_text())
    data["files"] += ["../outside.txt", str(outside), "lnk/outside.txt", "./../outside.txt"]
    (out / MANIFEST).write_text(json.dumps(data))
    assert main(["export", "clear-pass", "-o", str(out), *ARGS]) == 0
    assert outside.read_text() == "keep"


def test_an_export_killed_mid_write_leaves_the_earlier_page_whole(tmp_path):
    """Each file goes through a temp file + rename: SIGKILL while ``data.js`` is being written leaves the earlier
    export's files byte for byte (and one named temp file, which the next export removes)."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "e"
    assert main(["export", "triangle", "-o", str(out), *ARGS]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    env = {**os.environ, "WGPURENDER_TEST_WRITE_DELAY": "60"}
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", "export", "clear-pass", "-o", str(out), *ARGS],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while not [p for p in out.iterdir() if p.name.startswith(".data.js.")]:
        assert proc.poll() is None, proc.stderr.read().decode()
        assert time.monotonic() < deadline, "the temp file never appeared"
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    after = {p.name: p.read_bytes() for p in out.iterdir() if not p.name.endswith(".tmp")}
    assert after == before  # the manifest lists the same three files: nothing new was claimed
    assert main(["export", "clear-pass", "-o", str(out), *ARGS]) == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(EXPORT_FILES | {MANIFEST})
