"""Issue 24's causes, one reproducer each: every case failed on main 53e5e7b (a traceback, a wrong "not found", a
clobbered link, gigabytes of memory, a check switched off) and must end as one line with exit 2, or as the right
result. Each input is made here, at run time (links, FIFOs, long names, PNG headers, nested TOML)."""

from __future__ import annotations

import json
import os
import resource
import signal
import struct
import subprocess
import sys
import textwrap
import time
import zlib
from pathlib import Path

import pytest
from helpers import one_line_refusal
from peak_memory import measured_argv, reported_peak_mib
from PIL import Image
from reliab_gen import run_cli, scene_text, triangle_gltf, write_gltf

from wgpurender.core.files import safe_write

LONG = "n" * 300  # a path component over the 255 bytes any Linux file system allows



CUBE = Path(__file__).resolve().parents[1] / "assets" / "models" / "brick_cube.obj"  # has texture coordinates


def _textured_scene(tmp_path: Path, texture: str) -> Path:
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text(extra="", model=None) + textwrap.dedent(f"""
        [materials.m]
        albedo_map = "{texture}"

        [[models]]
        path = "{CUBE}"
        material = "m"
        """))
    return scene


def _render(tmp_path: Path, scene: Path, *extra: str) -> tuple[int, str, str]:
    return run_cli("render", scene, "-o", tmp_path / "out.png", *extra)


# --- paths ---------------------------------------------------------------------------------------------------

def test_a_texture_that_is_a_symlink_loop_is_named_as_one(tmp_path):
    os.symlink("loop_b.png", tmp_path / "loop_a.png")
    os.symlink("loop_a.png", tmp_path / "loop_b.png")
    code, _, err = _render(tmp_path, _textured_scene(tmp_path, "loop_a.png"))
    one_line_refusal(code, err, "albedo_map", "symbolic link loop")
    assert not (tmp_path / "out.png").exists()


@pytest.mark.parametrize("where", ["texture", "model", "scene", "compare"])
def test_a_path_component_over_255_bytes_is_one_line(tmp_path, where):
    if where == "texture":
        code, _, err = _render(tmp_path, _textured_scene(tmp_path, f"{LONG}.png"))
        needle = "albedo_map"
    elif where == "model":
        (tmp_path / "scene.toml").write_text(scene_text(model=f"{LONG}.gltf"))
        code, _, err = _render(tmp_path, tmp_path / "scene.toml")
        needle = "path"
    elif where == "scene":
        code, _, err = _render(tmp_path, tmp_path / f"{LONG}.toml")
        needle = "too long"
    else:
        Image.new("RGB", (4, 4)).save(tmp_path / "a.png")
        code, _, err = run_cli("compare", tmp_path / "a.png", tmp_path / f"{LONG}.png")
        needle = "too long"
    one_line_refusal(code, err, needle)


@pytest.mark.parametrize("length", [240, 250, 255])
def test_an_output_name_near_the_limit_is_written_and_leaves_no_temp_file(tmp_path, length):
    out = tmp_path / ("o" * (length - 4) + ".png")
    safe_write.atomic_write(out, b"new bytes")
    assert out.read_bytes() == b"new bytes"
    assert sorted(p.name for p in tmp_path.iterdir()) == [out.name]
    temp = safe_write.temp_name(out)
    assert len(os.fsencode(temp.name)) <= 255 and safe_write._TEMP.match(temp.name)  # the sweep still finds it


def test_a_render_to_a_255_byte_name_ends_clean(tmp_path):
    out = tmp_path / ("r" * 251 + ".png")
    code, _, err = run_cli("render", "clear-pass", "-o", out, "--size", "8x8")
    assert code == 0, err
    assert Image.open(out).size == (8, 8)
    assert [p.name for p in tmp_path.iterdir()] == [out.name]


def test_follow_symlinks_never_replaces_a_link_of_a_loop(tmp_path, monkeypatch):
    monkeypatch.setenv(safe_write.FOLLOW_SYMLINKS_ENV, "1")
    os.symlink("b.png", tmp_path / "a.png")
    os.symlink("a.png", tmp_path / "b.png")
    Image.new("RGB", (4, 4)).save(tmp_path / "x.png")
    code, _, err = run_cli("compare", tmp_path / "x.png", tmp_path / "x.png", "--heatmap", tmp_path / "a.png")
    one_line_refusal(code, err, "symbolic link loop")
    assert os.readlink(tmp_path / "a.png") == "b.png" and os.readlink(tmp_path / "b.png") == "a.png"


def test_follow_symlinks_writes_through_a_link_and_keeps_it(tmp_path, monkeypatch):
    monkeypatch.setenv(safe_write.FOLLOW_SYMLINKS_ENV, "1")
    (tmp_path / "real.bin").write_bytes(b"old")
    os.symlink("real.bin", tmp_path / "link.bin")
    safe_write.atomic_write(tmp_path / "link.bin", b"new")
    assert os.readlink(tmp_path / "link.bin") == "real.bin" and (tmp_path / "real.bin").read_bytes() == b"new"


@pytest.mark.parametrize("kind", ["fifo", "device", "directory"])
@pytest.mark.parametrize("as_what", ["scene", "texture", "image"])
def test_a_special_file_given_as_input_is_named_as_what_it_is(tmp_path, kind, as_what):
    special = tmp_path / "special.png"
    if kind == "fifo":
        os.mkfifo(special)
        expected = "FIFO"
    elif kind == "device":
        special = Path("/dev/null")
        expected = "character device"
    else:
        special.mkdir()
        expected = "directory"
    if as_what == "scene":  # a scene is named by its suffix: reach the special file through a .toml name
        os.symlink(special, tmp_path / "special.toml")
        code, _, err = run_cli("render", tmp_path / "special.toml", "-o", tmp_path / "out.png")
    elif as_what == "texture":
        code, _, err = _render(tmp_path, _textured_scene(tmp_path, str(special)))
    else:
        Image.new("RGB", (4, 4)).save(tmp_path / "a.png")
        code, _, err = run_cli("compare", tmp_path / "a.png", special)
    line = one_line_refusal(code, err, expected)
    assert "not found" not in line


def test_a_scene_file_that_is_a_fifo_is_named_as_one(tmp_path):
    os.mkfifo(tmp_path / "scene.toml")
    code, _, err = _render(tmp_path, tmp_path / "scene.toml")  # must not open it: that would block
    one_line_refusal(code, err, "FIFO")


# --- resources -----------------------------------------------------------------------------------------------

def _png_declaring(path: Path, width: int, height: int) -> Path:
    """A valid greyscale PNG of width x height zeros, written row by row (a few hundred KB for 12000x12000)."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    packer, row, parts = zlib.compressobj(9), bytes(width + 1), []
    for _ in range(height):
        parts.append(packer.compress(row))
    parts.append(packer.flush())
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
                     + chunk(b"IDAT", b"".join(parts)) + chunk(b"IEND", b""))
    return path


def _limit_memory() -> None:  # the old code took 20 GB: keep a failing run from taking the machine
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))


def test_compare_of_pngs_declaring_12000x12000_is_one_line_in_bounded_memory(tmp_path):
    a = _png_declaring(tmp_path / "a.png", 12000, 12000)
    b = _png_declaring(tmp_path / "b.png", 12000, 12000)
    assert a.stat().st_size < 1_000_000
    report = tmp_path / "peak.txt"
    with open(tmp_path / "err.txt", "wb") as err:
        proc = subprocess.run(measured_argv("wgpurender", ["compare", a, b], report), stdout=subprocess.DEVNULL,
                              stderr=err, preexec_fn=_limit_memory, timeout=300)
    one_line_refusal(proc.returncode, (tmp_path / "err.txt").read_text(), "declares 12000x12000",
                    "WGPURENDER_MAX_IMAGE_PIXELS")
    peak = reported_peak_mib(report)  # the child's own (wait4's ru_maxrss folds in this worker's peak)
    assert peak is not None and peak < 1024, f"peak RSS {peak} MiB"


def test_a_texture_declaring_too_many_pixels_is_refused_before_decoding(tmp_path):
    _png_declaring(tmp_path / "huge.png", 8192, 4096)
    code, _, err = _render(tmp_path, _textured_scene(tmp_path, "huge.png"))
    one_line_refusal(code, err, "declares 8192x4096")


def _png_rows(path: Path, width: int, height: int, rows: int) -> Path:
    """A greyscale PNG declaring width x height whose zlib stream (complete) holds only ``rows`` rows."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    data = zlib.compress(bytes((width + 1) * rows))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
                     + chunk(b"IDAT", data) + chunk(b"IEND", b""))
    return path


@pytest.mark.parametrize("as_what", ["image", "texture"])
def test_a_png_whose_data_ends_early_is_refused_not_zero_filled(tmp_path, as_what):
    """Found by the declared-size fuzz: Pillow decodes it at the declared size, the missing rows black."""
    png = _png_rows(tmp_path / "short.png", 64, 64, 8)
    if as_what == "image":
        code, _, err = run_cli("compare", png, png)
    else:
        code, _, err = _render(tmp_path, _textured_scene(tmp_path, "short.png"))
    one_line_refusal(code, err, "short.png", "ends early", "12%")
    full = _png_rows(tmp_path / "full.png", 64, 64, 64)
    assert run_cli("compare", full, full)[0] == 0


@pytest.mark.parametrize("depth", [40, 500, 3000])
def test_deeply_nested_toml_is_one_line(tmp_path, depth):
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_text() + "deep = " + "[" * depth + "]" * depth + "\n")
    code, _, err = _render(tmp_path, scene)
    one_line_refusal(code, err, "nested more than 32 deep")


def test_a_model_file_over_the_size_bound_is_refused_before_parsing(tmp_path):
    model = tmp_path / "model.obj"
    with open(model, "wb") as f:  # sparse: no disk space used
        f.write(b"v 0 0 0\n")
        f.truncate(600 * 2**20)
    (tmp_path / "scene.toml").write_text(scene_text(model="model.obj"))
    code, _, err = _render(tmp_path, tmp_path / "scene.toml")
    one_line_refusal(code, err, "600 MiB", "WGPURENDER_MAX_MODEL_BYTES")


def test_the_model_size_bound_is_an_environment_setting(tmp_path, monkeypatch):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    (tmp_path / "scene.toml").write_text(scene_text())
    monkeypatch.setenv("WGPURENDER_MAX_MODEL_BYTES", "100")
    code, _, err = _render(tmp_path, tmp_path / "scene.toml")
    one_line_refusal(code, err, "over the limit")


@pytest.mark.parametrize("command", ["render", "reference"])  # the wgpu path, the raw-Vulkan path
@pytest.mark.parametrize("target", ["msaa", "scene"])
def test_a_size_the_adapter_cannot_hold_is_refused_before_allocation(tmp_path, monkeypatch, ctx, target, command):
    """16384x16384 at MSAA 4 is about 10 GB of attachments: over lavapipe's 2 GiB allocation; a GPU's memory is
    unknown to WebGPU (an H100 holds it), so there the budget is given the way a user would, in bytes."""
    if ctx.info.get("adapter_type") != "CPU":
        monkeypatch.setenv("WGPURENDER_GPU_MEMORY", str(10**9))
    if target == "scene":
        write_gltf(tmp_path / "model.gltf", triangle_gltf())
        (tmp_path / "scene.toml").write_text(scene_text())
        target = tmp_path / "scene.toml"
    code, _, err = run_cli(command, target, "-o", tmp_path / "out.png", "--size", "16384x16384", "--msaa", "4")
    one_line_refusal(code, err, "16384x16384", "--size")
    assert not (tmp_path / "out.png").exists()


def test_explain_shows_the_memory_estimate(tmp_path):
    write_gltf(tmp_path / "model.gltf", triangle_gltf())
    (tmp_path / "scene.toml").write_text(scene_text(size=(1000, 500)))
    code, out, err = run_cli("render", tmp_path / "scene.toml", "--explain", "--msaa", "4")
    assert code == 0, err
    line = next(ln for ln in out.splitlines() if ln.startswith("memory:"))
    # independent arithmetic: 4-sample rgba8 colour + 4-sample depth32 + output + readback, 1000x500
    assert f"{(4 * 4 + 4 * 4 + 4 + 4) * 1000 * 500 / 1e6:.1f} MB" in line, line


LONG_NATIVE_WORK = """
import os, sys, zlib
import wgpurender.core.verdict.compare as compare
from wgpurender.cli import main

def busy_flip(a, b):  # one long call into C that never checks for signals, like FLIP, numpy or a lavapipe frame
    data = os.urandom(200 << 20)
    print("busy", flush=True)
    zlib.compress(data, 9)
    return 0.0, None

compare.flip_mean = busy_flip
sys.exit(main(["compare", sys.argv[1], sys.argv[2]]))  # two unequal images: equal ones skip FLIP
"""


def test_sigterm_ends_long_native_work_at_once(tmp_path):
    """A Python signal handler runs only between bytecodes: the old handler let a compare run on for minutes."""
    Image.new("RGB", (8, 8)).save(tmp_path / "a.png")
    Image.new("RGB", (8, 8), (255, 255, 255)).save(tmp_path / "b.png")
    proc = subprocess.Popen([sys.executable, "-c", LONG_NATIVE_WORK, str(tmp_path / "a.png"), str(tmp_path / "b.png")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        assert proc.stdout.readline() == b"busy\n", proc.stderr.read().decode()
        time.sleep(0.5)  # into zlib: a signal between bytecodes would reach any handler
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=5) in (-signal.SIGTERM, 128 + signal.SIGTERM)
    finally:
        proc.kill()
        proc.wait()


# --- glTF shapes ---------------------------------------------------------------------------------------------

def _gltf_fails(tmp_path, doc: dict, *needles: str) -> None:
    write_gltf(tmp_path / "model.gltf", doc)
    (tmp_path / "scene.toml").write_text(scene_text())
    code, _, err = _render(tmp_path, tmp_path / "scene.toml")
    one_line_refusal(code, err, "malformed glTF file", *needles)


def test_a_node_that_is_its_own_child_is_refused_up_front(tmp_path):
    _gltf_fails(tmp_path, triangle_gltf(node={"children": [0]}), "$.nodes[0].children[0]", "own child")
    doc = triangle_gltf(node={"children": [1]})
    doc["nodes"].append({"children": [1, 2]})  # node 1 lists itself first: its index differs from its position
    doc["nodes"].append({})
    _gltf_fails(tmp_path, doc, "$.nodes[1].children[0] = 1", "own child")


def test_a_node_cycle_through_two_nodes_is_refused(tmp_path):
    doc = triangle_gltf(node={"children": [1]})
    doc["nodes"].append({"children": [0]})
    _gltf_fails(tmp_path, doc, "cycle")


def test_a_node_with_two_parents_is_refused(tmp_path):
    doc = triangle_gltf(node={"children": [2]})
    doc["nodes"] += [{"children": [2]}, {}]
    doc["scenes"][0]["nodes"] = [0, 1]
    _gltf_fails(tmp_path, doc, "already has the parent")


def test_a_scalar_position_accessor_is_refused_up_front(tmp_path):
    doc = triangle_gltf()
    doc["accessors"][0]["type"] = "SCALAR"
    del doc["accessors"][0]["min"], doc["accessors"][0]["max"]
    _gltf_fails(tmp_path, doc, "$.meshes[0].primitives[0].attributes.POSITION", "VEC3", "SCALAR")


def test_float_indices_are_refused(tmp_path):
    doc = triangle_gltf()
    doc["accessors"][-1]["componentType"] = 5126
    _gltf_fails(tmp_path, doc, "indices", "UNSIGNED")


def test_attributes_of_unequal_counts_are_refused(tmp_path):
    doc = triangle_gltf()
    doc["accessors"][1]["count"] = 2
    _gltf_fails(tmp_path, doc, "$.meshes[0].primitives[0].attributes.NORMAL has 2 elements, POSITION 3")


# --- formats, thresholds -------------------------------------------------------------------------------------

def test_a_float32_format_is_refused_for_a_stage_with_msaa(tmp_path):
    code, _, err = run_cli("render", "msaa", "-o", tmp_path / "out.png", "--format", "rgba32float", "--msaa", "4")
    one_line_refusal(code, err, "rgba32float", "rgba16float")


@pytest.mark.parametrize("metric", ["psnr", "max_abs", "over_1", "over_2", "flip_mean"])
def test_a_nan_threshold_is_refused_not_switched_off(tmp_path, metric):
    Image.new("RGB", (8, 8), (0, 0, 0)).save(tmp_path / "black.png")
    Image.new("RGB", (8, 8), (255, 255, 255)).save(tmp_path / "white.png")
    code, _, err = run_cli("compare", tmp_path / "black.png", tmp_path / "white.png", "--threshold", f"{metric}=nan")
    one_line_refusal(code, err, metric, "finite")


def test_black_against_white_fails_every_finite_threshold(tmp_path):
    Image.new("RGB", (8, 8), (0, 0, 0)).save(tmp_path / "black.png")
    Image.new("RGB", (8, 8), (255, 255, 255)).save(tmp_path / "white.png")
    code, out, _ = run_cli("compare", tmp_path / "black.png", tmp_path / "white.png", "--json",
                           "--threshold", "psnr=20", "--threshold", "max_abs=10", "--threshold", "over_1=1%")
    assert code == 1 and json.loads(out)["failed"] == ["psnr", "max_abs", "over_1"]
