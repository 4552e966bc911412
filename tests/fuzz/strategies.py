"""Hypothesis strategies for the fuzz tests: byte and text mutations of the repository's assets, and generated
scene files, meshes and images with values at the edges (huge, tiny, NaN, wrong types)."""

from __future__ import annotations

import json
import os
from pathlib import Path

from harness import LONG
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

REPO = Path(__file__).resolve().parents[2]
ASSETS = REPO / "assets"

EDGE_NUMBERS = ["0", "-0.0", "1", "-1", "0.5", "1e-7", "1e-45", "1e-300", "3.4e38", "3.5e38", "1e39", "1e200",
                "1e308", "-1e308", "nan", "inf", "-inf", "65535", "65536", "4294967296", "16384", "16385", "-7"]
EDGE_TOML = EDGE_NUMBERS + ['"x"', '""', "[]", "{}", "true", "[0, 0, 0]", "[1e39, 0, 0]", '"\\u0000"', '"a\\nb"']


def fuzz_settings(ci: int, long: int) -> settings:
    """``ci`` examples in ``make test`` (derandomized: the same cases every run), ``long`` in ``make fuzz``."""
    factor = float(os.environ.get("WGPURENDER_FUZZ_FACTOR", "1"))  # e.g. 0.1 for a quick long-mode look
    return settings(max_examples=max(1, round(long * factor)) if LONG else ci, deadline=None,
                    derandomize=not LONG, database=None, suppress_health_check=list(HealthCheck), print_blob=True)


finite = st.floats(-10, 10, allow_nan=False).map(lambda v: f"{v:.4g}")
number_text = st.one_of(finite, finite, st.sampled_from(EDGE_NUMBERS))
toml_value = st.one_of(number_text, st.sampled_from(EDGE_TOML))


@st.composite
def vector(draw, n: int = 3) -> str:
    return "[" + ", ".join(draw(number_text) for _ in range(draw(st.sampled_from([n, n, n, n - 1, n + 1])))) + "]"


@st.composite
def mutated_bytes(draw, data: bytes, max_ops: int = 4) -> bytes:
    """A few random edits: flip a byte, overwrite with edge bytes, insert, delete a span, truncate."""
    out = bytearray(data)
    for _ in range(draw(st.integers(1, max_ops))):
        if not out:
            break
        at = draw(st.integers(0, len(out) - 1))
        op = draw(st.sampled_from(["flip", "edge", "insert", "delete", "truncate"]))
        if op == "flip":
            out[at] ^= 1 << draw(st.integers(0, 7))
        elif op == "edge":
            edge = draw(st.sampled_from([b"\x00", b"\xff", b"\xff\xff\xff\x7f", b"\x00\x00\x80\x7f", b"9e99"]))
            out[at:at + len(edge)] = edge
        elif op == "insert":
            out[at:at] = draw(st.binary(min_size=1, max_size=8))
        elif op == "delete":
            del out[at:at + draw(st.integers(1, 64))]
        else:
            del out[at:]
    return bytes(out)


@st.composite
def mutated_text(draw, text: str, max_ops: int = 3) -> str:
    """Line edits: replace a number or value with an edge value, delete, duplicate or swap lines."""
    lines = text.splitlines()
    for _ in range(draw(st.integers(1, max_ops))):
        if not lines:
            break
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["value", "value", "number", "delete", "duplicate", "swap"]))
        line = lines[i]
        if op == "value" and "=" in line:
            key = line.split("=", 1)[0]
            lines[i] = f"{key}= {draw(toml_value)}"
        elif op == "number":
            tokens = line.split()
            if tokens:
                j = draw(st.integers(0, len(tokens) - 1))
                tokens[j] = draw(number_text)
                lines[i] = " ".join(tokens)
        elif op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, line)
        else:
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
    return "\n".join(lines) + "\n"


JSON_EDGE = [None, True, 0, -1, 5, 1e308, 2**40, "x", "", [], {}, ["x"], [{"uri": 5}], {"index": 99}]


@st.composite
def mutated_json(draw, doc, max_ops: int = 3):
    """Replace values at random JSON paths with values of other shapes (or delete keys)."""
    doc = json.loads(json.dumps(doc))
    for _ in range(draw(st.integers(1, max_ops))):
        holder, key = _random_slot(draw, doc)
        if holder is None:
            break
        if isinstance(holder, dict) and draw(st.booleans()) and draw(st.booleans()):
            del holder[key]
        else:
            holder[key] = json.loads(json.dumps(draw(st.sampled_from(JSON_EDGE))))  # a fresh copy, never shared
    return doc


def _random_slot(draw, doc):
    holder, key = None, None
    node = doc
    for _ in range(draw(st.integers(1, 6))):
        keys = list(node.keys()) if isinstance(node, dict) else list(range(len(node))) if isinstance(node, list) else []
        if not keys:
            break
        holder, key = node, draw(st.sampled_from(keys))
        node = node[key]
    return holder, key


def link_assets(folder: Path) -> None:
    """folder/models and folder/textures point at the repository's, so a scene in folder/scenes finds ../models."""
    for name in ("models", "textures"):
        link = folder / name
        if not link.exists():
            os.symlink(ASSETS / name, link)
