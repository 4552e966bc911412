"""wgpurender concepts: the Vulkan -> wgpu mapping table (plain text, or the markdown of docs/vulkan-mapping.md)."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "concepts",
        help="list the course's Vulkan concepts with their wgpu equivalents and where each path implements them",
        description="One entry per course concept: the Vulkan calls, the raw-Vulkan path's functions, the wgpu "
        "API, the wgpu path's functions, and what differs. --markdown prints docs/vulkan-mapping.md.",
    )
    p.add_argument("--markdown", action="store_true", help="print the markdown table (docs/vulkan-mapping.md)")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..concepts import markdown, plain_text

    print(markdown() if args.markdown else plain_text(), end="")
    return 0
