"""export writes only into a new folder, an empty one, or one holding an earlier export.

``wgpurender export triangle -o out/report`` overwrote the course report's index.html with the triangle's page
(exit 0): export wrote index.html, data.js and player.js into any folder. report -o already refuses a
non-empty folder that holds no earlier report; export now does the same for its three files.
"""

from __future__ import annotations

from wgpurender.cli import main

EXPORT_FILES = {"index.html", "data.js", "player.js"}


def test_a_folder_of_other_files_is_refused(capsys, tmp_path):
    site = tmp_path / "site"
    site.mkdir()
    (site / "index.html").write_text("<p>my page</p>")
    (site / "photo.png").write_bytes(b"x")
    assert main(["export", "triangle", "-o", str(site), "--size", "32x24"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(site) in err[0]
    assert (site / "index.html").read_text() == "<p>my page</p>"
    assert {p.name for p in site.iterdir()} == {"index.html", "photo.png"}


def test_a_lone_foreign_index_is_refused(capsys, tmp_path):
    (tmp_path / "index.html").write_text("mine")
    assert main(["export", "triangle", "-o", str(tmp_path), "--size", "32x24"]) == 2
    assert (tmp_path / "index.html").read_text() == "mine"


def test_an_earlier_export_and_an_empty_folder_are_written(capsys, tmp_path):
    out = tmp_path / "e"
    out.mkdir()
    assert main(["export", "triangle", "-o", str(out), "--size", "32x24"]) == 0
    assert {p.name for p in out.iterdir()} == EXPORT_FILES
    assert main(["export", "clear-pass", "-o", str(out), "--size", "32x24"]) == 0
    assert "clear-pass" in (out / "index.html").read_text()
