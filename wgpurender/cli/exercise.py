"""wgpurender exercise / wgpurender check: the learner's side of the course (wgpurender/exercises/)."""

from __future__ import annotations

from pathlib import Path

from wgpurender.cli._args import positive_float

PATH_HELP = "which path the stage is written for: wgpu (default) or raw (the raw-Vulkan reference path)"


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "exercise", help="write a starter for one course step: the step's stage with its key parts cut out",
        description="Write a starter folder for course step STEP: step_<STEP>.py (the step's stage with its key parts "
        "replaced by TODOs naming the concept to read), test_<STEP>.py (pytest checks it), README.md and goal.png "
        "(the raw-Vulkan reference). Existing files are never overwritten.")
    p.add_argument("step", metavar="STEP", help="the course step: 1a, 1b, 2a, 2b, 3a, 3b, 3c, 4, 5 or 6")
    p.add_argument("-o", "--out", metavar="DIR", default=None, help="the folder to write (default: exercise-STEP)")
    p.add_argument("--path", choices=("wgpu", "raw"), default="wgpu", help=PATH_HELP)
    p.set_defaults(func=run_exercise)

    c = subparsers.add_parser(
        "check", help="check a learner's stage against the step's reference, with a diagnosis",
        description="Render the stage in FILE headless (in its own process, with a time limit) at the step's size "
        "and times, compare it with the step's raw-Vulkan reference under the step's tolerances and print the "
        "verdict, the metrics and the heatmaps; a wrong image is matched against the step's catalogue of classic "
        "mistakes. Exit 0: pass, 1: fail, 2: bad input.")
    c.add_argument("step", metavar="STEP", help="the course step the file is for")
    c.add_argument("file", metavar="FILE", help="the learner's stage module (a .py file; step 6: the scene shader)")
    c.add_argument("--path", choices=("wgpu", "raw"), default="wgpu", help=PATH_HELP)
    c.add_argument("--out", metavar="DIR", default=None,
                   help="where images and heatmaps go (default: FILE's folder/check-STEM)")
    c.add_argument("--timeout", type=positive_float, default=None, metavar="S",
                   help="seconds the stage may take to render before it counts as hung (default 120)")
    c.set_defaults(func=run_check)


def run_exercise(args) -> int:
    from wgpurender.exercises.catalogue import exercise
    from wgpurender.exercises.starter import write_exercise

    ex = exercise(args.step, args.path)
    for path in write_exercise(ex, Path(args.out or f"exercise-{args.step}")):
        print(path)
    return 0


def run_check(args) -> int:
    from wgpurender.exercises.catalogue import exercise
    from wgpurender.exercises.check import check_file, learner_file
    from wgpurender.exercises.sandbox import DEFAULT_TIMEOUT

    ex = exercise(args.step, args.path)
    file = learner_file(args.file, ex)
    out = Path(args.out) if args.out else file.parent / f"check-{file.stem}"
    verdict = check_file(file, ex, out, args.timeout or DEFAULT_TIMEOUT)
    print(verdict.report())
    return verdict.exit_code
