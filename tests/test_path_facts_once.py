"""Issue 31.3's load, load7: a model's path facts worked out once (its file's suffix, its transform's mirroring,
the plan's OBJ files), a folder's files made as pathlib's own children, the TOML nesting walk over tables and
arrays only. Each is checked against an independent answer: pathlib's own rules, numpy's determinant, the scene
text's names, the structures built here. API-free."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core.files import input_files
from wgpurender.core.files.input_files import FolderResolver, nesting_depth
from wgpurender.core.models import procedural
from wgpurender.core.plan import resolve_plan
from wgpurender.core.plan.mesh_loading import obj_keys
from wgpurender.core.plan.meshes import PlanMeshes
from wgpurender.core.scene import Transform
from wgpurender.core.scene.load import load_scene

HEAD = ("[camera]\neye = [0.0, 0.0, 5.0]\ntarget = [0.0, 0.0, 0.0]\n\n[materials.red]\nalbedo_color = [1, 0, 0]\n\n"
        "[materials.blue]\nalbedo_color = [0, 0, 1]\n\n")
ASSETS = Path(__file__).resolve().parent.parent / "assets" / "models"


def _scene(folder: Path, names: list[str], materials: list[str] | None = None) -> Path:
    path = folder / "s.toml"
    materials = materials or ["red"] * len(names)
    path.write_text(HEAD + "".join(f'[[models]]\npath = "{n}"\nmaterial = "{m}"\n\n'
                                   for n, m in zip(names, materials, strict=True)))
    return path


def test_a_models_suffix_is_its_resolved_files_in_lower_case(tmp_path):
    procedural.write_obj(tmp_path / "A.OBJ", procedural.box(1.0))
    procedural.write_obj(tmp_path / "m.obj", procedural.box(1.0))
    (tmp_path / "l.glb").symlink_to(tmp_path / "m.obj")  # written .glb, read as the OBJ it links to
    (tmp_path / "t.glb").write_bytes((ASSETS / "gltf_features.glb").read_bytes())
    names = ["A.OBJ", "l.glb", "t.glb", "m.obj"]
    models = load_scene(_scene(tmp_path, names)).models
    assert [m.suffix for m in models] == [Path(os.path.realpath(tmp_path / n)).suffix.lower() for n in names]
    assert [m.suffix for m in models] == [".obj", ".obj", ".glb", ".obj"]


def test_the_plans_obj_files_are_the_scenes_obj_files_with_or_without_its_models(tmp_path):
    for name in ("b.obj", "a.OBJ"):
        procedural.write_obj(tmp_path / name, procedural.box(1.0))
    (tmp_path / "t.glb").write_bytes((ASSETS / "gltf_features.glb").read_bytes())
    names = ["b.obj", "t.glb", "a.OBJ", "b.obj", "t.glb"]  # repeated files count once, in first-use order
    scene = load_scene(_scene(tmp_path, names, ["red", "red", "red", "blue", "red"]))  # blue: a draw of its own
    plan = resolve_plan(scene, None, mesh_workers="off")
    draws = plan.scene_pass.draws
    assert [d.model_path.name for d in draws].count("b.obj") == 2  # the file is drawn twice, counted once below
    want = [(tmp_path / n).resolve() for n in ("b.obj", "a.OBJ")]
    assert [path for path, _ in obj_keys(draws, scene.models)] == want
    assert [path for path, _ in obj_keys(draws)] == want  # each draw's path looked at instead
    assert all(pose is None for _, pose in obj_keys(draws))
    assert [path for path, _ in PlanMeshes(plan)._obj_keys] == want


@pytest.mark.parametrize("written", ["m.obj", "M.Obj", "x.glb", "x.tar.gz", ".obj", "a.", "a..obj", "noext"])
def test_file_suffix_is_pathlibs_for_each_kind_of_name(written):
    assert input_files.file_suffix(f"/some/folder/{written}") == Path(f"/some/folder/{written}").suffix


def _nest(depth: int, kind: str):
    value: object = 1.5
    for level in range(depth):
        value = [value, "s"] if (kind == "list" or (kind == "mixed" and level % 2)) else {"k": value, "n": 2}
    return value


@pytest.mark.parametrize("kind", ["list", "dict", "mixed"])
@pytest.mark.parametrize("depth", [1, 2, 5, 40])
def test_nesting_depth_counts_the_tables_and_arrays_built_inside_each_other(depth, kind):
    assert nesting_depth(_nest(depth, kind)) == depth
    beside = {"models": [{"path": "m.obj"}] * 3, "deep": _nest(depth, kind)}  # the deepest branch decides
    assert nesting_depth(beside) == 1 + max(depth, 2)  # models: an array of tables (2)


def test_nesting_depth_of_what_holds_no_table_or_array():
    assert nesting_depth(3) == 0
    assert nesting_depth("text") == 0
    assert nesting_depth([]) == 1
    assert nesting_depth({"a": [], "b": 1}) == 2


def test_a_folders_files_are_the_same_paths_without_pathlibs_child_maker(tmp_path, monkeypatch):
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "in").symlink_to(real)  # a linked folder: its files are named in the resolved one
    names = ["a.obj", "b c.obj", "missing.obj"]
    procedural.write_obj(real / "a.obj", procedural.box(1.0))
    procedural.write_obj(real / "b c.obj", procedural.box(1.0))
    want = [real.resolve() / n for n in names]
    with_maker = FolderResolver().names_in(str(tmp_path / "in"), names)
    monkeypatch.setattr(input_files, "_MAKE_CHILD", None)  # a Python whose pathlib has no such maker (3.13)
    resolver = FolderResolver()
    without = resolver.names_in(str(tmp_path / "in"), names)
    assert with_maker == without == want
    assert [str(p) for p in without] == [str(p) for p in want]
    assert [resolver.regular(p) for p in without] == [True, True, False]


@pytest.mark.parametrize("factors", [(1, 1, 1), (-1, 1, 1), (1, -2, 1), (-1, -1, 1), (-1, -1, -1), (2, 3, 0.5)])
def test_a_transform_mirrors_where_its_3x3_determinant_is_negative(factors):
    rng = np.random.default_rng(len(str(factors)))
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rotation = q * np.sign(np.linalg.det(q))  # a proper rotation (det +1): it never mirrors by itself
    m = np.eye(4)
    m[:3, :3] = rotation @ np.diag(factors)
    m[:3, 3] = (1.0, -2.0, 3.0)
    t = Transform(tuple(tuple(float(v) for v in row) for row in m))
    assert t.mirrors == bool(np.linalg.det(m[:3, :3]) < 0)
    assert t.mirrors == (np.prod(factors) < 0)


WRITTEN = ["", "transform = { scale = [-1, 1, 1] }\n", "transform = { scale = [-1, -1, 1] }\n",
           "transform = { translate = [1, 2, 3] }\n"]


@pytest.mark.parametrize("transform", WRITTEN)
def test_a_draws_winding_follows_its_written_transform(tmp_path, transform):
    """No transform (the shared IDENTITY, asked no determinant) draws counter-clockwise; a mirroring one (an odd
    count of negative scale factors, the scene's own numbers) clockwise."""
    procedural.write_obj(tmp_path / "m.obj", procedural.box(1.0))
    (tmp_path / "s.toml").write_text(HEAD + f'[[models]]\npath = "m.obj"\nmaterial = "red"\n{transform}\n')
    plan = resolve_plan(load_scene(tmp_path / "s.toml"), None, mesh_workers="off")
    (draw,) = plan.scene_pass.draws
    negatives = transform.count("-1")
    assert plan.pipeline(draw.pipeline_key).front_face == ("cw" if negatives % 2 else "ccw")


def test_a_name_holding_this_systems_separator_is_not_made_a_folders_child(tmp_path, monkeypatch):
    """On Windows a backslash separates folders: "sub\\x.obj" is two names, and pathlib's child maker would make it
    ONE part (its parent the scene's folder, its name "sub\\x.obj": a path unequal to the same file named any other
    way), where os.path.join and Path parse it. names_in must leave such a value to the one-by-one resolve. Played
    here by making os.sep a backslash for the call (what os.path.split and Path use stays POSIX's)."""
    procedural.write_obj(tmp_path / "a.obj", procedural.box(1.0))
    resolver = FolderResolver()
    with monkeypatch.context() as patch:
        patch.setattr(os, "sep", "\\")
        got = resolver.names_in(str(tmp_path), ["a.obj", "sub\\x.obj"])
    assert got == [tmp_path.resolve() / "a.obj", None]


DEEP = 10_000
DEEP_SHAPES = {  # every way TOML nests: tomllib recurses on the first three, builds the rest in a loop
    "arrays": "x = " + "[" * DEEP + "]" * DEEP,
    "inline tables": "x = " + "{a = " * DEEP + "1" + "}" * DEEP,
    "inline tables in arrays": "x = " + "[{a = " * (DEEP // 2) + "1" + "}]" * (DEEP // 2),
    "a table header": "[" + ".".join(["a"] * DEEP) + "]",
    "an array-of-tables header": "[[" + ".".join(["a"] * DEEP) + "]]",
    "a dotted key": ".".join(["a"] * DEEP) + " = 1",
    "arrays under a deep header": "[" + ".".join(["a"] * 20) + "]\nb = " + "[" * 20 + "]" * 20,
}


@pytest.mark.parametrize("shape", list(DEEP_SHAPES))
def test_a_scene_nested_deeper_than_the_bound_in_any_shape_is_one_line(shape):
    from wgpurender.core.errors import UserError
    from wgpurender.core.scene.load import parse_scene

    with pytest.raises(UserError) as err:
        parse_scene(HEAD + DEEP_SHAPES[shape] + "\n", "/nowhere/s.toml")
    message = str(err.value)
    assert "\n" not in message and f"nested more than {input_files.MAX_NESTING} deep" in message, message
