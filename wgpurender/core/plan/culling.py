"""Frustum culling: which instanced draws the GPU culls, decided by their instance count.

A culled draw (``ScenePipeline.culled``) is drawn with ``draw_indexed_indirect``: when the camera changes (the
objects are static: the first frame, a resize, an orbit step; a still camera costs nothing) a compute pass tests
every instance's bounding sphere (the mesh's, moved and scaled by the instance's world matrix) against the six
planes of the camera's frustum and appends the index of each instance that may be seen to a ``visible`` list,
counting them into the indirect draw's ``instance_count``; the vertex shader reads ``objects[visible[i]]``.

Small draws are not culled: the rasteriser already drops triangles outside the view, and below
:data:`GPU_CULL_MIN` instances a compute dispatch, a buffer reset and an indirect draw cost more than the
vertices they save (the CPU-side alternative, a test per instance per frame in Python, is the per-object cost
instancing removed). The ``culling`` knob: "auto" (this rule), "gpu" (every instanced draw), "cpu" (every
instanced draw, on the CPU), "off".

Without a GPU pass (per-instance vertex attributes, core/plan/instance_data.py, or no compute) the same test runs
on the CPU in numpy (setting "cpu"). The GPU pass needs the device feature ``indirect-first-instance`` (each
culled draw's visible list starts at its ``first_instance``). The raw-Vulkan reference path draws every instance
of a culled draw: culling changes no pixel, which tests/test_culling.py checks against the unculled render.
"""

from __future__ import annotations

import dataclasses

from wgpurender.core.errors import UserError

GPU_CULL_MIN = 16_384
CULLING = ("auto", "gpu", "cpu", "off")
FEATURE = "indirect-first-instance"


def decide(draws: list, pipelines: dict, knob: str, features: frozenset[str] | None,
           instance_data: str = "storage", compute: bool = True) -> tuple[list, str, str]:
    """(draws with culled pipelines where culled, the setting, why); registers the culled pipelines.

    The GPU pass writes a visible list the vertex shader reads from storage and needs compute: with per-instance
    vertex attributes (``instance_data`` "vertex") or without compute, the large draws are culled on the CPU
    instead (:func:`cpu_culled`), and the knob "gpu" is refused."""
    if knob == "off":
        return draws, "off", "knob culling = off: every instance is drawn"
    least = GPU_CULL_MIN if knob == "auto" else 2
    if not any(d.instance_count >= least for d in draws):
        return draws, "off", _rule(knob) + "; no draw qualifies"
    if knob == "cpu" or instance_data == "vertex" or not compute:
        return cpu_culled(draws, knob, least, instance_data)
    if features is not None and FEATURE not in features:
        return draws, "off", f"the device lacks '{FEATURE}' (a culled draw's visible list starts at its first instance)"
    out, culled = [], []
    for d in draws:
        pipeline = pipelines[d.pipeline_key]
        if d.instance_count >= least and not pipeline.blend:
            wanted = dataclasses.replace(pipeline, culled=True)
            pipelines.setdefault(wanted.key, wanted)
            d = dataclasses.replace(d, pipeline_key=wanted.key)
            culled.append(_named(d))
        out.append(d)
    used = {d.pipeline_key for d in out}
    for key in [k for k in pipelines if k not in used]:  # a pipeline every user of which is now culled
        del pipelines[key]
    return out, "gpu", f"{_rule(knob)}: {', '.join(culled)} (the raw path draws every instance: the same pixels)"


def cpu_culled(draws: list, knob: str, least: int, instance_data: str) -> tuple[list, str, str]:
    """The draws of at least ``least`` instances marked ``cpu_culled``: when the camera moves, numpy tests each
    instance's bounding sphere against the frustum and the visible instances' blocks are written, packed, where
    the draw's instances start (wgpu_path/scene/cpu_culling.py); the draw then draws that many."""
    why = ("instances reach the vertex shader as vertex attributes, so no shader reads a visible list"
           if instance_data == "vertex" else "the device runs no compute shaders")
    if knob == "gpu":
        raise UserError(f"culling = gpu cannot apply here: {why}; use culling = auto or cpu (the CPU culls) or off")
    out = [dataclasses.replace(d, cpu_culled=True) if d.instance_count >= least else d for d in draws]
    named = ", ".join(_named(d) for d in out if d.cpu_culled)
    rule = ("knob culling = cpu: every instanced draw is culled on the CPU" if knob == "cpu" else
            f"auto: draws of at least {GPU_CULL_MIN} instances are culled on the CPU ({why}; the GPU pass needs "
            "both a storage visible list and compute)")
    return out, "cpu", f"{rule}: {named} (the raw path draws every instance: the same pixels)"


def _named(d) -> str:
    return f"{d.label.split(' + ')[0]} ({d.instance_count} instances)"


def _rule(knob: str) -> str:
    return "knob culling = gpu: every instanced draw" if knob == "gpu" else (
        f"auto: draws of at least {GPU_CULL_MIN} instances are culled on the GPU, smaller ones not at all (the "
        "rasteriser drops what is outside the view; a compute pass would cost more than it saves)")
