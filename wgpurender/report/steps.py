"""One course step of the report: render it on both paths, compare, time, and find its words and concept rows.

A step is a stage (by name) or a scene file. Where the raw path cannot draw a step (a
stage it does not have, a post effect that reads neighbouring pixels), the section says
why with the raw path's own error text instead of an image; the same goes for the wgpu path.
"""

from __future__ import annotations

import inspect
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpurender.concepts import Concept
from wgpurender.core.errors import UserError
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY
from wgpurender.core.scene.credits import scene_credits
from wgpurender.core.verdict.compare import Comparison, compare_images, heatmap
from wgpurender.report import code, timings
from wgpurender.report.concept_rows import REPO_ROOT, rows_for
from wgpurender.report.timings import Timing
from wgpurender.wgpu_path.device.context import GPUContext

LARGE_SCALE = 2
HEATMAP_GAIN = 32.0  # as `wgpurender compare`: a 1/255 difference shows as 32/255


@dataclass
class Step:
    """Everything one section of the page shows."""

    key: str  # a stage name, or a scene file's stem
    title: str
    course_step: str
    summary: str
    words: list[str]  # paragraphs
    wgpu: np.ndarray | None = None
    raw: np.ndarray | None = None
    wgpu_note: str = ""
    raw_note: str = ""
    comparison: Comparison | None = None
    heat: np.ndarray | None = None
    timing: dict[str, Timing | None] = field(default_factory=dict)
    concepts: list[Concept] = field(default_factory=list)
    plan: str = ""  # the --explain text, scenes only
    code: dict[str, list[code.Excerpt]] = field(default_factory=dict)  # "wgpu"/"raw": the lines that make it
    lanes: list[tuple[str, float]] = field(default_factory=list)  # labels under the images: (text, width share)
    links: list[tuple[str, str]] = field(default_factory=list)  # (text, href): more views of this step (a hook)
    missing: str = ""  # one line: why this step is not rendered (the tutorial's files are absent)
    diffs: dict = field(default_factory=dict)  # "wgpu"/"raw": report.diffs.CodeDiff from the previous step
    large: dict = field(default_factory=dict)  # "wgpu"/"raw": the image at twice the size, what a click opens
    credits: list[str] = field(default_factory=list)  # attribution lines for files it shows (core/files/credits.py)


def larger(size: tuple[int, int]) -> tuple[int, int]:
    """The size of the image a click on a step's picture opens: twice the page's, for a projector's zoom."""
    return (LARGE_SCALE * size[0], LARGE_SCALE * size[1])


def textured_lanes() -> list[tuple[str, float]]:
    """The textured stage's image, left to right: the combined sampler's half, then one lane per sampler."""
    from wgpurender.core.course.textured import COMBINED_SAMPLER, SEPARATE_SAMPLERS

    combined = f"combined image sampler ({COMBINED_SAMPLER.max_anisotropy}x anisotropic, mirror-repeat)"
    share = 0.5 / len(SEPARATE_SAMPLERS)
    return [(combined, 0.5)] + [(name, share) for name, _ in SEPARATE_SAMPLERS]


def _paragraphs(doc: str | None) -> list[str]:
    text = inspect.cleandoc(doc or "")
    return [" ".join(p.split()) if not p.lstrip().startswith("-") else p for p in text.split("\n\n") if p.strip()]


def _try(what, log) -> tuple[object | None, str]:
    """(value, "") or (None, the one-line reason) for a UserError (what the path cannot do)."""
    try:
        return what(), ""
    except UserError as err:
        log(f"  {err}")
        return None, str(err).splitlines()[0]


def stage_step(ctx: GPUContext, name: str, size: tuple[int, int], log=print) -> Step:
    """A stage: the wgpu stage and the raw stage of the same name (either may be missing)."""
    from wgpurender.raw_path import render_reference
    from wgpurender.raw_path.stages import all_ref_stages
    from wgpurender.wgpu_path.render import render_stage
    from wgpurender.wgpu_path.stages import all_stages

    cls = all_stages().get(name)
    ref_cls = all_ref_stages().get(name)
    main = cls or ref_cls
    module = sys.modules[main.__module__]
    from wgpurender.core.course.steps import course_step

    number = course_step(name)
    step = Step(name, name, f"course step {number.number}: {number.title}" if number else "", main.summary,
                _paragraphs(module.__doc__))
    if cls is not None:
        step.wgpu = render_stage(name, size, ctx=ctx, frames=1).pixels
        step.large["wgpu"] = render_stage(name, larger(size), ctx=ctx, frames=1).pixels
        step.timing["wgpu"] = timings.stage_wgpu(ctx, name, size)
    else:
        step.wgpu_note = "the wgpu path has no stage of this name yet"
    if ref_cls is not None:
        step.raw, step.raw_note = _try(lambda: render_reference(name, size), log)
        step.timing["raw"] = timings.stage_raw(name, size) if step.raw is not None else None
        if step.raw is not None:
            step.large["raw"] = render_reference(name, larger(size))
    else:
        step.raw_note = "the raw-Vulkan path has no stage of this name"
    modules = tuple(m for m in (cls and cls.__module__, ref_cls and ref_cls.__module__) if m)
    step.concepts = rows_for(name, tuple(m.removeprefix("wgpurender.") for m in modules))
    step.code = code.excerpts(code.stage_locations(cls, ref_cls))
    if name == "textured":
        step.lanes = textured_lanes()
    _compare(step)
    return step


def _scene_course_step(path: Path) -> str:
    """'course step 6: ...' for the scene a course step is (the final model), else 'scene file'."""
    from wgpurender.core.course.steps import COURSE

    step = next((s for s in COURSE if s.scene == path.stem), None)
    return f"course step {step.number}: {step.title}" if step else "scene file"


def scene_step(ctx: GPUContext, path: Path, size: tuple[int, int] | None, log=print,
               anisotropy: str = DEFAULT_ANISOTROPY) -> Step:
    """A scene file: its description, the plan drawn on this adapter, and the scene on both paths (each
    path's plan resolved for its own adapter by the one function, core/plan/resolve.py)."""
    from wgpurender.core.plan import resolve_plan
    from wgpurender.raw_path import render_reference
    from wgpurender.wgpu_path.scene import render_plan

    plan = resolve_plan(path, ctx.adapter_facts(), size=size, anisotropy=anisotropy)
    text = plan.explain().replace(f"{REPO_ROOT}{os.sep}", "")  # no build machine's paths
    step = Step(path.stem, path.name, _scene_course_step(path), plan.scene.description, _scene_words(path), plan=text)
    step.wgpu = render_plan(ctx, plan, frames=1).pixels
    large = resolve_plan(path, ctx.adapter_facts(), size=larger(plan.size), anisotropy=anisotropy)
    step.large["wgpu"] = render_plan(ctx, large, frames=1).pixels
    step.timing["wgpu"] = timings.scene_wgpu(ctx, path, size, anisotropy)
    step.raw, step.raw_note = _try(lambda: render_reference(str(path), size, anisotropy=anisotropy), log)
    step.timing["raw"] = timings.scene_raw(path, size, anisotropy) if step.raw is not None else None
    if step.raw is not None:
        step.large["raw"] = render_reference(str(path), large.size, anisotropy=anisotropy)
    step.concepts = rows_for("scene")
    step.code = code.excerpts(code.scene_locations())
    step.credits = [c.line() for c in scene_credits(path)]
    _compare(step)
    return step


def missing_scene_step(path: Path, reason: str) -> Step:
    """A scene that cannot be rendered here (the tutorial's model and texture are absent): one line says so."""
    return Step(path.stem, path.name, "scene file", "not rendered on this machine", [], missing=reason,
                code=code.excerpts(code.scene_locations()), credits=[c.line() for c in scene_credits(path)])


def _scene_words(path: Path) -> list[str]:
    """The scene file's leading comment block, as a paragraph."""
    lines = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.startswith("#"):
            break
        lines.append(line.lstrip("# ").rstrip())
    return [" ".join(lines)] if lines else []


def _compare(step: Step) -> None:
    if step.wgpu is None or step.raw is None:
        return
    if step.wgpu.shape != step.raw.shape or step.wgpu.dtype != np.uint8 or step.raw.dtype != np.uint8:
        step.raw_note = f"not compared: wgpu {step.wgpu.shape} {step.wgpu.dtype}, raw {step.raw.shape} {step.raw.dtype}"
        return
    step.comparison = compare_images(step.raw, step.wgpu)
    step.heat = heatmap(step.raw, step.wgpu, HEATMAP_GAIN)


def heatmap_scale(block: int = 24, height: int = 14) -> tuple[np.ndarray, list[int]]:
    """The heatmap's colour scale, drawn by :func:`~wgpurender.core.verdict.compare.heatmap` itself: (image, levels).

    8-bit images differ in whole steps of 1/255, so the scale is one block per step, from 0 to
    the first step that saturates (255 / gain rounded up: 8 at gain 32, white and above).
    """
    levels = list(range(int(np.ceil(255.0 / HEATMAP_GAIN)) + 1))
    ref = np.zeros((1, len(levels), 3), np.uint8)
    test = np.array(levels, np.uint8)[None, :, None].repeat(3, axis=2)
    row = heatmap(ref, test, HEATMAP_GAIN)[0]
    image = np.repeat(np.repeat(row[None], height, axis=0), block, axis=1)
    return image, levels
