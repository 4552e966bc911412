"""The credits a scene file needs: those of every file its TOML names (models' paths, materials' maps).

A scene-level question over the files-level credits table (core/files/credits.py), so it lives above both.
API-free.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from wgpurender.core.files.credits import Credit, file_credits
from wgpurender.core.scene.copy import file_references


def scene_credits(scene_file: str | Path) -> list[Credit]:
    """The credits ``scene_file`` needs, each once, in the credits table's order."""
    table = tomllib.loads(Path(scene_file).read_text(encoding="utf-8"))
    return file_credits(written for _, written in file_references(table))
