"""The course map: per course step, where it lives on both paths, generated from the code.

One row per step of the course table (core/course/steps.py): the wgpu module and the WGSL it names, the raw
module and the GLSL it names, the course data it imports (core/course/), the committed reference image, the
tests that check it and the course text it comes from. Nothing here is written by hand except the texts'
names (steps.py's STEP_TEXTS: the texts live in ../shared/course, outside the repository, and are named,
never read). ``wgpurender stages --map`` prints it; docs/course-map.md is this output (a test keeps it current).

How each column is found:
- modules: the stage registries (the stage class's module); step 6 (a scene) is drawn by the scene
  renderer's packages, wgpu_path/scene + post and raw_path/scene;
- shaders: string constants in those modules, and in the loose modules of their path folder they import
  (textures.py's mip-chain shader), and defaults of the base-class methods they call, that are whole shader
  file names; an f-string such as ``f"post_{name}.wgsl"`` stands for the files it can match;
- course data: the ``wgpurender.core.course`` modules they import;
- reference: ``assets/reference/<stage>.png``, or for a scene step the scene references made from its scene
  files (raw_path/make_references.SCENE_REFERENCES);
- tests: the test files that import the step's modules or name the stage (a string passed to a call, alone or
  in a list: its name, its scene file or its reference). The wheel carries no tests/: there the column says so.
"""

from __future__ import annotations

import ast
import fnmatch
import functools
import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from wgpurender.core.course.steps import COURSE, Step, step_texts
from wgpurender.core.files.assets import CHECKOUT, reference_dir, scene_dir
from wgpurender.core.shaders.shader_files import shader_folder

PACKAGE = Path(__file__).resolve().parent
TESTS = CHECKOUT / "tests"
SHADER_NAME = re.compile(r"[\w*]+\.(wgsl|vert|frag|comp)")
META_TESTS = ("test_course_map.py", "test_layering.py")  # they check the map and the tree, not a step
SCENE_PACKAGES = {"wgpu": ("wgpu_path/scene", "wgpu_path/post"), "raw": ("raw_path/scene", "raw_path/post")}


@dataclass(frozen=True)
class Row:
    step: Step
    wgpu: tuple[str, ...]
    wgsl: tuple[str, ...]
    raw: tuple[str, ...]
    glsl: tuple[str, ...]
    data: tuple[str, ...]
    reference: tuple[str, ...]
    tests: tuple[str, ...] | None  # None: no tests/ folder here (an installed wheel)
    texts: tuple[tuple[str, str], ...]


@functools.cache
def _tree(path: Path) -> ast.AST:
    """A source file parsed once per process (the map reads every test file for every step)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _rel(path: Path) -> str:
    return path.relative_to(PACKAGE.parent).as_posix()


def _module_files(module: str) -> list[Path]:
    return [PACKAGE.parent / (module.replace(".", "/") + ".py")]


def _step_files(step: Step, path: str) -> list[Path]:
    """The source files that draw ``step`` on ``path`` ("wgpu" or "raw")."""
    if step.scene is not None:
        return sorted(p for folder in SCENE_PACKAGES[path] for p in (PACKAGE / folder).glob("*.py"))
    if path == "wgpu":
        from wgpurender.wgpu_path.stages import all_stages

        cls = all_stages().get(step.stage)
    else:
        from wgpurender.raw_path.stages import all_ref_stages

        cls = all_ref_stages().get(step.stage)
    return _module_files(cls.__module__) if cls is not None else []


def _pattern(node: ast.expr) -> str | None:
    """A string constant, or an f-string with its replacement fields as ``*``."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr):
        return "".join(v.value if isinstance(v, ast.Constant) else "*" for v in node.values)
    return None


def _base_defaults(base: Path) -> dict[str, list[str]]:
    """Method name -> the shader names among its parameters' defaults (e.g. ``frag="color.frag"``)."""
    out: dict[str, list[str]] = {}
    for node in ast.walk(_tree(base)):
        if isinstance(node, ast.FunctionDef):
            names = [d.value for d in node.args.defaults
                     if isinstance(d, ast.Constant) and isinstance(d.value, str) and SHADER_NAME.fullmatch(d.value)]
            if names:
                out[node.name] = names
    return out


def _shaders(files: Iterable[Path], kind: str) -> tuple[str, ...]:
    """Shader files of ``kind`` ("wgsl" or "glsl") that the sources name, as repository paths."""
    folder = shader_folder(kind, "WGPURENDER_SHADERS" if kind == "wgsl" else "WGPURENDER_GLSL")
    available = sorted(p.name for p in folder.iterdir() if p.is_file())
    found: set[str] = set()
    for path in files:
        tree = _tree(path)
        defaults = _base_defaults(path.parent / "base.py") if (path.parent / "base.py").is_file() else {}
        for node in ast.walk(tree):
            pattern = _pattern(node) if isinstance(node, (ast.Constant, ast.JoinedStr)) else None
            if pattern and SHADER_NAME.fullmatch(pattern):
                found.update(fnmatch.filter(available, pattern))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in defaults:
                found.update(defaults[node.func.attr])
    top = "shaders_wgsl" if kind == "wgsl" else "shaders_glsl"
    suffixes = (".wgsl",) if kind == "wgsl" else (".vert", ".frag", ".comp")
    return tuple(f"{top}/{name}" for name in sorted(found) if name.endswith(suffixes) and name in available)


def _helpers(files: list[Path]) -> list[Path]:
    """The device-layer modules of the same path that ``files`` import (``wgpu_path/device/textures.py`` makes the
    mip chain with mipmap.wgsl for the textured stage): their shaders are the step's too."""
    if not files:
        return []
    folder = files[0].relative_to(PACKAGE).parts[0]  # wgpu_path or raw_path
    prefix = f"wgpurender.{folder}."
    out = []
    for name in sorted(_imports(files)):
        rest = name[len(prefix):].removeprefix("device.") if name.startswith(prefix) else None
        path = PACKAGE / folder / "device" / (rest + ".py") if rest else None
        if path is not None and "." not in rest and path.is_file() and path not in files:
            out.append(path)
    return out


def _imports(files: Iterable[Path]) -> set[str]:
    return set().union(*(_imports_of(path) for path in files))


@functools.cache
def _imports_of(path: Path) -> frozenset[str]:
    found = set()
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.ImportFrom) and node.module:
            found.add(node.module)
            found.update(f"{node.module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return frozenset(found)


def _course_data(step: Step, files: list[Path]) -> tuple[str, ...]:
    course = PACKAGE / "core" / "course"
    modules = {p.stem for p in course.glob("*.py")} - {"__init__", "steps"}
    used = {m for m in modules if f"wgpurender.core.course.{m}" in _imports(files)}
    data = [f"wgpurender/core/course/{m}.py" for m in sorted(used)]
    if step.scene is not None:
        data.insert(0, f"assets/scenes/{step.scene}.toml")
    return tuple(data)


def _scene_references(scene: str) -> list[str]:
    from wgpurender.raw_path.make_references import SCENE_REFERENCES

    return [name for name, file in SCENE_REFERENCES.items() if Path(file).stem in (scene, f"{scene}_subpass")]


def _references(step: Step) -> tuple[str, ...]:
    names = _scene_references(step.scene) if step.scene is not None else [step.stage]
    return tuple(f"assets/reference/{n}.png" for n in names if (reference_dir() / f"{n}.png").is_file())


def _tests(step: Step, files: list[Path], references: tuple[str, ...]) -> tuple[str, ...] | None:
    if not (TESTS.is_dir() and (TESTS.parent / "pyproject.toml").is_file()):  # a checkout, not site-packages
        return None
    modules = {".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts) for p in files}
    names = {step.stage, *(Path(r).stem for r in references)}
    if step.scene is not None:
        names |= {step.scene, f"{step.scene}.toml", *(Path(f).name for f in _scene_files(step.scene))}
    out = []
    for path in sorted(p for p in TESTS.rglob("test_*.py") if p.name not in META_TESTS):
        if _call_arguments(path) & names or _imports_of(path) & modules:
            out.append(path.relative_to(CHECKOUT).as_posix())
    return tuple(out)


@functools.cache
def _call_arguments(path: Path) -> frozenset[str]:
    """String constants passed to calls, directly or in a list/tuple (``get_stage("msaa")``,
    ``main(["render", "msaa"])``, ``parametrize("name", ["3d", ...])``); ``with_(msaa=4)`` or ``plan["msaa"]``
    do not name the stage."""
    out = set()
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.Call):
            for arg in node.args:
                items = arg.elts if isinstance(arg, (ast.List, ast.Tuple)) else [arg]
                out.update(i.value for i in items if isinstance(i, ast.Constant) and isinstance(i.value, str))
    return frozenset(out)


def _scene_files(scene: str) -> list[Path]:
    return [p for p in (scene_dir() / f"{scene}.toml", scene_dir() / f"{scene}_subpass.toml") if p.is_file()]


def course_map() -> list[Row]:
    """One row per course step, in course order."""
    rows = []
    for step in COURSE:
        wgpu_files, raw_files = _step_files(step, "wgpu"), _step_files(step, "raw")
        references = _references(step)
        rows.append(Row(
            step, tuple(_rel(p) for p in wgpu_files), _shaders(wgpu_files + _helpers(wgpu_files), "wgsl"),
            tuple(_rel(p) for p in raw_files), _shaders(raw_files + _helpers(raw_files), "glsl"),
            _course_data(step, wgpu_files + raw_files), references,
            _tests(step, wgpu_files + raw_files, references), step_texts(step)))
    return rows


def _cell(items: Iterable[str]) -> str:
    items = list(items)
    return "<br>".join(f"`{i}`" for i in items) if items else "-"


def _modules_cell(paths: tuple[str, ...], step: Step) -> str:
    if step.scene is None or not paths:
        return _cell(paths)
    folders = dict.fromkeys(p.rsplit("/", 1)[0] + "/" for p in paths)
    return _cell(folders) + f" ({len(paths)} modules)"


def course_map_markdown() -> str:
    """The map as a Markdown table (docs/course-map.md's body; ``wgpurender stages --map`` prints it)."""
    head = ["step", "wgpu module", "WGSL", "raw module", "GLSL", "course data", "reference image", "tests",
            "course text"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in course_map():
        tests = "(tests/ is in the repository, not in the wheel)" if r.tests is None else _cell(
            Path(t).name for t in r.tests)
        texts = "<br>".join(f"{name}: {where}" for name, where in r.texts) or "-"
        cells = [f"**{r.step.number}** `{r.step.stage}`: {r.step.title}", _modules_cell(r.wgpu, r.step),
                 _cell(r.wgsl), _modules_cell(r.raw, r.step), _cell(r.glsl), _cell(r.data), _cell(r.reference),
                 tests, texts]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines) + "\n"


DOC_HEAD = """# The course map

Generated from the code by `make docs` (`python -m wgpurender.course_map > docs/course-map.md`; the same table as
`wgpurender stages --map`); tests/test_course_map.py fails when this file is not its output. One row per course
step (wgpurender/core/course/steps.py), in the course's order: where the step lives on the wgpu path and on the
raw-Vulkan path, the shaders those modules name, the API-free course data they use, the committed reference image
the raw path's render is checked against, the tests that check the step, and the course text it comes from (in
../shared/course, outside the repository: named here, never needed). Step 6, the final model, is a scene file
(`wgpurender render final`) drawn by each path's scene renderer. How each column is found:
wgpurender/course_map.py's docstring.

"""


def course_map_doc() -> str:
    """docs/course-map.md: a short header and the map."""
    return DOC_HEAD + course_map_markdown()


if __name__ == "__main__":
    print(course_map_doc(), end="")
