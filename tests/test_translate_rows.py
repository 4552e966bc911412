"""A model's translate-only ``transform`` (the common case of a large scene: N placed copies of one mesh) is built
without numpy: its matrix must be the translation the scene writes, exactly as the general TRS path builds it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgpurender.core.errors import UserError
from wgpurender.core.scene import load_scene

OFFSETS = ([1.5, -2.25, 3.0], [0, -0.0, 7], [-0.0, 0.0, -0.0], [1e30, -3.4e38, 2.5e-300], [1, 2, 3])


def _scene(tmp_path, transforms: list[str]):
    (tmp_path / "cube.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    camera = '[camera]\neye = [0.0, 0.0, 5.0]\ntarget = [0.0, 0.0, 0.0]\n'
    models = "".join(f'[[models]]\npath = "cube.obj"\ntransform = {t}\n' for t in transforms)
    (tmp_path / "s.toml").write_text(camera + models)
    return load_scene(tmp_path / "s.toml")


@pytest.mark.parametrize("offset", OFFSETS, ids=str)
def test_translate_only_moves_points_by_the_offset(tmp_path, offset):
    model = _scene(tmp_path, [f"{{ translate = [{', '.join(map(repr, offset))}] }}"]).models[0]
    m = model.transform.array()
    point = np.array([0.5, -4.0, 2.0, 1.0])
    expect = np.array([0.5 + offset[0], -4.0 + offset[1], 2.0 + offset[2], 1.0])
    assert np.array_equal(m @ point, expect)
    assert np.array_equal(m[:3, :3], np.eye(3)) and np.array_equal(m[3], [0, 0, 0, 1])
    assert all(type(v) is float for row in model.transform.matrix for v in row)
    assert not any(math.copysign(1.0, v) < 0 for row in model.transform.matrix for v in row if v == 0)
    assert model.transform.description == f"translate {[float(v) for v in offset]}"


def test_translate_only_equals_the_trs_path(tmp_path):
    """The same offset through the general path (with a unit scale, which multiplies by the identity) gives the
    same rows, bit for bit."""
    scene = _scene(tmp_path, ["{ translate = [0.1, -0.2, 0.3] }", "{ translate = [0.1, -0.2, 0.3], scale = 1 }"])
    fast, general = (m.transform.matrix for m in scene.models)
    assert fast == general


@pytest.mark.parametrize("bad, said", [("[1, 2]", "array of 3 numbers"), ('[1, "a", 3]', "must be a number"),
                                       ("[1, 2, nan]", "must be a number")])
def test_translate_only_refuses_bad_offsets_in_one_line(tmp_path, bad, said):
    with pytest.raises(UserError, match=said) as info:
        _scene(tmp_path, [f"{{ translate = {bad} }}"])
    assert "models[0].transform.translate" in str(info.value) and "\n" not in str(info.value)


def test_a_translate_with_more_keeps_them(tmp_path):
    """Only a transform of translate alone takes the short way: with a scale or a rotation beside it, the matrix
    is T @ R @ S, checked on a point against the formula."""
    scene = _scene(tmp_path, ["{ translate = [1.0, 2.0, 3.0], scale = 2.0 }",
                              "{ translate = [1.0, 2.0, 3.0], rotate = { axis = [0, 0, 1], degrees = 90 } }"])
    scaled, turned = (m.transform for m in scene.models)
    point = np.array([1.0, 1.0, 1.0, 1.0])
    assert np.allclose(scaled.array() @ point, [3.0, 4.0, 5.0, 1.0], atol=1e-12)
    assert np.allclose(turned.array() @ point, [0.0, 3.0, 4.0, 1.0], atol=1e-12)  # (1, 1) turned to (-1, 1)
    assert scaled.description == "translate [1.0, 2.0, 3.0], scale 2.0"
