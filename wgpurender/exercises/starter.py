"""``wgpurender exercise``: a starter folder for one course step (the learner's file, its test, a README, the goal).

Nothing already there is overwritten: a folder that holds any of the files is refused, so a learner's work is
never clobbered by a second run. A symbolic link as the folder is refused as every writer refuses it
(core/files/owned_files.resolve_folder: followed only with $WGPURENDER_FOLLOW_SYMLINKS=1).
"""

from __future__ import annotations

import os
from pathlib import Path

from wgpurender.core.errors import UserError
from wgpurender.core.files.owned_files import resolve_folder
from wgpurender.core.files.safe_write import atomic_write
from wgpurender.exercises.catalogue import Exercise
from wgpurender.exercises.source import course_step, starter_source


def file_names(ex: Exercise) -> dict[str, str]:
    stage = ex.shader or f"step_{ex.step}.py"
    return {"stage": stage, "test": f"test_{ex.step}.py", "readme": "README.md", "goal": "goal.png"}


def test_source(ex: Exercise) -> str:
    names = file_names(ex)
    return (f'"""Checks {names["stage"]} against the course\'s raw-Vulkan reference (the wgpurender pytest plugin).\n\n'
            f"Run: pytest {names['test']}   (or: wgpurender check {ex.step} {names['stage']} --path {ex.path})\n"
            '"""\n\nfrom pathlib import Path\n\n\n'
            f"def test_step_{ex.step}(wgpurender_check):\n"
            f'    wgpurender_check(Path(__file__).with_name("{names["stage"]}"), step="{ex.step}", path="{ex.path}")\n')


def readme(ex: Exercise) -> str:
    step, names = course_step(ex.step), file_names(ex)
    todos = "\n".join(f"- {part.todo} (concept: `{part.concept}`, see `wgpurender concepts`)" for part in ex.parts)
    return (f"# Course step {ex.step}: {step.title} ({ex.path} path)\n\n"
            f"Your image must match the goal, made by the raw-Vulkan reference path:\n\n![goal](goal.png)\n\n"
            f"Fill in the TODOs of `{names['stage']}`:\n\n{todos}\n\n"
            f"Then check it: `wgpurender check {ex.step} {names['stage']} --path {ex.path}` or "
            f"`pytest {names['test']}`.\n"
            "When the image is wrong, the check says which classic mistake it looks like.\n")


def write_exercise(ex: Exercise, out: Path) -> list[Path]:
    """Write the starter folder; the paths written."""
    from wgpurender.exercises.check import reference_file

    names = file_names(ex)
    out = resolve_folder(Path(out), "-o")
    taken = [name for name in names.values() if os.path.lexists(out / name)]  # a dangling link's name is taken
    if taken:
        raise UserError(f"{out / taken[0]} exists: choose another folder with -o (your work is never overwritten)")
    if out.exists() and not out.is_dir():
        raise UserError(f"{out} is not a folder: choose a folder with -o")
    out.mkdir(parents=True, exist_ok=True)
    written = [atomic_write(out / names["stage"], starter_source(ex).encode()),
               atomic_write(out / names["test"], test_source(ex).encode()),
               atomic_write(out / names["readme"], readme(ex).encode())]
    written.append(atomic_write(out / names["goal"], reference_file(ex).read_bytes()))  # never through a link
    return written
