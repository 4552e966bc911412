"""The course's order: every step, its number and title, in the order the course teaches them.

Both stage registries (wgpurender/wgpu_path/stages/ and wgpurender/raw_path/stages/) list their stages
in this order, and ``wgpurender stages`` prints it. A stage whose name is not here comes after
the listed ones (in name order), so a new stage is listed before it is given its place.

Steps 1 to 5 are stage modules (one per path). Step 6, the course's goal, is the final model: a scene
file (``scene``: a bundled scene's name, ``assets/scenes/<scene>.toml``) drawn by each path's scene renderer
(wgpu_path/scene/ and post/; raw_path/scene/).

MSAA is a fact of the step, so both paths' stages read it from here: ``msaa`` is the sample count a step
renders with by default, and ``takes_msaa`` whether ``--msaa 4`` applies to it at all.
"""

from __future__ import annotations

from typing import NamedTuple


class Step(NamedTuple):
    number: str
    stage: str
    title: str
    takes_msaa: bool = False
    msaa: int = 1
    scene: str | None = None  # a bundled scene's name: the step is a scene file, not a stage module


COURSE = (
    Step("1a", "clear", "clear without a render pass (vkCmdClearColorImage)"),
    Step("1b", "clear-pass", "clear with a render pass (loadOp CLEAR, VkClearValue)"),
    Step("2a", "triangle", "first triangle in NDC, attribute-less", takes_msaa=True),
    Step("2b", "triangle-buffers", "vertex + index buffers and the input layout", takes_msaa=True),
    Step("3a", "offscreen", "offscreen rendering and readback"),
    Step("3b", "msaa", "4x MSAA with a resolve attachment", takes_msaa=True, msaa=4),
    Step("3c", "msaa-post", "4x MSAA, then a post effect reading the resolved image", takes_msaa=True, msaa=4),
    Step("4", "3d", "3D with uniform buffers in bind groups (descriptor sets) and push constants", takes_msaa=True),
    Step("5", "textured", "textures, combined or separate (texture + one or several samplers)", takes_msaa=True),
    Step("6", "final", "the final model: textured, normal-mapped and lit, 4x MSAA into an HDR target, then "
         "post-processing (a scene file)", takes_msaa=True, msaa=4, scene="final"),
)
_POSITION = {step.stage: k for k, step in enumerate(COURSE)}

# The course texts each step comes from (../shared/course/, never in the repository: named, not required).
# "000 goals" is the slides' list of the sessions' goals, "000 step N" their step N.
COURSE_TEXTS = {
    "000": "000_875fa49d9f08787a.txt (the course slides, French)",
    "001": "001_fc132b440c510919.txt (descriptor set layout, pool, sets; French)",
    "002": "002_efacf0121d42d5a4.txt (every Vulkan object, instance to render loop; Chinese)",
    "003": "003_b8f42c17b130dbb4.txt (uniform buffers and std140; French)",
    "004": "004_201fafb2b87eaddd.txt (descriptors with Vulkan-Hpp, stage and access flags; Chinese)",
}
STEP_TEXTS = {  # chapter -> (text, where in it)
    "1": (("000", "step 1: clear backbuffer, without then with a render pass"),
          ("002", "render pass, framebuffer, command buffer")),
    "2": (("000", "step 2: first triangle in NDC, attribute-less, then vertex/index buffers"),
          ("002", "pipeline: vertex input, input assembly")),
    "3": (("000", "step 3: offscreen rendering, then MSAA; the goals' input-attachment post pass"),
          ("002", "VkPipelineMultisampleStateCreateInfo, images and views")),
    "4": (("000", "step 4: 3D, descriptor sets for uniform buffers; push constants"),
          ("001", "the whole chapter"), ("003", "UBOs and std140 alignment"), ("004", "descriptor pool/set/update")),
    "5": (("000", "step 5: textures, combined or separate samplers"), ("004", "combined image sampler descriptors")),
    "6": (("000", "goals: a textured, lit, normal-mapped 3D model, 2 UBOs, 4x MSAA render target, one post pass"),),
}


def step_texts(step: Step) -> tuple[tuple[str, str], ...]:
    """(course text file, where in it) pairs for a step, by its chapter (the number's digits)."""
    chapter = step.number.rstrip("abcdefghijklmnopqrstuvwxyz")
    return tuple((COURSE_TEXTS[key].split(" ")[0], where) for key, where in STEP_TEXTS.get(chapter, ()))


def course_position(stage: str) -> tuple[int, str]:
    """A sort key: the stage's place in the course, unknown stages last by name."""
    return (_POSITION.get(stage, len(COURSE)), stage)


def course_step(stage: str) -> Step | None:
    """The course step a stage stands for, or None for a stage the table does not list yet."""
    k = _POSITION.get(stage)
    return None if k is None else COURSE[k]


def stage_steps() -> tuple[Step, ...]:
    """The steps drawn by stage modules (all but the scene steps)."""
    return tuple(step for step in COURSE if step.scene is None)


def msaa_steps() -> list[str]:
    """The stages ``--msaa 4`` applies to, in course order (for messages)."""
    return [step.stage for step in stage_steps() if step.takes_msaa]


def step_msaa(stage: str) -> tuple[bool, int]:
    """(takes --msaa 4, default sample count) of a stage; a stage the table does not list takes no MSAA."""
    step = course_step(stage)
    return (step.takes_msaa, step.msaa) if step else (False, 1)
