"""The layering rule of docs/architecture.md, enforced from the imports (ast) of every module in wgpurender/.

Modules are classified by folder, so a module added later is classified without editing this file:

- core: ``wgpurender/core/`` (API-free: course data, scene model, plan, uniforms, image I/O, compare, tolerances);
- wgpu path: ``wgpurender/wgpu_path/``;
- raw path: ``wgpurender/raw_path/``;
- outer (the tools: cli, api, bench, verify, report, concepts, the package itself): everything else.

Every import counts, also the ones inside functions (a lazy import is still a dependency) and the ones made by
string through ``importlib.import_module("wgpurender....")``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "wgpurender"
GPU_APIS = ("wgpu", "vulkan")
CORE, WGPU, RAW = "wgpurender.core", "wgpurender.wgpu_path", "wgpurender.raw_path"
STAGE_PACKAGES = ("wgpurender.wgpu_path.stages", "wgpurender.raw_path.stages")
STAGE_IMPORTERS = ("wgpurender.cli", "wgpurender.bench", "wgpurender.wgpu_path.render", "wgpurender.raw_path.render",
                   "wgpurender.wgpu_path.window", "wgpurender.concepts")  # registry, CLI/runners, bench, mapping table
RENDERERS = ("wgpurender.wgpu_path.scene", "wgpurender.raw_path.scene", "wgpurender.wgpu_path.render",
             "wgpurender.raw_path.render")
MAX_STAGE_LINES = 150
# Known breaks, each named with its owner. The test fails when one is gone (delete its line then), so this list
# can only shrink.
PENDING: set[str] = set()


def within(module: str, prefixes) -> bool:
    prefixes = (prefixes,) if isinstance(prefixes, str) else prefixes
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def module_name(path: Path, root: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    return ".".join(parts[:-1] if is_package else parts), is_package


def imports_of(tree: ast.AST, module: str, is_package: bool, known: set[str]) -> set[str]:
    """Everything a module imports: external top-level names and wgpurender modules (``from . import x``
    counts as the submodule x when it is one)."""
    found = set()
    base = module.split(".") if is_package else module.split(".")[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = base[: len(base) - (node.level - 1)]
                prefix = ".".join(anchor + ([node.module] if node.module else []))
            else:
                prefix = node.module
            for alias in node.names:
                candidate = f"{prefix}.{alias.name}"
                found.add(candidate if candidate in known else prefix)
        elif isinstance(node, ast.Call) and _is_import_module(node.func) and node.args:
            found.update(_string_prefix(node.args[0]))
    return found


def _is_import_module(func: ast.expr) -> bool:
    """``importlib.import_module(...)``, ``import_module(...)`` or ``__import__(...)``."""
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
    return name in ("import_module", "__import__")


def _string_prefix(arg: ast.expr) -> set[str]:
    """The module named by a string argument: a constant, or an f-string's constant head
    (``f"wgpurender.wgpu_path.stages.{name}"`` imports something in that package)."""
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        return {arg.value}
    if isinstance(arg, ast.JoinedStr) and arg.values and isinstance(arg.values[0], ast.Constant):
        return {str(arg.values[0].value).rstrip(".")}
    return set()


def resolve(name: str, known: set[str]) -> str:
    """The wgpurender module an imported name lives in (``wgpurender.core.course.cubes.CubeSpec`` -> the module)."""
    while name not in known and "." in name:
        name = name.rsplit(".", 1)[0]
    return name


def import_graph(root: Path = PACKAGE) -> tuple[dict[str, set[str]], dict[str, set[str]], dict[str, Path]]:
    """(internal edges, external top-level imports, paths) for every module under ``root``."""
    files = {}
    for path in sorted(root.rglob("*.py")):
        name, is_package = module_name(path, root)
        files[name] = (path, is_package)
    known = set(files)
    internal, external = {}, {}
    for name, (path, is_package) in files.items():
        names = imports_of(ast.parse(path.read_text(encoding="utf-8")), name, is_package, known)
        internal[name] = {m for m in (resolve(n, known) for n in names if n.startswith("wgpurender")) if m != name}
        external[name] = {n.split(".")[0] for n in names if not n.startswith("wgpurender")}
    return internal, external, {name: path for name, (path, _) in files.items()}


def uses_gpu(name: str, external: dict[str, set[str]]) -> bool:
    return bool(external[name] & set(GPU_APIS))


def layer(name: str, external: dict[str, set[str]] | None = None) -> str:
    """The layer of a module, by its folder alone."""
    for prefix, kind in ((CORE, "core"), (WGPU, "wgpu"), (RAW, "raw")):
        if within(name, prefix):
            return kind
    return "outer"


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def is_stage_module(name: str) -> bool:
    return any(name.startswith(p + ".") for p in STAGE_PACKAGES) and name.rsplit(".", 1)[1] != "base"


def violations(root: Path = PACKAGE) -> list[str]:
    """Every break of the layering rule, one line each (empty when the rule holds)."""
    internal, external, paths = import_graph(root)
    out = []
    for name, targets in sorted(internal.items()):
        mine = layer(name)
        for target in sorted(targets):
            theirs = layer(target)
            if mine == "raw" and theirs == "wgpu":
                out.append(f"{name} (raw path) imports {target} (wgpu path): the two paths never import each other")
            if mine == "wgpu" and theirs == "raw":
                out.append(f"{name} (wgpu path) imports {target} (raw path): the two paths never import each other")
            if mine in ("core", "raw", "wgpu") and theirs == "outer":
                out.append(f"{name} imports {target} (outer): only the tools (cli, api, bench, verify, report) "
                           "import the tools")
            if mine == "core" and theirs in ("raw", "wgpu"):
                out.append(f"{name} (core) imports {target} ({theirs} path): the core imports no path")
            if is_stage_module(target) and not (within(name, STAGE_IMPORTERS) or within(name, STAGE_PACKAGES)
                                                and not is_stage_module(name)):
                out.append(f"{name} imports the stage {target}: only the registry, the CLI/runners and the bench may")
            if is_stage_module(name) and is_stage_module(target):
                out.append(f"{name} imports the stage {target}: stages are leaves")
        if mine == "core" and uses_gpu(name, external):
            out.append(f"{name} (core) imports a GPU API: the core is API-free")
    for component in cycles(internal):
        out.append("import cycle: " + " <-> ".join(component))
    for name, path in sorted(paths.items()):
        if is_stage_module(name):
            lines = len(path.read_text(encoding="utf-8").splitlines())
            if lines > MAX_STAGE_LINES:
                out.append(f"{name} has {lines} lines: a stage module reads as its course step in <= {MAX_STAGE_LINES}")
    return out


def test_the_layering_rule_holds():
    found = violations()
    assert [v for v in found if v not in PENDING] == []
    assert sorted(PENDING - set(found)) == [], "fixed: remove these from PENDING"


def test_the_course_core_is_api_free():
    """Direct check of the core package, whatever the classification above says."""
    _, external, _ = import_graph()
    course = {n: external[n] & set(GPU_APIS) for n in external if within(n, "wgpurender.core.course")}
    assert course and not any(course.values()), course


# -- the rule can fail: each case is a copy of the package with one injected violation --------------------------

INJECTED = [
    ("raw_path/stages/cube3d.py", "from wgpurender.wgpu_path.stages import cube3d\n",
     "(raw path) imports wgpurender.wgpu_path.stages.cube3d"),
    ("wgpu_path/stages/cube3d.py", "from wgpurender.raw_path.device import images\n",
     "(wgpu path) imports wgpurender.raw_path.device.images"),
    ("core/course/cubes.py", "import wgpu\n", "(core) imports a GPU API"),
    ("core/course/cubes.py", "from wgpurender.wgpu_path.stages import triangle\n",
     "(core) imports wgpurender.wgpu_path.stages.triangle"),
    ("core/course/cubes.py", "from wgpurender.cli import _args\n", "only the tools"),
    ("core/course/cubes.py", "import importlib\nimportlib.import_module('wgpurender.wgpu_path.device.context')\n",
     "(core) imports wgpurender.wgpu_path.device.context"),
    ("core/plan/build.py", "from importlib import import_module\nimport_module(f'wgpurender.raw_path.stages.{x}')\n",
     "(core) imports wgpurender.raw_path.stages"),
    ("core/view/transforms.py", "from wgpurender.core.course import cubes\n", "import cycle"),
    ("wgpu_path/stages/base.py", "from wgpurender.wgpu_path.stages import all_stages\n",
     "import cycle: wgpurender.wgpu_path.stages <-> wgpurender.wgpu_path.stages.base"),
    ("wgpu_path/stages/msaa.py", "from wgpurender.wgpu_path.stages.triangle import Triangle\n", "stages are leaves"),
    ("wgpu_path/scene/scene_pass.py", "from wgpurender.wgpu_path.stages.cube3d import Cube3D\n",
     "only the registry"),
    ("wgpu_path/stages/triangle.py", "\n" * 200, "lines: a stage module"),
]


@pytest.mark.parametrize("relative, line, message", INJECTED, ids=[f"{r}:{m[:24]}" for r, _, m in INJECTED])
def test_an_injected_violation_is_found(tmp_path, relative, line, message):
    import shutil

    copy = tmp_path / "wgpurender"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    target = copy / relative
    target.write_text(target.read_text(encoding="utf-8") + line, encoding="utf-8")
    found = violations(copy)
    assert any(message in v for v in found), found


# -- course order ----------------------------------------------------------------------------------------------


def _step_key(number: str) -> tuple[int, str]:
    """'3b' -> (3, 'b'): the course numbers its steps, chapter then letter."""
    digits = number.rstrip("abcdefghijklmnopqrstuvwxyz")
    return int(digits), number[len(digits):]


def test_both_registries_and_the_cli_list_stages_in_course_order(capsys):
    """Each registry lists its stages by the course's step numbers (course/steps.py numbers them; the
    order is checked from the numbers, not from the table's row order), the course's own sequence of the
    wgpu steps is the list below, and `wgpurender stages` prints the stages in that order."""
    from wgpurender.cli import main
    from wgpurender.core.course.steps import course_step
    from wgpurender.raw_path.stages import all_ref_stages
    from wgpurender.wgpu_path.stages import all_stages

    for registry in (all_stages(), all_ref_stages()):
        names = list(registry)
        assert all(course_step(n) for n in names), [n for n in names if not course_step(n)]
        assert names == sorted(names, key=lambda n: _step_key(course_step(n).number))
    course = ["clear", "clear-pass", "triangle", "triangle-buffers", "offscreen", "msaa", "msaa-post", "3d", "textured"]
    assert list(all_stages()) == [n for n in course if n in all_stages()]
    assert main(["stages"]) == 0
    printed = [line.split()[0] for line in capsys.readouterr().out.splitlines() if not line.startswith(" ")]
    assert printed == [*course, "final"]  # step 6, the final model, is the bundled scene 'final'
    assert course_step("final").number == "6" and course_step("final").scene == "final"


# -- the package graph of docs/architecture.md, generated from the same imports ----------------------------------

LAYER_TITLES = {"outer": "outer: the tools (may import everything below)",
                "wgpu": "wgpu path (imports the core, wgpu, itself)",
                "raw": "raw path (imports the core, vulkan, itself)",
                "core": "API-free core (imports the core only; numpy, pillow, trimesh)"}
FORBIDDEN = (("wgpu", "raw"), ("raw", "wgpu"), ("core", "wgpu"), ("core", "raw"), ("core", "outer"),
             ("wgpu", "outer"), ("raw", "outer"))
GRAPH_START = "<!-- package graph: generated by `python tests/test_layering.py`; tests/test_layering.py checks it -->"
GRAPH_END = "<!-- end of the generated package graph -->"


LAYER_FOLDERS = ("core", "wgpu_path", "raw_path")


def package_of(name: str, packages: set[str]) -> str:
    """A module's box in the diagram: its subpackage (``wgpu_path/stages/``, ``cli/``), the loose modules of a layer
    folder together (``wgpu_path/*.py``), or a loose top-level module (``api.py``)."""
    parts = name.split(".")[1:]
    if parts and parts[0] in LAYER_FOLDERS:
        if len(parts) >= 3 or (len(parts) == 2 and name in packages):
            return f"{parts[0]}/{parts[1]}/"
        return f"{parts[0]}/*.py"
    if not parts or parts == ["__main__"]:
        return "__init__.py, __main__.py"
    return parts[0] + "/" if len(parts) >= 2 or name in packages else parts[0] + ".py"


def _wrapped(prefix: str, items: list[str], width: int = 116) -> list[str]:
    lines, line = [], prefix
    for k, item in enumerate(items):
        piece = item + (", " if k < len(items) - 1 else "")
        if len(line) + len(piece.rstrip()) > width and line.strip() != prefix.strip():
            lines.append(line.rstrip())
            line = " " * len(prefix)
        line += piece
    return lines + [line.rstrip()]


def package_graph(root: Path = PACKAGE) -> str:
    """Every box of the tree by layer, with the boxes it imports and how many module imports cross each layer
    boundary: the diagram of docs/architecture.md, which therefore cannot drift from the tree."""
    internal, _, paths = import_graph(root)
    packages = {n for n, p in paths.items() if p.name == "__init__.py"}
    box = {n: package_of(n, packages) for n in internal}
    boxes: dict[str, set[str]] = {b: set() for b in box.values()}
    counts: dict[tuple[str, str], int] = {}
    for name, targets in internal.items():
        for target in targets:
            if box[target] != box[name]:
                boxes[box[name]].add(box[target])
            if layer(target) != layer(name):
                counts[layer(name), layer(target)] = counts.get((layer(name), layer(target)), 0) + 1
    layer_of_box = {box[n]: layer(n) for n in internal}
    lines = []
    for kind in ("outer", "wgpu", "raw", "core"):
        lines.append(LAYER_TITLES[kind])
        for b in sorted(b for b in boxes if layer_of_box[b] == kind):
            members = sorted(m for m in box if box[m] == b)
            lines.append(f"  {b}")
            if b.endswith("*.py"):
                lines += _wrapped("      = ", [m.rsplit(".", 1)[1] for m in members])
            lines += _wrapped("      -> ", sorted(boxes[b]) or ["(nothing of ours)"])
        lines.append("")
    crossings = [f"{a} -> {b}: {counts.get((a, b), 0)}" for a, b in FORBIDDEN]
    lines += _wrapped("forbidden imports (module count): ", crossings)
    top = len([p for p in root.iterdir() if p.suffix == ".py" or (p / "__init__.py").is_file()])  # modules, packages
    lines.append(f"import cycles: {len(cycles(internal))}; top level of wgpurender/: {top} entries")
    return "\n".join(lines) + "\n"


def _doc_graph(text: str) -> str:
    start, end = text.index(GRAPH_START), text.index(GRAPH_END)
    block = text[start + len(GRAPH_START):end].strip("\n")
    assert block.startswith("```") and block.endswith("```"), "the graph is one fenced block between the markers"
    return block.split("\n", 1)[1].rsplit("```", 1)[0]


def test_the_architecture_doc_shows_the_generated_package_graph():
    doc = (PACKAGE.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    assert _doc_graph(doc) == package_graph(), "regenerate: python tests/test_layering.py --write"


def test_the_package_graph_shows_the_rule():
    """Read from the generated text, not from violations(): no arrow between the paths, none out of the core,
    no cycle, at most ~20 entries at the top of the package."""
    import re

    graph = package_graph()
    counts = {(a, b): int(n) for a, b, n in re.findall(r"(\w+) -> (\w+): (\d+)", graph)}
    assert set(counts) == set(FORBIDDEN) and not any(counts.values()), counts
    assert "import cycles: 0;" in graph
    top = int(graph.rsplit("top level of wgpurender/: ", 1)[1].split()[0])
    assert top <= 20, top


def write_doc(path: Path = PACKAGE.parent / "docs" / "architecture.md") -> None:
    text = path.read_text(encoding="utf-8")
    start, end = text.index(GRAPH_START) + len(GRAPH_START), text.index(GRAPH_END)
    path.write_text(text[:start] + "\n```\n" + package_graph() + "```\n" + text[end:], encoding="utf-8")


if __name__ == "__main__":
    import sys

    write_doc() if "--write" in sys.argv else print(package_graph(), end="")
