"""Shader variants: one WGSL template, specialised by the features a material actually uses.

WGSL has ``override`` constants, but they cannot remove a binding, a vertex
attribute or a struct member, and the render plan promises exactly that (no
tangent attribute and no normal-map texture when no material has a normal map).
So variants come from a tiny preprocessor over the template, line by line:

    #if FEATURE            keep the following lines when FEATURE is on
    #if !FEATURE           ... when it is off
    #else / #endif
    {{NAME}}               replaced by a value (e.g. the generated uniform structs)

Nesting is allowed. Anything else starting with '#' is an error, so a typo in
a directive cannot silently drop code.
"""

from __future__ import annotations

import re

from wgpurender.core.errors import UserError

_PLACEHOLDER = re.compile(r"\{\{([A-Za-z_][A-Za-z0-9_]*)\}\}")


def specialise(template: str, features: frozenset[str] | set[str], values: dict[str, str] | None = None,
               name: str = "shader") -> str:
    """The template with #if blocks resolved for ``features`` and {{placeholders}} filled in."""
    out: list[str] = []
    stack: list[tuple[bool, bool]] = []  # (this block's condition, all enclosing blocks active)
    active = True
    for number, line in enumerate(template.splitlines(), start=1):
        directive = line.strip()
        if directive.startswith("#if "):
            cond = directive[4:].strip()
            want = not cond.startswith("!")
            on = (cond.lstrip("!") in features) == want
            stack.append((on, active))
            active = active and on
        elif directive == "#else":
            if not stack:
                raise UserError(f"{name}:{number}: #else without #if")
            on, outer = stack[-1]
            stack[-1] = (not on, outer)
            active = outer and not on
        elif directive == "#endif":
            if not stack:
                raise UserError(f"{name}:{number}: #endif without #if")
            _, active = stack.pop()
        elif directive.startswith("#"):
            raise UserError(f"{name}:{number}: unknown directive {directive.split()[0]!r}")
        elif active:
            out.append(line)
    if stack:
        raise UserError(f"{name}: {len(stack)} #if block(s) without #endif")
    text = "\n".join(out) + "\n"
    values = values or {}

    def fill(match: re.Match) -> str:
        key = match.group(1)
        if key not in values:
            raise UserError(f"{name}: no value for placeholder {{{{{key}}}}}")
        return values[key]

    return _PLACEHOLDER.sub(fill, text)
