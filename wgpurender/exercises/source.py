"""Source text of an exercise: the solution (the project's own stage), the starter cut from it, and the mistakes.

All three come from the solution module's file by exact snippet replacement (catalogue.py), so a change to a
stage changes its starter and its mistakes with it; a snippet that no longer matches is an error here (and a
test failure), never a stale copy.
"""

from __future__ import annotations

import inspect
from pathlib import Path

from wgpurender.core.course.steps import COURSE, step_texts
from wgpurender.core.errors import UserError
from wgpurender.exercises.catalogue import Exercise, Mistake, Part


def course_step(number: str):
    """The course's Step for a step number ("2a"), or a UserError listing them."""
    for step in COURSE:
        if step.number == number:
            return step
    raise UserError(f"unknown step {number!r}: the course's steps are {', '.join(s.number for s in COURSE)} "
                    "(wgpurender stages)")


def solution_class(ex: Exercise) -> type:
    """The project's stage class for the exercise's step and path (the registries: the stages are not imported
    one by one here)."""
    stage = course_step(ex.step).stage
    if ex.path == "wgpu":
        from wgpurender.wgpu_path.stages import get_stage

        return get_stage(stage)
    from wgpurender.raw_path.stages import get_ref_stage

    return get_ref_stage(stage)


def solution_file(ex: Exercise) -> Path:
    """The stage module's file, or for a scene step the path's shader file (the wheel's or the checkout's)."""
    if ex.shader:
        return shader_folder(ex.path) / ex.shader
    return Path(inspect.getsourcefile(solution_class(ex)))


def shader_folder(path: str) -> Path:
    """The path's shader folder as shipped (never a $WGPURENDER_SHADERS/$WGPURENDER_GLSL override)."""
    from wgpurender.core.shaders.shader_files import checkout_folder, packaged_folder

    kind = "wgsl" if path == "wgpu" else "glsl"
    return packaged_folder(kind) or checkout_folder(kind)


def solution_source(ex: Exercise) -> str:
    return solution_file(ex).read_text(encoding="utf-8")


def replace_once(source: str, old: str, new: str, what: str) -> str:
    """``source`` with its one occurrence of ``old`` replaced; an error when there is none or several."""
    count = source.count(old)
    if count != 1:
        raise ValueError(f"{what}: the snippet {old[:60]!r} occurs {count} times in the solution, not once")
    return source.replace(old, new)


def todo_lines(ex: Exercise, part: Part) -> str:
    """The TODO comment a starter has where a part was cut out, indented like the part."""
    indent, c = part.old[: len(part.old) - len(part.old.lstrip())], ex.comment
    texts = "; ".join(f"{name} ({where})" for name, where in step_texts(course_step(ex.step))) or "the course"
    return (f"{indent}{c} TODO (step {ex.step}, concept {part.concept!r} in `wgpurender concepts`): {part.todo}.\n"
            f"{indent}{c}   course text: {texts}\n")


def starter_source(ex: Exercise) -> str:
    """The solution with every part replaced by its TODO and stub: it runs, and fails its check."""
    source = solution_source(ex)
    for part in ex.parts:
        indent = part.old[: len(part.old) - len(part.old.lstrip())]
        stub = part.stub or f"{indent}pass\n"
        source = replace_once(source, part.old, todo_lines(ex, part) + stub, f"step {ex.step} part {part.concept!r}")
    what = f"the scene's {ex.shader}" if ex.shader else "a stage"
    lines = [f"Exercise: course step {ex.step} on the {ex.path} path. Fill in the TODOs, then run",
             f"    wgpurender check {ex.step} {{this file}} --path {ex.path}",
             f"docs/exercises.md says what {what} must provide."]
    if ex.shader:  # a shader keeps its first line (a GLSL #version must come first)
        first, _, rest = source.partition("\n")
        return first + "\n" + "".join(f"// {line}\n" for line in lines) + rest
    return '"""' + "\n".join(lines) + '"""\n\n' + _without_docstring(source)


def _without_docstring(source: str) -> str:
    """The module without its docstring (the solution's explains the answer)."""
    if source.startswith('"""'):
        end = source.index('"""', 3) + 3
        return source[end:].lstrip("\n")
    return source


def mistake_source(ex: Exercise, mistake: Mistake) -> str:
    return replace_once(solution_source(ex), mistake.old, mistake.new, f"step {ex.step} mistake {mistake.key!r}")
