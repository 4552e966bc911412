"""``wgpurender check``: a learner's stage against the step's raw-Vulkan reference, with a diagnosis.

The learner's file is rendered in its own process (sandbox.py) at the step's size and times. At every time the
image is compared with the solution rendered here, on the same path, under the step's rounding bound
(rounding_tolerance); at t = 0 also with the committed reference (assets/reference/<stage>.png, made by the
raw-Vulkan path) under the step's row of assets/reference/tolerances.toml for this driver class, the check that
does not rest on this machine's own stage. Within every bound: a pass. (A GPU's row alone is too wide to judge
with where its filtering differs from lavapipe's: step 5's lets 'one sampler for all four lanes' pass on an H100.)

Otherwise the diagnosis: every catalogued mistake of the step (catalogue.py) is rendered the same way, on the
same machine, and compared with the learner's image under the step's rounding bound (rounding_tolerance). The
nearest one (least FLIP) that is within it names the mistake; when none is, "no known mistake matches" (with the
nearest, for a hint).
"""

from __future__ import annotations

import functools
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import load_png, save_png
from wgpurender.core.verdict.tolerances import Metrics, Tolerance, driver_class, measure, tolerance
from wgpurender.exercises.catalogue import Exercise, Mistake
from wgpurender.exercises.render import render_source
from wgpurender.exercises.sandbox import DEFAULT_TIMEOUT, LearnerError, render_isolated
from wgpurender.exercises.source import course_step, mistake_source, solution_source

PASS, FAIL, ERROR = "pass", "fail", "error"


@dataclass
class Diagnosis:
    mistake: Mistake | None  # None: no known mistake matches
    flip: float  # FLIP mean of the learner's image against the nearest mistake (summed over the times)
    nearest: Mistake | None

    def text(self) -> str:
        if self.mistake is not None:
            return (f"your image matches '{self.mistake.title}' (FLIP {self.flip:.4f}): see concept "
                    f"'{self.mistake.concept}' in `wgpurender concepts`")
        if self.nearest is None:
            return "no known mistake matches (this step has none catalogued)"
        return f"no known mistake matches (the nearest, '{self.nearest.title}', is at FLIP {self.flip:.4f})"


@dataclass
class Verdict:
    step: str
    path: str
    file: Path
    status: str  # pass | fail | error
    metrics: list[tuple[float, Metrics, list[str]]] = field(default_factory=list)  # (t, metrics, exceeded bounds)
    diagnosis: Diagnosis | None = None
    message: str = ""  # the learner's error (status error)
    images: dict[str, Path] = field(default_factory=dict)  # what was written: "t=0 image", "t=0 heatmap", ...

    @property
    def exit_code(self) -> int:
        return 0 if self.status == PASS else 1

    def line(self) -> str:
        """One line: the verdict and why."""
        head = f"{self.file.name}: step {self.step} ({self.path}) {self.status.upper()}"
        if self.status == ERROR:
            return f"{head}: {self.message.strip().splitlines()[-1]}"
        if self.status == FAIL and self.diagnosis is not None:
            return f"{head}: {self.diagnosis.text()}"
        return head

    def report(self) -> str:
        """Every line ``wgpurender check`` prints."""
        lines = [self.line()]
        if self.status == ERROR and "\n" in self.message.strip():
            lines.append(self.message)
        for t, m, exceeded in self.metrics:
            lines.append(f"  t={t:g}: {m.summary()}" + (f"; over the bound: {'; '.join(exceeded)}" if exceeded else ""))
        lines += [f"  {what}: {path}" for what, path in self.images.items()]
        return "\n".join(lines)


def check_file(file: Path, ex: Exercise, out: Path | None = None, timeout: float = DEFAULT_TIMEOUT) -> Verdict:
    """Render the learner's stage in its own process and judge it; images and heatmaps go to ``out``."""
    try:
        images = render_isolated(file, ex, timeout)
    except LearnerError as err:
        return Verdict(ex.step, ex.path, file, ERROR, message=str(err))
    return judge(images, ex, file, out)


def judge(images: list[np.ndarray], ex: Exercise, file: Path, out: Path | None = None) -> Verdict:
    """The verdict on the learner's images (one per time of the step); the metrics shown are against what the
    heatmaps show (expected_images)."""
    tol, rounding = step_tolerance(ex), rounding_tolerance(ex)
    metrics = []
    for k, (t, expected, solution, actual) in enumerate(zip(ex.times, expected_images(ex), _solution_images(ex),
                                                            images, strict=True)):
        m = measure(expected, actual)
        here = [f"against the solution rendered here: {e}" for e in rounding.exceeded(measure(solution, actual))]
        metrics.append((t, m, (tol.exceeded(m) if k == 0 else []) + here))
    verdict = Verdict(ex.step, ex.path, file, FAIL if any(e for _, _, e in metrics) else PASS, metrics)
    if verdict.status == FAIL:
        verdict.diagnosis = diagnose(images, ex, rounding_tolerance(ex))
    if out is not None:
        verdict.images = write_images(out, file.stem, ex, images)
    return verdict


def diagnose(images: list[np.ndarray], ex: Exercise, tol: Tolerance) -> Diagnosis:
    """The nearest catalogued mistake by FLIP, named only when it is within the step's bounds at every time."""
    best: tuple[float, bool, Mistake] | None = None
    for mistake in ex.mistakes:
        variant = mistake_images(ex, mistake.key)
        found = [measure(v, a) for v, a in zip(variant, images, strict=True)]
        flip = sum(m.flip_mean for m in found)
        within = not any(tol.exceeded(m) for m in found)
        if best is None or (within, -flip) > (best[1], -best[0]):
            best = (flip, within, mistake)
    if best is None:
        return Diagnosis(None, 0.0, None)
    flip, within, mistake = best
    return Diagnosis(mistake if within else None, flip, mistake)


def write_images(out: Path, stem: str, ex: Exercise, images: list[np.ndarray]) -> dict[str, Path]:
    from wgpurender.core.verdict.compare import heatmap_with_scale

    written = {}
    out.mkdir(parents=True, exist_ok=True)
    for t, expected, actual in zip(ex.times, expected_images(ex), images, strict=True):
        written[f"t={t:g} image"] = save_png(out / f"{stem}-t{t:g}.png", actual)
        written[f"t={t:g} heatmap"] = save_png(out / f"{stem}-t{t:g}-heatmap.png", heatmap_with_scale(expected, actual))
    return written


def reference_name(ex: Exercise) -> str:
    """The committed reference (and tolerance row) of the step: its stage's, or its scene's."""
    if ex.scene:
        from wgpurender.raw_path.make_references import SCENE_REFERENCES

        return next(name for name, file in SCENE_REFERENCES.items() if Path(file).stem == ex.scene)
    return course_step(ex.step).stage


def reference_file(ex: Exercise) -> Path:
    from wgpurender.core.files.assets import reference_dir

    return reference_dir() / f"{reference_name(ex)}.png"


@functools.cache
def _driver_class(path: str) -> str:
    if path == "wgpu":
        from wgpurender.wgpu_path.device.context import get_context

        return driver_class(get_context("Vulkan").adapter.info["device"])
    from wgpurender.raw_path.device.context import get_vulkan

    return driver_class(get_vulkan().device_name)


def step_tolerance(ex: Exercise) -> Tolerance:
    """The bounds against the committed reference: this driver class's row (two machines' spread)."""
    return tolerance(reference_name(ex), _driver_class(ex.path))


ROUNDING_CLASS = "lavapipe"  # the class whose rows measure rounding alone (see rounding_tolerance)


def rounding_tolerance(ex: Exercise) -> Tolerance:
    """The bounds that tell catalogued mistakes apart, on any adapter: the step's lavapipe row, calibrated from the
    same shaders compiled for two CPUs (rounding alone). The learner's image and every mistake are rendered on
    the same machine in the same run, so only rounding may separate two renders of equivalent code; the driver
    class's own row measures a GPU against the lavapipe-made reference (filtering hardware included: step 5's gpu
    row allows FLIP 0.058, wider than 'mips not generated' against 'one sampler', FLIP 0.044 on an H100)."""
    return tolerance(reference_name(ex), ROUNDING_CLASS)


def expected_images(ex: Exercise) -> list[np.ndarray]:
    """t = 0: the committed raw-Vulkan reference; later times: the solution rendered here (no reference is
    committed for them)."""
    return [load_png(reference_file(ex)), *_solution_images(ex)[1:]]


@functools.cache
def _solution_images(ex: Exercise) -> list[np.ndarray]:
    """The project's own stage for the step, rendered here at every time (what the learner's images must equal
    up to rounding)."""
    return render_variant(solution_source(ex), ex)


@functools.cache
def mistake_images(ex: Exercise, key: str) -> list[np.ndarray]:
    mistake = next(m for m in ex.mistakes if m.key == key)
    return render_variant(mistake_source(ex, mistake), ex)


def render_variant(source: str, ex: Exercise) -> list[np.ndarray]:
    """Our own source (the solution, a starter, a mistake): a stage in this process; a scene step's shader in a
    process of its own (it changes the process's shader folder)."""
    if not ex.shader:
        return render_source(source, ex)
    with tempfile.TemporaryDirectory(prefix="wgpurender-exercise-") as folder:
        file = Path(folder) / ex.shader
        file.write_text(source, encoding="utf-8")
        try:
            return render_isolated(file, ex)
        except LearnerError as err:  # our own variant is broken: a bug, not a verdict
            raise UserError(f"step {ex.step} ({ex.path}): a catalogue variant does not render: {err}") from None


def learner_file(name: str, ex: Exercise) -> Path:
    """The learner's file, checked before anything runs: a readable .py file (a scene step: its shader's kind)."""
    file = Path(name)
    suffix = learner_suffix(ex)
    if file.suffix != suffix:
        what = f"the scene's shader ({ex.shader})" if ex.shader else "a stage is a Python module"
        raise UserError(f"{name}: step {ex.step} is {what}: give its {suffix} file")
    if not file.is_file():
        raise UserError(f"{name}: no such file")
    return file.resolve()


def learner_suffix(ex: Exercise) -> str:
    return Path(ex.shader).suffix if ex.shader else ".py"
