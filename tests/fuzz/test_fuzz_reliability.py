"""Generators for what the earlier fuzz missed (issue 24): paths as the OS sees them, image headers declaring huge
sizes, deep TOML nesting, glTF node graphs and accessor layouts, and calls of the Python API. Each case is a clean
render (or a correct API result) or one clean error; an API call that returns a wrong answer counts as "wrong"."""

from __future__ import annotations

import json
import os
import struct
import traceback
import zlib

import numpy as np
import pytest
from harness import PASSING, _count, check, render_argv, reset_folder, run_case, time_bound
from hypothesis import given
from hypothesis import strategies as st
from reliab_gen import SCENE_CAMERA, scene_text, triangle_gltf
from strategies import ASSETS, fuzz_settings

import wgpurender.api as api
from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import srgb_encode


@pytest.fixture
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("reliability")


# --- paths --------------------------------------------------------------------------------------------------

PATH_KINDS = ("file", "loop", "dangling", "long", "fifo", "directory", "device", "through-file", "link-to-dir",
               "chain", "long-dir", "missing")


def _make_path(folder, kind: str, source, n: int) -> str:
    """A name in ``folder`` that is ``kind``; ``source`` is a real file's path (for "file" and "chain")."""
    name = f"p{n}{source.suffix}"
    target = folder / name
    if kind == "file":
        target.symlink_to(source)
    elif kind == "loop":
        target.symlink_to(f"q{n}{source.suffix}")
        (folder / f"q{n}{source.suffix}").symlink_to(name)
    elif kind == "dangling":
        target.symlink_to(folder / "nowhere" / "x")
    elif kind == "long":
        return "x" * (250 + n % 20) + source.suffix
    elif kind == "long-dir":
        return "d" * (256 + n % 9) + "/" + source.name
    elif kind == "fifo":
        os.mkfifo(target)
    elif kind == "directory":
        target.mkdir()
    elif kind == "device":
        target.symlink_to("/dev/null")
    elif kind == "through-file":
        (folder / f"f{n}").write_text("x")
        return f"f{n}/{source.name}"
    elif kind == "link-to-dir":
        target.symlink_to(folder)
    elif kind == "chain":
        (folder / f"c{n}{source.suffix}").symlink_to(source)
        target.symlink_to(f"c{n}{source.suffix}")
    return name


@st.composite
def path_case(draw):
    role = draw(st.sampled_from(("texture", "model", "scene", "compare", "output")))
    return role, draw(st.sampled_from(PATH_KINDS)), draw(st.integers(0, 99)), draw(st.booleans())


@fuzz_settings(ci=12, long=1500)
@given(case=path_case())
def test_paths_as_the_os_sees_them(folder, case):
    role, kind, n, follow = case
    reset_folder(folder)
    (folder / "out").mkdir()
    texture, model = ASSETS / "textures" / "brick_albedo.png", ASSETS / "models" / "brick_cube.obj"
    real_scene = folder / "real.toml"
    real_scene.write_text(scene_text(model=str(model)))
    scene = folder / "scene.toml"
    output = folder / "out" / "out.png"
    judged_output = output
    if role == "compare":
        argv = ["compare", texture, folder / _make_path(folder, kind, texture, n)]
        judged_output = None
    elif role == "output":  # links lead to a file of this case's own, never to the repository's
        existing = folder / "out" / "existing.png"
        existing.write_bytes(texture.read_bytes())
        output = folder / "out" / _make_path(folder / "out", kind, existing, n)
        argv = ["render", real_scene, "-o", output, "--size", "40x30"]
        judged_output = output if kind in ("long", "missing") else None
    else:
        source = {"texture": texture, "model": model, "scene": real_scene}[role]
        name = _make_path(folder, kind, source, n)
        if role == "texture":
            scene.write_text(f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\n\n[[models]]\npath = \"{model}\"\n"
                             f"material.albedo_map = \"{name}\"\n")
        elif role == "model":
            scene.write_text(scene_text(model=name))
        else:
            scene = folder / name
        argv = render_argv(scene, output)
    os.environ.pop("WGPURENDER_FOLLOW_SYMLINKS", None)
    if follow:
        os.environ["WGPURENDER_FOLLOW_SYMLINKS"] = "1"
    try:
        outcome = run_case(argv, judged_output, None, f"path {role} {kind} follow={follow}")
    finally:
        os.environ.pop("WGPURENDER_FOLLOW_SYMLINKS", None)
    if role == "output" and kind == "loop":  # a link of a loop is never replaced, whatever the policy
        out_dir = folder / "out"
        if not (os.path.islink(out_dir / f"p{n}.png") and os.path.islink(out_dir / f"q{n}.png")):
            outcome = _count("partial", "loop replaced", str(case))
    check(outcome, f"{outcome}: {case}")


# --- declared image sizes -----------------------------------------------------------------------------------

def png_declaring(width: int, height: int, body_rows: int) -> bytes:
    """A greyscale PNG whose header says width x height; only ``body_rows`` rows of data follow (truncated when
    fewer than height), so the file stays small whatever it declares."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    packer = zlib.compressobj(6)
    rows = min(body_rows, height) if width <= 65536 else 0  # wider: the header alone (no 2 GB row here)
    data = b"".join(packer.compress(bytes(width + 1)) for _ in range(rows)) + packer.flush()
    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", data) + chunk(b"IEND", b"")


SIDES = st.one_of(st.integers(1, 64), st.sampled_from([4096, 4097, 8192, 12000, 16384, 16385, 30000, 65535, 2**31 - 1]))


@fuzz_settings(ci=8, long=1000)
@given(width=SIDES, height=SIDES, rows=st.integers(0, 8), role=st.sampled_from(["texture", "compare"]))
def test_declared_image_sizes(folder, width, height, rows, role):
    reset_folder(folder)
    (folder / "out").mkdir()
    (folder / "image.png").write_bytes(png_declaring(width, height, rows))
    label = f"declared {width}x{height} ({rows} rows) as {role}"
    if role == "compare":
        outcome = run_case(["compare", folder / "image.png", folder / "image.png"], None, None, label)
    else:
        scene = folder / "scene.toml"
        scene.write_text(f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\n\n[[models]]\npath = "
                         f"\"{ASSETS / 'models' / 'brick_cube.obj'}\"\nmaterial.albedo_map = \"image.png\"\n")
        output = folder / "out" / "out.png"
        outcome = run_case(render_argv(scene, output), output, None, label)
    check(outcome, f"{outcome}: {label}")


# --- nesting ------------------------------------------------------------------------------------------------

@st.composite
def nested_value(draw) -> str:
    depth = draw(st.one_of(st.integers(1, 40), st.sampled_from([100, 500, 1000, 3000, 20000])))
    opens = "".join(draw(st.sampled_from(["[", "{a = "])) for _ in range(min(depth, 60)))
    opens = opens + "[" * max(0, depth - 60)
    closes = "".join("]" if ch == "[" else "}" for ch in reversed(opens.replace("{a = ", "{")))
    return opens + draw(st.sampled_from(["", "1", "\"x\""])) + closes


@fuzz_settings(ci=8, long=800)
@given(value=nested_value(), where=st.sampled_from(["top", "camera.eye", "render.size", "models.transform",
                                                   "post", "materials.m"]))
def test_nested_toml(folder, value, where):
    reset_folder(folder)
    (folder / "out").mkdir()
    base = scene_text(model=str(ASSETS / "models" / "brick_cube.obj"))
    if where == "top":
        text = f"deep = {value}\n" + base
    elif where == "camera.eye":
        text = base.replace("eye = [0, 0, 3]", f"eye = {value}")
    elif where == "render.size":
        text = base.replace("size = [32, 24]", f"size = {value}")
    elif where == "models.transform":
        text = base + f"transform = {value}\n"
    elif where == "post":
        text = base + f"\npost = {value}\n"
    else:
        text = base + f"\n[materials.m]\nalbedo_color = {value}\n"
    scene = folder / "scene.toml"
    scene.write_text(text)
    output = folder / "out" / "out.png"
    outcome = run_case(render_argv(scene, output), output, None, f"nested {len(value)} chars at {where}")
    check(outcome, f"{outcome}: nested at {where}: {value[:80]}")


# --- glTF graphs and accessors -------------------------------------------------------------------------------

TYPES = ("SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4", "VEC5", "")
COMPONENTS = (5120, 5121, 5122, 5123, 5125, 5126, 5124, 0)


@st.composite
def gltf_graph(draw) -> dict:
    doc = triangle_gltf(normals=draw(st.booleans()))
    count = draw(st.integers(1, 6))
    nodes = [{"mesh": 0} if draw(st.booleans()) or i == 0 else {} for i in range(count)]
    for node in nodes:
        if draw(st.booleans()):
            node["children"] = draw(st.lists(st.integers(0, count - 1), max_size=4))
        if draw(st.integers(0, 3)) == 0:
            node["scale"] = draw(st.sampled_from([[1, 1, 1], [0, 1, 1], [2, 2, 2], [-1, 1, 1]]))
    doc["nodes"] = nodes
    doc["scenes"] = [{"nodes": draw(st.lists(st.integers(0, count - 1), min_size=1, max_size=3))}]
    for acc in doc["accessors"]:
        if draw(st.integers(0, 3)) == 0:
            acc["type"] = draw(st.sampled_from(TYPES))
        if draw(st.integers(0, 3)) == 0:
            acc["componentType"] = draw(st.sampled_from(COMPONENTS))
        if draw(st.integers(0, 4)) == 0:
            acc["count"] = draw(st.sampled_from([0, 1, 2, 4, 1000, 2**31]))
        if draw(st.integers(0, 6)) == 0:
            acc.pop("min", None), acc.pop("max", None)
    prim = doc["meshes"][0]["primitives"][0]
    if draw(st.integers(0, 4)) == 0:
        extra = draw(st.sampled_from(["TEXCOORD_0", "TANGENT", "COLOR_0", "JOINTS_0", "WEIGHTS_0", "_CUSTOM"]))
        prim["attributes"][extra] = draw(st.integers(0, len(doc["accessors"]) - 1))
    if draw(st.integers(0, 4)) == 0:
        prim["mode"] = draw(st.sampled_from([0, 1, 2, 3, 4, 5, 6]))
    return doc


@fuzz_settings(ci=10, long=1200)
@given(doc=gltf_graph())
def test_gltf_graphs_and_accessors(folder, doc):
    reset_folder(folder)
    (folder / "out").mkdir()
    (folder / "model.gltf").write_text(json.dumps(doc))
    scene = folder / "scene.toml"
    scene.write_text(scene_text())
    output = folder / "out" / "out.png"
    outcome = run_case(render_argv(scene, output), output, scene, f"glTF graph {json.dumps(doc['nodes'])[:200]}")
    check(outcome, f"{outcome}: {json.dumps(doc)[:400]}")


# --- the Python API ------------------------------------------------------------------------------------------

ARRAY_DTYPES = (np.uint8, np.uint16, np.float32, np.float64, np.float16, np.int32, np.bool_, np.int8)


@st.composite
def image_value(draw):
    kind = draw(st.sampled_from(["array", "array", "array", "path", "odd"]))
    if kind == "path":
        return draw(st.sampled_from([str(ASSETS / "textures" / "brick_albedo.png"), "missing.png", "", "/dev/null",
                                     str(ASSETS)]))
    if kind == "odd":
        return draw(st.sampled_from([None, 5, "x", [[1, 2]], b"png", 1.5]))
    dtype = draw(st.sampled_from(ARRAY_DTYPES))
    shape = draw(st.sampled_from([(4, 4, 3), (4, 4, 4), (4, 4), (0, 0, 3), (4, 0, 4), (4, 4, 2), (1, 1, 4), (4, 4, 5),
                                  (2, 4, 4, 3)]))
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    fill = draw(st.sampled_from(["random", "zero", "max", "nan", "inf", "negative"]))
    if np.dtype(dtype).kind == "f":
        values = {"random": rng.random(shape), "zero": np.zeros(shape), "max": np.ones(shape) * 1e30,
                  "nan": np.full(shape, np.nan), "inf": np.full(shape, np.inf), "negative": -rng.random(shape)}[fill]
    elif dtype is np.bool_:
        values = rng.integers(0, 2, shape)
    else:
        info = np.iinfo(dtype)
        values = rng.integers(max(info.min, -1000), min(info.max, 70000), shape) if fill == "random" else \
            np.full(shape, info.max if fill == "max" else 0)
    with np.errstate(over="ignore"):  # 1e30 as float16 is inf: meant
        return np.asarray(values).astype(dtype)


ANY_VALUE = st.sampled_from([None, 0, -1, 1, 4, 4.0, True, float("nan"), float("inf"), "4", "x", "", (320, 240),
                             (0, 0), "64x48", [1, 2, 3], {"a": 1}, b"x", 2**70, -2**70, "Vulkan", "rgba8unorm",
                             "rgba32float", "auto", "scene"])


@st.composite
def api_call(draw):
    name = draw(st.sampled_from(["compare", "heatmap", "side_by_side", "render", "reference", "explain", "plan"]))
    if name in ("compare", "heatmap"):
        kwargs = {"a": draw(image_value()), "b": draw(image_value())}
        if name == "heatmap" and draw(st.booleans()):
            kwargs["gain"] = draw(st.one_of(ANY_VALUE, st.floats(allow_nan=True, allow_infinity=True)))
        if name == "compare":
            kwargs["flip"] = draw(st.sampled_from([False, False, True, "yes", 0, None]))
        return name, kwargs
    if name == "side_by_side":
        images = draw(st.lists(image_value(), max_size=3))
        return name, {"images": images, "gap": draw(st.one_of(st.integers(-5, 5000), ANY_VALUE))}
    target = draw(st.sampled_from(["triangle", "clear-pass", str(ASSETS / "scenes" / "unlit.toml"), "nope", 5, None,
                                   ""]))
    kwargs = {"target" if name in ("render", "reference") else "scene": target}
    for arg in draw(st.lists(st.sampled_from(["size", "msaa", "format", "backend", "t", "anisotropy"]), max_size=3,
                             unique=True)):
        if arg == "t" and name in ("explain", "plan"):
            continue
        if arg == "backend" and name == "reference":
            continue
        kwargs[arg] = draw(ANY_VALUE)
    if name in ("render", "reference") and "size" not in kwargs:
        kwargs["size"] = (24, 16)  # keep renders small
    return name, kwargs


def _expected_rgb8(value) -> np.ndarray | None:
    """The 8-bit pixels an accepted array must be compared as (written here, not from the API)."""
    if not isinstance(value, np.ndarray):
        return None
    if value.dtype == np.uint8:
        return value[..., :3].astype(int)
    if value.dtype == np.uint16:
        return np.round(value[..., :3] / 257.0).astype(int)
    return np.round(srgb_encode(value[..., :3].astype(np.float64)) * 255).astype(int)


def _wrong_answer(name: str, kwargs: dict, result) -> str | None:
    """A silent wrong result of an accepted compare: the metrics against the test's own arithmetic."""
    if name != "compare":
        return None
    a, b = _expected_rgb8(kwargs["a"]), _expected_rgb8(kwargs["b"])
    if a is None or b is None:
        return None
    diff = np.abs(a - b).max()
    if result.max_abs != diff:
        return f"max_abs {result.max_abs}, expected {diff}"
    if (diff == 0) != (result.psnr == float("inf")):
        return f"psnr {result.psnr} with max difference {diff}"
    return None


@fuzz_settings(ci=30, long=1500)
@given(call=api_call())
def test_api_calls(call):
    name, kwargs = call
    label = f"api {name}({', '.join(f'{k}={type(v).__name__}' for k, v in kwargs.items())})"
    try:
        with time_bound(30):
            if name == "side_by_side":
                result = api.side_by_side(*kwargs["images"], gap=kwargs["gap"])
            else:
                result = getattr(api, name)(**kwargs)
    except UserError as err:
        outcome = _count("error" if "\n" not in str(err) and str(err) else "multiline", label, str(err))
    except BaseException as exc:  # noqa: BLE001 - any other escape is the finding
        outcome = _count("traceback", label, "".join(traceback.format_exception(exc))[-1500:])
    else:
        wrong = _wrong_answer(name, kwargs, result)
        outcome = _count("wrong", label, wrong) if wrong else _count("render", label, "")
    check(outcome, f"{outcome}: {label}")
    assert PASSING == ("render", "error")
