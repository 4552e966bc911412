"""Output folders shared with the user: report, export and record own only the files they wrote.

A folder the user points a writer at may hold their own work. The writer keeps a manifest there,
``.wgpurender-manifest.json``, listing (relative paths) every file it wrote; a rebuild replaces those and removes
the ones it no longer writes, and never touches any other file. The rules (docs/security.md):

- a new or empty folder is written; a non-empty folder without a manifest is refused (one line) unless
  ``force``: then the writer writes beside the user's files, replacing only files of the names it writes
  (``--force`` means "these names may be replaced"), and never deletes a file it did not list;
- with a manifest, a file the writer is about to write that exists but is not listed is the user's: refused
  unless ``force``;
- a symlinked folder (or a symlink inside it on the way to a file) is refused unless
  ``$WGPURENDER_FOLLOW_SYMLINKS=1``; a dangling one is refused either way;
- the manifest is itself untrusted: an entry that is absolute, climbs out (``..``) or passes a symlink is
  ignored, and only regular files are ever removed;
- every file is written by temp file + rename (safe_write.atomic_write), and a file is added to the manifest
  on disk before it is written, so a killed run leaves only files the next run owns.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import stat
from collections.abc import Iterator
from pathlib import Path, PurePosixPath

from wgpurender.core.errors import UserError
from wgpurender.core.files.safe_write import FOLLOW_SYMLINKS_ENV, atomic_write, follow_symlinks, sweep_stale

MANIFEST = ".wgpurender-manifest.json"


def _clean_entry(entry: object) -> str | None:
    """A manifest entry as a safe relative POSIX path, or None (absolute, ``..``, empty, the manifest)."""
    if not isinstance(entry, str) or not entry or "\0" in entry or "\\" in entry:
        return None
    path = PurePosixPath(entry)
    if path.is_absolute() or any(part in ("", ".", "..") for part in path.parts) or str(path) == MANIFEST:
        return None
    return str(path)


def read_manifest(folder: Path) -> set[str] | None:
    """The files the manifest in ``folder`` lists (unsafe entries dropped); None when there is none."""
    path = folder / MANIFEST
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return None
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list):
        return None
    return {clean for clean in map(_clean_entry, files) if clean is not None}


def resolve_folder(folder: Path, flag: str) -> Path:
    """The folder to write: a symlink only when asked (and never a dangling one), never a file. Every writer's
    rule for its output folder (OwnedFolder's, and ``wgpurender exercise``'s)."""
    try:
        mode = os.lstat(folder).st_mode
    except FileNotFoundError:
        return folder
    except OSError as err:
        raise UserError(f"{flag} {folder}: {err.strerror or err}") from None
    if stat.S_ISLNK(mode):
        if not follow_symlinks():
            raise UserError(f"{flag} {folder}: refusing to write into a symbolic link (to {os.readlink(folder)}); "
                            f"give the real folder, or set {FOLLOW_SYMLINKS_ENV}=1")
        target = Path(os.path.realpath(folder))
        if not target.is_dir():
            raise UserError(f"{flag} {folder}: the symbolic link leads to {target}, which is not a folder")
        return target
    if not stat.S_ISDIR(mode):
        raise UserError(f"{flag} {folder}: exists and is not a folder; give a folder")
    return folder


class OwnedFolder:
    """The output folder of one writer run: checked when made, before any work (see the module doc)."""

    def __init__(self, folder: str | os.PathLike, writer: str, force: bool = False, flag: str = "-o") -> None:
        self.flag, self.writer, self.force = flag, writer, bool(force)
        self.folder = resolve_folder(Path(folder), flag)
        self.owned: set[str] = set()  # listed by the earlier run
        self.written: list[str] = []  # by this run, in order
        self._listed: set[str] = set()  # what the manifest on disk lists now
        if self.folder.is_dir():
            self._check_existing()
        elif not self.folder.parent.is_dir():
            raise UserError(f"{flag} {self.folder}: folder {self.folder.parent} does not exist (create it first)")
        probe_writable(self.folder if self.folder.is_dir() else self.folder.parent, flag, named=self.folder)

    def _check_existing(self) -> None:
        listed = read_manifest(self.folder)
        if listed is None:
            others = [p.name for p in self.folder.iterdir()]
            if others and not self.force:
                raise UserError(f"{self.flag} {self.folder}: the folder is not empty and holds no earlier "
                                f"wgpurender output ({MANIFEST}); give a new or empty folder, or --force "
                                "(force=True) to write beside its files (never deleting them)")
            listed = set()
        self.owned = set(listed)
        self._listed = set(listed)

    def path(self, rel: str) -> Path:
        """Where ``rel`` goes: inside the folder, through no symlink (unless asked); parents made."""
        clean = _clean_entry(rel)
        if clean is None:
            raise ValueError(f"not a relative output path: {rel!r}")  # a bug of the writer, not of the user
        target = self.folder
        for part in PurePosixPath(clean).parts[:-1]:
            target = target / part
            if target.is_symlink() and not follow_symlinks():
                raise UserError(f"{self.flag} {self.folder}: refusing to write through the symbolic link {target}")
            try:
                target.mkdir(exist_ok=True)
            except OSError as err:
                raise UserError(f"{self.flag} {target}: cannot create it ({err.strerror or err})") from None
        return target / PurePosixPath(clean).name

    def check_names(self, names) -> None:
        """Refuse (unless ``force``) when a file to be written exists and is the user's (not listed)."""
        for rel in names:
            if rel not in self.owned and os.path.lexists(self.folder / rel) and not self.force:
                raise UserError(f"{self.flag} {self.folder}: {rel} exists and was not written by wgpurender; move "
                                "it, or pass --force (force=True) to replace it")

    def claim(self, names) -> None:
        """List ``names`` in the manifest on disk before they are written (a killed run leaves no stranger)."""
        new = set(names) - self._listed
        if new:
            self.folder.mkdir(exist_ok=True)
            self._listed |= new
            self._save(self._listed)

    def write(self, rel: str, data: bytes) -> Path:
        self.check_names([rel])
        self.claim([rel])
        path = atomic_write(self.path(rel), data)
        if rel not in self.written:
            self.written.append(rel)
        return path

    def finish(self) -> list[str]:
        """Remove what the earlier run wrote and this one did not, then list only this run's files."""
        self.folder.mkdir(exist_ok=True)
        stale = sorted(self.owned - set(self.written))
        removed = [rel for rel in stale if _remove_owned(self.folder, rel)]
        self._listed = set(self.written)
        self._save(self._listed)
        return removed

    def _save(self, files: set[str]) -> None:
        data = {"wgpurender": 1, "writer": self.writer, "files": sorted(files)}
        atomic_write(self.folder / MANIFEST, (json.dumps(data, indent=1) + "\n").encode())


def _remove_owned(folder: Path, rel: str) -> bool:
    """Unlink ``folder/rel`` if it is a regular file reached through no symlink; drop folders it left empty."""
    parts = PurePosixPath(rel).parts
    here = folder
    for part in parts[:-1]:
        here = here / part
        if here.is_symlink() or not here.is_dir():
            return False
    path = here / parts[-1]
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return False
        path.unlink()
    except OSError:
        return False
    for depth in range(len(parts) - 1, 0, -1):
        try:
            folder.joinpath(*parts[:depth]).rmdir()  # only when empty
        except OSError:
            break
    return True


def probe_writable(folder: Path, flag: str, named: Path | None = None) -> None:
    """Create and remove a file in ``folder``: a read-only mount refuses root too, where os.access says yes.
    ``named``: the path the user gave when ``folder`` is its parent (the refusal names both)."""
    probe = folder / f".probe.wgpurender-{os.getpid()}.tmp"  # safe_write.sweep_stale's pattern
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        where = f"{folder}: cannot write there"
        if named is not None and named != folder:
            where = f"{named}: cannot write in {folder}"
        raise UserError(f"{flag} {where} ({err.strerror or err})") from None


_BUILD = re.compile(r"^\..+\.wgpurender-(\d+)\.build$")


def sweep_stale_builds(parent: Path) -> list[Path]:
    """Remove the staging folders of killed builds in ``parent``: ours by name, real folders, process gone."""
    return sweep_stale(parent, _BUILD, folders=True)


@contextlib.contextmanager
def staging(folder: OwnedFolder) -> Iterator[Path]:
    """A private folder beside the output (``.NAME.wgpurender-PID.build``) to build a whole site in before
    :func:`install`; removed on the way out, and by the next build if a kill (SIGKILL) left it."""
    parent = folder.folder.parent
    sweep_stale_builds(parent)
    path = parent / f".{folder.folder.name}.wgpurender-{os.getpid()}.build"
    shutil.rmtree(path, ignore_errors=True)
    try:
        path.mkdir()
    except OSError as err:
        raise UserError(f"{folder.flag} {folder.folder}: cannot create {path} ({err.strerror or err})") from None
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)


def install(folder: OwnedFolder, built: Path) -> list[str]:
    """Copy every file of ``built`` into the folder (each atomically), then drop what the last run owned and
    this one did not write. The user's files are checked for first: nothing is written when one is in the way."""
    names = sorted(p.relative_to(built).as_posix() for p in built.rglob("*") if p.is_file() and not p.is_symlink())
    folder.check_names(names)
    folder.claim(names)
    for rel in names:
        folder.write(rel, (built / rel).read_bytes())
    return folder.finish()
