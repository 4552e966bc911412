"""One mesh worker: a fresh interpreter (``python -m wgpurender.core.models.mesh_worker_main``) started by
core/models/worker_processes.py, never a fork of the renderer (issue 31.3: forking a large, multi-threaded parent
cost ~0.1 s of its load and risks a lock held by another thread). It imports only what reading needs, at once,
so its start-up overlaps the parent's scene checks; then it reads one request from stdin (the paths the parent's
read rule let through, the parse cache's folder, its chunks of jobs) and answers each chunk, in order, on stdout
with what :func:`~wgpurender.core.models.mesh_workers.read_chunk` returns. It ends at the end of its request, at
an end of its stdin (the parent gone or done), or after :data:`IDLE_S` seconds with no request (a reading never
asked for): no orphan outlives its parent's pipe.
"""

from __future__ import annotations

import os
import select
import sys
from pathlib import Path

from trimesh.visual.texture import unmerge_faces  # noqa: F401  the simple reader's import (~0.1 s), at boot

from wgpurender.core.files import read_jail
from wgpurender.core.models import frames, obj_cached
from wgpurender.core.models.mesh_workers import read_chunk

IDLE_S = 60.0  # a worker booted for a reading that never comes ends by itself after this


def main() -> int:
    answers = os.fdopen(os.dup(1), "wb")  # the parent's pipe; stdout itself goes to stderr, so no stray print
    os.dup2(2, 1)  # can corrupt a frame
    obj_cached.parser_version()  # the cache key's parser hash, before the request comes
    requests = os.fdopen(0, "rb", closefd=False)
    if not select.select([requests], [], [], IDLE_S)[0]:
        return 0
    request = frames.receive(requests)
    if request is None:  # the parent ended the reading before it began
        return 0
    checked, where, chunks = request
    read_jail.vouch(checked)  # the parent's rule let these through: read_checked verifies each is still that file
    for chunk in chunks:
        frames.send(answers, read_chunk(chunk, None if where is None else Path(where)))
    answers.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
