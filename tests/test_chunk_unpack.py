"""A worker's chunk of meshes unpacked as one array (mesh_pack.unpack_alike, mesh_workers.unpack_chunk; issue 31.3,
the load6 pass): each run of alike meshes in a chunk is one reshape with a view per mesh, and every mesh equals the
same blob unpacked alone; unlike, broken or partial blobs fall back to one at a time, and a refusal stays the
file's own.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.models import mesh_pack, mesh_workers, procedural
from wgpurender.core.models.mesh import load_mesh


def _same(a, b):
    for name in ("positions", "normals", "uvs", "indices"):
        got, want = getattr(a, name), getattr(b, name)
        assert got.dtype == want.dtype and np.array_equal(got, want), name
    assert (a.tangents is None) == (b.tangents is None)
    if a.tangents is not None:
        assert np.array_equal(a.tangents, b.tangents)
    assert (a.has_uvs, a.tangents_source, a.parts, a.source) == (b.has_uvs, b.tangents_source, b.parts, b.source)



def _packed(folder, sizes, tangents=False):
    meshes = []
    for k, size in enumerate(sizes):
        procedural.write_obj(folder / f"p{k}.obj", procedural.box(size))
        meshes.append(load_mesh(folder / f"p{k}.obj", generate_tangents=tangents))
    return meshes, [mesh_pack.pack(m) for m in meshes]



@pytest.mark.parametrize("tangents", [False, True])
def test_alike_meshes_unpack_as_one_array_as_each_alone(tmp_path, tangents):
    meshes, blobs = _packed(tmp_path, [0.5, 0.7, 0.9], tangents)
    sources = [tmp_path / f"m{k}.obj" for k in range(3)]
    data = np.frombuffer(bytearray(b"".join(blobs)), np.uint8)
    got = mesh_pack.unpack_alike(data, sources)
    for mesh, blob, source in zip(got, blobs, sources, strict=True):
        _same(mesh, mesh_pack.unpack(blob, source))
        assert mesh.positions.flags.writeable and np.shares_memory(mesh.positions, data)
    assert (got[1].tangents is not None) == tangents


def test_unlike_or_broken_blobs_are_not_unpacked_as_one(tmp_path):
    _, blobs = _packed(tmp_path, [0.5, 0.7])
    (tmp_path / "t.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n")
    other = mesh_pack.pack(load_mesh(tmp_path / "t.obj", generate_tangents=False))
    sources = [None, None]
    two = np.frombuffer(bytearray(blobs[0] + blobs[1]), np.uint8)
    assert mesh_pack.unpack_alike(two[:-1], sources) is None  # not two whole blobs
    padded = np.frombuffer(bytearray(blobs[0] + b"\0" * (len(blobs[1]) - len(other)) + other), np.uint8)
    assert mesh_pack.unpack_alike(padded, sources, indices_checked=True) is None  # the second's header is another's
    assert mesh_pack.unpack_alike(np.frombuffer(bytearray(b"\0" * 2 * len(other)), np.uint8), sources) is None
    assert mesh_pack.unpack_alike(two[:0], []) is None
    broken = bytearray(blobs[0] + blobs[1])
    n = len(mesh_pack.unpack(blobs[1], None).positions)
    broken[-2:] = n.to_bytes(2, "little")  # the second's last index one past its vertices
    assert mesh_pack.unpack_alike(np.frombuffer(broken, np.uint8), sources) is None
    assert len(mesh_pack.unpack_alike(np.frombuffer(broken, np.uint8), sources, indices_checked=True)) == 2


def test_a_chunk_unpacks_each_run_in_order(tmp_path):
    meshes, blobs = _packed(tmp_path, [0.5, 0.6, 0.7])
    (tmp_path / "t.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n")
    other = mesh_pack.pack(load_mesh(tmp_path / "t.obj", generate_tangents=False))
    chunk = [(tmp_path / f"j{k}.obj", False) for k in range(7)]
    entries = [("mesh", len(blobs[0])), ("mesh", None), ("mesh", len(blobs[1])), ("mesh", len(blobs[2])),
               ("mesh", len(other)), ("refused", "j5.obj: bad"), ("mesh", len(blobs[0]))]
    out = mesh_workers.unpack_chunk(chunk, (entries, blobs[0] + blobs[1] + blobs[2] + other + blobs[0]))
    assert list(out) == chunk and out[chunk[1]] is None
    assert isinstance(out[chunk[5]], UserError) and str(out[chunk[5]]) == "j5.obj: bad"
    for k, blob in ((0, blobs[0]), (2, blobs[1]), (3, blobs[2]), (4, other), (6, blobs[0])):
        _same(out[chunk[k]], mesh_pack.unpack(blob, chunk[k][0]))
    twin = bytearray(blobs[1])
    twin[mesh_pack.HEADER.size - 10] ^= 1  # has_uvs flipped: as long as the first, but not alike
    pair = mesh_workers.unpack_chunk(chunk[:2], ([("mesh", len(blobs[1]))] * 2, blobs[1] + bytes(twin)))
    _same(pair[chunk[0]], mesh_pack.unpack(blobs[1], chunk[0][0]))
    _same(pair[chunk[1]], mesh_pack.unpack(bytes(twin), chunk[1][0]))
    assert pair[chunk[0]].has_uvs != pair[chunk[1]].has_uvs
    with pytest.raises(ValueError, match="answered 6 files of a chunk of 7"):
        mesh_workers.unpack_chunk(chunk, (entries[:6], b""))
