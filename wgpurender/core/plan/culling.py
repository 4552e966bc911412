"""Frustum culling: which instanced draws the GPU culls, decided by their instance count.

A culled draw (``ScenePipeline.culled``) is drawn with ``draw_indexed_indirect``: when the camera changes (the
objects are static: the first frame, a resize, an orbit step; a still camera costs nothing) a compute pass tests
every instance's bounding sphere (the mesh's, moved and scaled by the instance's world matrix) against the six
planes of the camera's frustum and appends the index of each instance that may be seen to a ``visible`` list,
counting them into the indirect draw's ``instance_count``; the vertex shader reads ``objects[visible[i]]``.

Small draws are not culled: the rasteriser already drops triangles outside the view, and below
:data:`GPU_CULL_MIN` instances a compute dispatch, a buffer reset and an indirect draw cost more than the
vertices they save (the CPU-side alternative, a test per instance per frame in Python, is the per-object cost
instancing removed). The ``culling`` knob: "auto" (this rule), "gpu" (every instanced draw), "off".

Needs the device feature ``indirect-first-instance`` (each culled draw's visible list starts at its
``first_instance``). The raw-Vulkan reference path draws every instance of a culled draw: culling changes no
pixel, which tests/test_culling.py checks against the unculled render.
"""

from __future__ import annotations

import dataclasses

GPU_CULL_MIN = 16_384
CULLING = ("auto", "gpu", "off")
FEATURE = "indirect-first-instance"


def decide(draws: list, pipelines: dict, knob: str, features: frozenset[str] | None) -> tuple[list, str, str]:
    """(draws with culled pipelines where culled, the setting, why); registers the culled pipelines."""
    if knob == "off":
        return draws, "off", "knob culling = off: every instance is drawn"
    least = 2 if knob == "gpu" else GPU_CULL_MIN
    if features is not None and FEATURE not in features and any(d.instance_count >= least for d in draws):
        return draws, "off", f"the device lacks '{FEATURE}' (a culled draw's visible list starts at its first instance)"
    out, culled = [], []
    for d in draws:
        pipeline = pipelines[d.pipeline_key]
        if d.instance_count >= least and not pipeline.blend:
            wanted = dataclasses.replace(pipeline, culled=True)
            pipelines.setdefault(wanted.key, wanted)
            d = dataclasses.replace(d, pipeline_key=wanted.key)
            culled.append(f"{d.label.split(' + ')[0]} ({d.instance_count} instances)")
        out.append(d)
    used = {d.pipeline_key for d in out}
    for key in [k for k in pipelines if k not in used]:  # a pipeline every user of which is now culled
        del pipelines[key]
    rule = "knob culling = gpu: every instanced draw" if knob == "gpu" else (
        f"auto: draws of at least {GPU_CULL_MIN} instances are culled on the GPU, smaller ones not at all (the "
        "rasteriser drops what is outside the view; a compute pass would cost more than it saves)")
    if not culled:
        return out, "off", rule + "; no draw qualifies"
    return out, "gpu", f"{rule}: {', '.join(culled)} (the raw path draws every instance: the same pixels)"
