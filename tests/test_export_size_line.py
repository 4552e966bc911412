"""export's last line says how much it wrote: the page's three files on disk.

It said "0.09 MB of data" for the 3d stage, whose data.js alone is 2.7 MB: the count was the decoded blobs only,
not the recorded frames' calls beside them, so a user checking the folder found 30 times what was announced.
"""

from __future__ import annotations

import re

from wgpurender.cli import main


def test_the_size_said_is_the_size_written(capsys, tmp_path):
    out = tmp_path / "page"
    assert main(["export", "3d", "-o", str(out), "--size", "32x24"]) == 0
    said = re.search(r"([0-9.]+) MB written\)$", capsys.readouterr().out.strip())
    assert said, "the line names the megabytes written"
    on_disk = sum((out / name).stat().st_size for name in ("index.html", "data.js", "player.js"))
    assert abs(float(said.group(1)) - on_disk / 1e6) <= 0.005
