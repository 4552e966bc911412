"""The plan's targets: where the scene pass writes (scene image, MSAA colour, depth) and the output.

The scene pass draws into the output itself when there is no post chain, else into a ``scene_color``
image that the first post pass samples; at ``msaa > 1`` it draws into a multisampled ``msaa_color``
resolved into that target; a ``depth`` attachment exists only when models are drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

from wgpurender.core.course.effects import EffectStep
from wgpurender.core.errors import UserError
from wgpurender.core.plan.model import HDR_FORMAT, LDR_SCENE_FORMAT, Attachment, Knobs
from wgpurender.core.scene import Scene


@dataclass(frozen=True)
class SceneTargets:
    """Where the scene pass writes: ``color`` (drawn into), ``target`` (resolved into or drawn into),
    ``format``, and ``srgb_output`` (why the scene shader encodes sRGB itself, or None)."""

    attachments: tuple[Attachment, ...]
    color: str
    target: str
    format: str
    depth: str | None
    srgb_output: str | None


def scene_format(scene: Scene, knobs: Knobs) -> tuple[str, str]:
    """The scene image's format when a post chain reads it, and why."""
    r = scene.render
    tonemaps = [s for s in scene.post if s.effect == "tonemap"]
    if knobs.scene_format is not None:
        return knobs.scene_format, f"knob scene_format = {knobs.scene_format}"
    if r.hdr:
        return HDR_FORMAT, "render.hdr = true: the scene is lit in linear HDR"
    if tonemaps:
        return HDR_FORMAT, f"post[{tonemaps[0].index}] tonemap maps HDR to [0, 1], so it needs HDR input"
    return LDR_SCENE_FORMAT, "render.hdr = false and no tone mapping: 8 bits (sRGB-encoded) suffice"


def plan_scene_targets(scene: Scene, steps: list[EffectStep], out_fmt: str, size: tuple[int, int], msaa: int,
                       msaa_why: str, knobs: Knobs, depth_compare: str, notes: list[str]) -> SceneTargets:
    """The attachments the scene pass writes (not the output's), appending to ``notes`` what a setting cannot do."""
    attachments: list[Attachment] = []
    if steps:
        scene_fmt, why = scene_format(scene, knobs)
        attachments.append(Attachment("scene_color", "scene-color", scene_fmt, size, 1, (
            why, f"post[0] {steps[0].effect} reads the scene image as a texture (WebGPU has no input attachments)")))
        scene_target = "scene_color"
    else:
        if knobs.scene_format is not None:
            raise UserError(f"{scene.path}: the scene_format knob needs a scene image that a post chain reads, "
                            "but this scene draws straight into its output: add [[post]] effects or drop the knob")
        scene_fmt, scene_target = out_fmt, "output"
        if scene.render.hdr and not out_fmt.endswith("float"):
            notes.append(f"render.hdr = true but no post effect reads an HDR image: the scene draws straight into the "
                         f"{out_fmt} output, clipping at 1 (add [[post]] effect = \"tonemap\" to use the HDR range)")
    srgb_output = None
    if not steps and out_fmt in ("rgba8unorm", "bgra8unorm"):
        srgb_output = (f"the scene draws straight into the {out_fmt} output, which does not encode: "
                       "the fragment shader applies the sRGB curve")
    color = scene_target
    if msaa > 1:
        if scene_fmt == "rgba32float":
            raise UserError("rgba32float cannot be multisampled in WebGPU: use msaa 1 with it")
        attachments.append(Attachment("msaa_color", "msaa-color", scene_fmt, size, msaa, (
            msaa_why + f": drawn multisampled, resolved into {scene_target} at the end of the pass, "
            "samples discarded (store_op discard)",)))
        color = "msaa_color"
    depth = None
    if scene.models:
        depth = "depth"
        attachments.append(Attachment("depth", "depth", knobs.depth_format, size, msaa, (
            f"{len(scene.models)} model(s) drawn with depth testing (compare {depth_compare})"
            + (f"; {msaa} samples to match msaa_color" if msaa > 1 else ""),)))
    return SceneTargets(tuple(attachments), color, scene_target, scene_fmt, depth, srgb_output)


def output_attachment(out_fmt: str, size: tuple[int, int], format_why: str, last_post: str | None,
                      resolved: bool, twin_of: str | None = None) -> Attachment:
    """The caller's output texture: who writes it (the last post pass, or the scene pass); ``twin_of``: the
    format whose bytes it holds when a compute pass writes it as its storage twin (``out_fmt``)."""
    writer = (last_post if last_post is not None else
              "resolve target of the scene pass" if resolved else "the scene pass draws into it directly")
    why = (format_why,) if twin_of is None else (
        f"{format_why}: made as its storage twin {out_fmt}, holding the same bytes (the sRGB curve applied in the "
        "shader); read back directly",)
    return Attachment("output", "output", out_fmt, size, 1, (*why, writer))
