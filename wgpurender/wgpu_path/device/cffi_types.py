"""A fast path for the C type names wgpu-py hands to cffi: 0.1 s per new struct type becomes microseconds.

wgpu-py makes every descriptor with ``ffi.new("WGPUSomething *")``. cffi parses such a string
with pycparser the first time it sees it, and every parse re-reads a prelude that declares all
of wgpu.h's ~440 typedef names: about 10-100 ms per type (on the machine and its load), and a
frame or a pipeline needs dozens of distinct types. That was most of the wgpu path's set-up and
first-frame time (profile in docs/benchmarks.md: 74 parses, more than the rest of a
``render final.toml`` together).

For the three shapes wgpu-py uses with a typedef'd name or a C primitive (``uint8_t``, ``void``...),
``NAME``, ``NAME *`` and ``NAME[]``, the parse has a known answer: cffi's own parser resolves a typedef
name to its declaration (``_declarations["typedef NAME"]``, the first branch of
``Parser._get_type_and_quals``), a primitive through ``commontypes.resolve_common_type``, a ``*`` to
``model.PointerType(that, quals)``, ``[]`` to ``model.ArrayType(that, None)``. We build those
directly and hand every other string to the real parser; tests/test_cffi_types.py checks the
fast answer equals the parser's for every typedef of wgpu.h. This uses cffi internals
(``ffi._parser``): if they are missing, nothing is installed.
"""

from __future__ import annotations

import re

_SHAPE = re.compile(r"^\s*([A-Za-z_]\w*)\s*(\*|\[\s*\])?\s*$")
_CONST_POINTER = re.compile(r"^\s*([A-Za-z_]\w*)\s+const\s*\*\s*$")
_FUNCTION = re.compile(r"^\s*([A-Za-z_]\w*)\s*\(([^()]*)\)\s*$")


def fast_parse_type_and_quals(parser, cdecl: str):
    """(model type, quals) for NAME, NAME * or NAME[] of a declared typedef (or a primitive), ``NAME const *``,
    and a callback's function type ``RET(ARG, ARG...)`` made of those; None for anything else."""
    from cffi import model

    m = _SHAPE.match(cdecl)
    if m is None:
        c = _CONST_POINTER.match(cdecl)
        if c is not None:
            return _const_pointer(parser, c.group(1))
        f = _FUNCTION.match(cdecl)
        return _function(parser, f.group(1), f.group(2)) if f is not None else None
    name = m.group(1)
    entry = parser._declarations.get("typedef " + name)
    if entry is None:
        entry = _primitive(parser, name)
    if entry is None:
        return None
    tp, quals = entry
    suffix = m.group(2)
    if suffix is None:
        return tp, quals
    if suffix == "*":
        return parser._get_type_pointer(tp, quals), 0
    return model.ArrayType(tp, None), quals


def _const_pointer(parser, name: str):
    """``NAME const *``: a pointer to the const-qualified item (cffi: PtrDecl of a TypeDecl with quals const)."""
    from cffi.model import Q_CONST

    entry = parser._declarations.get("typedef " + name) or _primitive(parser, name)
    if entry is None:
        return None
    tp, quals = entry
    return parser._get_type_pointer(tp, quals | Q_CONST), 0


def _function(parser, result: str, args: str):
    """A function type as cffi's ``_parse_function_type`` makes it (no ellipsis, no __stdcall), or None."""
    from cffi import model

    res = fast_parse_type_and_quals(parser, result)
    if res is None or "..." in args or isinstance(res[0], model.RawFunctionType):
        return None
    parsed = []
    for arg in (a for a in args.split(",")) if args.strip() else ():
        one = fast_parse_type_and_quals(parser, arg)
        if one is None or isinstance(one[0], model.RawFunctionType):
            return None
        parsed.append(parser._as_func_arg(*one))
    if parsed == [model.void_type]:
        parsed = []
    return model.RawFunctionType(tuple(parsed), res[0], False, None), 0


def _primitive(parser, name: str):
    """(type, quals) of ``void`` or a C primitive such as uint8_t, as the parser's common-type branch gives them."""
    from cffi import model
    from cffi.commontypes import resolve_common_type

    if name == "void":
        return model.void_type, 0
    if name in model.PrimitiveType.ALL_PRIMITIVE_TYPES:
        return resolve_common_type(parser, name)
    return None


def install(ffi) -> bool:
    """Give ``ffi``'s parser the fast path (once); False where cffi's internals differ."""
    parser = getattr(ffi, "_parser", None)
    original = getattr(parser, "parse_type_and_quals", None)
    if original is None or not hasattr(parser, "_declarations") or not hasattr(parser, "_get_type_pointer"):
        return False
    if getattr(original, "_wgpurender_fast", False):
        return True

    def parse_type_and_quals(cdecl):
        return fast_parse_type_and_quals(parser, cdecl) or original(cdecl)

    parse_type_and_quals._wgpurender_fast = True
    parse_type_and_quals.original = original
    parser.parse_type_and_quals = parse_type_and_quals
    return True


def install_for_wgpu() -> bool:
    from wgpurender.wgpu_path.device.wgpu_private import native

    try:
        ffi, _ = native()
    except ImportError:
        return False
    return install(ffi)
