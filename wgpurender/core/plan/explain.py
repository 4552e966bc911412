"""The render plan as text: every pass, attachment, pipeline, texture and knob, each with what asked for it.

This is what ``wgpurender render SCENE.toml --explain`` and ``python -m wgpurender.core.plan SCENE.toml`` print.
"""

from __future__ import annotations

import os
from typing import Any

from wgpurender.core.plan import gpu_memory

# No import of .model: RenderPlan.explain() calls this module, so it reads the plan's passes by their ``kind``.


def playback_lines(plan: Any) -> list[str]:
    """What the window plays (core/scene/playback.py): one line per animated model, none for a still scene."""
    if not plan.playing:
        return []
    from wgpurender.core.scene.playback import describe

    return describe(plan.playing, plan.scene)


def explain(plan: Any) -> str:
    """Passes, attachments, pipelines, textures and samplers, each with what asked for it."""
    w, h = plan.size
    out = [f"scene: {plan.scene_path}", f"output: {w}x{h} {plan.output_format}, msaa {plan.msaa}",
           f"memory: {gpu_memory.describe(gpu_memory.plan_bytes(plan))}"]
    if plan.camera_note:
        out.append(f"camera: {plan.camera_note}")
    out.extend(f"animation: {line}" for line in playback_lines(plan))
    out.append("")
    out.append("knobs:")
    for knob, value, why in plan.settings:
        out.append(f"  {knob}: {value} <- {why}")
    out.append("")
    out.append("passes:")
    adapter = plan.knobs.adapter.name if plan.knobs.adapter is not None else None
    for i, p in enumerate(plan.passes, start=1):
        out.extend(_explain_pass(i, p, plan.size))
        out.append("       " + _measured(plan, p, adapter))
    out.append("")
    out.append("attachments:")
    for a in plan.attachments:
        samples = f"{a.sample_count} sample{'s' if a.sample_count > 1 else ''}"
        out.append(f"  {a.name}: {a.format}, {a.size[0]}x{a.size[1]}, {samples} ({a.role})")
        out.extend(f"      <- {r}" for r in a.reasons)
    out.append("")
    out.append("scene pipelines:" if plan.pipelines else "scene pipelines: none (no models)")
    for pl in plan.pipelines:
        v = pl.variant
        out.append(f"  {pl.key}")
        out.append(f"      vertex attributes: {', '.join(v.vertex_attributes)}")
        if not v.reasons:
            out.append("      features: none (flat colour, unlit)")
        for feature, why in v.reasons:
            out.append(f"      {feature}: {why}")
        users = [d.label for d in plan.scene_pass.draws if d.pipeline_key == pl.key]
        out.append(f"      used by: {', '.join(users)}")
    out.append("post pipelines:" if plan.post_pipelines else "post pipelines: none")
    out.extend(f"  {pl.key}" for pl in plan.post_pipelines)
    out.append("")
    out.append("textures:" if plan.textures else "textures: none")
    for t in plan.textures:
        mips = "with mipmaps" if t.mipmaps else "no mipmaps"
        shown = os.path.relpath(t.path, plan.scene_path.parent)
        out.append(f"  {shown} as {t.format}, {mips} <- {'; '.join(t.used_by)}")
    if plan.mipmap_formats:
        out.append("mipmap pipelines: " + ", ".join(plan.mipmap_formats)
                   + " (one render pipeline per format generates every mip chain of that format)")
    out.append("samplers:" if plan.samplers else "samplers: none")
    for s in plan.samplers:
        spec = s.spec
        out.append(
            f"  filter {spec.min_filter}/{spec.mag_filter}, mipmap {spec.mipmap_filter}, "
            f"address {spec.address_mode_u}, anisotropy {spec.max_anisotropy} <- {'; '.join(s.used_by)}"
        )
    filtering = [p.effect for p in plan.post_passes if p.steps[0].spec.filtering]
    if filtering:
        out.append(f"  post-linear-clamp (linear, clamp to edge) <- {', '.join(filtering)} samples between pixels")
    out.append("")
    out.append("buffers:")
    out.extend(f"  {name}: {what}" for name, what in plan.buffers)
    out.append("")
    out.extend(_explain_objects(plan))
    if plan.absent:
        out.append("")
        out.append("left out:")
        out.extend(f"  {what}: none <- {why}" for what, why in plan.absent)
    if plan.notes:
        out.append("")
        out.append("notes:")
        out.extend(f"  - {n}" for n in plan.notes)
    return "\n".join(out) + "\n"


def _explain_objects(plan: Any) -> list[str]:
    """Every object the wgpu renderer creates, per device call, each with why (core/plan/objects.py)."""
    objects = plan.objects
    kinds = list(dict.fromkeys(o.kind for o in objects))
    head = ("objects the wgpu renderer creates (device.create_* calls; the caller's are not listed: the output "
            "texture, the frame's command encoder and readback, a benchmark's timestamp query set):")
    out = [head if objects else head[:-1] + ": none, the scene pass only clears"]
    for kind in kinds:
        mine = [o for o in objects if o.kind == kind]
        out.append(f"  {kind}: {sum(o.count for o in mine)}")
        out.extend(f"      {o.name}{f' x{o.count}' if o.count > 1 else ''} <- {o.reason}" for o in mine)
    return out


def _megabytes(n: int) -> str:
    return f"{n / 1e6:.1f} MB"


def _explain_pass(number: int, p: Any, size: tuple[int, int]) -> list[str]:
    if p.kind == "scene":
        into = f"{p.color} resolved into {p.resolve_target}" if p.resolve_target else p.color
        depth = f", depth attachment {p.depth}" if p.depth else ""
        clear = ", ".join(f"{c:g}" for c in p.clear_color)
        if not p.draws:
            return [f"  {number}. scene: clear {into} to ({clear}), nothing to draw (no models)"]
        instances = sum(d.instance_count for d in p.draws)
        what = f"{instances} object(s) in {len(p.draws)} draw(s)"
        lines = [f"  {number}. scene: draw {what} into {into}{depth}, clear ({clear})"]
        for d in p.draws:
            who = d.label if d.material_label == d.label else f"{d.label}: {d.material_label}"  # file materials: once
            lines.append(f"       {who}, variant {d.variant_key}")
            lines.append(f"         material factors: {d.factors_text()}")
            if d.batch:
                lines.append(f"         batch: instances {d.first_instance}..{d.first_instance + d.instance_count - 1}"
                             f" <- {d.batch}")
        return lines
    steps = " + ".join(s.label() for s in p.steps)
    into = f"{p.output} ({p.output_format})" + (f", copied into {p.copy_to}" if p.copy_to else "")
    lines = [f"  {number}. post {steps} [{p.path}]: {p.input} ({p.input_format}) -> {into}"]
    lines.extend(f"       <- {s.asked_by}" for s in p.steps)
    if p.fusion:
        lines.append(f"       fused: {p.fusion}")
    if p.mask:
        lines.append(f"       mask: {p.mask} (depth test skips blocks without an edge pixel)")
    if p.shape:
        lines.append(f"       dispatch: workgroups of {p.shape[0]}x{p.shape[1]}, {p.shape[2]} row(s) per invocation "
                     f"({p.shape_why})")
    lines.append(f"       bytes: {_megabytes(p.bytes_read)} read + {_megabytes(p.bytes_written)} written = "
                 f"{_megabytes(p.bytes_moved)} at {size[0]}x{size[1]} (each texel once)")
    lines.extend(f"       note: {n}" for n in p.notes)
    return lines


def scene_pass_bytes(plan: Any) -> tuple[int, int]:
    """(bytes the scene pass must write: its stored image, bytes it reads at most: every texture level once)."""
    from wgpurender.core.course.formats import BYTES_PER_PIXEL

    sp = plan.scene_pass
    w, h = plan.size
    stored = sp.resolve_target or sp.color
    fmt = next(a.format for a in plan.attachments if a.name == stored) if stored != "output" else plan.output_format
    written = w * h * BYTES_PER_PIXEL.get(fmt, 4)
    read = 0
    for t in plan.textures:
        if t.size is not None:
            chain = 4 / 3 if t.mipmaps else 1.0
            read += int(t.size[0] * t.size[1] * BYTES_PER_PIXEL.get(t.format, 4) * chain)
    return written, read


def _measured(plan: Any, p: Any, adapter: str | None) -> str:
    """The pass's bytes (the scene pass's; a post pass lists its own above) and the last measurement here."""
    from wgpurender.core.files import bandwidth

    size = f"{plan.size[0]}x{plan.size[1]}"
    if p.kind == "scene":
        written, read = scene_pass_bytes(plan)
        head = (f"bytes: {_megabytes(written)} written (the stored image) + up to {_megabytes(read)} of textures "
                f"read; ")
        key = bandwidth.pass_key(plan.scene_path.stem, "scene", "render")
        measure = "wgpurender bench perf --only scene (at the bench's own sizes)"
    else:
        head = ""
        key = bandwidth.pass_key(plan.scene_path.stem, p.effect, p.path)
        measure = f"wgpurender bench post-roofline SCENE --size {size}"  # SCENE: the first line's file
    if adapter is None:
        return head + "bandwidth: not measured (no adapter known to this plan)"
    found = bandwidth.lookup(adapter, key)
    if found is None or found.size != size:  # a measurement at another size is not this plan's
        return head + f"bandwidth: not measured at {size} on {adapter} (`{measure}` measures it)"
    return head + "bandwidth: " + found.text()
