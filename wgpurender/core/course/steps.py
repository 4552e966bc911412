"""The course's order: every step, its number and title, in the order the course teaches them.

Both stage registries (wgpurender/wgpu_path/stages/ and wgpurender/raw_path/stages/) list their stages
in this order, and ``wgpurender stages`` prints it. A stage whose name is not here comes after
the listed ones (in name order), so a new stage is listed before it is given its place.
"""

from __future__ import annotations

from typing import NamedTuple


class Step(NamedTuple):
    number: str
    stage: str
    title: str


COURSE = (
    Step("1a", "clear", "clear without a render pass (vkCmdClearColorImage)"),
    Step("1b", "clear-pass", "clear with a render pass (loadOp CLEAR, VkClearValue)"),
    Step("2a", "triangle", "first triangle in NDC, attribute-less"),
    Step("2b", "triangle-buffers", "vertex + index buffers and the input layout"),
    Step("3a", "offscreen", "offscreen rendering and readback"),
    Step("3b", "msaa", "4x MSAA with a resolve attachment"),
    Step("3c", "msaa-post", "4x MSAA, then a post effect reading the resolved image"),
    Step("4", "3d", "3D with uniform buffers in bind groups (descriptor sets) and push constants"),
    Step("5", "textured", "textures, combined or separate (texture + one or several samplers)"),
)
_POSITION = {step.stage: k for k, step in enumerate(COURSE)}


def course_position(stage: str) -> tuple[int, str]:
    """A sort key: the stage's place in the course, unknown stages last by name."""
    return (_POSITION.get(stage, len(COURSE)), stage)


def course_step(stage: str) -> Step | None:
    """The course step a stage stands for, or None for a stage the table does not list yet."""
    k = _POSITION.get(stage)
    return None if k is None else COURSE[k]
