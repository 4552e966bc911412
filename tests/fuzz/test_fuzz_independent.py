"""An independent attack on issue 28's surfaces, written apart from the code it attacks (and from the other fuzz
files): real model files mutated structurally (GLB chunk lengths and types, the JSON inside a GLB edited at a
random JSON path, overlapping buffer views, data: URIs with bad base64 or huge declared sizes), references of
every kind (percent- and double-encoded, NUL and unicode, symlink chains and loops made at run time, hard links),
OBJ ``mtllib`` and ``map_Kd`` with options, scene TOML paths of every kind, output folders holding a user's files
(export, exercise; with and without --force; killed by SIGKILL/SIGTERM at a random moment) and damaged caches.

Oracles, each independent of the code under test:

- reads: a Python audit hook (``sys.addaudithook``, event "open") records every file the render opens; one under
  the case's ``outside`` folder (after resolving links), or a special file such as /proc/self/environ, is
  ``escaped``. A hard link inside the model's folder to a file outside IS inside the folder (the user or the
  model's author put it there; it is the same as a copy): reading it is allowed, and it must render;
- images: a mutation that must not change the image (a reference spelled another way that names the same file
  inside the folder, an unknown GLB chunk, JSON padding, ``map_Kd -s 1 1 1 tex.png``) must render exactly the
  image of the unmutated file rendered in the same process (``wrong`` otherwise; ``refused`` when it is refused);
- user files: every file under the output folder and ``outside`` is hashed before and after (``clobbered``);
- tracebacks, hangs, stray lines and partial files: harness.run_case's classification; peak memory over 2 GB:
  ``memory`` (each process's own peak, tests/peak_memory.py: this worker's VmHWM in-process, and what each CLI
  subprocess reports at its exit; a subprocess killed by a signal reports none).
"""

from __future__ import annotations

import base64
import json
import os
import signal
import struct
import subprocess
import sys
import time
import urllib.parse
from pathlib import Path

import numpy as np
import pytest
from harness import _count, check, render_argv, reset_folder, run_case, tree_snapshot
from hypothesis import given
from hypothesis import strategies as st
from peak_memory import measured_argv, peak_mib, reported_peak_mib
from PIL import Image
from reliab_gen import SCENE_CAMERA, triangle_gltf
from strategies import ASSETS, REPO, fuzz_settings

MAX_RSS_MB = 2048
SPECIAL = ("/proc/self/environ", "/etc/passwd", "/dev/zero", "/dev/urandom")
_OPENS: list | None = None


def _audit(event: str, args: tuple) -> None:
    if event == "open" and _OPENS is not None and not isinstance(args[0], int):
        _OPENS.append(args[0])


sys.addaudithook(_audit)  # once per process; it records only while a case runs (_OPENS is a list)


def audited(argv: list, output: Path | None, label: str, scene: Path | None = None) -> tuple[str, list]:
    """harness.run_case with every file opened recorded."""
    global _OPENS
    _OPENS = []
    try:
        outcome = run_case(argv, output, scene, label)
    finally:
        opened, _OPENS = _OPENS, None
    return outcome, opened


def escape_of(opened: list, outside: Path) -> str | None:
    """The first opened path that lies outside the model's folder: under ``outside`` after resolving, or special."""
    root = os.path.realpath(outside)
    for p in opened:
        text = os.fsdecode(p) if isinstance(p, (str, bytes, os.PathLike)) else str(p)
        real = os.path.realpath(text) if "\0" not in text else text
        if real == root or real.startswith(root + os.sep) or text in SPECIAL or real in SPECIAL:
            return text
    return None


def recount(old: str, new: str, label: str, detail: str) -> str:
    """Move one case from the outcome run_case counted to a finding of this file."""
    from harness import OUTCOMES

    OUTCOMES[old] -= 1
    if not OUTCOMES[old]:
        del OUTCOMES[old]
    return _count(new, label, detail)


def memory_checked(outcome: str, label: str, reports: tuple[Path, ...] = ()) -> str:
    """The outcome, or ``memory`` when this worker's own peak or a subprocess's reported one passed MAX_RSS_MB
    (getrusage's ru_maxrss would add the parent's peak: tests/peak_memory.py)."""
    rss = max([peak_mib(), *(p for p in map(reported_peak_mib, reports) if p is not None)])
    return recount(outcome, "memory", label, f"peak RSS {rss} MiB") if rss > MAX_RSS_MB else outcome


def pixels(path: Path) -> np.ndarray:
    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


@pytest.fixture
def base(tmp_path_factory):
    return tmp_path_factory.mktemp("indep")


def layout(base: Path) -> tuple[Path, Path]:
    """A fresh ``base/model`` (the model's folder) and ``base/outside`` (files no model may read)."""
    reset_folder(base)
    model, outside = base / "model", base / "outside"
    model.mkdir()
    outside.mkdir()
    return model, outside


def scene_for(model_dir: Path, name: str, unlit: bool = True) -> Path:
    text = f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\nmsaa = 1\nhdr = false\n\n[[models]]\n"
    text += f'path = "{name}"\n' + ("material = { unlit = true }\n" if unlit else "")
    (model_dir / "scene.toml").write_text(text)
    return model_dir / "scene.toml"


# --- sources: real files with their unmutated images -----------------------------------------------------------

def checker_png() -> bytes:
    import io

    rgba = np.zeros((8, 8, 4), np.uint8)
    rgba[..., 3] = 255
    rgba[(np.indices((8, 8)).sum(0) % 2) == 0, 0] = 255
    rgba[(np.indices((8, 8)).sum(0) % 2) == 1, 1] = 255
    out = io.BytesIO()
    Image.fromarray(rgba, "RGBA").save(out, format="PNG")
    return out.getvalue()


def split_data_uri(doc: dict) -> bytes:
    return base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])


def tri_source() -> tuple[dict, bytes]:
    doc = triangle_gltf()
    return doc, split_data_uri(doc)


def textured_source() -> tuple[dict, bytes]:
    """A quad with UVs and a base-colour texture whose image is an external file (the image reference)."""
    pos = np.float32([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]])
    uv = np.float32([[0, 1], [1, 1], [1, 0], [0, 0]])
    nrm = np.tile(np.float32([0, 0, 1]), (4, 1))
    idx = np.uint16([0, 1, 2, 0, 2, 3])
    blobs = [pos.tobytes(), nrm.tobytes(), uv.tobytes(), idx.tobytes()]
    views, off = [], 0
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(b)})
        off += len(b)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                       "material": 0}]}],
           "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
           "textures": [{"source": 0, "sampler": 0}], "samplers": [{"magFilter": 9728, "minFilter": 9728}],
           "images": [{"uri": "tex.png"}], "bufferViews": views,
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                          "min": [-1, -1, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                         {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                         {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
           "buffers": [{"byteLength": off}]}
    return doc, b"".join(blobs)


_BASELINES: dict[str, np.ndarray] = {}


def baseline(key: str, base: Path, write) -> np.ndarray | None:
    """The image of the unmutated source (``write(model_dir) -> scene``), rendered once per process."""
    if key not in _BASELINES:
        model, _ = layout(base)
        scene = write(model)
        out = base / "baseline.png"
        if run_case(render_argv(scene, out), out, None, f"baseline {key}") != "render":
            pytest.fail(f"the unmutated source {key} does not render")
        _BASELINES[key] = pixels(out)
        reset_folder(base)
    return _BASELINES[key]


# --- references of every kind ----------------------------------------------------------------------------------

# kind -> (must it be refused, how the reference is spelled for a file called NAME inside the folder)
REF_KINDS = {
    "plain": (False, "{name}"),
    "dot": (False, "./{name}"),
    "sub-dotdot": (False, "realsub/../{name}"),
    "percent-name": (False, "{pname}"),
    "link-in": (False, "li-{name}"),
    "link-chain-in": (False, "lc1-{name}"),
    "hardlink-out": (False, "hl-{name}"),
    "unicode": (False, "{uname}"),
    "absolute": (True, "{outside}/{name}"),
    "file-url": (True, "file://{outside}/{name}"),
    "file-localhost": (True, "file://localhost{outside}/{name}"),
    "dotdot": (True, "../outside/{name}"),
    "deep-dotdot": (True, "realsub/../../outside/{name}"),
    "pct-dots": (True, "%2e%2e/outside/{name}"),
    "pct-slash": (True, "..%2foutside%2f{name}"),
    "pct-upper": (True, "%2E%2E%2Foutside%2F{name}"),
    "link-out": (True, "lo-{name}"),
    "link-chain-out": (True, "lco1-{name}"),
    "link-dir-out": (True, "ldo/{name}"),
    "link-loop": (True, "loop-a"),
    "link-self": (True, "loop-self"),
    "double-pct": (True, "%252e%252e/outside/{name}"),
    "nul": (True, "{name}\0../../outside/{name}"),
    "pct-nul": (True, "{name}%00.png"),
    "fullwidth-dots": (True, "\uff0e\uff0e/outside/{name}"),
    "backslash": (True, "..\\outside\\{name}"),
    "proc": (True, "/proc/self/environ"),
    "proc-climb": (True, "../../../../../../../../proc/self/environ"),
    "device": (True, "/dev/zero"),
    "net-path": (True, "//outside/{name}"),
    "dir": (True, "realsub"),
    "missing": (True, "nope-{name}"),
    "empty": (True, ""),
}


def plant(model: Path, outside: Path, name: str, data: bytes) -> None:
    """``name`` inside (and its aliases: links, hard link, unicode copy) and a copy outside."""
    (model / name).write_bytes(data)
    (outside / name).write_bytes(data)
    (model / "realsub").mkdir(exist_ok=True)
    (model / f"li-{name}").symlink_to(name)
    (model / f"lc2-{name}").symlink_to(f"li-{name}")
    (model / f"lc1-{name}").symlink_to(f"lc2-{name}")
    (model / f"lo-{name}").symlink_to(outside / name)
    (model / f"lco2-{name}").symlink_to(outside / name)
    (model / f"lco1-{name}").symlink_to(f"lco2-{name}")
    if not (model / "ldo").exists():
        (model / "ldo").symlink_to(outside)
    if not os.path.lexists(model / "loop-a"):
        (model / "loop-a").symlink_to("loop-b")
        (model / "loop-b").symlink_to("loop-a")
        (model / "loop-self").symlink_to("loop-self")
    os.link(outside / name, model / f"hl-{name}")
    (model / f"ü {name}").write_bytes(data)


def spelled(kind: str, name: str, outside: Path, raw: bool = False) -> str:
    """``kind``'s spelling of the file ``name``: percent-encoded as a glTF URI must be, or ``raw`` (OBJ, MTL)."""
    quote = (lambda s: s) if raw else urllib.parse.quote
    return REF_KINDS[kind][1].format(name=quote(name), outside=outside,
                                     pname="".join(f"%{b:02X}" for b in name.encode()), uname=quote(f"ü {name}"))


NAME_CHARS = list("abcXYZ019_-.~+=,;&@!$'()") + ["ü", "€", "日", " ", "%", "#", "?"]


def file_name(suffix: str, raw: bool = False):
    """Random file names (an OBJ/MTL name, ``raw``, has no spaces: its readers split options at them)."""
    chars = [c for c in NAME_CHARS if not (raw and c in " #")]
    return st.text(st.sampled_from(chars), min_size=1, max_size=10).map(lambda s: s + suffix)


# names of files that do not exist inside the folder: an OBJ without its MTL renders in the default material
# (as every OBJ reader does), so either outcome passes there, as long as nothing outside was read; OBJ names are
# plain paths: a percent-encoded or fullwidth spelling is such a missing name
MISSING_KINDS = ("missing", "empty", "dir", "link-loop", "link-self", "backslash", "pct-dots", "pct-slash",
                 "pct-upper", "double-pct", "fullwidth-dots")


def judge_reference(kind: str, outcome: str, opened: list, outside: Path, out: Path, label: str, expect,
                    lenient: bool = False) -> str:
    must_refuse = REF_KINDS[kind][0] and not (lenient and kind in MISSING_KINDS)
    leak = escape_of(opened, outside)
    if leak is not None:
        return recount(outcome, "escaped", label, f"opened {leak!r}")
    if outcome == "render" and must_refuse:
        return recount(outcome, "escaped", label, "rendered although the reference leaves the folder")
    if not REF_KINDS[kind][0] and outcome == "error":
        return recount(outcome, "refused", label, "refused a reference to a file inside the folder")
    if not REF_KINDS[kind][0] and outcome == "render" and expect is not None and not np.array_equal(
            pixels(out), expect):
        return recount(outcome, "wrong", label, "another image than the unmutated file's")
    return memory_checked(outcome, label)


def write_gltf_source(model: Path, source: str, buffer_uri: str | None, image_uri: str | None) -> Path:
    doc, data = tri_source() if source == "tri" else textured_source()
    doc = json.loads(json.dumps(doc))
    doc["buffers"] = [{"byteLength": len(data), "uri": buffer_uri if buffer_uri is not None else "buf.bin"}]
    if source == "tex":
        doc["images"][0]["uri"] = image_uri if image_uri is not None else "tex.png"
    (model / "model.gltf").write_text(json.dumps(doc))
    return scene_for(model, "model.gltf", unlit=source == "tri")


def _plain_gltf(source: str):
    def write(model: Path) -> Path:
        doc, data = tri_source() if source == "tri" else textured_source()
        (model / "buf.bin").write_bytes(data)
        (model / "tex.png").write_bytes(checker_png())
        return write_gltf_source(model, source, None, None)
    return write


@given(source=st.sampled_from(["tri", "tex"]), role=st.sampled_from(["buffer", "image"]),
       kind=st.sampled_from(sorted(REF_KINDS)), bin_name=file_name(".bin"), png_name=file_name(".png"))
@fuzz_settings(ci=12, long=2600)
def test_gltf_references(base, source, role, kind, bin_name, png_name):
    if role == "image" and source == "tri":
        source = "tex"
    expect = baseline(f"gltf-{source}", base, _plain_gltf(source))
    model, outside = layout(base)
    doc, data = tri_source() if source == "tri" else textured_source()
    plant(model, outside, bin_name, data)
    plant(model, outside, png_name, checker_png())
    name = bin_name if role == "buffer" else png_name
    uri = spelled(kind, name, outside)
    scene = write_gltf_source(model, source, uri if role == "buffer" else urllib.parse.quote(bin_name),
                              uri if role == "image" else urllib.parse.quote(png_name))
    out = base / "out.png"
    label = f"gltf {source} {role} {kind} {uri!r}"
    outcome, opened = audited(render_argv(scene, out), out, label, scene)
    check(judge_reference(kind, outcome, opened, outside, out, label, expect), label)


# --- OBJ: mtllib and map_Kd of every kind, with options -------------------------------------------------------

MAP_OPTIONS = ("", "-s 1 1 1 ", "-o 0 0 0 ", "-s 1 1 1 -o 0 0 0 ", "-blendu on -blendv on ", "-mm 0 1 ",
               "-bm 1 ", "-clamp off ", "-imfchan l ", "-texres 8 ")


def obj_text(mtllib: str) -> str:
    lines = (ASSETS / "models" / "brick_cube.obj").read_text().splitlines()
    return "\n".join(f"mtllib {mtllib}" if ln.startswith("mtllib") else ln for ln in lines) + "\n"


def mtl_text(map_line: str) -> str:
    return f"newmtl brick\nKd 1 1 1\n{map_line}\n"


def _plain_obj(model: Path) -> Path:
    (model / "tex.png").write_bytes(checker_png())
    (model / "m.mtl").write_text(mtl_text("map_Kd tex.png"))
    (model / "model.obj").write_text(obj_text("m.mtl"))
    return scene_for(model, "model.obj", unlit=False)


@given(role=st.sampled_from(["mtllib", "map_Kd"]), kind=st.sampled_from(sorted(REF_KINDS)),
       option=st.sampled_from(MAP_OPTIONS), mtl_name=file_name(".mtl", raw=True),
       png_name=file_name(".png", raw=True))
@fuzz_settings(ci=10, long=1600)
def test_obj_references(base, role, kind, option, mtl_name, png_name):
    expect = baseline("obj", base, _plain_obj)
    model, outside = layout(base)
    plant(model, outside, png_name, checker_png())
    plant(model, outside, mtl_name, mtl_text(f"map_Kd {option}{png_name}").encode())
    if kind in ("nul", "pct-nul", "percent-name"):
        kind = "plain"  # OBJ/MTL names are plain paths, not URIs: no percent-decoding, no NUL in a text line
    ref = spelled(kind, mtl_name if role == "mtllib" else png_name, outside, raw=True)
    if kind == "unicode":
        kind = "plain"  # a raw name is unicode already (file_name)
    (model / "model.obj").write_text(obj_text(ref if role == "mtllib" else mtl_name))
    if role == "map_Kd":
        (model / mtl_name).write_text(mtl_text(f"map_Kd {option}{ref}"))
    scene = scene_for(model, "model.obj", unlit=False)
    out = base / "out.png"
    label = f"obj {role} {kind} {option!r}{ref!r}"
    outcome, opened = audited(render_argv(scene, out), out, label, scene)
    exact = option in ("", "-s 1 1 1 ", "-o 0 0 0 ", "-s 1 1 1 -o 0 0 0 ", "-mm 0 1 ") and ref.strip() == ref
    check(judge_reference(kind, outcome, opened, outside, out, label, expect if exact else None,
                                lenient=True), label)


# --- GLB containers: chunk lengths and types, the JSON inside, buffer views ---------------------------------------

GLB_SOURCES = ("brick_torus.glb", "gltf_features.glb", "metal_rough_spheres.glb", "mirrored_quad.glb")
SAME_IMAGE = ("pad-json", "unknown-chunk", "resort-keys", "overlap-copy")
GLB_OPS = SAME_IMAGE + ("json-len", "bin-len", "total-len", "version", "magic", "swap-chunks", "truncate",
                        "two-json", "json-path", "overlap-views", "buffer-uri", "bad-base64", "huge-data-uri",
                        "huge-count", "view-past-end", "no-bin")
EDGE_JSON = [0, -1, 1, 3, 4, 2 ** 31, 2 ** 32, 2 ** 53 + 1, 10 ** 12, 1e300, -1e300, 0.5, "x", "", None, True,
             [], {}, [0] * 3, {"a": 1}, "../outside/buf.bin", "data:,", "/proc/self/environ"]


def glb_source(name: str, model: Path) -> bytes:
    """An asset GLB whose external images (the bundled ``../textures/``) are copied beside it and named so."""
    data = (ASSETS / "models" / name).read_bytes()
    doc, binary = glb_split(data)
    for image in doc.get("images", []):
        if "uri" in image and not image["uri"].startswith("data:"):
            (model / Path(image["uri"]).name).write_bytes((ASSETS / "models" / image["uri"]).read_bytes())
            image["uri"] = Path(image["uri"]).name
    return glb_join(json.dumps(doc).encode(), binary)


def glb_split(data: bytes) -> tuple[dict, bytes]:
    jlen = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + jlen])
    rest = data[20 + jlen:]
    return doc, rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else b""


def glb_join(json_bytes: bytes, bin_bytes: bytes | None, extra: bytes = b"", total: int | None = None,
             json_len: int | None = None, bin_len: int | None = None, version: int = 2) -> bytes:
    json_bytes += b" " * (-len(json_bytes) % 4)
    body = struct.pack("<II", len(json_bytes) if json_len is None else json_len, 0x4E4F534A) + json_bytes
    if bin_bytes is not None:
        bin_bytes += b"\0" * (-len(bin_bytes) % 4)
        body += struct.pack("<II", len(bin_bytes) if bin_len is None else bin_len, 0x004E4942) + bin_bytes
    body += extra
    return struct.pack("<III", 0x46546C67, version, 12 + len(body) if total is None else total) + body


def json_paths(node, prefix=()):
    """Every JSON path of ``node`` (dict keys and list indices), short lists only (no vertex arrays)."""
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from json_paths(v, prefix + (k,))
    elif isinstance(node, list) and len(node) <= 16:
        for i, v in enumerate(node):
            yield from json_paths(v, prefix + (i,))


def set_path(doc, path, value):
    for key in path[:-1]:
        doc = doc[key]
    doc[path[-1]] = value


@st.composite
def glb_case(draw):
    source = draw(st.sampled_from(GLB_SOURCES))
    op = draw(st.sampled_from(GLB_OPS))
    return source, op, draw(st.integers(0, 2 ** 16)), draw(st.sampled_from(range(len(EDGE_JSON))))


def mutate_glb(data: bytes, op: str, r: int, edge, outside: Path) -> bytes:
    doc, binary = glb_split(data)
    text = json.dumps(doc).encode()
    if op == "pad-json":
        return glb_join(b"  \n" + json.dumps(doc, indent=1).encode() + b"\n ", binary)
    if op == "unknown-chunk":
        return glb_join(text, binary, extra=struct.pack("<II", 8, 0x12345678) + b"\1" * 8)
    if op == "resort-keys":
        return glb_join(json.dumps(doc, sort_keys=True).encode(), binary)
    if op == "overlap-copy":  # a second buffer view over the same bytes as the first, used by nothing
        doc["bufferViews"].append(dict(doc["bufferViews"][0]))
        return glb_join(json.dumps(doc).encode(), binary)
    if op in ("json-len", "bin-len", "total-len"):
        value = [0, 1, 4, 7, len(text) - 4, len(text) + 4, len(data), 2 ** 31, 2 ** 32 - 1][r % 9]
        return glb_join(text, binary, **{{"json-len": "json_len", "bin-len": "bin_len",
                                           "total-len": "total"}[op]: value})
    if op == "version":
        return glb_join(text, binary, version=[0, 1, 3, 2 ** 32 - 1][r % 4])
    if op == "magic":
        return b"glTF"[::-1] + data[4:]
    if op == "swap-chunks":
        pad = binary + b"\0" * (-len(binary) % 4)
        body = struct.pack("<II", len(pad), 0x004E4942) + pad + data[12:20 + len(text) + (-len(text) % 4)]
        return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body
    if op == "truncate":
        return data[:r % len(data)]
    if op == "two-json":
        return glb_join(text, None, extra=struct.pack("<II", len(text) + (-len(text) % 4), 0x4E4F534A)
                        + text + b" " * (-len(text) % 4))
    if op == "json-path":
        paths = [p for p in json_paths(doc) if p]
        set_path(doc, paths[r % len(paths)], edge)
    elif op == "overlap-views":
        for view in doc.get("bufferViews", []):
            view["byteOffset"] = 0
            view["byteLength"] = len(binary) // (1 + r % 3)
    elif op == "buffer-uri":
        (outside / "buf.bin").write_bytes(binary)
        doc["buffers"][0]["uri"] = spelled(sorted(REF_KINDS)[r % len(REF_KINDS)], "buf.bin", outside)
    elif op == "bad-base64":
        good = base64.b64encode(binary).decode()
        bad = [good[:-1], good + "=", "!!!!" + good, good.replace("A", "-"), "%" + good, ""][r % 6]
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + bad
        binary = None
    elif op == "huge-data-uri":
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(binary).decode()
        doc["buffers"][0]["byteLength"] = [10 ** 12, 2 ** 62, 10 ** 9, len(binary) + 1][r % 4]
        binary = None
    elif op == "huge-count":
        acc = doc["accessors"][r % len(doc["accessors"])]
        acc["count"] = [10 ** 9, 10 ** 12, 2 ** 31, 2 ** 32 + 3][r % 4]
    elif op == "view-past-end":
        view = doc["bufferViews"][r % len(doc["bufferViews"])]
        view["byteOffset"] = len(binary) - [0, 4, 1][r % 3]
    elif op == "no-bin":
        binary = None
    return glb_join(json.dumps(doc).encode(), binary)


@given(case=glb_case())
@fuzz_settings(ci=15, long=3600)
def test_glb_containers(base, case):
    source, op, r, edge_index = case

    def plain(model: Path) -> Path:
        (model / "m.glb").write_bytes(glb_source(source, model))
        return scene_for(model, "m.glb")

    expect = baseline(source, base, plain) if op in SAME_IMAGE else None
    model, outside = layout(base)
    data = glb_source(source, model)
    (model / "m.glb").write_bytes(mutate_glb(data, op, r, EDGE_JSON[edge_index], outside))
    scene = scene_for(model, "m.glb")
    out = base / "out.png"
    label = f"glb {source} {op} r={r} edge={EDGE_JSON[edge_index]!r}"
    outcome, opened = audited(render_argv(scene, out), out, label, scene)
    leak = escape_of(opened, outside)
    if leak is not None:
        outcome = recount(outcome, "escaped", label, f"opened {leak!r}")
    elif op in SAME_IMAGE and outcome == "error":
        outcome = recount(outcome, "refused", label, "refused a file the mutation must not change")
    elif op in SAME_IMAGE and outcome == "render" and not np.array_equal(pixels(out), expect):
        outcome = recount(outcome, "wrong", label, "another image than the unmutated file's")
    else:
        outcome = memory_checked(outcome, label)
    check(outcome, label)


# --- scene TOML paths of every kind -------------------------------------------------------------------------------

SCENE_KINDS = {  # kind -> (allowed, path relative to the scene in base/project/[scenes/]scene.toml)
    "same-folder": (True, "{m}.gltf"),
    "sub": (True, "models/{m}.gltf"),
    "absolute-in": (True, "{project}/{m}.gltf"),
    "link-in": (True, "li-{m}.gltf"),
    "assets": (True, "{assets}/models/mirrored_quad.glb"),
    "allowed-env": (True, "{outside}/{m}.gltf"),
    "outside": (False, "{outside}/{m}.gltf"),
    "dotdot": (False, "../outside/{m}.gltf"),
    "link-out": (False, "lo-{m}.gltf"),
    "link-dir-out": (False, "ldo/{m}.gltf"),
    "file-url": (False, "file://{outside}/{m}.gltf"),
    "tilde": (False, "~/{m}.gltf"),
    "env-var": (False, "$HOME/{m}.gltf"),
    "proc": (False, "/proc/self/environ"),
    "loop": (False, "loop-a"),
    "backslash": (False, "..\\outside\\{m}.gltf"),
}


@given(kind=st.sampled_from(sorted(SCENE_KINDS)), role=st.sampled_from(["model", "albedo_map"]),
       nested=st.booleans(), stem=file_name(""))
@fuzz_settings(ci=8, long=1200)
def test_scene_paths(base, kind, role, nested, stem, monkeypatch):
    reset_folder(base)
    project, outside = base / "project", base / "outside"
    where = project / "scenes" if nested else project
    (where / "models").mkdir(parents=True)
    outside.mkdir()
    doc, data = textured_source()  # with UVs: a scene's albedo_map needs them
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    for folder in (where, where / "models", outside):
        (folder / f"{stem}.gltf").write_text(json.dumps(doc))
        (folder / f"{stem}.png").write_bytes(checker_png())
        (folder / "tex.png").write_bytes(checker_png())  # the model's own texture
    for ext in (".gltf", ".png"):
        (where / f"li-{stem}{ext}").symlink_to(f"{stem}{ext}")
        (where / f"lo-{stem}{ext}").symlink_to(outside / f"{stem}{ext}")
    (where / "ldo").symlink_to(outside)
    (where / "loop-a").symlink_to("loop-b")
    (where / "loop-b").symlink_to("loop-a")
    allowed, path = SCENE_KINDS[kind]
    if role == "albedo_map":
        path = path.replace(".gltf", ".png").replace("mirrored_quad.glb", "../textures/brick_albedo.png")
    path = path.format(project=where, outside=outside, assets=ASSETS, m=stem)
    if role == "albedo_map":
        model = f"path = {json.dumps(stem + '.gltf')}\nmaterial = \"mat\"\n"
        extra = f'[materials.mat]\nalbedo_map = {json.dumps(path)}\n'
    else:
        model, extra = f"path = {json.dumps(path)}\nmaterial = {{ unlit = true }}\n", ""
    text = f"[camera]\n{SCENE_CAMERA}\n[render]\nsize = [40, 30]\nmsaa = 1\nhdr = false\n{extra}\n[[models]]\n{model}"
    (where / "scene.toml").write_text(text)
    monkeypatch.setenv("WGPURENDER_ALLOW_PATHS", str(outside) if kind == "allowed-env" else "")
    monkeypatch.setenv("HOME", str(outside))
    out = base / "out.png"
    label = f"scene {role} {kind} nested={nested} {path!r}"
    outcome, opened = audited(render_argv(where / "scene.toml", out), out, label, None)
    leak = None if allowed else escape_of(opened, outside)
    if leak is not None or (outcome == "render" and not allowed):
        outcome = recount(outcome, "escaped", label, f"read outside the project: {leak!r}")
    elif outcome == "error" and allowed:
        outcome = recount(outcome, "refused", label, "refused a path the documented rule allows")
    else:
        outcome = memory_checked(outcome, label)
    check(outcome, label)


# --- output folders holding a user's files ------------------------------------------------------------------------

USER_FILES = ("notes.txt", "index.html", "data.js", "player.js", "step_1a.py", "README.md", "goal.png",
              "sub/keep.bin", ".wgpurender-manifest.json", "frame_00000.png")


LINKED = ("index.html", "data.js", "step_1a.py", "README.md", "goal.png", "player.js")


def user_folder(base: Path, files: list[str], link: str, which: int = 0) -> Path:
    """``base/out`` holding the user's ``files`` (random bytes); ``link``: the folder or a file is a symlink."""
    out, outside = base / "out", base / "outside"
    outside.mkdir()
    (outside / "secret.txt").write_bytes(os.urandom(16))
    target = outside / "real" if link == "folder-link" else out
    target.mkdir(parents=True, exist_ok=True)
    if link == "folder-link":
        out.symlink_to(target)
    for name in files:
        (target / name).parent.mkdir(parents=True, exist_ok=True)
        (target / name).write_bytes(os.urandom(24))
    if link == "file-link":  # the writer's names as links to a file outside
        for name in LINKED:
            if not os.path.lexists(target / name):
                (target / name).symlink_to(outside / "secret.txt")
    if link == "dangling-link" and not os.path.lexists(target / LINKED[which % 6]):  # one name, to nothing yet
        (target / LINKED[which % 6]).symlink_to(outside / f"new-{LINKED[which % 6]}")
    return out


def lost_files(before: dict, after: dict, ours: set) -> list[str]:
    """Files changed or deleted (but ``ours``), and any file that appeared in ``outside`` (but in ``outside/real``,
    the target of a symlinked output folder: the folder the user named)."""
    return [k for k, v in before.items() if after.get(k) != v and k not in ours] + [
        k for k in after if k.startswith("outside/") and not k.startswith("outside/real/") and k not in before]


@given(command=st.sampled_from(["export", "exercise"]), files=st.lists(st.sampled_from(USER_FILES), max_size=4,
                                                                        unique=True),
       link=st.sampled_from(["none", "none", "folder-link", "file-link", "dangling-link"]), force=st.booleans(),
       twice=st.booleans(), which=st.integers(0, 5))
@fuzz_settings(ci=8, long=1200)
def test_output_folders(base, command, files, link, force, twice, which):
    reset_folder(base)
    out = user_folder(base, files, link, which)
    (base / "model").mkdir()
    (base / "model" / "m.gltf").write_text(json.dumps(triangle_gltf()))
    scene = scene_for(base / "model", "m.gltf")
    before = tree_snapshot(base)
    argv = ["export", scene, "-o", out, "--size", "40x30"] if command == "export" else ["exercise", "1a", "-o", out]
    argv += ["--force"] if force and command == "export" else []
    label = f"{command} files={files} link={link}:{LINKED[which]} force={force} twice={twice}"
    outcome, _ = audited(argv, None, label)
    if twice and outcome == "render":  # a rebuild over its own earlier output (counted as a case of its own)
        outcome, _ = audited(argv, None, label + " (again)")
    # --force means "these names may be replaced" (core/files/owned_files.py, docs/security.md): export's names then
    ours = {f"out/{n}" for n in ("index.html", "data.js", "player.js", ".wgpurender-manifest.json")} if force else set()
    lost = lost_files(before, tree_snapshot(base), ours if command == "export" else set())
    if lost:
        outcome = recount(outcome, "clobbered", label, f"changed or deleted {lost}")
    elif leftovers(base):
        outcome = recount(outcome, "partial", label, f"left {leftovers(base)}")
    else:
        outcome = memory_checked(outcome, label)
    check(outcome, label)


def leftovers(root: Path) -> list[str]:
    return [str(p.relative_to(root)) for p in root.rglob("*") if ".tmp" in p.name or p.name.startswith(".DIR")
            or p.name.startswith(".tmp")]


# --- killed mid-write ---------------------------------------------------------------------------------------------

def cli_env(base: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(REPO), LP_NUM_THREADS="1", XDG_CACHE_HOME=str(base / "cache"))
    env.pop("WGPURENDER_FUZZ", None)
    return env


@given(files=st.lists(st.sampled_from(("notes.txt", "README.md", "sub/keep.bin", "goal.png")), max_size=3, unique=True),
       sig=st.sampled_from([signal.SIGKILL, signal.SIGTERM]), delay=st.floats(0.0, 4.0), earlier=st.booleans())
@fuzz_settings(ci=1, long=60)
def test_killed_export(base, files, sig, delay, earlier):
    """export killed at a random moment, then run again: the user's files are intact, the folder ends complete."""
    reset_folder(base)
    out = user_folder(base, files, "none")
    (base / "model").mkdir()
    (base / "model" / "m.gltf").write_text(json.dumps(triangle_gltf()))
    scene = scene_for(base / "model", "m.gltf")
    args = ["export", scene, "-o", out, "--size", "40x30", "--force"]
    reports = (base / "peak-earlier.txt", base / "peak-again.txt")  # the killed run reports none
    if earlier:
        subprocess.run(measured_argv("wgpurender", args, reports[0]), env=cli_env(base), capture_output=True,
                       timeout=120)
    before = tree_snapshot(out)
    proc = subprocess.Popen([sys.executable, "-m", "wgpurender", *map(str, args)], env=cli_env(base),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(delay)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    label = f"killed export sig={sig.name} delay={delay:.2f} files={files} earlier={earlier}"
    again = subprocess.run(measured_argv("wgpurender", args, reports[1]), env=cli_env(base), capture_output=True,
                           text=True, timeout=120)
    ours = {"index.html", "data.js", "player.js", ".wgpurender-manifest.json"}
    lost = lost_files(before, tree_snapshot(out), ours)
    if b"Traceback" in err or "Traceback" in again.stderr:
        outcome = _count("traceback", label, (err.decode() + again.stderr)[-800:])
    elif lost:
        outcome = _count("clobbered", label, f"changed or deleted {lost}")
    elif again.returncode != 0 or not (out / "index.html").is_file():
        outcome = _count("refused", label, f"the run after the kill: {again.returncode} {again.stderr[-300:]}")
    elif leftovers(out):
        outcome = _count("partial", label, f"left {leftovers(out)}")
    else:
        outcome = _count("render", label, "")
    check(memory_checked(outcome, label, reports), label)


# --- damaged cache entries ----------------------------------------------------------------------------------------

CACHE_DAMAGE = ("empty", "truncate", "flip", "swap-key", "directory", "symlink-out", "fifo", "garbage-json",
                "huge-length")


@given(damage=st.sampled_from(CACHE_DAMAGE), r=st.integers(0, 2 ** 20))
@fuzz_settings(ci=1, long=60)
def test_damaged_cffi_cache(base, damage, r):
    """A fresh process over a damaged wgpu.h parse cache renders the same image as over a sound one."""
    reset_folder(base)
    (base / "m").mkdir()
    (base / "m" / "m.gltf").write_text(json.dumps(triangle_gltf()))
    scene = scene_for(base / "m", "m.gltf")
    env = cli_env(base)
    reports = (base / "peak-first.txt", base / "peak-second.txt")
    args = ["render", scene, "-o", base / "a.png", "--size", "40x30"]
    first = subprocess.run(measured_argv("wgpurender", args, reports[0]), env=env, capture_output=True, timeout=120)
    entries = sorted((base / "cache" / "wgpurender").glob("cffi-wgpu-h-*.json"))
    label = f"cache {damage} r={r}"
    if first.returncode != 0 or not entries:
        check(_count("refused", label, f"no sound cache entry: {first.stderr[-300:]!r}"), label)
        return
    entry = entries[0]
    blob = entry.read_bytes()
    entry.unlink()
    if damage == "empty":
        entry.write_bytes(b"")
    elif damage == "truncate":
        entry.write_bytes(blob[:r % len(blob)])
    elif damage == "flip":
        entry.write_bytes(blob[:r % len(blob)] + bytes([blob[r % len(blob)] ^ 0x20]) + blob[r % len(blob) + 1:])
    elif damage == "swap-key":  # a sound seal of another key's payload
        from wgpurender.core.files import cache_entry

        entry.write_bytes(cache_entry.seal("another key", blob[cache_entry.HEADER:]))
    elif damage == "directory":
        entry.mkdir()
    elif damage == "symlink-out":
        (base / "outside.json").write_text('{"x": 1}')
        entry.symlink_to(base / "outside.json")
    elif damage == "fifo":
        os.mkfifo(entry)
    elif damage == "garbage-json":
        entry.write_bytes(blob[:100] + b'{"_declarations": [1, 2, {"a": null}]}')
    else:
        entry.write_bytes(blob[:57 + 32] + (2 ** 62).to_bytes(8, "little") + blob[57 + 40:])
    try:
        second = subprocess.run(measured_argv("wgpurender", [*args[:-3], base / "b.png", "--size", "40x30"],
                                              reports[1]), env=env, capture_output=True, timeout=120)
    except subprocess.TimeoutExpired:
        check(_count("hang", label, "timeout"), label)
        return
    if b"Traceback" in second.stderr or second.returncode not in (0, 2):
        outcome = _count("traceback", label, second.stderr[-800:].decode(errors="replace"))
    elif second.returncode != 0:
        outcome = _count("refused", label, second.stderr[-300:].decode(errors="replace"))
    elif not np.array_equal(pixels(base / "a.png"), pixels(base / "b.png")):
        outcome = _count("wrong", label, "another image over the damaged cache")
    elif second.stderr.strip():
        outcome = _count("multiline", label, second.stderr[-300:].decode(errors="replace"))
    else:
        outcome = _count("render", label, "")
    check(memory_checked(outcome, label, reports), label)


# --- record into folders holding an earlier recording and the user's files ------------------------------------------

@given(first=st.integers(0, 5), second=st.integers(1, 4), files=st.lists(st.sampled_from(
    ("notes.txt", "frame_1.png", "frame_00002.png", "frames.txt", "sub/keep.bin")), max_size=3, unique=True),
       force=st.booleans())
@fuzz_settings(ci=2, long=200)
def test_record_folders(base, first, second, files, force):
    """An earlier recording of ``first`` frames, then one of ``second``: the folder holds exactly the new frames,
    the user's files intact (a name the recorder writes may be replaced only with force)."""
    import wgpurender as w
    from wgpurender.core.errors import UserError

    reset_folder(base)
    out = user_folder(base, files, "none")
    (base / "model").mkdir()
    (base / "model" / "m.gltf").write_text(json.dumps(triangle_gltf()))
    scene = scene_for(base / "model", "m.gltf")
    label = f"record first={first} second={second} files={files} force={force}"
    try:
        if first:
            w.record(scene, out, seconds=first, fps=1, size=(16, 12), turn=0, force=True)
        before = tree_snapshot(base)
        w.record(scene, out, seconds=second, fps=1, size=(16, 12), turn=0, force=force)
    except UserError as err:
        outcome = _count("error", label, "") if len(str(err).splitlines()) == 1 else _count("multiline", label,
                                                                                             str(err))
        check(outcome, label)
        return
    except Exception as exc:  # noqa: BLE001 - any other escape is the finding
        check(_count("traceback", label, repr(exc)[-500:]), label)
        return
    frames = sorted(p.name for p in out.glob("frame_*.png"))
    ours = {f"out/frame_{k:05d}.png" for k in range(max(first, second))} | {"out/.wgpurender-manifest.json"}
    lost = lost_files(before, tree_snapshot(base), ours)
    # the user's frame files kept: those the first recording (force=True) did not replace as its own names
    users = {Path(f).name for f in files if f.startswith("frame_")} - {f"frame_{k:05d}.png" for k in range(first)}
    expect = sorted({f"frame_{k:05d}.png" for k in range(second)} | users)
    if lost:
        outcome = _count("clobbered", label, f"changed or deleted {lost}")
    elif frames != expect:
        outcome = _count("wrong", label, f"frames {frames}, expected {expect}")
    else:
        outcome = _count("render", label, "")
    check(memory_checked(outcome, label), label)


# --- the public API with arguments of every type ------------------------------------------------------------------

ODD = [None, 0, -1, 5, 2 ** 70, 1.5, float("nan"), float("inf"), True, "", " ", "x", "\0", "a\0b", b"bytes",
       "40x30", "0x0", "-4x4", "99999x99999", (40, 30), (0, 0), (-1, 5), [40], {}, [], object(), Path(""),
       Path("/proc/self/environ"), Path("/dev/null"), "triangle", "../../outside/x.toml"]


@given(fn=st.sampled_from(["render", "export", "reference", "compare", "plan", "explain", "record", "heatmap"]),
       a=st.sampled_from(range(len(ODD))), b=st.sampled_from(range(len(ODD))), c=st.sampled_from(range(len(ODD))))
@fuzz_settings(ci=6, long=600)
def test_api_argument_types(base, fn, a, b, c):
    """Each public function with odd values: a result or one UserError line, never another exception."""
    import wgpurender as w
    from wgpurender.core.errors import UserError

    reset_folder(base)
    args = [ODD[a], ODD[b]]
    kwargs = {"size": ODD[c]} if fn in ("render", "export", "reference", "plan", "explain", "record") else {}
    if fn in ("export", "record") and isinstance(args[1], (str, Path)) and str(args[1]) not in ("", "\0", "a\0b"):
        args[1] = base / "o" / Path(str(args[1])).name  # never write outside the case folder
    if fn in ("render", "export", "reference", "plan", "explain"):
        args = args[:1] + ([args[1]] if fn == "export" else [])
    label = f"api {fn}{tuple(map(repr, args))} {kwargs!r}"
    try:
        getattr(w, fn)(*args, **kwargs)
        outcome = _count("render", label, "")
    except UserError as err:
        outcome = _count("error" if len(str(err).splitlines()) == 1 else "multiline", label, str(err))
    except Exception as exc:  # noqa: BLE001 - any other escape is the finding
        outcome = _count("traceback", label, f"{type(exc).__name__}: {exc}"[-500:])
    check(memory_checked(outcome, label), label)
