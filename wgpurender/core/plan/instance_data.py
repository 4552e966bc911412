"""Where the vertex shader finds each instance's data (world matrix, normal matrix, mirror sign), per adapter.

Two ways, the same 128-byte Object block per instance (core/plan/batches.py packs it once for both):

- ``storage``: one read-only storage buffer read at ``instance_index`` (the course's descriptor-set way; the GPU
  culling pass writes a list of visible indices the shader reads through it).
- ``vertex``: a second vertex buffer with step mode "instance" (Vulkan's ``VK_VERTEX_INPUT_RATE_INSTANCE``, the
  learn-wgpu instancing chapter): the world matrix's four columns, the normal matrix's three and the mirror sign
  are vertex attributes that advance once per instance, starting at the draw's ``first_instance``. It needs no
  storage buffer in the vertex stage, so it runs where wgpu lacks ``DownlevelFlags::VERTEX_STORAGE``.

The "auto" rule: ``vertex`` on OpenGL and wherever the adapter offers no storage buffers at all
(``max-storage-buffers-per-shader-stage`` 0, GLES 3.0, or a GL context whose GLSL naga cannot give storage:
:func:`wgpurender.core.plan.gl_facts.glsl_allows`), ``storage`` elsewhere. On GL the vertex stage's own
storage-buffer count is hidden: wgpu-hal reports the fragment stage's limit when the vertex stage has none
(gles/adapter.rs), wgpu-py 0.32 exposes no downlevel flags, and NVIDIA's EGL context (driver 580: exactly GL 3.3)
failed every scene with naga's "The selected version doesn't support BUFFER_STORAGE" while llvmpipe's GL 4.5 did not
(docs/backends.md, "Instance data on OpenGL"). Both ways give the same pixels (tests/test_instance_data.py); on the
H100's Vulkan the vertex way took 2.5-3x the GPU time (docs/perf-h100/2026-11-27-glinst), so it is used only where it
must be.
"""

from __future__ import annotations

from wgpurender.core.errors import UserError

INSTANCE_DATA = ("auto", "storage", "vertex")
HIDDEN_VERTEX_STORAGE = {
    "OpenGL": "wgpu's GL backend hides whether the vertex stage has storage buffers (wgpu-hal reports the "
              "fragment stage's limit when the vertex stage has none, and wgpu-py 0.32 exposes no downlevel flags); "
              "NVIDIA's EGL context (GL 3.3) failed every scene with naga's \"The selected version doesn't support "
              "BUFFER_STORAGE\"",
}


def resolve_instance_data(knob: str, adapter) -> tuple[str, str]:
    """(``storage`` or ``vertex``, why) for ``adapter`` (an AdapterFacts, or None when not known yet)."""
    if adapter is not None and knob == "storage" and not adapter.storage:
        raise UserError(f"instance_data = storage cannot run on {adapter.name or adapter.backend or 'this adapter'}: "
                        "it offers no storage buffers (max-storage-buffers-per-shader-stage is 0, or a GL context "
                        "below 4.0); use instance_data = vertex or auto")
    if knob != "auto":
        return knob, f"knob instance_data: {_WAYS[knob]}"
    if adapter is None:
        return "storage", f"adapter not known yet: {_WAYS['storage']} (the renderer re-plans for its adapter)"
    if not adapter.storage:
        return "vertex", (f"{_WAYS['vertex']}: the {adapter.backend or 'adapter'} device offers no storage buffers "
                          "(max-storage-buffers-per-shader-stage is 0, or a GL context below 4.0)")
    hidden = HIDDEN_VERTEX_STORAGE.get(adapter.backend)
    if hidden:
        return "vertex", f"{_WAYS['vertex']}: {hidden}"
    return "storage", f"{_WAYS['storage']}: the {adapter.backend or 'adapter'} device reads storage buffers in " \
                      "every stage"


def fit_binding(way: str, why: str, knob: str, instances: int, block_bytes: int, adapter) -> tuple[str, str]:
    """The way again once the draws are known: ``storage`` binds every instance's Object block in one storage
    binding (the vertex stage's, and the GPU culling pass's), which may not pass the device's
    max-storage-buffer-binding-size (128 MiB on lavapipe: 1,048,576 blocks). Past it, "auto" takes ``vertex`` (a
    vertex buffer has only max-buffer-size, and the culling is then the CPU's) and ``storage`` asked for is refused
    in one line. ``block_bytes``: one Object block's (core/plan/batches.py); ``adapter``: AdapterFacts, whose limit
    None (not known) leaves the way as it was."""
    limit = getattr(adapter, "max_storage_binding", None)
    need = instances * block_bytes
    if way != "storage" or limit is None or need <= limit:
        return way, why
    over = (f"{instances} instances' Object blocks ({need} bytes) pass the device's max-storage-buffer-binding-size "
            f"({limit} bytes)")
    if knob == "storage":
        raise UserError(f"instance_data = storage: {over}; use instance_data = vertex or auto, or fewer copies")
    return "vertex", f"{_WAYS['vertex']}: {over}"


_WAYS = {
    "storage": "every instance's Object block in one storage buffer, read at instance_index",
    "vertex": "every instance's Object block in a vertex buffer stepped per instance (world, normal matrix and "
              "mirror as instance attributes): no storage buffer in the vertex stage",
}
