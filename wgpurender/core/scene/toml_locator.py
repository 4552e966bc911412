"""Where a key sits in a TOML text: tomllib gives no line numbers for values, so :class:`KeyLines` finds them
by scanning the text for table headers and keys. Scene errors use it to say ``FILE:LINE``."""

from __future__ import annotations

import re

KeyPath = tuple  # of str (table keys) and int (array indices)

_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\[\]]+?)\s*\]\]?\s*$")
_KEY = re.compile(r"^\s*((?:[A-Za-z0-9_-]+|\"[^\"]*\"|'[^']*')(?:\s*\.\s*(?:[A-Za-z0-9_-]+|\"[^\"]*\"|'[^']*'))*)\s*=")
_INLINE_KEY = re.compile(r"([A-Za-z0-9_-]+|\"[^\"]*\")\s*=")


def _split_dotted(name: str) -> tuple[str, ...]:
    return tuple(part.strip().strip("\"'") for part in re.findall(r"\"[^\"]*\"|'[^']*'|[^.]+", name))


def _strip_comment(line: str) -> str:
    """The line without a trailing # comment (a # inside a string stays)."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:i]
    return line


def _bracket_depth(text: str) -> int:
    """Open [ and { minus closed ones, outside strings."""
    depth, quote = 0, None
    for ch in text:
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
    return depth


class KeyLines:
    """Maps key paths such as ``("models", 1, "transform", "rotate")`` to 1-based line numbers.

    Handles [table] and [[array]] headers (with dotted names), dotted keys, and keys
    inside one-line inline tables; values spanning lines (arrays) are skipped over.
    A path it cannot place falls back to its nearest known parent.
    """

    def __init__(self, text: str) -> None:
        self.lines: dict[KeyPath, int] = {}
        self._counts: dict[KeyPath, int] = {}
        table: KeyPath = ()
        depth = 0
        for number, raw in enumerate(text.splitlines(), start=1):
            line = _strip_comment(raw)
            if depth > 0:  # inside a value that spans lines
                depth += _bracket_depth(line)
                continue
            header = _HEADER.match(line)
            if header and not _KEY.match(line):
                table = self._header(header.group(1) == "[[", _split_dotted(header.group(2)), number)
                continue
            key = _KEY.match(line)
            if key:
                path = table + _split_dotted(key.group(1))
                self.lines.setdefault(path, number)
                rest = line[key.end() :]
                self._inline(path, rest, number)
                depth = _bracket_depth(rest)

    def _resolve(self, names: tuple[str, ...]) -> KeyPath:
        path: KeyPath = ()
        for name in names:
            path += (name,)
            if path in self._counts:
                path += (self._counts[path] - 1,)
        return path

    def _header(self, is_array: bool, names: tuple[str, ...], number: int) -> KeyPath:
        parent = self._resolve(names[:-1])
        path = parent + (names[-1],)
        if is_array:
            index = self._counts.get(path, 0)
            self._counts[path] = index + 1
            self.lines.setdefault(path, number)
            path += (index,)
        self.lines.setdefault(path, number)
        return path

    def _inline(self, path: KeyPath, rest: str, number: int) -> None:
        """Keys of inline tables on this line: ``material = { unlit = true, sampler = { filter = ... } }``."""
        stack: list[KeyPath] = []
        last_key: KeyPath | None = None
        i, quote = 0, None
        while i < len(rest):
            ch = rest[i]
            if quote:
                quote = None if ch == quote else quote
            elif ch in "\"'" and not _INLINE_KEY.match(rest, i):
                quote = ch
            elif ch == "{":
                stack.append(last_key if (stack and last_key) else path)
            elif ch == "}":
                if stack:
                    stack.pop()
            elif stack:
                m = _INLINE_KEY.match(rest, i)
                if m and (i == 0 or not (rest[i - 1].isalnum() or rest[i - 1] in "_-")):
                    last_key = stack[-1] + (m.group(1).strip("\""),)
                    self.lines.setdefault(last_key, number)
                    i = m.end()
                    continue
            i += 1

    def line_of(self, path: KeyPath) -> int | None:
        path = tuple(path)
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path[:-1]
        return None


def format_path(path: KeyPath) -> str:
    """``("models", 0, "transform")`` -> ``models[0].transform``."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out
