"""Length-prefixed pickled frames over a pipe between the renderer and its own mesh workers
(core/models/worker_processes.py, core/models/mesh_worker_main.py): both ends are this package, started by the
parent itself; nothing else writes these pipes."""

from __future__ import annotations

import pickle
from typing import BinaryIO

HEADER = 8  # bytes of the frame's length, little-endian


def send(pipe: BinaryIO, value: object) -> None:
    data = pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL)
    pipe.write(len(data).to_bytes(HEADER, "little"))
    pipe.write(data)
    pipe.flush()


def receive(pipe: BinaryIO) -> object | None:
    """The next frame's value; None at the end of the pipe (or a frame cut short: the writer died)."""
    header = pipe.read(HEADER)
    if len(header) < HEADER:
        return None
    size = int.from_bytes(header, "little")
    data = pipe.read(size)
    return pickle.loads(data) if len(data) == size else None
