"""A worker's chunk of simple OBJ files cached as ONE sealed entry (core/models/obj_cached_chunks.py, issue 31.3's
cold load): one file per chunk, a hit parses nothing and gives the parsed meshes, an edited file misses only its
chunk, a damaged, forged or foreign entry is a miss (parsed again, rewritten whole), a chunk with a refused file is
not stored, an unwritable cache only costs time. The expected meshes come from the serial loader
(core/models/mesh.load_mesh), never from the cache under test."""

from __future__ import annotations

import os
import struct

import numpy as np
import pytest
from helpers import same_mesh as _same

from wgpurender.core.errors import UserError
from wgpurender.core.files import cache_entry
from wgpurender.core.models import mesh_pack, mesh_workers, obj_cached, obj_cached_chunks, obj_simple, procedural
from wgpurender.core.models.mesh import load_mesh
from wgpurender.core.plan import mesh_loading

NAN_CUBE = "v nan 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n"


@pytest.fixture
def where(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    return obj_cached.folder()


def _cubes(folder, n, first=0):
    for k in range(first, first + n):
        procedural.write_obj(folder / f"c{k}.obj", procedural.box(0.5 + 0.01 * k))  # distinct files
    return [(folder / f"c{k}.obj", False) for k in range(first, first + n)]


def _meshes(chunk, result):
    """The chunk's meshes as the parent takes them (mesh_workers._take), in chunk order."""
    taken = {}
    mesh_workers._take(chunk, result, taken)
    return [taken[job] for job in chunk]


def _parses(monkeypatch) -> list[int]:
    """Counts the simple parser's calls (a forked worker inherits the patch)."""
    calls: list[int] = []
    real = obj_simple.parse
    monkeypatch.setattr(obj_simple, "parse", lambda data: calls.append(1) or real(data))
    return calls


def _entries(where):
    return sorted(where.glob("*.meshes")) if where.is_dir() else []


def test_a_cold_chunk_writes_one_entry_and_a_warm_one_parses_nothing(tmp_path, where, monkeypatch):
    chunk = _cubes(tmp_path, 5)
    (tmp_path / "bare.obj").write_text("o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")  # not simple: None
    chunk.insert(2, (tmp_path / "bare.obj", False))
    cold = mesh_workers.read_chunk(chunk, where)
    assert len(_entries(where)) == 1 and list(where.glob("*.mesh")) == []
    calls = _parses(monkeypatch)
    warm = mesh_workers.read_chunk(chunk, where)
    assert calls == [] and warm == cold
    assert warm[0][2] == ("mesh", None)
    for got, (path, _) in zip(_meshes(chunk, warm), chunk, strict=True):
        if path.name == "bare.obj":
            assert got is None
        else:
            _same(got, load_mesh(path, generate_tangents=False))


def test_tangents_are_part_of_the_key(tmp_path, where):
    chunk = _cubes(tmp_path, 2)
    mesh_workers.read_chunk(chunk, where)
    with_tangents = [(path, True) for path, _ in chunk]
    got = _meshes(with_tangents, mesh_workers.read_chunk(with_tangents, where))
    assert len(_entries(where)) == 2
    for mesh, (path, _) in zip(got, chunk, strict=True):
        assert mesh.tangents is not None
        _same(mesh, load_mesh(path, generate_tangents=True))


def test_an_edited_file_misses_only_its_own_chunk(tmp_path, where, monkeypatch):
    first, second = _cubes(tmp_path, 3), _cubes(tmp_path, 3, first=3)
    for chunk in (first, second):
        mesh_workers.read_chunk(chunk, where)
    procedural.write_obj(second[1][0], procedural.box(2.0))
    calls = _parses(monkeypatch)
    mesh_workers.read_chunk(first, where)
    assert calls == []
    got = _meshes(second, mesh_workers.read_chunk(second, where))
    assert len(calls) == 3  # the edited chunk is parsed again, every file of it
    assert np.allclose(np.ptp(got[1].positions, axis=0), 2.0)
    _same(got[1], load_mesh(second[1][0], generate_tangents=False))
    assert len(_entries(where)) == 3


def _damaged(blob: bytes, how: str, key: str) -> bytes:
    payload = cache_entry.unseal(blob, key)
    count = struct.unpack_from("<Q", payload, 8)[0]
    if how == "truncate":
        return blob[:-5]
    if how == "flip":
        return blob[:-3] + bytes([blob[-3] ^ 0x40]) + blob[-2:]
    if how == "count":  # sealed again with a valid seal: only the chunk's own checks find it
        return cache_entry.seal(key, payload[:8] + struct.pack("<Q", count + 1) + payload[16:])
    if how == "length":  # one length one byte short, the sum still matching the bytes: a mesh that is not whole
        lengths = list(struct.unpack_from(f"<{count}q", payload, 16))
        lengths[0] -= 1
        lengths[1] += 1
        return cache_entry.seal(key, payload[:16] + struct.pack(f"<{count}q", *lengths) + payload[16 + 8 * count:])
    if how == "index":  # a mesh whose last index points past its vertices, under a valid seal
        mesh = mesh_pack.unpack(payload[16 + 8 * count:16 + 8 * count + struct.unpack_from("<q", payload, 16)[0]],
                                None)
        first_end = 16 + 8 * count + struct.unpack_from("<q", payload, 16)[0]
        bad = payload[:first_end - 2] + len(mesh.positions).to_bytes(2, "little") + payload[first_end:]
        return cache_entry.seal(key, bad)
    if how == "part":  # the first mesh's first part runs 3 indices past its triangles, under a valid seal
        at = 16 + 8 * count + mesh_pack.HEADER.size
        material, first, size = mesh_pack.PART.unpack_from(payload, at)
        lying = mesh_pack.PART.pack(material, first, size + 3)
        return cache_entry.seal(key, payload[:at] + lying + payload[at + mesh_pack.PART.size:])
    raise AssertionError(how)


@pytest.mark.parametrize("how", ["truncate", "flip", "count", "length", "index", "part"])
def test_a_damaged_or_forged_entry_is_parsed_again_and_rewritten(tmp_path, where, monkeypatch, how):
    chunk = _cubes(tmp_path, 3)
    first = mesh_workers.read_chunk(chunk, where)
    (entry,) = _entries(where)
    blob = entry.read_bytes()
    key = obj_cached_chunks.chunk_key([(p, t, p.read_bytes()) for p, t in chunk])
    entry.write_bytes(_damaged(blob, how, key))
    calls = _parses(monkeypatch)
    again = mesh_workers.read_chunk(chunk, where)
    assert len(calls) == 3 and again == first and entry.read_bytes() == blob
    for got, (path, _) in zip(_meshes(chunk, again), chunk, strict=True):
        _same(got, load_mesh(path, generate_tangents=False))


def test_an_entry_another_user_owns_is_parsed_again_and_replaced(tmp_path, where, monkeypatch):
    """The module docstring's "foreign": a whole, well-sealed chunk entry that another user owns (a shared
    $XDG_CACHE_HOME) is not used; the chunk is parsed and its entry written again, ours."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        pytest.skip("handing a file to another user takes root")
    chunk = _cubes(tmp_path, 3)
    first = mesh_workers.read_chunk(chunk, where)
    (entry,) = _entries(where)
    os.chown(entry, os.geteuid() + 4242, -1)
    calls = _parses(monkeypatch)
    assert mesh_workers.read_chunk(chunk, where) == first and len(calls) == 3
    assert entry.stat().st_uid == os.geteuid()


def test_decode_takes_only_a_whole_chunk():
    packed = [b"abc", None, b"de"]
    payload = obj_cached_chunks.encode(packed)
    assert obj_cached_chunks.decode(payload, 3) == packed
    assert obj_cached_chunks.decode(obj_cached_chunks.encode([]), 0) == []
    head = obj_cached_chunks.HEAD.size
    bad = {"another count": (payload, 2), "short": (payload[:-1], 3), "left over": (payload + b"x", 3),
           "magic": (b"x" + payload[1:], 3), "no lengths": (payload[:head], 3),
           "lengths past the bytes": (payload[:head] + struct.pack("<3q", 3, -1, 3) + payload[head + 24:], 3)}
    for what, (blob, count) in bad.items():
        assert obj_cached_chunks.decode(blob, count) is None, what


def test_a_chunk_with_a_refused_file_is_not_stored_and_says_the_serial_line(tmp_path, where):
    chunk = _cubes(tmp_path, 2)
    (tmp_path / "bad.obj").write_text(NAN_CUBE)
    chunk.insert(1, (tmp_path / "bad.obj", False))
    entries, _ = mesh_workers.read_chunk(chunk, where)
    with pytest.raises(UserError) as serial:
        load_mesh(tmp_path / "bad.obj", generate_tangents=False)
    assert entries[1] == ("refused", str(serial.value)) and entries[0][0] == entries[2][0] == "mesh"
    assert _entries(where) == []


def test_an_unwritable_cache_only_costs_time(tmp_path, monkeypatch):
    blocker = tmp_path / "xdg"
    blocker.write_text("a file where the cache folder would be")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    chunk = _cubes(tmp_path, 2)
    for got, (path, _) in zip(_meshes(chunk, mesh_workers.read_chunk(chunk, obj_cached.folder())), chunk,
                              strict=True):
        _same(got, load_mesh(path, generate_tangents=False))


def test_a_chunk_too_large_to_read_back_is_not_written(tmp_path, where, monkeypatch):
    """The bound is the payload's size (worked out from the files' packed meshes, not from the code's encode) plus
    1 KiB for the entry's seal: one byte less and nothing is written, the bound itself and the entry is."""
    chunk = _cubes(tmp_path, 2)
    sizes = [len(mesh_pack.pack(load_mesh(path, generate_tangents=False))) for path, _ in chunk]
    payload = 8 + 8 + 8 * len(chunk) + sum(sizes)  # magic, count, one length per file, the meshes
    monkeypatch.setattr(obj_cached_chunks, "MAX_ENTRY", payload + 1023)
    mesh_workers.read_chunk(chunk, where)
    assert _entries(where) == []
    monkeypatch.setattr(obj_cached_chunks, "MAX_ENTRY", payload + 1024)
    mesh_workers.read_chunk(chunk, where)
    assert len(_entries(where)) == 1


def test_another_parser_version_is_a_miss(tmp_path, where, monkeypatch):
    chunk = _cubes(tmp_path, 2)
    mesh_workers.read_chunk(chunk, where)
    monkeypatch.setattr(obj_cached, "parser_version", lambda: "another parser")
    calls = _parses(monkeypatch)
    mesh_workers.read_chunk(chunk, where)
    assert len(calls) == 2 and len(_entries(where)) == 2


def test_the_parser_version_covers_the_chunk_format():
    assert "obj_cached_chunks.py" in obj_cached.CODE


@pytest.mark.skipif(not mesh_loading.can_fork(), reason="worker processes need fork (Linux)")
def test_workers_write_one_entry_per_chunk_and_read_them_back(tmp_path, where, monkeypatch):
    jobs = _cubes(tmp_path, 130)
    reading = mesh_workers.Reading(jobs, 2, where)
    cold = reading.finish()
    assert len(reading.chunks) == -(-130 // mesh_workers.CHUNK) == len(_entries(where))
    assert list(where.glob("*.mesh")) == []
    want = {job: load_mesh(job[0], generate_tangents=False) for job in jobs[::13]}  # the serial loader's

    def refuse(data):
        raise AssertionError("parsed although its chunk is cached")
    monkeypatch.setattr(obj_simple, "parse", refuse)  # inherited by the forked workers
    warm = mesh_workers.Reading(jobs, 2, where).finish()
    for job, mesh in want.items():
        _same(warm[job], cold[job])
        _same(warm[job], mesh)
