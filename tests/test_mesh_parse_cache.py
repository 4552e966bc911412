"""The verified parse cache of simple OBJ files (core/models/obj_cached.py) and its packed meshes
(core/models/mesh_pack.py): a warm load gives exactly the mesh trimesh's own reader gives, a hit does not parse,
an edited file / parser / damaged entry is a miss, entries live under $XDG_CACHE_HOME (tests/conftest.py points it
at a folder of the session's own, never ~/.cache), nothing is written beside the model. API-free."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from helpers import same_mesh as _same

from wgpurender.core.files import cache_entry
from wgpurender.core.models import mesh as mesh_module
from wgpurender.core.models import mesh_pack, obj_cached, obj_simple, procedural


def _trimesh(monkeypatch, path, **kwargs):
    """trimesh's mesh of the file: the uncached loader with the simple reader off (tests/test_obj_simple.py)."""
    with monkeypatch.context() as m:
        m.setattr(obj_simple, "read", lambda p: None)
        return mesh_module.load_mesh(path, **kwargs)


def _no_parse(monkeypatch):
    def refuse(data):
        raise AssertionError("parsed although the cache holds the file")
    monkeypatch.setattr(obj_simple, "parse", refuse)


def _entries() -> list[Path]:
    where = obj_cached.folder()
    return sorted(where.glob("*.mesh")) if where.is_dir() else []


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty cache of this test's own: $XDG_CACHE_HOME under tmp_path."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    return tmp_path / "xdg" / "wgpurender" / "meshes"


def test_the_cache_lives_under_xdg_cache_home_never_beside_the_model(tmp_path, cache):
    (tmp_path / "models").mkdir()
    model = procedural.write_obj(tmp_path / "models" / "m.obj", procedural.box(1.0))
    obj_cached.load_mesh(model)
    assert obj_cached.folder() == cache and len(_entries()) == 1
    assert sorted(p.name for p in model.parent.iterdir()) == ["m.obj"]
    home = Path.home() / ".cache" / "wgpurender" / "meshes"
    assert not obj_cached.folder().is_relative_to(home)


@pytest.mark.parametrize("tangents", [True, False])
def test_a_warm_load_is_trimeshs_mesh_and_does_not_parse(tmp_path, monkeypatch, cache, tangents):
    path = procedural.write_obj(tmp_path / "t.obj", procedural.torus(segments=10, rings=5))
    cold = obj_cached.load_mesh(path, generate_tangents=tangents)
    assert len(_entries()) == 1
    _no_parse(monkeypatch)
    warm = obj_cached.load_mesh(path, generate_tangents=tangents)
    _same(warm, cold)
    _same(warm, _trimesh(monkeypatch, path, generate_tangents=tangents))
    assert (warm.tangents is not None) == tangents


def test_with_and_without_tangents_are_two_entries(tmp_path, cache):
    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    assert obj_cached.load_mesh(path, generate_tangents=False).tangents is None
    assert obj_cached.load_mesh(path, generate_tangents=True).tangents is not None
    assert len(_entries()) == 2


def test_an_edited_file_is_a_miss(tmp_path, cache):
    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    obj_cached.load_mesh(path)
    moved = procedural.box(1.0)
    moved = replace(moved, positions=moved.positions + np.array([5.0, 0.0, 0.0]))
    procedural.write_obj(path, moved)
    again = obj_cached.load_mesh(path)
    numbers = [[float(t) for t in line.split()[1:]] for line in path.read_text().splitlines()
               if line.startswith("v ")]
    assert np.allclose(again.positions.min(axis=0), np.min(numbers, axis=0))
    assert again.positions[:, 0].min() > 4.0 and len(_entries()) == 2


def test_another_parser_version_is_a_miss(tmp_path, monkeypatch, cache):
    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    obj_cached.load_mesh(path)
    monkeypatch.setattr(obj_cached, "parser_version", lambda: "another parser")
    parsed = []
    real = obj_simple.parse
    monkeypatch.setattr(obj_simple, "parse", lambda data: parsed.append(1) or real(data))
    obj_cached.load_mesh(path)
    assert parsed == [1] and len(_entries()) == 2


def test_the_parser_version_covers_the_parsers_source():
    for name in ("obj_simple.py", "mesh.py", "tangents.py", "mesh_pack.py", "obj_cached.py"):
        assert name in obj_cached.CODE
    assert {"numpy", "trimesh"} <= set(obj_cached.LIBRARIES)


@pytest.mark.parametrize("damage", ["truncate", "flip", "empty", "foreign"])
def test_a_damaged_entry_is_parsed_again_and_rewritten(tmp_path, monkeypatch, cache, damage):
    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    first = obj_cached.load_mesh(path)
    (entry,) = _entries()
    blob = entry.read_bytes()
    entry.write_bytes({"truncate": blob[:-7], "flip": blob[:-3] + bytes([blob[-3] ^ 0x40]) + blob[-2:],
                       "empty": b"", "foreign": blob.replace(b"wrmesh1", b"xxxxxx1")}[damage])
    parsed = []
    real = obj_simple.parse
    monkeypatch.setattr(obj_simple, "parse", lambda data: parsed.append(1) or real(data))
    _same(obj_cached.load_mesh(path), first)
    assert parsed == [1] and entry.read_bytes() == blob


def test_a_file_the_simple_reader_refuses_is_not_cached(tmp_path, cache):
    path = procedural.write_obj(tmp_path / "m.obj", procedural.box(1.0), mtl_name="m.mtl")
    obj_cached.load_mesh(path)
    assert _entries() == []


def test_an_unwritable_cache_only_costs_time(tmp_path, monkeypatch):
    blocker = tmp_path / "xdg"
    blocker.write_text("a file where the cache folder would be")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    _same(obj_cached.load_mesh(path), _trimesh(monkeypatch, path))


def test_packing_round_trips_and_refuses_what_is_not_whole(tmp_path, cache):
    mesh = obj_cached.load_mesh(procedural.write_obj(tmp_path / "t.obj", procedural.torus(segments=8, rings=4)))
    blob = mesh_pack.pack(mesh)
    _same(mesh_pack.unpack(blob, mesh.source), mesh)
    back = mesh_pack.unpack(blob, mesh.source)
    back.positions[0, 0] = 99.0  # writable, as a fresh load's arrays are
    for bad in (blob[:-1], blob + b"\0", blob[:mesh_pack.HEADER.size - 1], b"x" + blob[1:]):
        assert mesh_pack.unpack(bad, None) is None
    out_of_range = bytearray(blob)
    out_of_range[-2:] = (len(mesh.positions)).to_bytes(2, "little")  # the last index one past the vertices
    assert mesh.indices.dtype == np.uint16 and mesh_pack.unpack(bytes(out_of_range), None) is None


def test_only_simple_meshes_are_packed(tmp_path, cache):
    mesh = obj_cached.load_mesh(procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0)))
    n = len(mesh.positions)
    assert mesh_pack.pack(replace(mesh, colors=np.ones((n, 4), np.float32))) is None
    assert mesh_pack.pack(replace(mesh, extra_uvs=(mesh.uvs,))) is None
    assert mesh_pack.pack(replace(mesh, extra_indices=np.array([0, 1], np.uint16))) is None
    lines = replace(mesh, parts=(mesh_module.MeshPart(None, 0, 2, "line-list"),))
    assert mesh_pack.pack(lines) is None
    with_parts = replace(mesh, parts=(mesh_module.MeshPart(3, 0, 6), mesh_module.MeshPart(None, 6, 30)))
    assert mesh_pack.unpack(mesh_pack.pack(with_parts), None).parts == with_parts.parts


def test_the_cache_folder_follows_xdg_cache_home(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cache_entry.cache_folder("meshes") == tmp_path / "wgpurender" / "meshes"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert cache_entry.cache_folder("x") == Path(os.path.expanduser("~")) / ".cache" / "wgpurender" / "x"


def test_the_cached_loader_refuses_as_load_mesh_does(tmp_path, monkeypatch, cache):
    from wgpurender.core.errors import UserError

    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    (tmp_path / "folder.obj").mkdir()
    monkeypatch.setenv("WGPURENDER_MAX_MODEL_BYTES", str(path.stat().st_size - 1))
    cases = {"missing": tmp_path / "gone.obj", "a folder": tmp_path / "folder.obj", "too large": path}
    for what, target in cases.items():
        messages = []
        for load in (obj_cached.load_mesh, mesh_module.load_mesh):
            with pytest.raises(UserError) as err:
                load(target)
            messages.append(str(err.value))
        assert messages[0] == messages[1] and "\n" not in messages[0], what
    assert _entries() == []


def test_the_general_loader_writes_no_entry(tmp_path, cache):
    mesh_module.load_mesh(procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0)))
    assert _entries() == []


def test_store_false_reads_the_cache_but_writes_nothing(tmp_path, monkeypatch, cache):
    """What a process reading thousands of files itself asks (core/plan/meshes.py): a hit is still served."""
    path = procedural.write_obj(tmp_path / "b.obj", procedural.box(1.0))
    first = obj_cached.load_mesh(path, store=False)
    assert _entries() == []
    obj_cached.load_mesh(path)
    assert len(_entries()) == 1
    _no_parse(monkeypatch)
    _same(obj_cached.load_mesh(path, store=False), first)
