"""The comparison tool on images with known differences."""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.cli import main
from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import save_png
from wgpurender.core.verdict.compare import compare_images, heatmap


def _image(seed=0, size=(48, 64)):
    return np.random.default_rng(seed).integers(0, 256, (*size, 4), dtype=np.uint8)


def test_identical_images():
    a = _image()
    r = compare_images(a, a)
    assert r.psnr == float("inf") and r.max_abs == 0 and r.over_1 == 0 and r.flip_mean == 0


def test_known_differences():
    """One pixel off by 3 and a quarter of pixels off by 1: shares and PSNR computed by hand."""
    a = np.full((40, 40, 4), 100, np.uint8)
    b = a.copy()
    b[:20, :20, 0] += 1  # 400 of 1600 pixels, off by 1 in one channel
    b[39, 39, 1] += 3
    r = compare_images(a, b, with_flip=False)
    assert r.max_abs == 3
    assert r.over_1 == pytest.approx(1 / 1600)
    assert r.over_2 == pytest.approx(1 / 1600)
    mse = (400 * 1 + 9) / (1600 * 3) / 255**2
    assert r.psnr == pytest.approx(10 * np.log10(1 / mse))


def test_flip_grows_with_the_difference():
    a = _image(1)
    noise = np.random.default_rng(2).integers(-20, 21, a.shape)
    small = np.clip(a.astype(int) + noise // 10, 0, 255).astype(np.uint8)
    large = np.clip(a.astype(int) + noise * 3, 0, 255).astype(np.uint8)
    assert 0 < compare_images(a, small).flip_mean < compare_images(a, large).flip_mean


def test_heatmap_magnifies_small_differences():
    a = np.zeros((4, 4, 4), np.uint8)
    b = a.copy()
    b[1, 2, 0] = 1
    h = heatmap(a, b)
    assert h[1, 2].max() > 0 and h.sum() == h[1, 2].sum()


def test_size_mismatch_is_a_clear_error():
    with pytest.raises(UserError, match="differ in size"):
        compare_images(_image(size=(4, 4)), _image(size=(4, 5)))


def test_cli_threshold_exit_codes(tmp_path, capsys):
    a, b = _image(3), _image(3)
    b[0, 0, 0] ^= 0xFF
    save_png(tmp_path / "a.png", a)
    save_png(tmp_path / "b.png", b)
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "a.png")]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "within threshold: flip_mean 0 <= 0.005"
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--threshold", "max_abs=255",
                 "--threshold", "psnr=1"]) == 0
    got = compare_images(a, b)
    assert capsys.readouterr().out.splitlines()[-1] == (f"within threshold: max_abs {got.max_abs:.6g} <= 255; "
                                                        f"psnr {got.psnr:.6g} >= 1")
    code = main(["compare", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--threshold", "max_abs=0",
                 "--heatmap", str(tmp_path / "h.png")])
    assert code == 1 and (tmp_path / "h.png").is_file()
    assert "over threshold: max_abs" in capsys.readouterr().out
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "nope.png")]) == 2
    assert "image not found" in capsys.readouterr().err
