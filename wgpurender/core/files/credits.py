"""Attribution for the files the course shows but did not make (assets/credits.toml, their one home).

The Vulkan tutorial's viking room (model and texture) is CC BY 4.0: wherever it is published (the report's
section of a tutorial scene, an exported page of it, the wheel, README) its title, author, source, licence and
changes go with it. :func:`file_credits` finds the credits of given file names (a scene's: core/scene/credits.py).
API-free.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import PurePath

from wgpurender.core.files.assets import assets_dir

CREDITS_FILE = "credits.toml"


@dataclass(frozen=True)
class Credit:
    files: tuple[str, ...]
    what: str
    title: str
    author: str
    source: str
    license: str
    license_url: str
    changes: str

    def line(self) -> str:
        """The attribution as one line of text (TASL: title, author, source, licence, and the changes)."""
        return (f'"{self.title}" by {self.author} ({self.source}), licensed {self.license} '
                f"({self.license_url}); {self.changes}")


def all_credits() -> list[Credit]:
    table = tomllib.loads((assets_dir() / CREDITS_FILE).read_text(encoding="utf-8"))
    return [Credit(**{**entry, "files": tuple(entry["files"])}) for entry in table.get("credit", [])]


def file_credits(paths) -> list[Credit]:
    """The credits of the files among ``paths`` (matched by file name), each once, in the table's order."""
    names = {PurePath(str(p)).name for p in paths}
    return [c for c in all_credits() if names & set(c.files)]
