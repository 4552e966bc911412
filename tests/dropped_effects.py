"""A repository scene with one ``[[post]]`` entry left out, written as a scene file (issue 32, item 6): what the
browser page records when an effect is dropped. The scene's own text is kept (a line-level cut of the one block),
its relative asset paths made absolute so the copy loads from any folder."""

from __future__ import annotations

from pathlib import Path

from wgpurender.implementations import SCENE_DIR


def post_blocks(text: str) -> list[tuple[int, int]]:
    """(first line, end line) of each ``[[post]]`` table: from its header to the next table header."""
    lines = text.splitlines()
    heads = [i for i, line in enumerate(lines) if line.lstrip().startswith("[")]
    return [(i, next((j for j in heads if j > i), len(lines))) for i in heads
            if lines[i].split("#")[0].strip() == "[[post]]"]


def without_post(scene: Path, k: int, out: Path) -> Path:
    """Write ``scene`` with its ``k``-th post entry cut out to ``out`` (a new file) and return it."""
    text = scene.read_text()
    start, end = post_blocks(text)[k]
    lines = text.splitlines()
    kept = "\n".join(lines[:start] + lines[end:]) + "\n"
    assets = SCENE_DIR.parent.resolve()
    out.write_text(kept.replace('"../', f'"{assets.as_posix()}/'))
    return out
