"""What a model or scene file may read: the one home of the rule (docs/scenes.md, "What a file may read").

A model file is untrusted input, as a web page is to a browser. It reads only what it ships:

- files under the model's own folder, after resolving symbolic links (``textures/a.png``, ``sub/../b.bin``); a
  model shipped in the bundled ``assets/`` may read all of ``assets/`` (the project's own files);
- files under a folder the user allows with ``$WGPURENDER_ALLOW_PATHS`` (the one allow-list, the scenes' too):
  a Blender export ``models/x.obj`` whose MTL names ``../textures/y.png`` loads once ``textures/`` is allowed;
- ``data:`` URIs and the GLB binary chunk (the callers read those without a file).

Refused, in one line naming the URI, before any byte of any file the model names is read: an absolute path, a
URI with a scheme (``file://``, ``http:``, ``C:``), a path that climbs out of the folder (``../``, also
percent-encoded as ``%2e%2e``, or through a link that points out), and a special file (a FIFO, a device, a
socket, a directory) even inside the folder. glTF ``buffers[].uri`` and ``images[].uri``, an OBJ's ``mtllib``
and the texture files its MTL names all go through :func:`model_file`.

A scene file is the user's own, but may be shared as well: the files it names (models, textures) must lie, after
resolving links, under the scene's project folder (its own folder, or the folder above it when that is named
``scenes``, as in the bundled layout), the bundled ``assets/`` folder, or a folder the user allows with
``$WGPURENDER_ALLOW_PATHS`` (folders separated by ``os.pathsep``), see :func:`outside`. The scenes that ship
with the package (``assets/scenes``) are the project's own and may read anything their authors wrote.

The check is of the file actually read: a path is checked (links resolved) before it is opened, so a folder or
file swapped for a link in between would be read unchecked. Every path the rule lets through is canonical (links
resolved) and remembered; :func:`open_checked` opens such a path without following a final link and without
blocking, and refuses the file unless the descriptor it opened is a regular file whose real path
(``/proc/self/fd``) is still the checked path. Readers of model and scene files open through it.
"""

from __future__ import annotations

import errno
import os
import re
import stat
import urllib.parse
from collections.abc import Callable
from pathlib import Path, PureWindowsPath
from typing import BinaryIO, NoReturn

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import file_kind, resolved

ALLOW_ENV = "WGPURENDER_ALLOW_PATHS"
SCENES_FOLDER = "scenes"  # a scene in PROJECT/scenes/ reads PROJECT/models, PROJECT/textures (the bundled layout)
SCHEME = re.compile(r"[A-Za-z][A-Za-z0-9+.\-]*:")  # RFC 3986 scheme (also matches a Windows drive "C:")


def model_file(model: Path, uri: str, where: str, *, base: Path | None = None, encoded: bool = True) -> Path:
    """The file a model's relative ``uri`` names (links resolved), inside the model's folder.

    ``where`` is the JSON path or ``FILE:LINE`` of the reference; ``base`` the folder the name is relative to
    (default the model's: an MTL's textures are relative to the MTL); ``encoded``: percent-encoded, as glTF URIs
    are (RFC 3986: ``%2e%2e`` is ``..``), not as OBJ/MTL names are. Nothing is opened; a missing file is returned
    as is (the reader says "not found"). UserError, naming the URI, for anything outside the folder or special.
    """
    name = urllib.parse.unquote(uri) if encoded else uri
    if not name or any(not ch.isprintable() for ch in name):
        raise UserError(f"malformed model file {model}: {where} {uri!r} is not a usable file name")
    folder = model_folder(model)
    if SCHEME.match(name) or name.startswith(("/", "\\")) or PureWindowsPath(name).is_absolute():
        _refuse(model, uri, where, folder, "is absolute or has a scheme (file://, http:, a drive)")
    target = resolved((base or model.parent) / name)
    if not any(target.is_relative_to(f) for f in (folder, *allowed_by_user())):
        raise UserError(f"model file {model}: {where} {uri!r} leads out of the model's folder {folder} (to "
                        f"{target}); a model reads only files under its own folder: move the file under "
                        f"{folder}, or allow its folder with ${ALLOW_ENV}={target.parent}")
    kind = special_kind(target)
    if kind is not None:
        _refuse(model, uri, where, folder, f"is {kind}, not a regular file")
    return _vouched(target)


def model_folder(model: Path) -> Path:
    """The folder a model may read from: its own, or the whole bundled ``assets/`` for a model shipped there (the
    project's own files: brick_cube.mtl names ../textures)."""
    from wgpurender.core.files.assets import assets_dir

    folder, assets = resolved(model.parent), resolved(assets_dir())
    return assets if folder.is_relative_to(assets) else folder


def _refuse(model: Path, uri: str, where: str, folder: Path, why: str) -> None:
    raise UserError(f"model file {model}: {where} {uri!r} {why}; a model reads only regular files in its own folder "
                    f"{folder}, data: URIs and GLB chunks: copy the file beside the model and name it relatively")


def special_kind(path: Path) -> str | None:
    """What ``path`` is when it exists and is not a regular file (a FIFO would block the reader), else None."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return None  # missing, a loop, too long: the reader's input_file says what it is
    return file_kind(mode)


def allowed_folders(scene: Path) -> list[Path]:
    """The folders a scene file's paths may lead into: its project folder (its own folder, or the one above a
    folder named ``scenes``: the bundled layout scenes/, models/, textures/), the bundled assets, and the folders
    of $WGPURENDER_ALLOW_PATHS."""
    from wgpurender.core.files.assets import assets_dir

    own = resolved(scene.parent)
    project = own.parent if own.name == SCENES_FOLDER else own
    return [project, resolved(assets_dir()), *allowed_by_user()]


def allowed_by_user() -> list[Path]:
    """The folders of $WGPURENDER_ALLOW_PATHS (``os.pathsep``-separated), links resolved: a model's references
    and a scene's paths may lead into them."""
    return [resolved(p) for p in os.environ.get(ALLOW_ENV, "").split(os.pathsep) if p.strip()]


def is_bundled_scene(scene: Path) -> bool:
    from wgpurender.core.files.assets import scene_dir

    return resolved(scene).parent == resolved(scene_dir())


def scene_folders(scene: Path) -> list[Path] | None:
    """The folders :func:`outside` allows for ``scene`` (None: a bundled scene, which may read anything). A
    scene with thousands of model files asks once (resolving them per file was ~0.3 ms of each file's load)."""
    return None if is_bundled_scene(scene) else allowed_folders(scene)


def outside(path: Path, folders: list[Path] | None, resolve: Callable[[Path], Path] = resolved) -> str | None:
    """Why a scene may not read ``path`` (already resolved), or None when it may (see the module docstring);
    ``folders``: what :func:`scene_folders` returned for the scene (None: a bundled scene); ``resolve``: how
    ``path`` is resolved once more (a scene's :class:`~.input_files.FolderResolver` resolves each folder once)."""
    if folders is None:
        return None
    real = resolve(path)
    if any(_within(real, folder) for folder in folders):
        # the scene reads the canonical path: its reader can check it is still this file
        if real == (path if isinstance(path, Path) else Path(path)):
            _vouched(real)
        return None
    return (f"{path} is outside the folders a scene may read ({', '.join(map(str, folders))}); move the file "
            f"under the scene's folder, or allow its folder with ${ALLOW_ENV}=FOLDER")


def inside_all(paths: list[Path], folders: list[Path] | None) -> list[bool] | None:
    """``outside(path, folders) is None`` for each of ``paths`` (canonical: a resolver's own results, regular files
    that are no link), as one pass over string prefixes, each path let through vouched for as :func:`outside`
    does; None where this pass cannot decide (not POSIX): the caller asks :func:`outside` per path."""
    if folders is None:
        return [True] * len(paths)
    if os.name != "posix":
        return None
    tops = [os.fspath(f) for f in folders]
    exact, prefixes = set(tops), tuple(t if t.endswith("/") else t + "/" for t in tops)
    out = []
    for path in paths:
        text = os.fspath(path)
        ok = text in exact or text.startswith(prefixes)
        if ok:
            _CHECKED.add(text)
        out.append(ok)
    return out


def _within(path: Path, folder: Path) -> bool:
    """``path.is_relative_to(folder)`` for resolved paths; on POSIX as a string prefix ending at a separator (the
    same answer for normalised absolute paths, without pathlib's per-call parse: 10k model files a scene)."""
    if os.name != "posix":
        return path.is_relative_to(folder)
    text, top = os.fspath(path), os.fspath(folder)
    return text == top or text.startswith(top if top.endswith("/") else top + "/")


_CHECKED: set[str] = set()  # canonical paths the rule let through: open_checked verifies the file it opens is one
# no final link followed, no FIFO waited on (each 0 where the platform lacks it)
_OPEN_FLAGS = (os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
               | getattr(os, "O_BINARY", 0))


def _vouched(path: Path) -> Path:
    _CHECKED.add(os.fspath(path))
    return path


def open_checked(path: str | os.PathLike) -> BinaryIO:
    """``path`` opened for reading (binary). When the rule let it through (:func:`model_file`, :func:`outside`),
    the file opened is the file checked: no final link followed (O_NOFOLLOW), no FIFO waited on (O_NONBLOCK), a
    regular file, whose real path is the checked one; else UserError naming both. Other paths open as usual."""
    name = os.fspath(path)
    if name not in _CHECKED:
        return open(name, "rb")
    try:
        fd = os.open(name, _OPEN_FLAGS)
    except OSError as err:
        if err.errno != errno.ELOOP:
            raise
        _changed(name, "is now a symbolic link")
    try:
        info = os.fstat(fd)
        kind = file_kind(info.st_mode) if not stat.S_ISREG(info.st_mode) else None
        if kind is not None:
            _changed(name, f"is now {kind}")
        real = _real_path(fd, info, name)
        if real != name:
            _changed(name, f"now leads to {real}")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_checked(path: str | os.PathLike, size_check: Callable[[int], None] | None = None) -> bytes:
    """All of ``path``'s bytes, through :func:`open_checked`; ``size_check(size)`` first, on the open file's size
    (a model's limit without a stat of its own: input_files.check_size)."""
    with open_checked(path) as f:
        if size_check is not None:
            size_check(os.fstat(f.fileno()).st_size)
        return f.read()


def is_checked(path: str | os.PathLike) -> bool:
    """Whether the rule let ``path`` through, so :func:`open_checked` verifies the file it opens (a regular file,
    no link, the checked path): a worker reading it needs no stat of its own first."""
    return os.fspath(path) in _CHECKED


def _real_path(fd: int, info: os.stat_result, name: str) -> str:
    """Where the open descriptor leads: its /proc/self/fd link; without /proc, ``name`` if it is still the same
    file (device and inode) as the one opened."""
    try:
        return os.readlink(f"/proc/self/fd/{fd}")
    except OSError:
        now = os.stat(name)
        return name if (now.st_dev, now.st_ino) == (info.st_dev, info.st_ino) else "another file"


def _changed(name: str, now: str) -> NoReturn:
    raise UserError(f"{name} changed between its check and its read: it {now}; a model or scene reads only "
                    "the files checked (no links swapped in while it loads): load it again from a folder nobody "
                    "else writes to")
