"""The simple-OBJ reader (core/models/obj_simple.py) gives exactly the mesh trimesh's path gives, and hands every
file it does not fully understand to trimesh (which then reports bad files as before).

The reference is trimesh's own OBJ loader, reached through load_mesh with the simple reader switched off.
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.models import mesh as mesh_module
from wgpurender.core.models import obj_simple, procedural


def _through_trimesh(monkeypatch, path, **kwargs):
    with monkeypatch.context() as m:
        m.setattr(obj_simple, "read", lambda p: None)
        return mesh_module.load_mesh(path, **kwargs)


def _assert_same(a, b) -> None:
    for f in fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            assert x is not None and y is not None, f.name
            assert x.dtype == y.dtype and x.shape == y.shape, f.name
            assert np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


def _scrambled(rng: np.random.Generator, triangles: int, share: bool) -> str:
    """An OBJ whose corners index v, vt and vn independently (shared positions with distinct uvs and normals, as
    exporters write seams), in a shuffled record order."""
    nv, nt, nn = 7, 5, 4
    lines = ["# scrambled"]
    lines += [f"v {x:.7g} {y:.7g} {z:.7g}" for x, y, z in rng.normal(size=(nv, 3))]
    lines += [f"vn {x:.5f} {y:.5f} {z:.5f}" for x, y, z in rng.normal(size=(nn, 3))]  # not unit length
    lines += [f"vt {u:.6f} {v:.6f}" for u, v in rng.random((nt, 2))]
    rng.shuffle(lines[1:])
    for _ in range(triangles):
        v = rng.choice(nv, 3, replace=False) + 1
        t = rng.integers(1, nt + 1, 3) if share else v % nt + 1
        n = rng.integers(1, nn + 1, 3)
        lines.append("f " + " ".join(f"{a}/{b}/{c}" for a, b, c in zip(v, t, n, strict=True)))
    return "\r\n".join(lines) + "\n"


@pytest.mark.parametrize("make", [lambda: procedural.box(1.0), lambda: procedural.torus(segments=12, rings=6),
                                  lambda: procedural.plane(cols=3, rows=2)])
@pytest.mark.parametrize("tangents", [True, False])
def test_written_meshes_equal_trimesh(tmp_path, monkeypatch, make, tangents) -> None:
    path = procedural.write_obj(tmp_path / "m.obj", make())
    assert obj_simple.read(path) is not None  # the fast path is taken for what wgpurender writes
    _assert_same(mesh_module.load_mesh(path, generate_tangents=tangents),
                 _through_trimesh(monkeypatch, path, generate_tangents=tangents))


@pytest.mark.parametrize("seed", range(6))
def test_scrambled_indices_equal_trimesh(tmp_path, monkeypatch, seed) -> None:
    rng = np.random.default_rng(seed)
    path = tmp_path / "s.obj"
    path.write_text(_scrambled(rng, triangles=9, share=seed % 2 == 0))
    assert obj_simple.read(path) is not None
    _assert_same(mesh_module.load_mesh(path), _through_trimesh(monkeypatch, path))


BOX = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"


@pytest.mark.parametrize("text", [
    BOX + "f 1/1/1 2/2/1 3/3/1 \\\n",  # a line continuation
    "# a comment that goes on \\\n" + BOX + "f 1/1/1 2/2/1 3/3/1\n",  # trimesh joins the next line to the comment
    BOX + "o thing\nf 1/1/1 2/2/1 3/3/1\n",  # another record
    BOX + "usemtl red\nf 1/1/1 2/2/1 3/3/1\n",
    BOX + "f 1/1/1 2/2/1 3/3/1 1/1/1\n",  # a quad
    BOX + "f 1//1 2//1 3//1\n",  # a corner without vt
    BOX + "f 1/1 2/2 3/3\n",  # without vn
    BOX + "f -3/-3/-1 -2/-2/-1 -1/-1/-1\n",  # negative (relative) indices
    BOX + "f 1/1/1 2/2/1 4/3/1\n",  # beyond the v records
    BOX + "f 1/1/1 2/2/1 3/4/1\n",  # beyond the vt records
    BOX + "f 1/1/1 2/2/1 3/3/2\n",  # beyond the vn records
    BOX + "f 0/1/1 2/2/1 3/3/1\n",  # OBJ counts from 1
    BOX + "f 0_1/1/1 2/2/1 3/3/1\n",  # Python's int() reads 0_1 as 1
    BOX + "f 1/1/1 2/2/1 3/3/1 1/1/1\nf 2/2/1 3/3/1\n",  # a quad and a two-corner face: six corners in all
    BOX.replace("vt 0 1", "vt 0 1 0") + "f 1/1/1 2/2/1 3/3/1\n",  # a vt with w
    BOX.replace("v 1 0 0", "v 1 0 0 1 1 1") + "f 1/1/1 2/2/1 3/3/1\n",  # a vertex colour
    BOX.replace("v 1 0 0", "v 1 0") + "f 1/1/1 2/2/1 3/3/1\n",  # too few numbers
    BOX.replace("v 1 0 0", "v 1_0 0 0") + "f 1/1/1 2/2/1 3/3/1\n",  # Python reads 1_0, numpy does not
    BOX.replace("v 1 0 0", "v 1-e3 0 0") + "f 1/1/1 2/2/1 3/3/1\n",  # trimesh rewrites -e
    BOX.replace("v 1 0 0", "v one 0 0") + "f 1/1/1 2/2/1 3/3/1\n",
    BOX.replace("v 1 0 0", " v 1 0 0") + "f 1/1/1 2/2/1 3/3/1\n",  # a blank before the record
    BOX,  # no faces
    "vt 0 0\nvn 0 0 1\n",  # no vertices
])
def test_anything_else_goes_to_trimesh(tmp_path, text) -> None:
    path = tmp_path / "odd.obj"
    path.write_text(text)
    assert obj_simple.read(path) is None


def test_large_files_go_to_trimesh(tmp_path, monkeypatch) -> None:
    path = procedural.write_obj(tmp_path / "m.obj", procedural.box(1.0))
    monkeypatch.setattr(obj_simple, "MAX_BYTES", path.stat().st_size - 1)
    assert obj_simple.read(path) is None


def test_bad_records_are_still_reported(tmp_path) -> None:
    path = tmp_path / "bad.obj"
    path.write_text(BOX.replace("vt 0 1", "vt 0.5") + "f 1/1/1 2/2/1 3/3/1\n")
    with pytest.raises(UserError, match=r"bad\.obj:6: OBJ record"):
        mesh_module.load_mesh(path)


def test_a_non_ascii_file_gets_trimeshs_verdict(tmp_path, monkeypatch) -> None:
    """A Latin-1 byte in a comment: the fast reader steps aside, so the file loads (or is refused) exactly as
    trimesh's reader alone decides (found by review: the fast reader accepted what trimesh refuses)."""
    path = tmp_path / "latin1.obj"
    path.write_bytes(b"# caf\xe9\n" + (BOX + "f 1/1/1 2/2/1 3/3/1\n").encode())
    assert obj_simple.read(path) is None

    def outcome():
        try:
            return mesh_module.load_mesh(path).positions.shape
        except UserError as err:
            return str(err)

    fast = outcome()
    monkeypatch.setattr(obj_simple, "read", lambda p: None)
    assert fast == outcome()
