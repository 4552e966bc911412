"""A scene's simple OBJ files read in worker processes (issue 31: 10k distinct mesh files, each ~0.3 ms of
Python parsing on one core); the plan decides whether and how many (core/plan/mesh_loading.py).

The parent has already checked every path against the read rule (the scene's folders: core/scene/checker.py);
each worker applies the same per-file checks as :func:`~wgpurender.core.models.mesh.load_mesh` (a readable
regular file, within the size limit) and parses it as the serial load does (core/models/obj_cached.py), so its
mesh is the serial load's; a chunk's meshes are cached as one entry (core/models/obj_cached_chunks.py). A worker
sends back packed meshes (core/models/mesh_pack.py) in chunks; a refused file comes back as its one-line message,
which the parent raises as the same :class:`UserError`, for the first such file in draw order. A file that is not
a simple OBJ comes back as None and is loaded by the parent the general way. Workers are forked (POSIX ``fork``: no
re-import of the caller's main module, no start-up beyond the fork); if one dies, the chunks not read yet are
loaded serially.
"""

from __future__ import annotations

import functools
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from itertools import repeat
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.files.input_files import check_size, input_file
from wgpurender.core.models import mesh_pack, obj_cached, obj_cached_chunks
from wgpurender.core.models.mesh import Mesh

CHUNK = 64  # files per task at least: one round trip carries 64 packed cubes or more (~200 KB)
CHUNKS_PER_WORKER = 4  # and no more tasks than this per worker: fewer round trips, still unpacked as they come
Job = tuple[Path, bool]  # (model file, make tangents)


def load_all(jobs: list[Job], workers: int, where: Path | None) -> dict[Job, Mesh | None]:
    """Every job's mesh (None: not a simple OBJ file), read by ``workers`` forked processes; raises the
    UserError of the first refused file in ``jobs`` order."""
    return Reading(jobs, workers, where).finish()


class Reading:
    """The jobs handed to ``workers`` forked processes at once (they read while this process goes on: the
    renderer sets up what needs no mesh meanwhile); :meth:`finish` takes their meshes, in ``jobs`` order, and
    reads here what a dead worker left. A reading never finished ends its workers when it goes (the executor's
    own collection hook)."""

    def __init__(self, jobs: list[Job], workers: int, where: Path | None) -> None:
        size = max(CHUNK, -(-len(jobs) // (workers * CHUNKS_PER_WORKER)))
        self.chunks = [jobs[i:i + size] for i in range(0, len(jobs), size)]
        self.where = where
        _before_fork()
        self.pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork"))
        # every chunk submitted now (Executor.map submits eagerly), read back in order by finish()
        self.results = self.pool.map(read_chunk, self.chunks, repeat(where))

    def finish(self) -> dict[Job, Mesh | None]:
        meshes: dict[Job, Mesh | None] = {}
        done = 0
        try:
            for result in self.results:  # in order, each as soon as it is read
                _take(self.chunks[done], result, meshes)  # unpacked here while the workers read the next chunks
                done += 1
        except BrokenProcessPool:  # a worker died (killed, out of memory): the rest in this process
            pass
        finally:
            self.pool.shutdown(wait=True, cancel_futures=True)  # a refusal stops the chunks not started yet
        for chunk in self.chunks[done:]:
            _take(chunk, read_chunk(chunk, self.where), meshes)
        return meshes


def _before_fork() -> None:
    """What every worker would otherwise do first, each on its own: import trimesh's ``unmerge_faces`` (the
    simple reader's, ~0.1 s) and hash the parser's source for the cache key (obj_cached.parser_version)."""
    from trimesh.visual.texture import unmerge_faces  # noqa: F401

    obj_cached.parser_version()


def _take(chunk: list[Job], result: tuple[list[tuple[str, object]], bytes],
          meshes: dict[Job, Mesh | None]) -> None:
    """Unpack a chunk's meshes into ``meshes``; raise the first refusal."""
    for job, mesh in unpack_chunk(chunk, result).items():
        if isinstance(mesh, UserError):
            raise mesh
        meshes[job] = mesh


def unpack_chunk(chunk: list[Job],
                 result: tuple[list[tuple[str, object]], bytes]) -> dict[Job, Mesh | UserError | None]:
    """A chunk's meshes, in ``chunk`` order: views of one copy of the chunk's bytes (the worker checked their
    indices), each run of alike meshes as one array (mesh_pack.unpack_alike); None (not a simple OBJ) or the
    file's refusal."""
    entries, blob = result
    if len(entries) != len(chunk):
        raise ValueError(f"a worker answered {len(entries)} files of a chunk of {len(chunk)}")
    data, at = np.frombuffer(bytearray(blob), np.uint8), 0
    out: dict[Job, Mesh | UserError | None] = {}
    for jobs, (kind, value) in _runs(chunk, entries):
        if kind == "refused":
            out[jobs[0]] = UserError(value)
        elif value is None:
            out.update(dict.fromkeys(jobs))
        else:
            sources = [path for path, _ in jobs]
            run = data[at:at + value * len(jobs)]
            meshes = mesh_pack.unpack_alike(run, sources, indices_checked=True) or [
                mesh_pack.unpack(memoryview(run[k * value:(k + 1) * value]), path, indices_checked=True)
                for k, path in enumerate(sources)]
            out.update(zip(jobs, meshes, strict=True))
            at += value * len(jobs)
    return out


def _runs(chunk: list[Job], entries: list[tuple[str, object]]):
    """(jobs, entry) for each run of equal consecutive entries (a refusal alone)."""
    k = 0
    while k < len(chunk):
        end = k + 1
        while entries[k][0] != "refused" and end < len(chunk) and entries[end] == entries[k]:
            end += 1
        yield chunk[k:end], entries[k]
        k = end


def read_chunk(chunk: list[Job], where: Path | None) -> tuple[list[tuple[str, object]], bytes]:
    """(entries, packed meshes one after another): per job ("mesh", its packed length, or None: not a simple OBJ)
    or ("refused", the one-line message). What runs in a worker: each file checked and read here, then the
    chunk's meshes from its one cache entry or parsed (core/models/obj_cached_chunks.py, which writes that entry);
    every packed mesh it sends had its indices checked here."""
    out: list[tuple[str, object] | None] = []
    files: list[obj_cached_chunks.File] = []
    for path, tangents in chunk:
        try:
            if not read_jail.is_checked(path):  # else the checked read refuses what is no regular file
                input_file(path, "model file")  # a folder, a FIFO, a missing file: one line (the read checks the size)
            # the file the scene's read rule checked, still that file, within the size limit (input_file's checks)
            data = read_jail.read_checked(path, functools.partial(check_size, path, what="model file"))
        except UserError as err:
            out.append(("refused", str(err)))
            continue
        except OSError:  # vanished or unreadable since the check: the parent's general load says what it is
            out.append(("mesh", None))
            continue
        out.append(None)  # its mesh, below
        files.append((path, tangents, data))
    found = iter(obj_cached_chunks.meshes(files, where))
    packed: list[bytes] = []
    for k, entry in enumerate(out):
        if entry is None:
            data = next(found)
            if isinstance(data, UserError):
                out[k] = ("refused", str(data))
                continue
            out[k] = ("mesh", None if data is None else len(data))
            packed += [] if data is None else [data]
    return out, b"".join(packed)
