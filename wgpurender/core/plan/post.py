"""Planning the post chain: which effect steps share a pass (fusion), on which path, through which textures.

Fusion: an effect that reads only the pixel it writes (``reach = "pixel"`` in wgpurender/core/course/effects.py)
runs as a function in the pass before it; a neighbourhood effect (FXAA, sharpen) starts a new pass, since it
must read a finished image. Path: "fragment" (a full-screen triangle) or "compute" (a dispatch writing a
storage texture; the ``-srgb`` formats cannot be one, so an offscreen rgba8unorm-srgb output is made as its
rgba8unorm twin holding the same bytes (:data:`~.model.STORAGE_TWINS`), a swapchain image is written through
a scratch and a copy, and an 8-bit sRGB scene image's intermediates become rgba16float). The "auto" rule and
the other knobs are resolved here too. Bytes per pass: the compulsory traffic (each texel read and written
once), what ``--explain`` and ``bench post-roofline`` report.
"""

from __future__ import annotations

from wgpurender.core.course.effects import EffectStep, group_passes, step_notes
from wgpurender.core.errors import UserError
from wgpurender.core.plan.dispatch import dispatch_shape
from wgpurender.core.plan.model import (
    BYTES_PER_PIXEL,
    HDR_FORMAT,
    STORAGE_FORMATS,
    STORAGE_TWINS,
    AdapterFacts,
    Attachment,
    Knobs,
    PostPass,
    PostPipeline,
)


def resolve_post_path(r, knobs: Knobs) -> tuple[str, str]:
    """fragment or compute, and why. The "auto" rule: compute on a discrete GPU (a fragment pass there is
    raster-bound, a compute pass uses every SM: facts.md on the H100/H200); fragment everywhere else (a CPU
    driver like lavapipe rasterises a full-screen triangle as cheaply as it runs a dispatch, and an
    integrated or mobile GPU's raster path is its fast path); fragment when the adapter is not known."""
    asked = knobs.post_path or r.post_path
    origin = "knob post_path" if knobs.post_path else f"render.post_path = {r.post_path}"
    adapter = knobs.adapter
    if asked != "auto" and not (asked == "compute" and adapter is not None and not adapter.compute):
        return asked, origin
    if asked == "compute":  # this device runs no compute shaders (a GL context below 4.3: core/plan/instance_data)
        if knobs.post_path:
            raise UserError(f"post_path = compute cannot run on {adapter.name or adapter.backend}: it runs no compute "
                            "shaders (a GL context below 4.3); use post_path = fragment or auto")
        return "fragment", f"{origin}, but {adapter.name or adapter.backend} runs no compute shaders: fragment"
    if adapter is not None and adapter.adapter_type == "DiscreteGPU" and not adapter.compute:
        return "fragment", f"{origin}: fragment on {adapter.name or adapter.backend}, which runs no compute shaders"
    if adapter is None:
        return "fragment", f"{origin}, adapter not known yet: fragment (the renderer re-plans for its adapter)"
    if adapter.adapter_type == "DiscreteGPU":
        return "compute", f"{origin}: compute on a discrete GPU ({adapter.name or adapter.adapter_type})"
    if not adapter.adapter_type:  # a browser's WebGPU: the page's adapter is picked there and has no type in WebGPU
        return "fragment", (f"{origin}: fragment on {adapter.name or 'an unnamed adapter'}, whose adapter type is "
                            "not known here (WebGPU does not report one)")
    return "fragment", f"{origin}: fragment on a {adapter.adapter_type} adapter ({adapter.name or 'unnamed'})"


# Backends whose adapters advertise "immediates" but do not deliver them correctly: the plan falls back to a
# uniform buffer there. docs/backends.md ("Immediates on OpenGL") has the measurement and the upstream code.
UNTRUSTED_IMMEDIATES = {
    "OpenGL": "wgpu's GL backend loses the values when the shader declares other types before them (it looks up "
              "each member's type in the wrong module: docs/backends.md, 'Immediates on OpenGL')",
}


def immediates_rule(adapter: AdapterFacts) -> tuple[bool, str]:
    """Whether a device's immediates can be used, and why: offered, and not on a backend known to lose them."""
    if "immediates" not in adapter.features:
        return False, "the device lacks 'immediates': material factors come from a uniform buffer slice per draw"
    broken = UNTRUSTED_IMMEDIATES.get(adapter.backend)
    if broken:
        return False, (f"the {adapter.backend} adapter offers 'immediates', but {broken}; material factors come "
                       "from a uniform buffer slice per draw")
    return True, "the device offers 'immediates': material factors are pushed per draw"


def resolve_immediates(knobs: Knobs) -> tuple[str, str]:
    if knobs.immediates != "auto":
        return knobs.immediates, "knob immediates"
    if knobs.adapter is None:
        return "auto", ("material factors pushed as immediates when the device offers the 'immediates' feature, "
                        "else read from a uniform buffer slice per draw")
    on, why = immediates_rule(knobs.adapter)
    return ("on" if on else "off"), why


def _fusion_text(group: tuple[EffectStep, ...]) -> str:
    if len(group) < 2:
        return ""
    pixel = [s.effect for s in group if s.spec.fusable]
    head = group[0] if not group[0].spec.fusable else None
    verb = "reads only the pixel it writes" if len(pixel) == 1 else "each read only the pixel they write"
    runs = "it runs as a function" if len(pixel) == 1 else "they run as functions"
    why = f"{', '.join(pixel)} {verb}, so {runs} in one shader"
    if head is not None:
        why += f" on the pixel {head.effect} just computed ({head.effect} reads neighbours, so it starts the pass)"
    return why + f"; saves {len(group) - 1} write and read of the whole image"


def plan_post_passes(steps: list[EffectStep], fuse: bool, path: str, scene_target: str, scene_fmt: str, out_fmt: str,
                     size: tuple[int, int], output_storage: bool = True, output_twin: bool = True,
                     intermediate: str = "auto") -> tuple[list[PostPass], list[Attachment]]:
    """The chain's passes and the attachments only they use (ping-pong intermediates, FXAA mask, scratch).

    ``output_storage``: whether the output texture can be bound as a storage texture (an offscreen target
    can; a swapchain image cannot), which decides how a compute pass writes it. ``output_twin``: whether the
    renderer makes the output texture from the plan, so it may be the storage twin of an -srgb format (a
    texture the caller made already has its format: it is written through a scratch and a copy).
    ``intermediate``: the knob post_intermediate (:func:`intermediate_note`)."""
    groups = group_passes(steps, fuse)
    preludes = [0] * len(groups)
    if intermediate == "none":
        groups, preludes = recomputed_groups(groups)
    n = len(groups)
    temp_fmt = scene_fmt
    notes_all: list[str] = []
    if intermediate not in ("auto", "none"):
        if n < 2:
            raise UserError(f"post_intermediate = {intermediate}: this post chain runs as {n} pass and stores no "
                            "image between passes; drop the knob (or post_fuse = off to split the chain)")
        temp_fmt = intermediate
        notes_all.append(intermediate_note(intermediate))
    elif path == "compute" and scene_fmt not in STORAGE_FORMATS and n > 1:
        temp_fmt = HDR_FORMAT
        notes_all.append(f"{scene_fmt} cannot be a storage texture: the compute path's intermediates are {HDR_FORMAT}")
    temps = ["post_a", "post_b"][:min(max(n - 1, 0), 2)]
    attachments = []
    for i, name in enumerate(temps):
        users = [j for j in range(n - 1) if j % 2 == i]
        attachments.append(Attachment(name, "post-intermediate", temp_fmt, size, 1, (
            "written by " + ", ".join(f"post pass {j + 1} ({'+'.join(s.effect for s in groups[j])})" for j in users)
            + " and read by the next pass (ping-pong)",) + tuple(notes_all)))
    pixels = size[0] * size[1]
    passes = []
    for i, group in enumerate(groups):
        last = i == n - 1
        src_name = scene_target if i == 0 else temps[(i - 1) % 2]
        src_fmt = scene_fmt if i == 0 else temp_fmt
        dst_name, dst_fmt = ("output", out_fmt) if last else (temps[i % 2], temp_fmt)
        notes = [n for s in group for n in step_notes(s, src_fmt, dst_fmt)]
        pass_path, copy_to, mask = path, None, None
        copy_format = twin_of = None
        writes_output = dst_name == "output"
        if path == "compute" and writes_output and output_storage and output_twin and dst_fmt in STORAGE_TWINS:
            twin_of, dst_fmt = dst_fmt, STORAGE_TWINS[dst_fmt]
            notes.append(f"{twin_of} cannot be a storage texture: the output texture is its {dst_fmt} twin, which "
                         f"the shader writes with the sRGB curve applied (the bytes of {twin_of}), read back as it "
                         "is: no scratch, no copy")
        if path == "compute" and (dst_fmt not in STORAGE_FORMATS or (writes_output and not output_storage)):
            scratch = dst_fmt if dst_fmt in STORAGE_FORMATS else ("rgba8unorm" if dst_fmt.startswith("rgba8") else None)
            why = (f"{dst_fmt} cannot be a storage texture" if dst_fmt not in STORAGE_FORMATS else
                   "the output texture is not a storage texture (a swapchain image: knob output_storage = off)")
            if scratch is not None:
                copy_to, copy_format, dst_name, dst_fmt = dst_name, dst_fmt, "post_scratch", scratch
                encoded = " with the sRGB curve applied" if scratch != copy_format else ""
                notes.append(f"{why}: the shader writes {scratch}{encoded}, then the image is copied into "
                             f"{copy_to} (same bytes)")
                attachments.append(Attachment("post_scratch", "post-scratch", scratch, size, 1, (
                    f"post pass {i + 1} on the compute path writes it; copied into {copy_to} ({why})",)))
            else:
                pass_path = "fragment"
                notes.append(f"{why}: this pass stays a fragment pass")
        head = group[0].spec
        if pass_path == "fragment" and head.mask_format:
            mask = f"{head.name}_mask"
            attachments.append(Attachment(mask, "post-mask", head.mask_format, size, 1, (
                f"post pass {i + 1} {head.name}: draw 1 marks edge pixels in depth, draw 2 runs the full "
                f"{head.name} depth-tested on edges only (wgpurender/wgpu_path/post/shaders.py says why)",)))
        read = pixels * BYTES_PER_PIXEL[src_fmt]
        written = pixels * BYTES_PER_PIXEL[dst_fmt]
        if mask:
            written += pixels * BYTES_PER_PIXEL[head.mask_format]
            read += pixels * BYTES_PER_PIXEL[head.mask_format]
        if copy_to:
            read += pixels * BYTES_PER_PIXEL[dst_fmt]
            written += pixels * BYTES_PER_PIXEL[copy_format]
        fusion = _recompute_text(group, preludes[i]) if preludes[i] else _fusion_text(group)
        shape, shape_why, tile = (dispatch_shape(dst_fmt, not head.fusable, preludes[i] > 0)
                                  if pass_path == "compute" else (None, "", ""))
        passes.append(PostPass(i, group, src_name, dst_name, src_fmt, dst_fmt, pass_path, fusion,
                               tuple(notes), mask, copy_to, read, written, copy_format=copy_format, twin_of=twin_of,
                               prelude=preludes[i], shape=shape, shape_why=shape_why, tile=tile))
    return passes, attachments


# Neighbourhood effects whose shader reads its input only through fxaa_texel / fxaa_sample
# (shaders_wgsl/post_fxaa.wgsl), so the per-pixel effects before it can be recomputed for every texel it reads
# (knob post_intermediate = none), and its texels can come from a workgroup tile on the compute path
# (core/plan/dispatch.py).
RECOMPUTING_READERS = ("fxaa",)


def recomputed_groups(groups: list[tuple[EffectStep, ...]]) -> tuple[list[tuple[EffectStep, ...]], list[int]]:
    """Knob post_intermediate = none: a pass of per-pixel effects followed by an FXAA pass become one pass, whose
    first ``prelude`` steps are applied to every texel FXAA reads (its bilinear taps computed in the shader from
    four such texels) instead of being stored in an image between the passes."""
    out: list[tuple[EffectStep, ...]] = []
    preludes: list[int] = []
    for group in groups:
        if (out and group[0].effect in RECOMPUTING_READERS and not preludes[-1]
                and all(s.spec.fusable for s in out[-1])):
            preludes[-1] = len(out[-1])
            out[-1] = out[-1] + group
        else:
            out.append(group)
            preludes.append(0)
    if not any(preludes):
        raise UserError("post_intermediate = none: no per-pixel effect comes before an FXAA pass, so no image "
                        "between passes can be recomputed instead of stored; drop the knob")
    return out, preludes


def _recompute_text(group: tuple[EffectStep, ...], prelude: int) -> str:
    head = group[prelude].effect
    before = ", ".join(s.effect for s in group[:prelude])
    return (f"knob post_intermediate = none: {before} recomputed for every texel {head} reads (its bilinear taps "
            f"computed in the shader), instead of stored in an image between two passes")


def intermediate_note(fmt: str) -> str:
    """Why the knob post_intermediate's format stores the chain between passes, and what it costs."""
    measured = "; its error against float64 is measured in tests/test_post_intermediate.py"
    if fmt == "rgba8unorm":
        return ("knob post_intermediate = rgba8unorm: the values between passes are stored in 8 bits, linear (steps "
                "of 1/255, coarse in the darks; values above 1 clip): half the bytes of rgba16float" + measured)
    if fmt == "rgba8unorm-srgb":
        return ("knob post_intermediate = rgba8unorm-srgb: the values between passes are stored in 8 bits, "
                "sRGB-encoded (decoded before filtering; values above 1 clip): half the bytes of rgba16float"
                + measured)
    return f"knob post_intermediate = {fmt}: the values between passes are stored as {fmt}"


def post_pipelines_of(passes: list[PostPass]) -> tuple[PostPipeline, ...]:
    out: list[PostPipeline] = []
    for p in passes:
        if p.path == "compute":
            out.append(PostPipeline(p.effect, "compute", "cs_main", p.output_format))
        elif p.mask:
            depth = p.steps[0].spec.mask_format
            out.append(PostPipeline(p.effect, "fragment", "fs_mark", p.output_format, depth))
            out.append(PostPipeline(p.effect, "fragment", "fs_main", p.output_format, depth))
        else:
            out.append(PostPipeline(p.effect, "fragment", "fs_main", p.output_format))
    return tuple(dict.fromkeys(out))
