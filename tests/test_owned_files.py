"""core/files/owned_files.py on its own (issue 28.4): the rules every writer (report, export, record) gets from it,
checked on folders built here, without a GPU."""

from __future__ import annotations

import json

import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.files.owned_files import MANIFEST, OwnedFolder, install, read_manifest, staging


def _listed(folder) -> list[str]:
    return json.loads((folder / MANIFEST).read_text())["files"]


def test_files_are_listed_before_they_are_written(tmp_path):
    out = OwnedFolder(tmp_path / "out", "test")
    out.claim(["a.txt", "sub/b.txt"])
    assert sorted(_listed(tmp_path / "out")) == ["a.txt", "sub/b.txt"]  # a kill now leaves nothing unlisted
    out.write("a.txt", b"A")
    out.write("sub/b.txt", b"B")
    out.finish()
    assert (tmp_path / "out" / "sub" / "b.txt").read_bytes() == b"B"


def test_a_rebuild_removes_only_what_the_last_one_wrote_and_empty_folders_it_made(tmp_path):
    first = OwnedFolder(tmp_path, "test")
    for rel in ("keep.txt", "old/gone.txt", "old/deeper/gone.txt"):
        first.write(rel, b"x")
    first.finish()
    (tmp_path / "mine.txt").write_text("user")
    second = OwnedFolder(tmp_path, "test")
    second.write("keep.txt", b"y")
    assert second.finish() == ["old/deeper/gone.txt", "old/gone.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([MANIFEST, "keep.txt", "mine.txt"])
    assert _listed(tmp_path) == ["keep.txt"]


def test_a_symlinked_folder_inside_is_not_written_through(tmp_path, monkeypatch):
    monkeypatch.delenv("WGPURENDER_FOLLOW_SYMLINKS", raising=False)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    (out / "img").symlink_to(elsewhere)
    folder = OwnedFolder(out, "test", force=True)
    with pytest.raises(UserError) as caught:
        folder.write("img/x.png", b"x")
    assert "symbolic link" in str(caught.value) and list(elsewhere.iterdir()) == []


def test_install_checks_every_name_before_writing_any(tmp_path):
    out = tmp_path / "site"
    out.mkdir()
    (out / MANIFEST).write_text(json.dumps({"files": []}))
    (out / "z.html").write_text("the user's")
    folder = OwnedFolder(out, "test")
    with staging(folder) as built:
        (built / "a.html").write_text("ours")
        (built / "z.html").write_text("ours")
        with pytest.raises(UserError) as caught:
            install(folder, built)
    assert "z.html exists and was not written by wgpurender" in str(caught.value)
    assert not (out / "a.html").exists() and (out / "z.html").read_text() == "the user's"
    assert [p.name for p in tmp_path.iterdir()] == ["site"]  # the staging folder is gone


@pytest.mark.parametrize("text, files", [
    ('{"files": ["a", "../b", "/c", "d/../e", "", 5, "f\\\\g", ".wgpurender-manifest.json", "h/i"]}', {"a", "h/i"}),
    ("[1]", None), ('{"files": "a"}', None), ("not json", None),
])
def test_manifest_entries_that_could_leave_the_folder_are_dropped(tmp_path, text, files):
    (tmp_path / MANIFEST).write_text(text)
    assert read_manifest(tmp_path) == files


def test_a_file_in_place_of_the_folder_is_one_line(tmp_path):
    (tmp_path / "out").write_text("x")
    with pytest.raises(UserError) as caught:
        OwnedFolder(tmp_path / "out", "test")
    assert "not a folder" in str(caught.value)
    with pytest.raises(UserError) as caught:
        OwnedFolder(tmp_path / "no" / "out", "test")
    assert "does not exist" in str(caught.value)


@pytest.mark.skipif(not __import__("os").path.isdir("/proc/self"), reason="needs Linux's /proc (no file can be made)")
def test_an_unwritable_parent_is_refused_naming_the_path_given():
    given = "/proc/wgpurender-out"  # the newcomer's `report -o /proc/x` named /proc alone
    with pytest.raises(UserError) as err:
        OwnedFolder(given, "test", flag="cannot write the report to")
    assert str(err.value).startswith(f"cannot write the report to {given}: ")
    assert "/proc" in str(err.value).split(": ", 1)[1]  # and the folder it could not write in
