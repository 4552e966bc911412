"""The Vulkan -> wgpu mapping table (wgpurender/concepts.py) and its generated docs/vulkan-mapping.md.

The table is documentation that points at code, so these tests keep it honest:
every required course concept has exactly one row, every code location in it
imports and resolves (module, then attributes, Class.method included), a row
without raw-path code says why, and the committed markdown equals a fresh
generation (so it cannot go stale). No GPU work: resolving only imports modules.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from wgpurender.cli import main
from wgpurender.concepts import CONCEPTS, markdown, plain_text, resolve

DOC = Path(__file__).resolve().parent.parent / "docs" / "vulkan-mapping.md"

# The course's concept list (issue 5), written out here independently of the data.
REQUIRED = (
    "instance", "physical device", "device", "queue families", "surface", "presentation and present modes",
    "heaps and memory types", "staging", "command pool and buffers", "descriptor pool", "set layouts",
    "sets and updates", "images", "views", "subresources", "layouts and transitions", "swapchain",
    "attachment descriptions and references", "subpasses and dependencies", "barriers with stage and access masks",
    "fences", "semaphores", "events", "render pass", "framebuffer", "begin info and clear values", "pipeline",
    "pipeline layout", "pipeline cache", "shader modules and SPIR-V", "vertex input bindings and attributes",
    "input assembly", "viewport and scissor", "rasterizer", "multisample", "dynamic state", "depth/stencil",
    "blending", "input attachments", "push constants", "UBO alignment", "frames in flight",
    # issue 23: the course concepts that both paths have code for and had no row
    "clear without a render pass", "buffer objects", "draw calls", "memory requirements", "device idle",
    "compute pipelines", "storage images",
)
# The course's Vulkan calls that must each appear in some row (issue 23), written out here.
REQUIRED_CALLS = ("vkCmdClearColorImage", "vkCreateBuffer", "vkCmdDraw", "vkCmdDrawIndexed",
                  "vkGetBufferMemoryRequirements", "vkDeviceWaitIdle", "vkCreateComputePipelines", "vkCmdDispatch")
# Concepts the raw path has no code for: their rows must say so (events: no natural use; the raw window,
# wgpurender/raw_path/window/__init__.py, has the surface, swapchain, semaphores and frames in flight).
NOT_IN_RAW_PATH = {"events", "storage images"}  # compute pipelines: raw_path/scene/ibl.py since 2026-11-27
# Concepts no path has code for: shown as "not demonstrated".
NOT_DEMONSTRATED = {"events"}
ALL_LOCATIONS = sorted({(row.name, loc) for row in CONCEPTS for loc in (*row.raw, *row.wgpu_where)})


def test_every_required_concept_has_exactly_one_row():
    names = [row.name for row in CONCEPTS]
    for concept in REQUIRED:
        assert names.count(concept) == 1, f"{concept!r} has {names.count(concept)} rows"
    assert len(set(names)) == len(names), "duplicate rows"


@pytest.mark.parametrize(("concept", "location"), ALL_LOCATIONS)
def test_location_exists(concept, location):
    """Import the module and walk the attribute path; a renamed function fails here."""
    assert location.startswith("wgpurender."), location
    obj = resolve(location)
    assert obj is not None


def test_the_course_calls_have_rows():
    named = " ".join(" ".join(row.vulkan) for row in CONCEPTS)
    for call in REQUIRED_CALLS:
        assert re.search(rf"\b{call}\b", named), f"no row names {call}"


def test_every_demonstrated_row_points_at_code_on_both_paths_or_says_why():
    """A row has wgpu code, and raw code or a note; a row with code on neither side is marked not demonstrated."""
    for row in CONCEPTS:
        has_code = bool(row.raw or row.wgpu_where)
        assert row.demonstrated == has_code, f"{row.name}: demonstrated={row.demonstrated}, code: {has_code}"
        if row.demonstrated:
            assert row.wgpu_where, f"{row.name}: no wgpu-path code"
            assert row.raw or row.raw_note, f"{row.name}: no raw-path code and no reason"
    assert {row.name for row in CONCEPTS if not row.demonstrated} == NOT_DEMONSTRATED
    assert "events (not demonstrated)" in plain_text() and "| events (not demonstrated) |" in markdown()


def test_raw_and_wgpu_locations_are_on_their_own_path():
    for row in CONCEPTS:
        assert all(loc.startswith("wgpurender.raw_path.") for loc in row.raw), row.name
        assert not any(loc.startswith("wgpurender.raw_path.") for loc in row.wgpu_where), row.name


def test_rows_without_raw_code_say_why():
    """Exactly the headless concepts have no raw-path code, each with a note; the window holds their wgpu side."""
    empty = {row.name for row in CONCEPTS if not row.raw}
    assert empty == NOT_IN_RAW_PATH
    for row in CONCEPTS:
        assert bool(row.raw_note) == (not row.raw), row.name
        if row.name in {"surface", "presentation and present modes", "swapchain", "semaphores"}:
            assert any(loc.startswith("wgpurender.wgpu_path.window:") for loc in row.wgpu_where), row.name
        assert row.vulkan and row.wgpu and len(row.differs) > 30, row.name


def test_resolve_rejects_missing_names():
    with pytest.raises(AttributeError):
        resolve("wgpurender.raw_path.device.context:no_such_function")
    with pytest.raises(AttributeError):
        resolve("wgpurender.wgpu_path.stages.cube3d:Cube3D.no_such_method")
    with pytest.raises(ImportError):
        resolve("wgpurender.no_such_module:x")


def test_markdown_is_one_table_row_per_concept():
    text = markdown()
    rows = [line for line in text.splitlines() if line.startswith("| ") and not line.startswith(("| Concept", "| ---"))]
    assert len(rows) == len(CONCEPTS)
    for line, row in zip(rows, CONCEPTS, strict=True):
        assert line.startswith(f"| {row.name}")
        cells = re.split(r"(?<!\\)\|", line)[1:-1]  # split on unescaped pipes
        assert len(cells) == 6, f"{row.name}: {len(cells)} cells, not 6"
    assert "GENERATED" in text.split("|")[0] and "python -m wgpurender.concepts" in text


def test_doc_is_current():
    """docs/vulkan-mapping.md == the generated markdown: regenerate with python -m wgpurender.concepts."""
    assert DOC.is_file(), f"{DOC} missing: python -m wgpurender.concepts > docs/vulkan-mapping.md"
    assert DOC.read_text(encoding="utf-8") == markdown(), (
        "docs/vulkan-mapping.md is stale: python -m wgpurender.concepts > docs/vulkan-mapping.md"
    )


def test_command_prints_text_and_markdown(capsys):
    assert main(["concepts"]) == 0
    assert capsys.readouterr().out == plain_text()
    assert main(["concepts", "--markdown"]) == 0
    assert capsys.readouterr().out == markdown()
    assert "  raw path:  (not in the raw path: no natural use" in plain_text()


def test_a_vulkan_call_named_exactly_finds_its_row():
    """`wgpurender concepts vkCmdDraw` (the README's tour): the row that lists vkCmdDraw itself, not every row whose
    items merely contain the text (instanced draws lists "vkCmdDrawIndexed (instanceCount, firstInstance)")."""
    from wgpurender.cli.concepts import find_concept
    from wgpurender.core.errors import UserError

    assert find_concept("vkCmdDraw").name == "draw calls"
    assert find_concept("vkcmddrawindexed").name == "draw calls"
    with pytest.raises(UserError, match="ambiguous"):
        find_concept("vkCmdDrawInd")  # only contained, in two rows
