"""The hard cases' WGSL probes live beside their Python (tests/numerics/shaders/), not in shaders_wgsl/."""

from __future__ import annotations

from pathlib import Path

SHADERS = Path(__file__).resolve().parent / "shaders"


def load_wgsl(name: str) -> str:
    """The text of tests/numerics/shaders/<name>."""
    return (SHADERS / name).read_text(encoding="utf-8")
