"""wgpurender stages: list the course stages."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "stages", help="list the course stages", description="List every stage with the course step it stands for."
    )
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.wgpu_path.stages import all_stages

    stages = all_stages()
    width = max(len(n) for n in stages)
    for name, cls in stages.items():
        print(f"{name:<{width}}  {cls.summary}")
        print(f"{'':<{width}}  course step {cls.course_step()}")
    return 0
