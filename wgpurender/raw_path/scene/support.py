"""What the raw path can render of a scene file, and a clear refusal for the rest.

The raw path draws a scene the course's way: the per-pixel post effects run in a second subpass
that reads the resolved scene image as an input attachment; the effects that read neighbouring
pixels (fxaa, sharpen), which an input attachment cannot feed (``subpassLoad`` gives only the
pixel under the fragment), each run in a render pass of their own that samples the previous
result (neighbourhood.py). Refusing the rest is the honest answer: dropping or approximating a
feature would give a different image under the same scene file, and the comparison with the wgpu
path would measure the omission instead of the two APIs.

Refused (each names itself in the UserError):
- a post effect the raw path has no shader for (a new effect added to the wgpu path only);
- more than ``MAX_POST_STEPS`` post effects (the size of the chain's uniform block);
- output formats the raw path has no image format for (``bgra8unorm``, ``bgra8unorm-srgb``: the
  raw path reads back RGBA images only; wgpu offers them for swapchains).

Everything else a scene file can say is supported: msaa 1 and 4, hdr true and false (the scene
image is then rgba8unorm-srgb, decoded by subpassLoad like a sampled texture), no post chain
(one subpass drawing straight into the output, with the shader's sRGB curve for rgba8unorm),
lit and unlit materials, every map, flipped v, both camera conventions, no models.
"""

from __future__ import annotations

from wgpurender.core.errors import UserError
from wgpurender.core.plan import DEPTH_FORMAT, RenderPlan
from wgpurender.core.plan.batches import OBJECT_BYTES
from wgpurender.raw_path.device.images import FORMATS
from wgpurender.raw_path.device.uniforms import MAX_POST_STEPS
from wgpurender.raw_path.post.neighbourhood import NEIGHBOUR_SHADERS

PIXEL_EFFECTS = ("tonemap", "vignette", "grayscale", "sepia", "srgb")  # post_chain.frag, in a subpass
NEIGHBOUR_EFFECTS = tuple(NEIGHBOUR_SHADERS)  # a render pass each (neighbourhood.py)
# Plan knobs the raw path draws only at their default (knob -> (default, what the raw path does instead)): asked
# for through the API (w.reference(scene, reverse_z=True)), they are refused rather than silently not drawn.
WGPU_ONLY_KNOBS = {
    "depth_format": (DEPTH_FORMAT, f"the raw path's depth image is {DEPTH_FORMAT}"),
    "reverse_z": (False, "the raw path draws depth 0 at near, compare less"),
    "post_path": (None, "the raw path runs the post chain in a subpass and neighbourhood passes"),
    "post_fuse": (None, "the raw path composes every per-pixel effect in one subpass"),
    "immediates": ("auto", "the raw path pushes material factors as push constants"),
}


def unsupported(plan: RenderPlan) -> list[str]:
    """One sentence per feature of the plan that the raw path cannot draw (empty: all supported)."""
    problems = []
    steps = plan.post_steps  # the effects in order, however the wgpu path groups them into passes
    for i, step in enumerate(steps):
        if step.effect not in PIXEL_EFFECTS + NEIGHBOUR_EFFECTS:
            problems.append(f"post[{i}] {step.effect}: the raw path has no {step.effect} effect "
                            f"(it has {', '.join(PIXEL_EFFECTS + NEIGHBOUR_EFFECTS)})")
    if len(steps) > MAX_POST_STEPS:
        problems.append(f"{len(steps)} post effects: the raw path's chain holds at most {MAX_POST_STEPS}")
    if plan.output_format not in FORMATS:
        problems.append(f"output format {plan.output_format}: the raw path renders only {', '.join(FORMATS)}")
    if plan.knobs.instance_data == "vertex":  # "storage" and "auto" are what the raw path does
        problems.append("plan knob instance_data = 'vertex': the raw path reads instances from a storage buffer "
                        "(leave the knob out, or say 'storage')")
    elif plan.instance_data == "vertex":  # "auto" past the one storage binding's limit (instance_data.fit_binding)
        room = plan.knobs.adapter.max_storage_binding // OBJECT_BYTES
        problems.append(f"{sum(d.instance_count for d in plan.scene_pass.draws)} instances: the raw path reads "
                        f"every instance from one storage buffer, and this device's maxStorageBufferRange holds "
                        f"{room} (draw at most {room} copies, or render on the wgpu path)")
    if plan.knobs.post_intermediate == "none":
        problems.append("plan knob post_intermediate = 'none': the raw path's FXAA samples a stored handoff image "
                        "(choose auto, rgba16float, rgba8unorm or rgba8unorm-srgb)")
    for knob, (default, instead) in WGPU_ONLY_KNOBS.items():
        if getattr(plan.knobs, knob) != default:
            problems.append(f"plan knob {knob} = {getattr(plan.knobs, knob)!r}: {instead} (leave the knob out)")
    return problems


def check_supported(plan: RenderPlan) -> None:
    """UserError naming every unsupported feature of the plan, so that no image is silently different."""
    problems = unsupported(plan)
    if problems:
        raise UserError(f"{plan.scene_path}: the raw-Vulkan path cannot render this scene: " + "; ".join(problems))
