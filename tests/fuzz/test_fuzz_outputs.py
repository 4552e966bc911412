"""Generators for issue 28's output and cache surfaces: output folders in every state a user (or an attacker who
can write the folder) leaves them, written by ``export`` (through the CLI) and ``record``'s frame writer; and cache
entries damaged at random. Findings: a user's file changed or deleted, a file outside the folder touched, a temp
file or staging folder left, more or less than one error line, a damaged cache entry served."""

from __future__ import annotations

import contextlib
import io
import json
import os
from pathlib import Path

import numpy as np
import pytest
from harness import _count, check, reset_folder, tree_snapshot
from hypothesis import given
from hypothesis import strategies as st
from strategies import fuzz_settings

from wgpurender.cli import main
from wgpurender.core.errors import UserError
from wgpurender.core.files import cache_entry
from wgpurender.core.files.owned_files import MANIFEST
from wgpurender.core.files.video import FrameWriter

OUR_NAMES = ("index.html", "data.js", "player.js", "frame_00000.png", "frame_00001.png", "frame_00007.png")
USER_NAMES = ("notes.txt", "img/mine.png", "a/b/c.bin", ".hidden", "index.htm", "frame_1.png", "live/x.js")
MANIFEST_KINDS = ("none", "valid", "garbage", "list", "climbs", "absolute", "through-link", "ours-and-users")
FOLDER_KINDS = ("new", "empty", "plain", "symlink", "dangling", "file", "symlink-inside")


@st.composite
def folder_state(draw):
    return {
        "kind": draw(st.sampled_from(FOLDER_KINDS)),
        "user": draw(st.lists(st.sampled_from(USER_NAMES + OUR_NAMES), max_size=5, unique=True)),
        "manifest": draw(st.sampled_from(MANIFEST_KINDS)),
        "force": draw(st.booleans()),
        "follow": draw(st.booleans()),
    }


def _build(base: Path, state: dict) -> Path:
    """``base/outside`` holds files nobody may touch; returns the output folder path in the state asked."""
    outside = base / "outside"
    outside.mkdir()
    (outside / "secret.txt").write_text("keep")
    (outside / "index.html").write_text("someone else's page")
    out = base / "out"
    kind = state["kind"]
    if kind == "new":
        return out
    if kind == "file":
        out.write_text("a file")
        return out
    if kind == "dangling":
        out.symlink_to(base / "nowhere")
        return out
    real = base / "real" if kind == "symlink" else out
    real.mkdir()
    if kind == "symlink":
        out.symlink_to(real)
    if kind == "empty":
        return out
    if kind == "symlink-inside":
        (real / "img").symlink_to(outside)
    for name in state["user"]:
        path = real / name
        if path.parent.is_symlink():
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(b"user bytes " + name.encode())
    files = {"valid": list(OUR_NAMES[:3]), "climbs": ["../outside/secret.txt", "./../outside/index.html"],
             "absolute": [str(outside / "secret.txt")], "through-link": ["img/secret.txt", "img/index.html"],
             "ours-and-users": list(state["user"])}.get(state["manifest"])
    if state["manifest"] == "garbage":
        (real / MANIFEST).write_bytes(b"\x00{not json")
    elif state["manifest"] == "list":
        (real / MANIFEST).write_text("[1, 2]")
    elif files is not None:
        (real / MANIFEST).write_text(json.dumps({"wgpurender": 1, "writer": "export", "files": files}))
    return out


def _judge(base: Path, out: Path, before: dict, code: int, err: str, state: dict, written: set[str]) -> str:
    """A file the manifest listed is the writer's to replace or remove; every other file in the folder is the
    user's (with --force and exit 0, the writer's own names may be replaced); outside the folder nothing moves."""
    label = json.dumps(state)
    if code not in (0, 2) or (code == 2 and len(err.strip().splitlines()) != 1) or "Traceback" in err:
        return _count("multiline", label, err[-400:])
    after = tree_snapshot(base)
    outside = {k: v for k, v in before.items() if k.startswith("outside/")}
    if any(after.get(k) != v for k, v in outside.items()):
        return _count("clobbered", label, "a file outside the output folder changed")
    real = "real/" if state["kind"] == "symlink" else "out/"
    listed = {"ours-and-users": set(state["user"]), "valid": set(OUR_NAMES[:3])}.get(state["manifest"], set())
    for key, digest in before.items():
        if not key.startswith(real) or key.endswith(MANIFEST):
            continue
        rel = key[len(real):]
        mine = rel not in listed and not (code == 0 and rel in written and state["force"]) and not key.endswith("img")
        if mine and after.get(key) != digest:
            return _count("clobbered", label, f"the user's {rel} changed or vanished (exit {code})")
    leftovers = [k for k in after if k.endswith((".tmp", ".build")) or ".build/" in k]
    if leftovers:
        return _count("partial", label, f"left {leftovers}")
    return _count("render" if code == 0 else "error", label, "")


def _run_export(out: Path, state: dict) -> tuple[int, str]:
    argv = ["export", "triangle", "-o", str(out), "--size", "16x12"] + (["--force"] if state["force"] else [])
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, err.getvalue()


def _run_record(out: Path, state: dict) -> tuple[int, str]:
    try:
        with FrameWriter(out, 10.0, force=state["force"]) as writer:
            for k in range(2):
                writer.write(np.full((6, 8, 3), 40 * k, np.uint8))
    except UserError as err:
        return 2, str(err) + "\n"
    return 0, ""


@pytest.mark.parametrize("writer", ["export", "record"])
@given(state=folder_state())
@fuzz_settings(ci=12, long=1500)
def test_output_folders_keep_the_users_files(tmp_path_factory, writer, state):
    base = tmp_path_factory.mktemp("outputs")
    try:
        out = _build(base, state)
        before = tree_snapshot(base)
        with pytest.MonkeyPatch.context() as patch:
            patch.setenv("WGPURENDER_FOLLOW_SYMLINKS", "1" if state["follow"] else "0")
            code, err = (_run_export if writer == "export" else _run_record)(out, state)
        written = set(OUR_NAMES[:3]) if writer == "export" else {"frame_00000.png", "frame_00001.png"}
        outcome = _judge(base, out, before, code, err, state, written)
        check(outcome, f"{writer} {state}: {outcome} {err}")
    finally:
        reset_folder(base)


@given(payload=st.binary(max_size=300), key=st.text(max_size=20), cuts=st.lists(st.integers(0, 400), max_size=4),
       flips=st.lists(st.integers(0, 500), max_size=3), tail=st.binary(max_size=4), other=st.text(max_size=20))
@fuzz_settings(ci=200, long=5000)
def test_a_damaged_cache_entry_is_never_served(payload, key, cuts, flips, tail, other):
    blob = bytearray(cache_entry.seal(key, payload))
    for at in flips:
        blob[at % len(blob)] ^= 1 + at % 255
    for at in cuts:
        del blob[at % max(1, len(blob)):]
    blob += tail
    ask = key if other == "" else other
    got = cache_entry.unseal(bytes(blob), ask)
    whole = bytes(blob) == cache_entry.seal(ask, payload)
    outcome = _count("wrong" if (got is not None and not whole) or (whole and got != payload) else "error",
                      "cache entry", f"served {got!r} for a damaged entry")
    check(outcome, f"damaged entry served: {got!r}")


@given(value=st.one_of(st.none(), st.text(max_size=30), st.sampled_from(["/", "/tmp", "relative", "/no/such", "~",
                                                                            "/dev/null", "/etc/hostname"])))
@fuzz_settings(ci=50, long=2000)
def test_any_runtime_dir_value_ends_valid_and_a_valid_one_is_kept(value):
    from wgpurender.core.files import runtime_dir

    with pytest.MonkeyPatch.context() as patch:
        if value is None or "\0" in value:
            patch.delenv("XDG_RUNTIME_DIR", raising=False)
        else:
            patch.setenv("XDG_RUNTIME_DIR", value)
        valid = runtime_dir.runtime_dir_valid(os.environ.get("XDG_RUNTIME_DIR"))
        made = runtime_dir.ensure_runtime_dir()
        good = os.path.isabs(made) and os.path.isdir(made) and os.environ["XDG_RUNTIME_DIR"] == made
        kept = not valid or made == value
        outcome = _count("render" if good and kept else "wrong", f"XDG_RUNTIME_DIR={value!r}", f"became {made!r}")
    check(outcome, f"XDG_RUNTIME_DIR={value!r} became {made!r}")
