"""A large scene file's TOML parsed once (core/scene/toml_cache.py, issue 31.3): the values read back are
tomllib's own for that text, an edited text or a damaged entry is parsed again, small scenes and scenes with
dates are never cached, and the entry lives under $XDG_CACHE_HOME."""

from __future__ import annotations

import math
import tomllib

import pytest

from wgpurender.core.scene import load_scene, toml_cache


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))


def _big_text(n: int = 2000, extra: str = "") -> str:
    """Every kind of value a scene holds, in a text past MIN_CHARS (n models)."""
    head = ('description = "caf\\u00e9 \\"quoted\\""\n' + extra +
            "[camera]\neye = [0.0, -0.0, 1e300]\ntarget = [1, 2, 3]\nfov_y = 45\n\n"
            "[render]\nsize = [64, 48]\nhdr = false\n\n[weird]\nbig = 12345678901234567890\nplus = inf\n"
            "minus = -inf\nnot_a_number = nan\ntiny = 5e-324\nthird = 0.1\n\n")
    body = "".join(f'[[models]]\npath = "m{k}.obj"\ntransform = {{ translate = [{k}.5, -{k}, 0.25] }}\n\n'
                   for k in range(n))
    text = head + body
    assert len(text) >= toml_cache.MIN_CHARS
    return text


def _same(a, b) -> None:
    """Equal values of equal types, nan included (nan != nan), in the same key order."""
    assert type(a) is type(b), (a, b)
    if isinstance(a, dict):
        assert list(a) == list(b)
        for k in a:
            _same(a[k], b[k])
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _same(x, y)
    elif isinstance(a, float) and math.isnan(a):
        assert math.isnan(b)
    else:
        assert a == b and (not isinstance(a, float) or math.copysign(1, a) == math.copysign(1, b))


def _entries():
    folder = toml_cache.folder()
    return sorted(folder.iterdir()) if folder.exists() else []


def test_a_large_scene_is_parsed_once_and_read_back_as_tomllib_gave_it(monkeypatch):
    text = _big_text()
    first = toml_cache.loads(text)
    _same(first, tomllib.loads(text))
    assert len(_entries()) == 1

    def no_parse(_text):
        raise AssertionError("parsed again")

    monkeypatch.setattr(toml_cache.tomllib, "loads", no_parse)
    _same(toml_cache.loads(text), first)


def test_an_edited_scene_is_a_miss(monkeypatch):
    text = _big_text()
    toml_cache.loads(text)
    edited = text.replace('path = "m7.obj"', 'path = "other.obj"')
    got = toml_cache.loads(edited)
    assert got["models"][7]["path"] == "other.obj"
    assert len(_entries()) == 2


@pytest.mark.parametrize("damage", ["truncate", "flip", "not json"])
def test_a_damaged_entry_is_parsed_again(damage):
    text = _big_text()
    toml_cache.loads(text)
    (entry,) = _entries()
    blob = entry.read_bytes()
    if damage == "truncate":
        entry.write_bytes(blob[:-10])
    elif damage == "flip":
        entry.write_bytes(blob[:-5] + bytes([blob[-5] ^ 1]) + blob[-4:])
    else:  # a well-sealed entry whose payload is not a table: the same key, other bytes
        from wgpurender.core.files.cache_entry import seal, unseal

        key = next(k for k in [_key(text)] if unseal(blob, k) is not None)
        entry.write_bytes(seal(key, b"[1, 2, 3]"))
    _same(toml_cache.loads(text), tomllib.loads(text))


def _key(text: str) -> str:
    import hashlib
    import sys

    return f"scene TOML as JSON; python {sys.version}; text sha256 {hashlib.sha256(text.encode()).hexdigest()}"


def test_a_small_scene_writes_no_entry():
    text = "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n"
    assert toml_cache.loads(text) == tomllib.loads(text)
    assert _entries() == []


def test_a_scene_with_a_date_is_parsed_each_time_and_not_cached():
    text = _big_text(extra="when = 2026-11-27T15:00:00Z\n")
    _same(toml_cache.loads(text), tomllib.loads(text))
    assert _entries() == []


def test_invalid_toml_is_still_tomllibs_error_and_caches_nothing():
    text = _big_text() + "\n[[models]\n"
    with pytest.raises(tomllib.TOMLDecodeError):
        toml_cache.loads(text)
    assert _entries() == []


def test_the_cache_is_under_xdg_cache_home_never_beside_the_scene(tmp_path):
    from wgpurender.core.models import procedural

    for k in range(2):
        procedural.write_obj(tmp_path / f"m{k}.obj", procedural.box(1.0))
    body = "".join(f'[[models]]\npath = "m{k % 2}.obj"\ntransform = {{ translate = [{k}, 0, 0] }}\n\n'
                   for k in range(1500))
    scene = tmp_path / "s.toml"
    scene.write_text("[camera]\neye = [0, 0, 50]\ntarget = [0, 0, 0]\n\n" + body)
    assert len(scene.read_text()) >= toml_cache.MIN_CHARS
    before = sorted(p.name for p in tmp_path.iterdir())
    first = load_scene(scene)
    second = load_scene(scene)  # from the entry
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([*before, "xdg"])  # nothing beside the scene
    assert [e.parent for e in _entries()] == [tmp_path / "xdg" / "wgpurender" / "scenes"]
    assert [m.path for m in first.models] == [m.path for m in second.models]
    assert [m.transform.matrix for m in second.models][5][0][3] == 5.0  # the 6th model's translate x, as written
