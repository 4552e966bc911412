"""``wgpurender new NAME --from SCENE``: a scene copied into a folder of its own, with the files it reads.

A bundled scene reads ``../models/...`` and ``../textures/...`` relative to ``assets/scenes/``; copied alone, those
paths point nowhere. The copy is ``NAME/NAME.toml`` beside ``NAME/models/`` and ``NAME/textures/``: every model
and map the scene names is copied there and its path in the TOML rewritten (the text is kept, comments included);
an OBJ's material library comes along with the maps it names, rewritten the same way, and a GLB's external
images are copied beside it (a model reads files of its own folder only). API-free.
"""

from __future__ import annotations

import json
import re
import shutil
import tomllib
from collections.abc import Iterator
from pathlib import Path

from wgpurender.core.errors import UserError

MODELS, TEXTURES = "models", "textures"


def file_references(node, key: str = "") -> Iterator[tuple[str, str]]:
    """(folder, written path) for every file the scene's TOML names: models' ``path`` and materials' ``*_map``."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from file_references(v, k)
    elif isinstance(node, list):
        for v in node:
            yield from file_references(v, key)
    elif isinstance(node, str) and key == "path":
        yield MODELS, node
    elif isinstance(node, str) and key.endswith("_map"):
        yield TEXTURES, node


def _replace_string(text: str, old: str, new: str) -> str:
    """``text`` with the TOML string literal ``"old"`` (or ``'old'``) written as ``new``."""
    return re.sub(rf"([\"']){re.escape(old)}\1", lambda m: f"{m.group(1)}{new}{m.group(1)}", text)


def _copy_mtl(obj: Path, dest: Path, folder: Path) -> None:
    """Copy the material libraries ``obj`` names (and the maps they name) beside its copy, paths rewritten."""
    for line in obj.read_text(errors="replace").splitlines():
        if not line.strip().startswith("mtllib"):
            continue
        mtl = obj.parent / line.split(None, 1)[1].strip()
        if not mtl.is_file():
            continue
        lines = []
        for entry in mtl.read_text(errors="replace").splitlines():
            words = entry.split()
            if words and words[0].lower().startswith("map_") and len(words) > 1:
                texture = mtl.parent / words[-1]
                if texture.is_file():
                    (folder / TEXTURES).mkdir(exist_ok=True)
                    shutil.copyfile(texture, folder / TEXTURES / texture.name)
                    entry = entry[: entry.rindex(words[-1])] + f"../{TEXTURES}/{texture.name}"
            lines.append(entry)
        (dest.parent / mtl.name).write_text("\n".join(lines) + "\n")


def _copy_glb(original: Path, dest: Path) -> None:
    """Copy a GLB whose images are files beside it: a model reads only files in its own folder (core/models), so
    each external image is copied next to the copy and its uri rewritten to the bare name (JSON chunk re-padded)."""
    data = original.read_bytes()
    size = int.from_bytes(data[12:16], "little")
    doc = json.loads(data[20:20 + size])
    for image in doc.get("images", []):
        uri = image.get("uri", "")
        if uri and not uri.startswith("data:") and (original.parent / uri).is_file():
            shutil.copyfile(original.parent / uri, dest.parent / Path(uri).name)
            image["uri"] = Path(uri).name
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    rest = data[20 + size:]
    total = 12 + 8 + len(text) + len(rest)
    dest.write_bytes(data[:8] + total.to_bytes(4, "little") + len(text).to_bytes(4, "little") + b"JSON" + text + rest)


def copy_scene(source: Path, folder: Path) -> Path:
    """Copy the scene file ``source`` to ``folder/<folder name>.toml`` with its models and maps; returns the new
    scene file. ``folder`` must not exist yet (nothing is overwritten)."""
    if folder.exists():
        raise UserError(f"{folder} already exists: give a new folder name (nothing was copied)")
    if not folder.parent.is_dir():
        raise UserError(f"cannot create {folder}: folder {folder.parent} does not exist")
    text = source.read_text()
    copies: dict[str, str] = {}
    for kind, written in file_references(tomllib.loads(text)):
        original = source.parent / written
        if not original.is_file():
            raise UserError(f"{source} names {written!r}, which is absent ({original}): cannot copy this scene")
        copies[written] = f"{kind}/{original.name}"
    folder.mkdir()
    for written, new in copies.items():
        original, dest = source.parent / written, folder / new
        dest.parent.mkdir(exist_ok=True)
        if original.suffix.lower() == ".glb":
            _copy_glb(original, dest)
        else:
            shutil.copyfile(original, dest)
        if original.suffix.lower() == ".obj":
            _copy_mtl(original, dest, folder)
        text = _replace_string(text, written, new)
    scene = folder / f"{folder.name}.toml"
    scene.write_text(text)
    return scene
