"""Input files as the operating system sees them, and bounds on how much work an input may ask for.

Every file the user names (a scene, a model, a texture, an image to compare) goes through :func:`input_file`
before it is opened: a symbolic link loop, a name component over the file system's limit, a directory, a FIFO
(opening it would block), a device or a socket is reported as what it is, in one line, instead of "not found" or
a traceback from ``Path.resolve``/``open``.

The bounds (each can be raised through its environment variable, e.g. for a machine with more memory):

- :data:`MAX_MODEL_BYTES`: a model file (or a glTF buffer file) larger than this is refused before parsing;
- :data:`MAX_IMAGE_PIXELS`: an image whose header declares more pixels is refused before decoding (a 560 KB PNG
  can declare 12000x12000, which took 20 GB to compare);
- :data:`MAX_MODEL_VERTICES`: a glTF whose drawn scene declares more vertices plus indices (each mesh counted once
  per node that places it) is refused from the declared counts, before any accessor is copied;
- :data:`MAX_NESTING`: scene TOML nested deeper is refused (the parser and the checker recurse).
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from wgpurender.core.errors import UserError

MAX_MODEL_BYTES_ENV = "WGPURENDER_MAX_MODEL_BYTES"
MAX_IMAGE_PIXELS_ENV = "WGPURENDER_MAX_IMAGE_PIXELS"
MAX_MODEL_BYTES = 512 * 1024 * 1024  # 512 MiB: a 2 GB sparse OBJ took ~60 s before its error
MAX_IMAGE_PIXELS = 4096 * 4096  # 16.8 Mpx (4K UHD fits): compare with FLIP peaks at ~160 B/px (2.7 GB here)
MAX_MODEL_VERTICES_ENV = "WGPURENDER_MAX_MODEL_VERTICES"
MAX_MODEL_VERTICES = 8_000_000  # vertices + indices a model's scene declares (~250 B each while loading: 2 GB)
MAX_NESTING = 32  # tables/arrays inside each other in a scene file: real scenes use 3


def file_kind(mode: int) -> str | None:
    """What a file of ``mode`` is when it is not a regular file ("a FIFO (named pipe)", ...), else None."""
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return None


def os_error_reason(path: str | os.PathLike, err: OSError) -> str:
    """What an OSError about ``path`` means to a user, with how to fix it."""
    if err.errno == errno.ELOOP:
        return "it is a symbolic link loop (a link that leads back to itself); point the link at a real file"
    if err.errno == errno.ENAMETOOLONG:
        longest = max((len(part.encode("utf-8", "surrogateescape")) for part in Path(path).parts), default=0)
        return (f"the path is too long for the file system (its longest name is {longest} bytes; names may have "
                "at most 255); use a shorter name")
    if err.errno == errno.ENOTDIR:
        return "a part of the path is a file, not a directory"
    if err.errno in (errno.EACCES, errno.EPERM):
        return "permission denied"
    return err.strerror or str(err)


class InputFileError(UserError):
    """An input file that cannot be read; ``missing`` when nothing is at that path (the caller may say where
    it looked)."""

    def __init__(self, message: str, missing: bool = False) -> None:
        super().__init__(message)
        self.missing = missing


def input_file(path: str | os.PathLike, what: str, missing: str | None = None) -> Path:
    """``path`` if it is a readable regular file (after following links); else UserError saying what it is.

    ``what`` names the input in the message ("scene file", "texture", "image", "model file"); ``missing`` is the
    message when nothing is there (default: "WHAT not found: PATH").
    """
    if os.fspath(path) == "":  # Path("") is ".": the message would name a folder nobody gave
        raise InputFileError(f"no {what} given: the path is empty")
    path = Path(path)
    shown = str(path)
    if "\0" in shown:
        raise UserError(f"cannot read {what} {shown!r}: the path contains a NUL character")
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        if os.path.islink(path):
            target = os.readlink(path)
            raise InputFileError(f"{what} {shown} is a symbolic link to {target}, which does not exist") from None
        raise InputFileError(missing or f"{what} not found: {shown}", missing=True) from None
    except OSError as err:
        raise InputFileError(f"cannot read {what} {shown}: {os_error_reason(path, err)}") from None
    kind = file_kind(mode)
    if kind is not None:
        raise InputFileError(f"cannot read {what} {shown}: it is {kind}, not a regular file; give the path of a file")
    return path


def resolved(path: str | os.PathLike) -> Path:
    """``path`` made absolute with links resolved where possible; a loop or an over-long name is left unresolved
    (``Path.resolve`` raises RuntimeError or OSError there), so that :func:`input_file` can say what it is."""
    try:
        return Path(path).resolve()
    except (RuntimeError, OSError):
        return Path(os.path.abspath(path))


class FolderResolver:
    """:func:`resolved` for the many files of a few folders (a scene of 10k mesh files): each folder is resolved
    once, then a file is its resolved folder plus its name, unless that name is itself a link (then resolved
    whole). ``realpath(folder/name) == realpath(realpath(folder)/name)`` for a plain name, so the result is
    :func:`resolved`'s; a result asked for again (the read rule resolves what it is given) is itself. Strings
    inside (pathlib's per-call cost was most of it); one resolver lives as long as one scene file's parse."""

    def __init__(self) -> None:
        self._folders: dict[str, Path] = {}
        self._done: dict[str, Path] = {}
        self._regular: set[str] = set()  # results whose one lstat found a regular file (so no link either)

    def regular(self, path: Path) -> bool:
        """Whether ``path`` (a result of this resolver) was a regular file, not a link, when it was resolved:
        then :func:`input_file` would pass it as it is, and the caller may skip that second stat."""
        return os.fspath(path) in self._regular

    def __call__(self, path: str | os.PathLike) -> Path:
        text = os.fspath(path)
        done = self._done.get(text)
        if done is not None:
            return done
        folder, name = os.path.split(text)
        if name in ("", ".", "..") or not folder:
            result = resolved(text)
            self._done[text] = self._done[os.fspath(result)] = result
            return result
        return self._settle(text, self._real(folder), name)

    def names_in(self, folder: str, values: list) -> list[Path | None]:
        """``self(os.path.join(folder, v))`` for each of ``values`` that is a printable plain name (a string
        without a separator, not "." or ".."), in one loop: the folder resolved once and each name's one lstat,
        without splitting and joining each path again (a scene's 10k model files, issue 31.3); None for any
        other value, which the caller resolves one by one (or refuses)."""
        given, real = os.path.join(folder, ""), self._real(folder)
        out: list[Path | None] = []
        for value in values:
            if type(value) is not str or not value.isprintable() or "/" in value or value in ("", ".", "..") \
                    or os.sep in value or (os.altsep and os.altsep in value):  # Windows: "\\" too (_child's rule)
                out.append(None)
                continue
            text = given + value
            done = self._done.get(text)
            out.append(done if done is not None else self._settle(text, real, value))
        return out

    def _real(self, folder: str) -> Path:
        real = self._folders.get(folder)
        if real is None:
            real = self._folders[folder] = resolved(folder)
        return real

    def _settle(self, text: str, folder: Path, name: str) -> Path:
        """The result for ``text``, whose plain ``name`` lies in its resolved ``folder``: one lstat says whether
        it is a link (then resolved whole) and whether it is a regular file (:meth:`regular`)."""
        candidate = _child(folder, name)
        try:
            mode = os.lstat(candidate).st_mode  # one call: is it a link, and is it a regular file
        except (OSError, ValueError):
            mode = 0  # missing or unreadable: input_file says what it is
        result = resolved(candidate) if stat.S_ISLNK(mode) else candidate
        if stat.S_ISREG(mode):
            self._regular.add(os.fspath(result))
        self._done[text] = self._done[os.fspath(result)] = result
        return result


_MAKE_CHILD = getattr(Path, "_make_child_relpath", None)  # pathlib's own, for a folder's entries (3.11, 3.12)


def _child(folder: Path, name: str) -> Path:
    """``folder / name`` for a plain ``name`` (no separator, not "." or ".."), made as pathlib makes the entries
    of ``iterdir``: the folder's parts are not parsed again for each of a scene's 10k model files (load7's pass in
    docs/benchmarks.md). Where this Python's pathlib has no such maker (3.13), ``/`` makes it. The maker does not
    parse ``name``: one holding a separator of this system (Windows: "\\" as well as "/") would become one part,
    so :meth:`FolderResolver.names_in` leaves such names to the one-by-one resolve."""
    return _MAKE_CHILD(folder, name) if _MAKE_CHILD is not None else folder / name


def file_suffix(text: str) -> str:
    """``Path(text).suffix`` without building a Path (a scene's 10k model paths, each asked several times):
    pathlib's own rule on the last name; a name that normalisation would change ("", ".", a trailing "/.") is
    left to pathlib."""
    name = text.rpartition("/")[2]
    if name in ("", ".", "..") or os.sep != "/" or (os.altsep and os.altsep in name):
        return Path(text).suffix
    at = name.rfind(".")
    return name[at:] if 0 < at < len(name) - 1 else ""


def env_limit(name: str, default: int) -> int:
    """A positive integer bound from the environment variable ``name``, else ``default``."""
    text = os.environ.get(name, "").strip()
    if not text:
        return default
    try:
        value = int(text)
    except ValueError:
        raise UserError(f"${name} must be a whole number, got {text!r}") from None
    if value <= 0:
        raise UserError(f"${name} must be above 0, got {value}")
    return value


def check_file_size(path: Path, what: str) -> None:
    """Refuse a model file larger than :data:`MAX_MODEL_BYTES` before anything reads it."""
    check_size(path, os.stat(path).st_size, what)


def check_size(path: Path, size: int, what: str) -> None:
    """:func:`check_file_size` for a size already known (the open file's fstat: read_jail.read_checked)."""
    limit = env_limit(MAX_MODEL_BYTES_ENV, MAX_MODEL_BYTES)
    if size > limit:
        raise UserError(f"{what} {path} is {size / 2**20:.0f} MiB, over the limit of {limit / 2**20:.0f} MiB; "
                        f"simplify the model, or raise the limit with ${MAX_MODEL_BYTES_ENV}=BYTES")


def check_image_pixels(width: int, height: int, name: str) -> None:
    """Refuse an image whose header declares more than :data:`MAX_IMAGE_PIXELS` pixels, before decoding it."""
    limit = env_limit(MAX_IMAGE_PIXELS_ENV, MAX_IMAGE_PIXELS)
    if width * height > limit:
        raise UserError(f"image {name} declares {width}x{height} pixels ({width * height / 1e6:.0f} Mpx), over the "
                        f"limit of {limit / 1e6:.0f} Mpx; scale it down, or raise the limit with "
                        f"${MAX_IMAGE_PIXELS_ENV}=PIXELS")


def nesting_depth(value: object) -> int:
    """How many tables/arrays sit inside each other in parsed TOML, one level at a time (no recursion to
    overflow); only tables and arrays are carried to the next level (a scene's 10k model tables hold strings)."""
    deepest, level = 0, [value] if isinstance(value, (dict, list)) else []
    while level:
        deepest += 1
        inner = []
        for item in level:
            inner += [child for child in (item.values() if isinstance(item, dict) else item)
                      if isinstance(child, (dict, list))]
        level = inner
    return deepest
