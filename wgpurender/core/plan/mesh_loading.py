"""How a plan's model files are read: in this process, or by worker processes (core/models/mesh_workers.py).

Decided by the count of distinct simple-OBJ candidates (``.obj`` files) the draws need. Worker processes pay
a fork each and a round trip per 64 files, and a file takes ~0.3 ms to parse on one core (lavapipe host,
2026-11-27), so below :data:`MIN_FILES` files the scene is read here (every tutorial and model scene); from
there on up to :data:`MAX_WORKERS` workers, one per usable core and at most one per 64 files. Workers need the
POSIX ``fork`` start method (Linux): elsewhere a pool would re-import the caller's main module, so the files are
read here. Knob ``mesh_workers``: "auto" (this rule), "off" (always here), "on" (workers whenever the scene has
an OBJ file and fork is available). ``--explain`` shows the choice and why.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
from collections.abc import Sequence

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import file_suffix

MESH_WORKERS = ("auto", "off", "on")
MIN_FILES = 256
MAX_WORKERS = 16
PER_WORKER = 64


def obj_keys(draws, models: Sequence | None = None) -> list[tuple]:
    """The distinct ``mesh_key`` (file, pose) of the draws whose file is an OBJ, in first-use order: the files the
    worker rule counts and the workers read. ``models``: the scene's, each draw's by its ``model_index``, whose
    file format each model worked out once (``Model.suffix``); without them each file's name is looked at once,
    as a string (10k draws of distinct files asked pathlib three times each, issue 31.3)."""
    if models is not None:
        return list(dict.fromkeys(d.mesh_key for d in draws if models[d.model_index].suffix == ".obj"))
    keys = dict.fromkeys(d.mesh_key for d in draws)
    return [key for key in keys if file_suffix(os.fspath(key[0])).lower() == ".obj"]


def usable_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def can_fork() -> bool:
    return sys.platform.startswith("linux") and "fork" in multiprocessing.get_all_start_methods()


def resolve_mesh_workers(knob: str, obj_files: int, cores: int | None = None,
                         fork: bool | None = None) -> tuple[int, str]:
    """(worker count, 0 = read here; why) for ``obj_files`` distinct OBJ files."""
    cores = usable_cores() if cores is None else cores
    fork = can_fork() if fork is None else fork
    if knob not in MESH_WORKERS:
        raise UserError(f"plan knob mesh_workers = {knob!r}: choose one of {', '.join(MESH_WORKERS)}")
    files = f"{obj_files} OBJ file(s)"
    if knob == "off":
        return 0, f"knob mesh_workers = off: the {files} are read in this process"
    if obj_files == 0:
        return 0, "no OBJ files: models are read in this process"
    if not fork:
        if knob == "on":  # asked for by name: refused, never dropped
            raise UserError("plan knob mesh_workers = on: worker processes need the fork start method (Linux), "
                            "which this platform does not offer; use auto or off")
        return 0, f"{files} read in this process: worker processes need the fork start method (Linux)"
    wanted = max(1, min(cores, MAX_WORKERS, -(-obj_files // PER_WORKER)))
    if knob == "on":
        return wanted, f"knob mesh_workers = on: {wanted} worker process(es) read the {files}"
    if obj_files < MIN_FILES:
        return 0, (f"{files}, fewer than {MIN_FILES}: read in this process (worker processes would cost more to "
                   "start than they save)")
    if cores < 2:
        return 0, f"{files}, but 1 usable core: read in this process"
    return wanted, (f"{files}, at least {MIN_FILES}: {wanted} worker process(es) (of {cores} usable cores, at most "
                    f"{MAX_WORKERS}, one per {PER_WORKER} files) read them, each from the parse cache when it "
                    "holds it")
