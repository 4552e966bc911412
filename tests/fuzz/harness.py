"""One fuzz case through the real entry point (the CLI's ``main()`` in-process), classified by outcome.

Outcomes (docs/reliability.md):

- ``render``: exit 0 and a complete PNG (Pillow decodes it fully);
- ``error``: exit 2, exactly one line on stderr, no output file;
- ``traceback``: an exception escaped ``main()`` (or "Traceback" on stderr);
- ``hang``: the case ran past its time bound (SIGALRM; a faulthandler watchdog ends the process if a native
  call never returns, so a hang can never pass silently);
- ``partial``: an output or temp file left after an error, or an output Pillow cannot decode;
- ``multiline``: exit 2 with more or fewer than one stderr line, or another exit code;
- ``blank``: exit 0 with a uniform image (every pixel the same) although the scene has a front-facing triangle
  wholly inside the view frustum whose projection covers at least :data:`BLANK_MIN_AREA` pixels: an image the
  scene did not ask for (back faces are culled, so those do not count; scenes with post effects are not judged,
  since an effect may darken everything on purpose, e.g. tonemap exposure = 0).

Only ``render`` and ``error`` pass.
"""

from __future__ import annotations

import contextlib
import faulthandler
import hashlib
import io
import os
import signal
import sys
import traceback
from collections import Counter
from pathlib import Path

import numpy as np
from PIL import Image

from wgpurender.cli import main

LONG = os.environ.get("WGPURENDER_FUZZ", "") == "long"
CASE_SECONDS = int(os.environ.get("WGPURENDER_FUZZ_CASE_SECONDS", "30"))
RENDER_SIZE = "40x30"  # every render case is small: the fuzz is about inputs, not pixels
BLANK_MIN_AREA = 8.0  # pixels: a triangle this large fully inside the frustum covers pixel centres
PASSING = ("render", "error")
OUTCOMES: Counter = Counter()
EXAMPLES: dict[str, list[str]] = {}


class CaseTimeout(Exception):
    pass


def _alarm(signum, frame):
    raise CaseTimeout()


@contextlib.contextmanager
def time_bound(seconds: int):
    """SIGALRM after ``seconds`` raises CaseTimeout; a watchdog at twice that kills the process with a dump."""
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(seconds)
    faulthandler.dump_traceback_later(seconds * 2 + 10, exit=True)
    try:
        yield
    finally:
        signal.alarm(0)
        faulthandler.cancel_dump_traceback_later()
        signal.signal(signal.SIGALRM, previous)


def run_case(argv: list, output: Path | None, scene: Path | None = None, label: str = "") -> str:
    """Run ``wgpurender ARGV``; classify, count and return the outcome."""
    out, err = io.StringIO(), io.StringIO()
    try:
        with time_bound(CASE_SECONDS), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main([str(a) for a in argv])
    except CaseTimeout:
        return _count("hang", label, "timeout")
    except BaseException as exc:  # noqa: BLE001 - any escape is the finding
        return _count("traceback", label, "".join(traceback.format_exception(exc))[-2000:])
    outcome = classify(code, err.getvalue(), output, scene)
    return _count(outcome, label, err.getvalue()[-500:])


def check(outcome: str, message: str) -> None:
    """In ``make test`` a failing outcome fails the test (and hypothesis shrinks it); in ``make fuzz`` every case is
    counted and the run goes on, so the summary covers all of them (the session then fails, see conftest.py)."""
    if not LONG:
        assert outcome in PASSING, message


def _count(outcome: str, label: str, detail: str) -> str:
    OUTCOMES[outcome] += 1
    if outcome not in PASSING:
        EXAMPLES.setdefault(outcome, []).append(f"{label}: {detail}")
    return outcome


def classify(code: int, stderr: str, output: Path | None, scene: Path | None) -> str:
    if "Traceback" in stderr:
        return "traceback"
    leftovers = [] if output is None else [p for p in output.parent.iterdir() if p.name.endswith(".tmp")]
    if code == 2:
        if leftovers or (output is not None and os.path.lexists(output)):  # os.path: no raise on a long name
            return "partial"
        return "error" if len(stderr.splitlines()) == 1 else "multiline"
    if code != 0:
        return "multiline"
    if output is None:
        return "render"
    if leftovers or not os.path.isfile(output):
        return "partial"
    try:
        with Image.open(output) as im:
            pixels = np.asarray(im.convert("RGBA"))
    except Exception:  # noqa: BLE001
        return "partial"
    if scene is not None and _uniform(pixels) and asks_for_a_picture(scene, pixels.shape[1], pixels.shape[0]):
        return "blank"
    return "render"


def _uniform(pixels: np.ndarray) -> bool:
    return bool((pixels == pixels[0, 0]).all())


def asks_for_a_picture(scene_path: Path, width: int, height: int) -> bool:
    """A scene without post effects (which may darken everything on purpose, e.g. exposure 0) that has a visible
    front-facing triangle: its image cannot be uniform."""
    from wgpurender.core.scene import load_scene

    return not load_scene(scene_path).post and visible_triangle(scene_path, width, height)


def visible_triangle(scene_path: Path, width: int, height: int) -> bool:
    """Whether some model triangle lies wholly inside the view frustum and projects to >= BLANK_MIN_AREA pixels."""
    from wgpurender.core.models.mesh import load_mesh
    from wgpurender.core.scene import load_scene

    scene = load_scene(scene_path)
    clip_from_world = scene.camera.projection(width / height) @ scene.camera.view()
    for model in scene.models:
        mesh = load_mesh(model.path, generate_tangents=False)
        world = np.c_[mesh.positions.astype(np.float64), np.ones(len(mesh.positions))] @ model.transform.array().T
        clip = world @ clip_from_world.T
        tri = clip[mesh.indices.astype(np.int64)]  # (F, 3, 4)
        w = tri[..., 3]
        with np.errstate(all="ignore"):
            inside = (w > 0) & (np.abs(tri[..., 0]) <= w) & (np.abs(tri[..., 1]) <= w) & (tri[..., 2] >= 0) & (
                tri[..., 2] <= w)
            ndc = tri[..., :2] / w[..., None]
        px = ndc * np.array([width / 2, height / 2])  # y up, as NDC: counter-clockwise = positive area
        signed = 0.5 * ((px[:, 1, 0] - px[:, 0, 0]) * (px[:, 2, 1] - px[:, 0, 1])
                        - (px[:, 2, 0] - px[:, 0, 0]) * (px[:, 1, 1] - px[:, 0, 1]))
        mirror = np.linalg.det(model.transform.array()[:3, :3]) < 0  # the renderer then culls the other side
        front = -signed if mirror else signed  # back faces are culled: a blank image is then what was asked
        if np.any(inside.all(axis=1) & (front >= BLANK_MIN_AREA)):
            return True
    return False


def summary() -> str:
    total = sum(OUTCOMES.values())
    parts = ", ".join(f"{k} {v}" for k, v in sorted(OUTCOMES.items()))
    return f"fuzz cases: {total} ({parts})"


def render_argv(scene: Path, output: Path) -> list:
    return ["render", scene, "-o", output, "--size", RENDER_SIZE]


def reset_folder(folder: Path) -> None:
    """Empty a per-case folder (cases reuse one tmp dir: hypothesis examples share a function-scoped fixture)."""
    for p in folder.iterdir():
        if p.is_dir() and not p.is_symlink():
            reset_folder(p)
            p.rmdir()
        else:
            p.unlink()


def stderr_sink() -> None:  # pragma: no cover - debugging aid
    print(summary(), file=sys.stderr)


def tree_snapshot(root: Path) -> dict[str, str]:
    """Every file and link under ``root`` (not following links): path -> content hash or link target. What the
    output-safety fuzzers compare before and after a run, so that a user's file lost or changed is named."""
    out = {}
    for here, dirs, files in os.walk(root):
        for name in files + [d for d in dirs if os.path.islink(os.path.join(here, d))]:
            path = Path(here) / name
            rel = str(path.relative_to(root))
            out[rel] = "-> " + os.readlink(path) if path.is_symlink() else hashlib.sha256(path.read_bytes()).hexdigest()
    return out
