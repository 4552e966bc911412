"""The scene renderer: a scene file (core/scene/) drawn exactly as its render plan (core/plan/) says.

Public API:

- :func:`render_plan` ``(ctx, plan, t=0.0) -> RenderResult``: headless, a plan resolved by
  :func:`wgpurender.core.plan.resolve_plan` for ``ctx.adapter_facts()`` (what ``wgpurender render SCENE.toml``
  and the API call); :func:`render_scene_file` ``(path, size=None, fmt=None, msaa=None, t=0.0, ctx=None)``
  resolves and renders in one call;
- :func:`scene_drawable_factory` ``(path, ctx, msaa=None) -> make(fmt) -> SceneRenderer``: for the window;
- :class:`SceneRenderer` ``(ctx, scene, plan)``: ``resize(size)``, ``record(encoder, target, t, timer=None)``;
  :func:`load_renderer` makes one from a file;
- :func:`shader_source` ``(variant, immediates) -> str``: the specialised WGSL of a plan's variant.

Modules, one idea each: ``shader_interface`` (what the shader and Python agree on: uniform structs, vertex
layouts, bindings, the WGSL variant), ``resources``
(meshes, buffers, textures, samplers), ``scene_pass`` (pipelines, UBOs, bind groups, the scene pass),
``frame`` (attachments, the post chain, a whole frame).

A model without a scene material draws with its file's own materials (a glTF's, an OBJ's MTL), read once
when the scene loads (core/scene/file_materials.py); the plan reads them from the scene model and never opens a
model file, and the renderer draws only what the plan lists (docs/scenes.md).
"""

from wgpurender.wgpu_path.scene.frame import (
    SceneRenderer,
    load_renderer,
    render_frame,
    render_plan,
    render_scene_file,
    scene_drawable_factory,
)
from wgpurender.wgpu_path.scene.shader_interface import shader_source

__all__ = [
    "SceneRenderer",
    "load_renderer",
    "render_frame",
    "render_plan",
    "render_scene_file",
    "scene_drawable_factory",
    "shader_source",
]
