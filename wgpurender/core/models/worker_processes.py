"""The mesh workers' processes: fresh interpreters of core/models/mesh_worker_main.py (``subprocess``: exec'd at
once, no Python of the parent runs in the child, so no copy of a large multi-threaded parent and no lock held by
one of its threads), booted as soon as a scene's TOML values say they will be wanted (:func:`boot_ahead`: the
plan's worker rule, core/plan/mesh_loading.py, says how many) so that they start up while the parent checks the
scene and makes the plan; :func:`claim` hands them to the reading (core/models/mesh_workers.py).

Each worker gets one request on its stdin (every chunk it reads) and answers chunk by chunk on its stdout; one
thread of the parent per worker writes the request and takes the answers as they come, so the workers read on
while the parent does other work. A worker that dies (killed, out of memory) leaves its chunks' futures failed
with :class:`WorkerDied`: the reading reads them itself. :meth:`Workers.end` kills what still runs and waits for
it; a pool never claimed or never ended is ended when it is collected or at exit, and a worker also ends by
itself at the end of its stdin (its parent gone) or when no request came for a minute.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import weakref
from concurrent.futures import Future
from pathlib import Path

from wgpurender.core.models import frames

MODULE = "wgpurender.core.models.mesh_worker_main"
ROOT = str(Path(__file__).resolve().parents[3])  # the folder holding this wgpurender package
_booted: Workers | None = None  # booted ahead by the scene's load, until a reading claims it


class WorkerDied(Exception):
    """A worker ended before answering a chunk."""


class Workers:
    """``count`` worker processes, started now."""

    def __init__(self, count: int) -> None:
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, (ROOT, os.environ.get("PYTHONPATH")))))
        self.procs = [subprocess.Popen([sys.executable, "-m", MODULE], stdin=subprocess.PIPE,
                                       stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env)
                      for _ in range(count)]
        self.threads: list[threading.Thread] = []
        self._end = weakref.finalize(self, _end, self.procs, self.threads)

    def alive(self) -> bool:
        return all(p.poll() is None for p in self.procs)

    def read(self, chunks: list, checked: list[str], where: Path | None) -> list[Future]:
        """One future per chunk (its worker's answer); chunk k goes to worker k mod the count."""
        futures = [Future() for _ in chunks]
        for k, proc in enumerate(self.procs):
            mine = list(range(k, len(chunks), len(self.procs)))
            request = (checked, None if where is None else str(where), [chunks[i] for i in mine])
            thread = threading.Thread(target=_serve, args=(proc, request, [futures[i] for i in mine]), daemon=True)
            thread.start()
            self.threads.append(thread)
        return futures

    def end(self) -> None:
        """Kill what still runs, wait for it and for the threads serving it (idempotent)."""
        self._end()


def _serve(proc: subprocess.Popen, request: tuple, futures: list[Future]) -> None:
    """Write ``proc`` its request, then set each future from its answers, in order; WorkerDied from the first
    answer it did not give."""
    try:
        frames.send(proc.stdin, request)
        proc.stdin.close()
        for future in futures:
            answer = frames.receive(proc.stdout)
            if answer is None:
                break
            future.set_result(answer)
    except (OSError, ValueError):  # its pipe broken or closed: it died
        pass
    for future in futures:
        if not future.done():
            future.set_exception(WorkerDied())


def _end(procs: list[subprocess.Popen], threads: list[threading.Thread]) -> None:
    for proc in procs:
        if proc.poll() is None:
            proc.kill()
    for proc in procs:
        proc.wait()
    for thread in threads:
        thread.join()
    for proc in procs:
        for pipe in (proc.stdin, proc.stdout):
            try:
                pipe.close()
            except (OSError, ValueError):
                pass


def boot_ahead(models: object, knob: str = "auto") -> None:
    """Start the workers the plan will want for a scene's ``[[models]]`` values (before they are checked): as
    many as the worker rule gives for their distinct ``.obj`` file names; none when it gives none."""
    global _booted
    from wgpurender.core.plan.mesh_loading import resolve_mesh_workers

    names = {m.get("path") for m in models if isinstance(m, dict)} if isinstance(models, list) else set()
    count = sum(1 for name in names if isinstance(name, str) and name.lower().endswith(".obj"))
    try:
        wanted, _ = resolve_mesh_workers(knob, count)
    except Exception:  # noqa: BLE001  the plan refuses a bad knob itself, in its own words
        return
    if _booted is not None and len(_booted.procs) != wanted:
        _booted.end()
        _booted = None
    if wanted and _booted is None:
        _booted = Workers(wanted)


def claim(count: int) -> Workers:
    """The workers booted ahead when there are ``count`` of them, all alive; else ``count`` new ones."""
    global _booted
    booted, _booted = _booted, None
    if booted is not None and len(booted.procs) == count and booted.alive():
        return booted
    if booted is not None:
        booted.end()
    return Workers(count)


def drop_booted() -> None:
    """End the workers booted ahead (the plan read its files here, or with another count)."""
    global _booted
    booted, _booted = _booted, None
    if booted is not None:
        booted.end()
