"""Output files written safely: atomically, never over a special file, and no temp file left behind.

What each exit path leaves (docs/reliability.md says the same for users):

- a normal exit, an error, Ctrl-C (SIGINT) or SIGTERM: the old file or the complete new one, and no temp file
  (the temp file is unlinked in ``finally``; :func:`install_signal_handlers` turns SIGTERM into an exception so
  that ``finally`` runs);
- SIGKILL (or a power cut) during the few milliseconds of the write: the old file or the complete new one, plus
  possibly one temp file ``.NAME.wgpurender-PID.tmp`` beside it. The next write into that folder removes such
  files whose process is gone (:func:`sweep_stale`), so they never pile up.

The image is encoded in memory first, so the temp file exists only while its bytes are written.

Refused targets (``UserError``): anything that exists and is not a regular file (a directory, a device such as
/dev/full, a FIFO, a socket), and a symbolic link unless ``$WGPURENDER_FOLLOW_SYMLINKS=1`` (then the link's target
is written, and must itself be a regular file or absent). An atomic rename would replace the special file itself.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import shutil
import signal
import stat
import time
from collections.abc import Callable
from pathlib import Path

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import os_error_reason

FOLLOW_SYMLINKS_ENV = "WGPURENDER_FOLLOW_SYMLINKS"
TEST_DELAY_ENV = "WGPURENDER_TEST_WRITE_DELAY"  # seconds to hold the temp file open: lets tests kill mid-write
_TEMP = re.compile(r"^\..+\.wgpurender-(\d+)\.tmp$")
_live: set[Path] = set()  # temp files of this process, removed by the signal handler


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISSOCK, "a socket"), (stat.S_ISLNK, "a symbolic link")):
        if test(mode):
            return name
    return "not a regular file"


def follow_symlinks() -> bool:
    """Whether $WGPURENDER_FOLLOW_SYMLINKS asks to write through symbolic links."""
    return os.environ.get(FOLLOW_SYMLINKS_ENV, "") not in ("", "0")


def _link_target(link: Path) -> tuple[Path, int | None]:
    """The file a symbolic link leads to and its mode (None when absent); UserError for a loop, where
    ``realpath`` would hand back a link of the loop and the rename would replace that link."""
    try:
        os.stat(link)
    except FileNotFoundError:
        pass  # a dangling link: its target is created
    except OSError as err:
        raise UserError(f"refusing to write {link}: {os_error_reason(link, err)}") from None
    target = Path(os.path.realpath(link))
    try:
        mode = os.lstat(target).st_mode
    except FileNotFoundError:
        return target, None
    except OSError as err:
        raise UserError(f"refusing to write {link}: {os_error_reason(target, err)}") from None
    if stat.S_ISLNK(mode):  # realpath gave up on it: never replace a link
        raise UserError(f"refusing to write {link}: it leads to the symbolic link {target}, which cannot be resolved")
    return target, mode


def temp_name(path: Path) -> Path:
    """The temp file beside ``path``: ``.NAME.wgpurender-PID.tmp``, or, when that would pass the file system's
    name limit (an output name of 240-255 bytes), ``.HASH.wgpurender-PID.tmp`` (same pattern, so
    :func:`sweep_stale` still finds it)."""
    name = f".{path.name}.wgpurender-{os.getpid()}.tmp"
    if len(os.fsencode(name)) > _name_max(path.parent):
        digest = hashlib.sha256(os.fsencode(path.name)).hexdigest()[:16]
        name = f".{digest}.wgpurender-{os.getpid()}.tmp"
    return path.parent / name


def _name_max(folder: Path) -> int:
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError):
        return 255


def output_target(path: str | os.PathLike) -> Path:
    """The file to write for ``path``, or UserError: never a special file, a symlink only when asked."""
    path = Path(path)
    if "\0" in str(path):
        raise UserError(f"cannot write {str(path)!r}: the path contains a NUL character")
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        mode = None
    except OSError as err:
        raise UserError(f"cannot write {path}: {err.strerror or err}") from None
    if mode is not None and stat.S_ISLNK(mode):
        if not follow_symlinks():
            raise UserError(f"refusing to write {path}: it is a symbolic link (to {os.readlink(path)}); give the "
                            f"real file name, or set {FOLLOW_SYMLINKS_ENV}=1 to write through links")
        path, mode = _link_target(path)
    if mode is not None and not stat.S_ISREG(mode):
        hint = "give a file name ending in .png" if stat.S_ISDIR(mode) else "give the path of a regular file"
        raise UserError(f"refusing to write {path}: it is {_kind(mode)}, not a regular file; {hint}")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise UserError(f"cannot write {path}: directory {parent} does not exist (create it first)")
    if not os.access(parent, os.W_OK):
        raise UserError(f"cannot write {path}: directory {parent} is not writable")
    return path


def pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def sweep_stale(folder: Path, pattern: re.Pattern = _TEMP, folders: bool = False) -> list[Path]:
    """Remove what a killed run (SIGKILL) left in ``folder``: ours by name (``pattern``, whose group 1 is the
    process id), their process gone. Temp files; with ``folders``, real folders (a report's staging folder)."""
    removed = []
    try:
        names = os.listdir(folder)
    except OSError:
        return removed
    for name in names:
        m = pattern.match(name)
        path = folder / name
        if not m or pid_alive(int(m.group(1))) or folders != (path.is_dir() and not path.is_symlink()):
            continue
        try:
            shutil.rmtree(path) if folders else path.unlink()
            removed.append(path)
        except OSError:
            pass
    return removed


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write(path: str | os.PathLike, data: bytes | Callable[[], bytes]) -> Path:
    """Write ``data`` to ``path`` atomically (temp file in the same folder, fsync, rename).

    ``data`` may be a function producing the bytes; it runs before the temp file is created.
    """
    path = output_target(path)
    try:
        payload = data() if callable(data) else data
    except OSError as err:
        raise UserError(f"cannot write {path}: {err.strerror or err}") from None
    sweep_stale(path.parent)
    tmp = temp_name(path)
    _live.add(tmp)
    with cleanup_on_signal():
        _write_and_rename(path, tmp, payload)
    return path


def _write_and_rename(path: Path, tmp: Path, payload: bytes) -> None:
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_EXCL, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as f:
            f.write(payload)
            delay = float(os.environ.get(TEST_DELAY_ENV, "0") or 0)
            if delay > 0:
                f.flush()
                time.sleep(delay)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, output_target(path))  # checked again: a FIFO could have appeared meanwhile
    except OSError as err:
        raise UserError(f"cannot write {path}: {err.strerror or err}") from None
    finally:
        tmp.unlink(missing_ok=True)
        _live.discard(tmp)


def _on_signal(signum: int, frame) -> None:
    for tmp in list(_live):
        tmp.unlink(missing_ok=True)
    raise SystemExit(128 + signum)


_ENDING_SIGNALS = tuple(s for s in (signal.SIGTERM, getattr(signal, "SIGHUP", None)) if s is not None)
_handlers_installed = False
_cleanup_depth = 0  # nested cleanup_on_signal blocks (the report's temp folder holds atomic writes)


def _set_handlers(handler) -> None:
    for sig in _ENDING_SIGNALS:
        try:
            signal.signal(sig, handler)
        except ValueError:  # not the main thread: the sweep of the next write removes what is left
            return


@contextlib.contextmanager
def cleanup_on_signal():
    """While a temp file exists, SIGTERM/SIGHUP raise SystemExit (so ``finally`` removes it); outside, they keep
    their default action. A Python handler only runs between bytecodes, so during long native work (FLIP, numpy,
    a lavapipe frame) it waited for that work to end: a compare of a huge image ignored SIGTERM for minutes. With
    the default action the process ends at once, and there is nothing to clean up outside a write."""
    global _cleanup_depth
    if not _handlers_installed:
        yield
        return
    _cleanup_depth += 1
    if _cleanup_depth == 1:
        _set_handlers(_on_signal)
    try:
        yield
    finally:
        _cleanup_depth -= 1
        if _cleanup_depth == 0:
            _set_handlers(signal.SIG_DFL)


def install_signal_handlers() -> None:
    """The CLI's signal policy: SIGTERM (and SIGHUP) end the process at once, except while an output's temp
    file exists, when they end it through SystemExit so that ``finally`` removes the file (exit 143 either way
    as the shell sees it). SIGINT raises KeyboardInterrupt, as always. Only from the main thread."""
    global _handlers_installed
    _handlers_installed = True
    _set_handlers(signal.SIG_DFL)


def output_folder(folder: str | os.PathLike, flag: str) -> Path:
    """Make the folder a command writes into, before it does any work: a file there was a traceback at the
    end (bench ran minutes of timings, then failed writing its results). ``flag`` names it in the refusal."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise UserError(f"{flag} {folder}: exists and is not a folder; give a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise UserError(f"{flag} {folder}: cannot create it ({err.strerror or err})") from None
    return folder
