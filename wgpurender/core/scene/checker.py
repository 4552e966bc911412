"""Type and value checks of TOML values that fail with ``FILE:LINE: what, and what is valid``."""

from __future__ import annotations

import functools
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.files.input_files import FolderResolver, InputFileError, input_file
from wgpurender.core.scene.toml_locator import KeyLines, KeyPath, format_path

FLOAT32_MAX = float(np.finfo(np.float32).max)


def _type_name(value: Any) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array",
            dict: "a table"}.get(type(value), type(value).__name__)


class Checker:
    """Type and value checks that fail with FILE:LINE messages."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.folder = path.parent
        self.text = text

    @functools.cached_property
    def keys(self) -> KeyLines:
        """Each key's line, indexed only when a message needs one (a scene of 10k models is checked without)."""
        return KeyLines(self.text)

    def error(self, key: KeyPath, message: str) -> UserError:
        line = self.keys.line_of(key)
        where = f"{self.path}:{line}" if line else f"{self.path}"
        return UserError(f"{where}: {message}")

    def table(self, value: Any, key: KeyPath, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> dict:
        if not isinstance(value, dict):
            raise self.error(key, f"{format_path(key) or 'the top level'} must be a table, got {_type_name(value)}")
        for k in value:
            if k not in allowed:
                raise self.error(key + (k,), f"unknown key '{k}' in {format_path(key) or 'the top level'}: valid "
                                             f"keys are {', '.join(allowed)}")
        for k in required:
            if k not in value:
                raise self.error(key, f"{format_path(key) or 'the top level'} needs '{k}'")
        return value  # the key's name is formatted only for a message (twice per model of a 10k-model scene)

    def number(self, value: Any, key: KeyPath, lo: float = -math.inf, hi: float = math.inf,
               open_lo: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(key, f"{format_path(key)} must be a number, got {_type_name(value)} {value!r}")
        if abs(value) > FLOAT32_MAX:
            raise self.error(key, f"{format_path(key)} = {value:g} is beyond float32's range (+-{FLOAT32_MAX:.4g}), "
                                  "the type the GPU gets; use a smaller number")
        if value < lo or value > hi or (open_lo and value == lo):
            low = f"> {lo}" if open_lo else f">= {lo}"
            bounds = low if hi == math.inf else f"in [{lo}, {hi}]"
            raise self.error(key, f"{format_path(key)} must be {bounds}, got {value}")
        return float(value)

    def integer(self, value: Any, key: KeyPath, choices: tuple[int, ...] | None = None,
                lo: int | None = None, hi: int | None = None) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, f"{format_path(key)} must be an integer, got {_type_name(value)} {value!r}")
        if choices is not None and value not in choices:
            raise self.error(key, f"{format_path(key)} must be one of {', '.join(map(str, choices))}, got {value}")
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            raise self.error(key, f"{format_path(key)} must be in {lo}..{hi}, got {value}")
        return value

    def boolean(self, value: Any, key: KeyPath) -> bool:
        if not isinstance(value, bool):
            raise self.error(key, f"{format_path(key)} must be true or false, got {_type_name(value)} {value!r}")
        return value

    def string(self, value: Any, key: KeyPath, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(value, str):
            raise self.error(key, f"{format_path(key)} must be a string, got {_type_name(value)} {value!r}")
        if choices is not None and value not in choices:
            raise self.error(key, f"{format_path(key)} must be one of {', '.join(choices)}, got {value!r}")
        return value

    def vector(self, value: Any, key: KeyPath, lengths: tuple[int, ...] = (3,), nonzero: bool = False) -> tuple:
        want = " or ".join(map(str, lengths))
        if not isinstance(value, list) or len(value) not in lengths:
            raise self.error(key, f"{format_path(key)} must be an array of {want} numbers, got {value!r}")
        out = tuple(self.number(v, key) for v in value)
        if nonzero and not any(out):
            raise self.error(key, f"{format_path(key)} must not be all zeros")
        return out

    def file(self, value: Any, key: KeyPath, what: str) -> Path:
        written = self.string(value, key)
        if not written.isprintable():  # some character is not
            raise self.error(key, f"{format_path(key)}: {what} path {written!r} contains a control character "
                                  "(NUL, newline, ...): give a plain file path")
        resolve = self._resolver()
        path = resolve(os.path.join(self.folder, written))  # the resolver normalises (Path.resolve)
        try:  # a stat only (none when the resolver's lstat found a regular file): what is missing or special is named
            found = path if resolve.regular(path) else input_file(path, what)
        except InputFileError as err:
            if not err.missing:
                raise self.error(key, f"{format_path(key)}: {err}") from None
        else:
            refused = read_jail.outside(found, self._jail_folders(), resolve)
            if refused is not None:
                raise self.error(key, f"{format_path(key)}: {what} '{written}': {refused}")
            return found
        raise self.error(
            key,
            f"{format_path(key)}: {what} '{written}' not found (looked for {path}; "
            f"paths are relative to the scene file's folder {self.folder}){_anchors_hint(written)}",
        )


    def files_ahead(self, values: list) -> list[Path | None]:
        """What :meth:`file` returns for each of ``values``, in ONE pass, where that is the plain case: a printable
        string naming a regular file (no link) that the read rule lets through, vouched for as :meth:`file` does;
        None for anything else, which :meth:`file` then checks and names in its one line (or returns) as before.
        A scene's 10k model paths: one loop, the rule's folders compared as strings (issue 31.3)."""
        resolve, folder = self._resolver(), os.fspath(self.folder)
        paths = resolve.names_in(folder, values)  # plain names in one loop; a path with folders one by one
        paths = [resolve(os.path.join(folder, v)) if p is None and type(v) is str and v.isprintable() else p
                 for p, v in zip(paths, values, strict=True)]
        plain = [p if p is not None and resolve.regular(p) else None for p in paths]
        inside = read_jail.inside_all([p for p in plain if p is not None], self._jail_folders())
        if inside is None:  # not decidable in one pass here: file() checks each
            return [None] * len(values)
        allowed = iter(inside)
        return [p if p is not None and next(allowed) else None for p in plain]

    def _resolver(self) -> FolderResolver:
        if not hasattr(self, "_resolve"):
            self._resolve = FolderResolver()  # each folder resolved once per scene, not once per file
        return self._resolve

    def _jail_folders(self) -> list[Path] | None:
        if not hasattr(self, "_jail"):
            self._jail = read_jail.scene_folders(self.path)  # once per scene, not per file
        return self._jail


def _anchors_hint(written: str) -> str:
    """Why a tutorial scene's file is missing: it lives in ../shared/anchors, which is neither in the repository
    nor in the wheel (the C++ tutorial's own model and texture), so a lone clone or the wheel cannot draw it."""
    if "shared/anchors/" not in written.replace("\\", "/"):
        return ""
    return ("; this scene reads the Vulkan tutorial's own files from ../shared/anchors beside the repository, "
            "which wgpurender does not ship: render it from a checkout that has that folder")
