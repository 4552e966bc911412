"""Where a mesh worker's cold file goes (issue 31.3's load, fourth pass): the distinct-mesh scene's cube files read
by the workers alone, no renderer, no GPU.

    python benchmarks/worker_cold_probe.py LABEL N WORKERS OUT.csv

Appends rows (label, n, workers, what, ms, note) for:
- ``phase:*``: one process, each file's steps timed apart (per file, microseconds as ms / 1000): the checks, the
  checked read, the SHA-256, a per-file cache lookup that misses, the simple parse (obj_simple + trimesh's
  unmerge_faces), the mesh built (checks, normals; no tangents: the scene's material has no normal map), the
  packing, and one per-file cache entry written (cache_entry.write_entry: mkdir, unlink, O_EXCL create, write,
  rename; no fsync), and the pickling of a chunk's result;
- ``entries_parallel``: WORKERS forked processes each writing N / WORKERS per-file entries into one folder at once
  (what the per-file cache made a cold load do), wall ms;
- ``reading_cold`` / ``reading_warm``: ``mesh_workers.Reading(jobs, WORKERS, folder).finish()`` with an empty cache
  folder, then again with what it stored, wall ms (forks included). Whichever wgpurender is first on PYTHONPATH is
  timed, so one call times two trees.
"""

from __future__ import annotations

import functools
import itertools
import multiprocessing
import os
import pickle
import sys
import tempfile
import time
from pathlib import Path

from wgpurender.bench import scale
from wgpurender.core.files import read_jail
from wgpurender.core.files.cache_entry import read_entry, write_entry
from wgpurender.core.files.input_files import check_file_size, check_size, input_file
from wgpurender.core.models import mesh_pack, mesh_workers, obj_cached
from wgpurender.core.models.mesh import mesh_of_parts, simple_obj_parts

STEPS = ("check", "read", "sha256", "lookup (miss)", "parse", "build", "pack", "entry write")


def phases(jobs: list[tuple[Path, bool]], where: Path) -> dict[str, float]:
    """Mean ms per file of each step, in this process."""
    spent = dict.fromkeys(STEPS, 0.0)
    clock = time.perf_counter
    for path, tangents in jobs:
        marks = [clock()]
        check_file_size(input_file(path, "model file"), "model file")
        marks.append(clock())
        data = read_jail.read_checked(path, functools.partial(check_size, path, what="model file"))
        marks.append(clock())
        key = obj_cached.entry_key(data, tangents)
        marks.append(clock())
        entry = obj_cached.entry_path(where, key)
        read_entry(entry, key)
        marks.append(clock())
        parts = simple_obj_parts(data)
        marks.append(clock())
        mesh = mesh_of_parts(path, parts, tangents)
        marks.append(clock())
        packed = mesh_pack.pack(mesh)
        marks.append(clock())
        write_entry(entry, key, packed)
        marks.append(clock())
        for step, (a, b) in zip(STEPS, itertools.pairwise(marks), strict=True):
            spent[step] += (b - a) * 1e3
    return {step: ms / len(jobs) for step, ms in spent.items()}


def _write_entries(folder: Path, start: int, count: int, payload: bytes) -> None:
    for k in range(start, start + count):
        write_entry(folder / f"{k:040x}.mesh", f"probe {k}", payload)


def entries_parallel(folder: Path, n: int, workers: int, payload: bytes) -> float:
    """Wall ms of ``workers`` forked processes writing n per-file entries into one folder between them."""
    folder.mkdir(parents=True)
    share = -(-n // workers)
    ctx = multiprocessing.get_context("fork")
    procs = [ctx.Process(target=_write_entries, args=(folder, w * share, min(share, n - w * share), payload))
             for w in range(workers) if w * share < n]
    start = time.perf_counter()
    for p in procs:
        p.start()
    for p in procs:
        p.join()
    return (time.perf_counter() - start) * 1e3


def reading(jobs: list[tuple[Path, bool]], workers: int, where: Path) -> float:
    start = time.perf_counter()
    mesh_workers.Reading(jobs, workers, where).finish()
    return (time.perf_counter() - start) * 1e3


def main() -> int:
    label, n, workers, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        files = Path(tmp) / "files"
        files.mkdir()
        scale.distinct_scene(files, n, (800, 600))
        jobs = [(files / f"m{k}.obj", False) for k in range(n)]
        mesh_workers._before_fork()
        some = jobs[:min(n, 500)]
        for step, ms in phases(some, Path(tmp) / "phases").items():
            rows.append((f"phase:{step}", ms, f"ms per file, one process, {len(some)} files"))
        result = mesh_workers.read_chunk(jobs[:64], None)
        start = time.perf_counter()
        pickle.dumps(result)
        rows.append(("phase:pickle", (time.perf_counter() - start) * 1e3 / 64, "ms per file, a 64-file chunk"))
        payload = mesh_pack.pack(obj_cached.load(jobs[0][0], False, None))
        rows.append(("entries_parallel", entries_parallel(Path(tmp) / "entries", n, workers, payload),
                     f"wall ms, {workers} processes, {n} per-file entries into one folder"))
        where = Path(tmp) / "cache"
        rows.append(("reading_cold", reading(jobs, workers, where), "wall ms, empty cache folder"))
        rows.append(("reading_warm", reading(jobs, workers, where), "wall ms, the folder the cold reading filled"))
        rows.append(("cache_files", len(os.listdir(where)) if where.is_dir() else 0, "files the cold reading wrote"))
    new = not out.exists()
    with out.open("a") as f:
        if new:
            f.write("tree,distinct_meshes,workers,what,value,note\n")
        for what, value, note in rows:
            f.write(f'{label},{n},{workers},"{what}",{value:.4f},"{note}"\n')
            print(f"{label} {what}: {value:.4f} ({note})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
