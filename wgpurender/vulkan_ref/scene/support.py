"""What the raw path can render of a scene file, and a clear refusal for the rest.

The raw path draws a scene the course's way: the post chain runs in a second subpass that reads
the resolved scene image as an input attachment. An input attachment gives a fragment only the
pixel under it (``subpassLoad`` takes no coordinates), so an effect that reads neighbouring pixels
cannot run there. Refusing is the honest answer: dropping or approximating the effect would give
a different image under the same scene file, and the comparison with the wgpu path would measure
the omission instead of the two APIs.

Refused (each names itself in the UserError):
- post effects that read neighbouring pixels: ``fxaa`` (its edge search samples along the edge,
  bilinearly, between pixels) and ``sharpen`` (a 3x3 Laplacian);
- more than ``MAX_POST_STEPS`` post effects (the size of the chain's uniform block);
- output formats the raw path has no image format for (``bgra8unorm``, ``bgra8unorm-srgb``: the
  raw path reads back RGBA images only; wgpu offers them for swapchains).

Everything else a scene file can say is supported: msaa 1 and 4, hdr true and false (the scene
image is then rgba8unorm-srgb, decoded by subpassLoad like a sampled texture), no post chain
(one subpass drawing straight into the output, with the shader's sRGB curve for rgba8unorm),
lit and unlit materials, every map, flipped v, both camera conventions, no models.
"""

from __future__ import annotations

from ...errors import UserError
from ...plan import RenderPlan
from ..images import FORMATS
from .uniforms import MAX_POST_STEPS

# effect -> why an input attachment cannot feed it
NEIGHBOUR_EFFECTS = {
    "fxaa": "fxaa reads neighbouring pixels (its edge search samples bilinearly along the edge)",
    "sharpen": "sharpen reads neighbouring pixels (a 3x3 Laplacian of the four neighbours)",
}
PIXEL_EFFECTS = ("tonemap", "vignette", "grayscale", "sepia", "srgb")


def unsupported(plan: RenderPlan) -> list[str]:
    """One sentence per feature of the plan that the raw path cannot draw (empty: all supported)."""
    problems = []
    steps = plan.post_steps  # the effects in order, however the wgpu path groups them into passes
    for i, step in enumerate(steps):
        if step.effect in NEIGHBOUR_EFFECTS:
            problems.append(
                f"post[{i}] {NEIGHBOUR_EFFECTS[step.effect]}; an input attachment gives only the current pixel "
                f"(subpassLoad takes no coordinates): the raw path cannot run {step.effect} in its post subpass "
                f"(remove the {step.effect} [[post]] entry to compare the rest of the chain)")
        elif step.effect not in PIXEL_EFFECTS:
            problems.append(f"post[{i}] {step.effect}: the raw path's post subpass has no {step.effect} effect "
                            f"(it has {', '.join(PIXEL_EFFECTS)})")
    if len(steps) > MAX_POST_STEPS:
        problems.append(f"{len(steps)} post effects: the raw path's chain holds at most {MAX_POST_STEPS}")
    if plan.output_format not in FORMATS:
        problems.append(f"output format {plan.output_format}: the raw path renders only {', '.join(FORMATS)}")
    return problems


def check_supported(plan: RenderPlan) -> None:
    """UserError naming every unsupported feature of the plan, so that no image is silently different."""
    problems = unsupported(plan)
    if problems:
        raise UserError(f"{plan.scene_path}: the raw-Vulkan path cannot render this scene: " + "; ".join(problems))
