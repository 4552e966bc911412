"""wgpurender stages: list the course's steps in order (the stages, then step 6, the final model's scene)."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "stages", help="list the course steps",
        description="List every course step in order: its stage (or, for the final model, its bundled scene) "
                    "and the course step it stands for. --map prints the course map instead: per step, the "
                    "module, shaders, course data, reference image, tests and course text of both paths "
                    "(docs/course-map.md is its output).")
    p.add_argument("--map", action="store_true", help="print the course map (a Markdown table, one row per step)")
    p.set_defaults(func=run)


def run(args) -> int:
    if args.map:
        from wgpurender.course_map import course_map_markdown

        print(course_map_markdown(), end="")
        return 0
    from wgpurender.core.course.steps import COURSE, course_step
    from wgpurender.wgpu_path.stages import all_stages

    stages = all_stages()
    rows = [(step.stage, _summary(step, stages.get(step.stage)), f"{step.number}: {step.title}") for step in COURSE]
    rows += [(name, cls.summary, cls.course_step()) for name, cls in stages.items() if course_step(name) is None]
    width = max(len(name) for name, _, _ in rows)
    for name, summary, step in rows:
        print(f"{name:<{width}}  {summary}")
        print(f"{'':<{width}}  course step {step}")
    return 0


def _summary(step, cls) -> str:
    if step.scene is not None:
        return f"the bundled scene {step.scene!r} (assets/scenes/{step.scene}.toml): wgpurender render {step.scene}"
    return cls.summary if cls is not None else "(no wgpu stage yet)"
