"""Every public function of the Python API (wgpurender.api) with wrong types and degenerate values: each call raises
UserError with a message saying what was wrong (the CLI's words where the CLI has the same argument), never a
numpy/wgpu exception and never a silent wrong result. One table: a new public function without rows fails
test_every_public_function_has_rows."""

from __future__ import annotations

import inspect

import numpy as np
import pytest
from reliab_gen import run_cli

import wgpurender as w
from wgpurender import api
from wgpurender.core.errors import UserError

NAN, INF = float("nan"), float("inf")
GREY = np.full((4, 4, 4), 128, np.uint8)

ARGUMENTS = {  # argument -> [(bad value, words the message must contain)]
    "size": [("64by48", "malformed size"), ((0, 10), "out of range"), ((10.5, 10), "malformed size"),
             ((True, 10), "malformed size"), ((10,), "malformed size"), (5, "malformed size"),
             ((16385, 10), "out of range"), ("6\u00b2x48", "malformed size")],  # '²' isdigit, int() refuses it
    "msaa": [(4.0, "whole number"), (True, "whole number"), (3, "sample count"), (0, "msaa must be"),
             ("4", "whole number"), (NAN, "whole number")],
    "format": [("rgba32float", "unsupported colour format"), (5, "unsupported colour format"),
               ("RGBA8", "unsupported colour format")],
    "backend": [(5, "unknown backend"), ("Glide", "unknown backend"), (["Vulkan"], "unknown backend")],
    "t": [(INF, "finite"), (NAN, "finite"), (-INF, "finite"), ("soon", "must be a number"), (None, "number")],
    "anisotropy": [("sometimes", "anisotropy must be one of"), (16, "anisotropy must be one of")],
}
TARGETS = [(5, "target must be"), ("", "target must be"), (None, "target must be")]
SCENE = "assets/scenes/final.toml"

IMAGES = [  # a bad image argument -> words
    (5, "expected a wgpurender.Image"), (np.zeros((0, 0, 3), np.uint8), "empty"),
    (np.zeros((4, 4), np.uint8), "shape"), (np.zeros((4, 4, 2), np.uint8), "shape"),
    (np.full((4, 4, 3), NAN), "NaN"), (np.zeros((4, 4, 3), bool), "dtype bool"),
    (np.zeros((4, 4, 3), np.int64), "dtype int64"), ("missing.png", "not found"), ([[1, 2]], "expected"),
]


def _rows():
    rows = []
    for name in ("render", "reference", "plan", "explain", "show", "record", "export"):
        params = inspect.signature(getattr(api, name)).parameters
        first = next(iter(params))
        extra = {"out": "frames" if name == "record" else "page"} if "out" in params else {}  # only one bad argument
        rows += [(name, {first: bad, **extra}, needle) for bad, needle in TARGETS]
        good = SCENE if name in ("plan", "explain") else "triangle"
        for arg, cases in ARGUMENTS.items():
            if arg in params:
                rows += [(name, {first: good, arg: bad, **extra}, needle) for bad, needle in cases]
    rows += [("record", {"target": "3d", "out": bad}, needle) for bad, needle in [
        ("clip.gif", "give a .mp4 file or a folder"), (5, "out must be"), ("no/such/clip.mp4", "does not exist")]]
    rows += [("record", {"target": "3d", "out": "frames", arg: bad}, needle) for arg, bad, needle in [
        ("seconds", 0, "> 0"), ("seconds", NAN, "finite"), ("fps", "30", "finite number"), ("fps", -1, "> 0"),
        ("turn", INF, "finite"), ("seconds", True, "finite number"), ("force", 1, "force must be True or False")]]
    rows += [("export", {"target": "triangle", "out": bad}, needle) for bad, needle in [  # issue 28.12
        (5, "out must be a folder or file path"), (None, "out must be a folder or file path"),
        ("", "out must be a folder or file path"), ("pa\0ge", "NUL character"), (b"page", "out must be")]]
    rows += [("export", {"target": "triangle", "out": "page", "force": bad}, "force must be True or False")
             for bad in ("yes", 1, None)]
    for name in ("compare", "heatmap"):
        rows += [(name, {"a": bad, "b": GREY}, needle) for bad, needle in IMAGES]
        rows += [(name, {"a": GREY, "b": bad}, needle) for bad, needle in IMAGES]
        rows.append((name, {"a": GREY, "b": np.zeros((5, 4, 4), np.uint8)}, "differ in size"))
    rows += [("compare", {"a": GREY, "b": GREY, "flip": "yes"}, "flip must be")]
    rows += [("heatmap", {"a": GREY, "b": GREY, "gain": bad}, needle) for bad, needle in [
        (0, "gain must be above 0"), (-1, "gain must be above 0"), (NAN, "finite"), (INF, "finite"),
        ("32", "gain must be a number"), (True, "gain must be a number")]]
    rows += [("side_by_side", {"images": images, "gap": gap}, needle) for images, gap, needle in [
        ((), 4, "at least one"), ((GREY,), "4", "gap must be a whole number"), ((GREY,), -1, "gap must be 0..4096"),
        ((GREY,), 4.0, "whole number"), ((np.zeros((4, 4), np.uint8),), 4, "shape"), ((5,), 4, "expected")]]
    return rows


ROWS = _rows()


def _call(name: str, kwargs: dict):
    kwargs = dict(kwargs)
    if name == "side_by_side":
        return api.side_by_side(*kwargs.pop("images"), **kwargs)
    return getattr(api, name)(**kwargs)


@pytest.mark.parametrize("name, kwargs, needle", ROWS, ids=[f"{r[0]}-{i}" for i, r in enumerate(ROWS)])
def test_a_bad_argument_is_a_user_error_that_says_what(name, kwargs, needle):
    with pytest.raises(UserError) as caught:
        _call(name, kwargs)
    message = str(caught.value)
    assert needle in message and "\n" not in message, message


def test_every_public_function_has_rows():
    without_arguments = {"stage_names", "reference_stage_names", "Image"}
    covered = {name for name, _, _ in ROWS}
    assert set(api.__all__) - without_arguments == covered


# The same mistake through the CLI and the API: the same words (argparse adds "argument --X:" before them).
SAME_MESSAGE = [
    (lambda: api.heatmap(GREY, GREY, gain=0), ["compare", "{a}", "{a}", "--gain", "0"]),
    (lambda: api.heatmap(GREY, GREY, gain=NAN), ["compare", "{a}", "{a}", "--gain", "nan"]),
    (lambda: api.render("triangle", size="64by48"), ["render", "triangle", "-o", "{out}", "--size", "64by48"]),
    (lambda: api.render("triangle", size=(0, 5)), ["render", "triangle", "-o", "{out}", "--size", "0x5"]),
    (lambda: api.render("triangle", t=INF), ["render", "triangle", "-o", "{out}", "--time", "inf"]),
    (lambda: api.render("triangle", msaa=3), ["render", "triangle", "-o", "{out}", "--msaa", "3"]),
    (lambda: api.render("triangle", format="rgba32float"),
     ["render", "triangle", "-o", "{out}", "--format", "rgba32float"]),
    (lambda: api.render("triangle", backend="Glide"), ["render", "triangle", "-o", "{out}", "--backend", "Glide"]),
    (lambda: api.reference("triangle", t=NAN), ["reference", "triangle", "-o", "{out}", "--time", "nan"]),
]


@pytest.mark.parametrize("index", range(len(SAME_MESSAGE)))
def test_the_cli_and_the_api_say_the_same(tmp_path, index):
    from PIL import Image

    call, argv = SAME_MESSAGE[index]
    Image.fromarray(GREY).save(tmp_path / "a.png")
    argv = [a.format(a=tmp_path / "a.png", out=tmp_path / "out.png") for a in argv]
    with pytest.raises(UserError) as caught:
        call()
    code, _, err = run_cli(*argv)
    assert code == 2 and str(caught.value) in err, (str(caught.value), err)


# --- degenerate values with a right answer ------------------------------------------------------------------

def test_uint16_pixels_are_scaled_not_read_as_bytes():
    full16 = np.full((4, 4, 4), 65535, np.uint16)
    full8 = np.full((4, 4, 4), 255, np.uint8)
    assert w.compare(full16, full8, flip=False).max_abs == 0
    one16 = np.ones((4, 4, 3), np.uint16)  # 1/65535: rounds to 0 of 255, not 1 (or 255)
    assert w.compare(one16, np.zeros((4, 4, 3), np.uint8), flip=False).max_abs == 0
    mid16 = np.full((4, 4, 3), 257 * 100, np.uint16)
    assert w.compare(mid16, np.full((4, 4, 3), 100, np.uint8), flip=False).max_abs == 0


def test_float_pixels_are_linear_and_srgb_encoded():
    half = np.full((2, 2, 3), 0.5, np.float32)
    encoded = round((1.055 * 0.5 ** (1 / 2.4) - 0.055) * 255)  # IEC 61966-2-1
    assert w.compare(half, np.full((2, 2, 3), encoded, np.uint8), flip=False).max_abs == 0
    dark = np.full((2, 2, 3), 0.002, np.float32)  # the linear segment: 12.92 x below 0.0031308
    assert w.compare(dark, np.full((2, 2, 3), round(12.92 * 0.002 * 255), np.uint8), flip=False).max_abs == 0


def test_heatmap_gain_scales_the_difference():
    a = np.zeros((4, 4, 3), np.uint8)
    b = a.copy()
    b[0, 0] = 4  # 4/255
    for gain in (1.0, 8.0, 32.0):
        heat = w.heatmap(a, b, gain=gain).pixels
        d = min(4 * gain / 255.0, 1.0)  # the ramp's input; red channel = clip(3d)
        assert heat[0, 0, 0] == round(min(3 * d, 1.0) * 255), gain
        assert heat[1, 1, :3].tolist() == [0, 0, 0]


def test_side_by_side_places_images_gap_apart():
    a, b = np.full((2, 3, 4), 10, np.uint8), np.full((4, 2, 4), 200, np.uint8)
    out = w.side_by_side(a, b, gap=5).pixels
    assert out.shape == (4, 3 + 5 + 2, 4)
    assert out[0, 0, 0] == 10 and out[0, 8, 0] == 200 and out[0, 4, 0] == 0 and out[3, 0, 0] == 0


def test_a_float_image_object_is_compared_as_its_srgb_bytes():
    """An rgba16float render (Image.pixels float16, linear) compares as the 8-bit image it saves as."""
    image = api.Image(np.full((2, 2, 4), 0.5, np.float16), "x", "wgpu")
    encoded = round((1.055 * 0.5 ** (1 / 2.4) - 0.055) * 255)
    assert w.compare(image, np.full((2, 2, 4), encoded, np.uint8), flip=False).max_abs == 0
