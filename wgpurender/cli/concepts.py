"""wgpurender concepts: the Vulkan -> wgpu mapping table (plain text, or the markdown of docs/vulkan-mapping.md)."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "concepts",
        help="list the course's Vulkan concepts with their wgpu equivalents and where each path implements them",
        description="One entry per course concept: the Vulkan calls, the raw-Vulkan path's functions, the wgpu "
        "API, the wgpu path's functions, and what differs. NAME shows one concept (a name, a unique part of "
        "one, or a Vulkan call such as vkCreateSampler). --markdown prints docs/vulkan-mapping.md.",
    )
    p.add_argument("name", nargs="*", metavar="NAME", help="one concept, e.g. 'render pass', mipmaps, vkCmdDraw")
    p.add_argument("--markdown", action="store_true", help="print the markdown table (docs/vulkan-mapping.md)")
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.concepts import CONCEPTS, markdown, plain_text

    rows = [find_concept(" ".join(args.name))] if args.name else CONCEPTS
    print(markdown(rows) if args.markdown else plain_text(rows), end="")
    return 0


def find_concept(query: str):
    """The one concept a query names: its exact name, a unique part of a name, or a unique Vulkan/wgpu item.

    UserError listing the close names when there is none, or the candidates when there are several.
    """
    import difflib

    from wgpurender.concepts import CONCEPTS
    from wgpurender.core.errors import UserError

    q = query.strip().lower()
    by_name = {row.name.lower(): row for row in CONCEPTS}
    if q in by_name:
        return by_name[q]
    matches = [row for row in CONCEPTS if q and q in row.name.lower()]
    if not matches:  # a Vulkan/wgpu item named exactly ("vkCmdDraw") before items that merely contain it
        matches = [row for row in CONCEPTS if any(q == item.lower() for item in (*row.vulkan, *row.wgpu))]
    if not matches:
        matches = [row for row in CONCEPTS if q and any(q in item.lower() for item in (*row.vulkan, *row.wgpu))]
    if len(matches) == 1:
        return matches[0]
    if matches:
        raise UserError(f"concept {query!r} is ambiguous: it matches {', '.join(repr(r.name) for r in matches)}; "
                        "give one of these names")
    close = difflib.get_close_matches(q, list(by_name), n=5, cutoff=0.5)
    hint = f"close names: {', '.join(repr(n) for n in close)}" if close else "'wgpurender concepts' lists them all"
    raise UserError(f"unknown concept {query!r}: {hint}")
