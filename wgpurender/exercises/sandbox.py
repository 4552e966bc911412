"""A learner's stage, rendered in a process of its own with a time limit (learner code is untrusted and fragile).

:func:`render_isolated` starts ``python -m wgpurender.exercises.sandbox STEP PATH FILE OUT`` and waits at most
``timeout`` seconds. The child loads the file, renders it (render.py) and saves the images to OUT (.npz). Whatever
goes wrong in the learner's code (an exception, a GPU validation error, a wrong class, a loop that never ends, a
crash of the process) comes back as a :class:`LearnerError` whose text shows the learner's own traceback frames
(their file only, not ours), so grading one submission never stops the grading of others.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

from wgpurender.exercises.catalogue import Exercise, exercise

DEFAULT_TIMEOUT = 120.0  # seconds; a stage renders in ~1-5 s on lavapipe, start-up included
LEARNER_FAILED = 3  # the child's exit status when the learner's code failed (its message in OUT.txt)


class LearnerError(Exception):
    """The learner's stage could not be rendered: the message is for the learner."""


def learner_traceback(err: BaseException, file: Path) -> str:
    """The exception as the learner should see it: only the frames of their file, then the error itself."""
    target = str(file.resolve())
    frames = [f for f in traceback.extract_tb(err.__traceback__) if str(Path(f.filename).resolve()) == target]
    if isinstance(err, SyntaxError) and err.filename and str(Path(err.filename).resolve()) == target:
        lines = ["your file does not parse (the line is below):"]  # it never ran: no frames, yet it is theirs
    else:
        lines = ["Traceback (your code):"] if frames else ["(raised outside your file, from what your code passed on)"]
    lines += [line.rstrip("\n") for line in traceback.format_list(frames)]
    lines.append("".join(traceback.format_exception_only(type(err), err)).strip())
    return "\n".join(lines)


def _child(step: str, path: str, file: Path, out: Path) -> int:
    from wgpurender.exercises.render import StageFileError, render_file

    ex = exercise(step, path)
    validation = _validation_log(path)
    message = out.with_suffix(".txt")  # stderr also has the libraries' noise: the learner's message goes here
    try:
        images = render_file(file, ex)
    except StageFileError as err:
        message.write_text(str(err))
        return LEARNER_FAILED
    except BaseException as err:  # anything the learner's code raises is reported, not re-raised
        message.write_text(learner_traceback(err, file))
        return LEARNER_FAILED
    if validation is not None and validation.messages:
        message.write_text(f"GPU validation error: {validation.messages[0]}")
        return LEARNER_FAILED
    np.savez(out, *images)
    return 0


def _validation_log(path: str):
    if path != "wgpu":
        return None  # the raw path's debug messenger raises ValidationFailed itself (when validation is on)
    from wgpurender.wgpu_path.device.validation import collect_validation_messages

    return collect_validation_messages()


def render_isolated(file: Path, ex: Exercise, timeout: float = DEFAULT_TIMEOUT) -> list[np.ndarray]:
    """Render the learner's ``file`` in a child process; a :class:`LearnerError` for anything that goes wrong."""
    with tempfile.TemporaryDirectory(prefix="wgpurender-sandbox-") as folder:
        out = Path(folder) / "images.npz"
        command = [sys.executable, "-m", "wgpurender.exercises.sandbox", ex.step, ex.path, str(file), str(out)]
        env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}  # the learner's folder gets no __pycache__
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=timeout, env=env,
                                  cwd=file.parent)
        except subprocess.TimeoutExpired:
            raise LearnerError(f"your stage did not finish within {timeout:g} s (an endless loop?)") from None
        if done.returncode == LEARNER_FAILED and out.with_suffix(".txt").is_file():
            raise LearnerError(out.with_suffix(".txt").read_text().strip())
        if done.returncode != 0 or not out.is_file():
            tail = "\n".join(done.stderr.strip().splitlines()[-5:])
            raise LearnerError(f"rendering your stage ended the process (exit status {done.returncode}): {tail}")
        with np.load(out) as data:
            return [data[f"arr_{k}"] for k in range(len(data.files))]


def main(argv: list[str]) -> int:
    step, path, file, out = argv
    return _child(step, path, Path(file), Path(out))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
