"""What each course step asks a learner to write, and the classic mistakes it can go wrong with: data, one row each.

An exercise is the project's own stage (the reference solution) with parts cut out. Both the cut-out parts and the
mistakes are declared here as exact snippets of the solution's source (``old`` -> ``new``), never as copies of it:

- a :class:`Part` is what the learner writes. The starter replaces ``old`` with ``stub`` (code that keeps the
  stage running, usually nothing but a comment) under a TODO line that paraphrases the course and names the
  concept's row of ``wgpurender concepts``;
- a :class:`Mistake` is the solution with ``old`` replaced by ``new``: rendered the same way as a learner's file,
  it is what that mistake looks like, and ``wgpurender check`` names the nearest one.

tests/test_exercises.py checks every snippet occurs exactly once in its stage, every starter fails, the solution
passes, every mistake is diagnosed as itself and no two mistakes of a step look alike. A new mistake is one row.

Mistakes left out because they do not render differently (say so here, not silently):
- step 1a (wgpu): forgetting the clear is invisible, WebGPU zero-fills new textures and the transfer clear is to
  zero; 3b: ``store_op`` store instead of discard keeps the same resolved image; 4: the depth test off (compare
  always) draws the same cubes, which back-face culling already sorts and which do not overlap; 5: the uv attribute
  at offset 8 rendered identical to the solution at both times (measured, FLIP 0).
- mistakes wgpu refuses with a validation error (the learner sees wgpu's message, which names the fault): 2b's
  wrong vertex stride, attribute format or an offset past the stride (wgpu checks them against the buffer and
  the shader).
"""

from __future__ import annotations

from typing import NamedTuple

PATHS = ("wgpu", "raw")


class Part(NamedTuple):
    """A piece of the solution the learner writes."""

    concept: str  # a row name of `wgpurender concepts` (wgpurender/concepts.py)
    todo: str  # what to write, paraphrasing the course (one line)
    old: str  # the solution's exact text (whole lines)
    stub: str = ""  # what stands there in the starter (whole lines, indented like ``old``); empty: nothing


class Mistake(NamedTuple):
    """A classic mistake: the solution with one snippet changed."""

    key: str  # short id, unique within its step and path (used in file names)
    title: str  # what the learner did, as the diagnosis names it
    concept: str  # the row of `wgpurender concepts` to read
    old: str
    new: str


class Exercise(NamedTuple):
    step: str  # the course step's number (core/course/steps.py)
    path: str  # "wgpu" or "raw"
    parts: tuple[Part, ...]
    mistakes: tuple[Mistake, ...]
    times: tuple[float, ...] = (0.0,)  # animated steps are checked at several t
    shader: str = ""  # a scene step: the shader file the learner writes (else: a stage module)
    scene: str = ""  # ... and the bundled scene it is checked with (a committed scene reference's)

    @property
    def comment(self) -> str:
        """How the learner's file writes a comment line."""
        return "//" if self.shader else "#"


_W, _R = "wgpu", "raw"
_ANIMATED = (0.0, 0.75)
# the raw path's y-flip mistake: the viewport set as Vulkan's default (y down) after the helper's flipped one
_UNFLIPPED = ("        set_viewport_and_scissor(cmd, self.size)\n"
              "        vk.vkCmdSetViewport(cmd, 0, 1, [vk.VkViewport(x=0.0, y=0.0, width=float(self.size[0]), "
              "height=float(self.size[1]), minDepth=0.0, maxDepth=1.0)])\n")

EXERCISES: tuple[Exercise, ...] = (
    Exercise("1a", _W, (
        Part("clear without a render pass", "clear the whole target with a transfer command, outside any pass",
             "        clear_texture(self.ctx, encoder, target)\n",
             "        placeholder = self.color_attachment(target, (1, 0, 1, 1))\n"
             "        encoder.begin_render_pass(color_attachments=[placeholder]).end()\n"),
    ), ()),
    Exercise("1b", _W, (
        Part("begin info and clear values", "begin a pass whose attachment is cleared to the step's colour, then end",
             "        render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, "
             "self.clear_color)])\n        render_pass.end()\n"),
    ), (
        Mistake("load", "the attachment loaded instead of cleared (load_op load)", "begin info and clear values",
                "render_pass = encoder.begin_render_pass(color_attachments=[self.color_attachment(target, "
                "self.clear_color)])",
                "render_pass = encoder.begin_render_pass(color_attachments=[{**self.color_attachment(target, "
                "self.clear_color), 'load_op': 'load'}])"),
        Mistake("bytes", "the clear colour given in 0..255 instead of 0..1", "begin info and clear values",
                "self.color_attachment(target, self.clear_color)",
                "self.color_attachment(target, tuple(255 * c for c in self.clear_color))"),
    )),
    Exercise("2a", _W, (
        Part("draw calls", "bind the pipeline and draw the three vertices the shader makes from the vertex index",
             "        render_pass.set_pipeline(self.pipeline)\n        render_pass.draw(3)\n"),
    ), (
        Mistake("background", "the clear colour left out (the attachment's default)", "begin info and clear values",
                "self.color_attachment(target, BACKGROUND)", "self.color_attachment(target, (1, 1, 1, 1))"),
        Mistake("count", "nothing drawn (no draw, or fewer than 3 vertices)", "draw calls",
                "render_pass.draw(3)", "render_pass.draw(2)"),
    )),
    Exercise("2b", _W, (
        Part("vertex input bindings and attributes",
             "describe one per-vertex buffer: its stride, a float32x2 position and a float32x3 colour after it",
             '    "array_stride": 5 * 4,\n    "step_mode": "vertex",\n    "attributes": [\n'
             '        {"shader_location": 0, "format": "float32x2", "offset": 0},\n'
             '        {"shader_location": 1, "format": "float32x3", "offset": 2 * 4},\n    ],\n',
             '    "array_stride": 5 * 4,\n    "step_mode": "vertex",\n    "attributes": [\n'
             '        {"shader_location": 0, "format": "float32x2", "offset": 0},\n'
             '        {"shader_location": 1, "format": "float32x3", "offset": 0},\n    ],\n'),
        Part("draw calls", "bind the vertex and index buffers, then draw the indexed triangle",
             '        render_pass.set_vertex_buffer(0, self.vertex_buffer)\n'
             '        render_pass.set_index_buffer(self.index_buffer, "uint16")\n'
             '        render_pass.draw_indexed(len(TRIANGLE_INDICES))\n'),
    ), (
        Mistake("offset", "the colour attribute at offset 0 (it reads the position)",
                "vertex input bindings and attributes", '"offset": 2 * 4}', '"offset": 0}'),
    )),
    Exercise("3a", _W, (
        Part("offscreen readback", "copy the offscreen image to the output, its whole size",
             "        encoder.copy_texture_to_texture({\"texture\": self.image}, {\"texture\": target}, "
             "(self.size[0], self.size[1], 1))\n"),
    ), (
        Mistake("half", "only part of the image copied (a wrong copy size)", "offscreen readback",
                "(self.size[0], self.size[1], 1))", "(self.size[0] // 2, self.size[1], 1))"),
        Mistake("clear", "the offscreen image cleared to the wrong colour", "begin info and clear values",
                '"clear_value": BACKGROUND', '"clear_value": (1, 1, 1, 1)'),
    )),
    Exercise("3b", _W, (
        Part("multisample", "draw into the multisampled image and resolve it into the output, dropping the samples",
             '            attachment = {"view": self._msaa_view, "resolve_target": output, "clear_value": BACKGROUND,\n'
             '                          "load_op": "clear", "store_op": "discard"}\n',
             '            attachment = {"view": self._msaa_view, "clear_value": BACKGROUND,\n'
             '                          "load_op": "clear", "store_op": "discard"}\n'),
    ), (
        Mistake("resolve", "the MSAA resolve missing (no resolve target)", "multisample",
                '"resolve_target": output, ', ""),
        Mistake("background", "the clear colour left out of the multisampled attachment", "begin info and clear values",
                '"resolve_target": output, "clear_value": BACKGROUND,', '"resolve_target": output, '
                '"clear_value": (1, 1, 1, 1),'),
    )),
    Exercise("3c", _W, (
        Part("input attachments", "a second pass: draw the full-screen post triangle reading the resolved image",
             "        self._post(encoder, target)\n"),
    ), (
        Mistake("no-effect", "the post effect's amount left at zero (the image passes through)", "input attachments",
                "GREY_AMOUNT = 1.0", "GREY_AMOUNT = 0.0"),
        Mistake("half-grey", "the post effect at half strength", "push constants",
                "GREY_AMOUNT = 1.0", "GREY_AMOUNT = 0.5"),
    )),
    Exercise("4", _W, (
        Part("depth/stencil", "clear the depth attachment to the far plane each frame",
             '        depth = {"view": self._depth_view, "depth_clear_value": 1.0, "depth_load_op": "clear",\n'
             '                 "depth_store_op": "discard"}\n',
             '        depth = {"view": self._depth_view, "depth_clear_value": 0.0, "depth_load_op": "clear",\n'
             '                 "depth_store_op": "discard"}\n'),
        Part("UBO alignment", "for each cube, bind its object data at its aligned dynamic offset",
             "            render_pass.set_bind_group(1, self.object_group, [k * self.object_stride])\n",
             "            render_pass.set_bind_group(1, self.object_group, [0])\n"),
    ), (
        Mistake("winding", "the winding wrong: front faces culled (front_face cw)", "rasterizer",
                '"front_face": "ccw", "cull_mode": "back"', '"front_face": "cw", "cull_mode": "back"'),
        Mistake("depth0", "depth cleared to 0 with compare less: nothing passes", "depth/stencil",
                '"depth_clear_value": 1.0', '"depth_clear_value": 0.0'),
        Mistake("offset0", "every cube drawn with dynamic offset 0", "UBO alignment",
                "[k * self.object_stride]", "[0]"),
        Mistake("stride", "a wrong vertex stride (one float too many)", "vertex input bindings and attributes",
                '"array_stride": course.VERTEX_FLOATS * 4', '"array_stride": (course.VERTEX_FLOATS + 1) * 4'),
    ), _ANIMATED),
    Exercise("5", _W, (
        Part("samplers", "swap the sampler's bind group (set 2) between the four lanes' draws",
             "                render_pass.set_bind_group(2, group)\n",
             "                render_pass.set_bind_group(2, self.sampler_groups[0])\n"),
        Part("mipmaps", "upload the pattern as an sRGB texture with a generated mip chain",
             '        self.texture = create_texture(self.ctx, course.pattern_pixels(), srgb=True, mips=True, '
             'label="textured-pattern")\n',
             '        self.texture = create_texture(self.ctx, course.pattern_pixels(), srgb=False, mips=False, '
             'label="textured-pattern")\n'),
    ), (
        Mistake("srgb", "the sRGB view forgotten (texture read as linear: too bright)", "views",
                "srgb=True, mips=True", "srgb=False, mips=True"),
        Mistake("mips", "mips not generated", "mipmaps", "srgb=True, mips=True", "srgb=True, mips=False"),
        Mistake("one-sampler", "one sampler for all four lanes", "samplers",
                "render_pass.set_bind_group(2, group)", "render_pass.set_bind_group(2, self.sampler_groups[0])"),
    ), _ANIMATED),
    # -- the raw-Vulkan path: the same steps in Vulkan calls (raw_path/stages/) --------------------------------
    Exercise("1a", _R, (
        Part("clear without a render pass", "fill a VkClearColorValue with the step's colour for vkCmdClearColorImage",
             "        color = vk.VkClearColorValue(float32=list(self.color))\n",
             "        color = vk.VkClearColorValue(float32=[1.0, 0.0, 1.0, 1.0])\n"),
    ), ()),
    Exercise("1b", _R, (
        Part("begin info and clear values", "a render pass whose colour attachment is cleared to the step's colour",
             "        self.render_pass = single_pass(self.ctx, self.owned, self.format, 1, CLEAR_COLOR)\n",
             "        self.render_pass = single_pass(self.ctx, self.owned, self.format, 1, (1.0, 0.0, 1.0, 1.0))\n"),
    ), (
        Mistake("bytes", "the clear colour given in 0..255 instead of 0..1", "begin info and clear values",
                "self.format, 1, CLEAR_COLOR)", "self.format, 1, tuple(255 * c for c in CLEAR_COLOR))"),
    )),
    Exercise("2a", _R, (
        Part("draw calls", "bind the pipeline, set the (flipped) viewport and scissor, draw three vertices",
             "        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)\n"
             "        set_viewport_and_scissor(cmd, self.size)\n        vk.vkCmdDraw(cmd, 3, 1, 0, 0)\n"),
    ), (
        Mistake("y-flip", "the y axis flipped (the viewport not flipped for wgpu's y-up NDC)", "viewport and scissor",
                "        set_viewport_and_scissor(cmd, self.size)\n", _UNFLIPPED),
        Mistake("count", "nothing drawn (no draw, or fewer than 3 vertices)", "draw calls",
                "vk.vkCmdDraw(cmd, 3, 1, 0, 0)", "vk.vkCmdDraw(cmd, 2, 1, 0, 0)"),
    )),
    Exercise("2b", _R, (
        Part("vertex input bindings and attributes", "the colour attribute: location 1, three floats after the "
             "position", "        vk.VkVertexInputAttributeDescription(location=1, binding=0, "
             "format=vk.VK_FORMAT_R32G32B32_SFLOAT, offset=8),\n",
             "        vk.VkVertexInputAttributeDescription(location=1, binding=0, "
             "format=vk.VK_FORMAT_R32G32B32_SFLOAT, offset=0),\n"),
    ), (
        Mistake("offset", "the colour attribute at offset 0 (it reads the position)",
                "vertex input bindings and attributes", "R32G32B32_SFLOAT, offset=8)", "R32G32B32_SFLOAT, offset=0)"),
        Mistake("y-flip", "the y axis flipped (the viewport not flipped for wgpu's y-up NDC)", "viewport and scissor",
                "        set_viewport_and_scissor(cmd, self.size)\n", _UNFLIPPED),
    )),
    Exercise("3a", _R, (
        Part("offscreen readback", "copy the whole offscreen image into the target with vkCmdCopyImage",
             "            extent=vk.VkExtent3D(width=self.size[0], height=self.size[1], depth=1),\n",
             "            extent=vk.VkExtent3D(width=1, height=1, depth=1),\n"),
    ), (
        Mistake("y-flip", "the y axis flipped (the viewport not flipped for wgpu's y-up NDC)", "viewport and scissor",
                "        set_viewport_and_scissor(cmd, self.size)\n", _UNFLIPPED),
    )),
    Exercise("3b", _R, (
        Part("draw calls", "inside the pass that resolves the samples: bind, set the viewport, draw the triangle",
             "        vk.vkCmdBindPipeline(cmd, vk.VK_PIPELINE_BIND_POINT_GRAPHICS, self.pipeline)\n"
             "        set_viewport_and_scissor(cmd, self.size)\n        vk.vkCmdDraw(cmd, 3, 1, 0, 0)\n"),
    ), (
        Mistake("y-flip", "the y axis flipped (the viewport not flipped for wgpu's y-up NDC)", "viewport and scissor",
                "        set_viewport_and_scissor(cmd, self.size)\n", _UNFLIPPED),
    )),
    Exercise("3c", _R, (
        Part("push constants", "push the grey amount (one float) to the post subpass's fragment shader",
             '        amount = vk.ffi.from_buffer(struct.pack("<f", GREY_AMOUNT))\n',
             '        amount = vk.ffi.from_buffer(struct.pack("<f", 0.0))\n'),
    ), (
        Mistake("no-effect", "the post effect's amount left at zero (the image passes through)", "push constants",
                'struct.pack("<f", GREY_AMOUNT)', 'struct.pack("<f", 0.0)'),
        Mistake("half-grey", "the post effect at half strength", "push constants",
                'struct.pack("<f", GREY_AMOUNT)', 'struct.pack("<f", 0.5 * GREY_AMOUNT)'),
    )),
    Exercise("4", _R, (
        Part("UBO alignment", "for each cube, bind its object set at its aligned dynamic offset",
             "            vk.vkCmdBindDescriptorSets(cmd, graphics, self.layout, 1, 1, [self.object_set], 1, "
             "[k * self.object_stride])\n",
             "            vk.vkCmdBindDescriptorSets(cmd, graphics, self.layout, 1, 1, [self.object_set], 1, [0])\n"),
    ), (
        Mistake("winding", "the wrong faces culled (cull mode front)", "rasterizer",
                "cull_mode=vk.VK_CULL_MODE_BACK_BIT", "cull_mode=vk.VK_CULL_MODE_FRONT_BIT"),
        Mistake("offset0", "every cube drawn with dynamic offset 0", "UBO alignment",
                "[k * self.object_stride]", "[0]"),
        Mistake("y-flip", "the y axis flipped (the viewport not flipped for wgpu's y-up NDC)", "viewport and scissor",
                "        set_viewport_and_scissor(cmd, self.size)\n", _UNFLIPPED),
    ), _ANIMATED),
    Exercise("5", _R, (
        Part("samplers", "re-bind set 2 with each lane's sampler before its draw",
             "                vk.vkCmdBindDescriptorSets(cmd, graphics, self.separate_layout, 2, 1, [sampler_set], 0, "
             "None)\n",
             "                vk.vkCmdBindDescriptorSets(cmd, graphics, self.separate_layout, 2, 1, "
             "[self.sampler_sets[0]], 0, None)\n"),
        Part("mipmaps", "upload the pattern into an sRGB image with a full mip chain",
             "        self.texture = upload_texture(ctx, owned, course.pattern_pixels(), srgb=True, mips=True)\n",
             "        self.texture = upload_texture(ctx, owned, course.pattern_pixels(), srgb=False, mips=False)\n"),
    ), (
        Mistake("srgb", "the sRGB format forgotten (texture read as linear: too bright)", "views",
                "srgb=True, mips=True", "srgb=False, mips=True"),
        Mistake("mips", "mips not generated", "mipmaps", "srgb=True, mips=True", "srgb=True, mips=False"),
        Mistake("one-sampler", "one sampler for all four lanes", "samplers",
                "[sampler_set], 0, None)", "[self.sampler_sets[0]], 0, None)"),
    ), _ANIMATED),
    # -- step 6, the final model: the learner writes the normal mapping of the scene shader ----------------------
    Exercise("6", _W, (
        Part("samplers", "perturb n by the normal map: the unit tangent from t_raw, the bitangent from the "
             "tangent's w, the texel remapped to -1..1 with its xy scaled by `strength` (the material's)",
             "    let t = normalize(t_raw);\n"
             "    let b = select(1.0, -1.0, tangent.w < 0.0) * cross(n, t);\n"
             "    var m = texel * 2.0 - 1.0;\n"
             "    m = vec3f(m.xy * strength, m.z);\n"
             "    return safe_normalize(t * m.x + b * m.y + n * m.z, n);\n",
             "    return n;\n"),
    ), (
        Mistake("no-normal-map", "the normal map ignored (the vertex normal kept)", "samplers",
                "    return safe_normalize(t * m.x + b * m.y + n * m.z, n);\n", "    return n;\n"),
        Mistake("no-remap", "the normal texel not remapped from 0..1 to -1..1", "samplers",
                "var m = texel * 2.0 - 1.0;", "var m = texel;"),
        Mistake("bitangent", "the bitangent's sign flipped (the tangent's w ignored or inverted)", "samplers",
                "select(1.0, -1.0, tangent.w < 0.0)", "select(-1.0, 1.0, tangent.w < 0.0)"),
    ), shader="scene.wgsl", scene="final_subpass"),
    Exercise("6", _R, (
        Part("samplers", "perturb n by the normal map: the bitangent from the tangent's w, the texel remapped to "
             "-1..1 with its xy scaled by `strength` (the material's)",
             "    vec3 b = (v_tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);\n"
             "    vec3 m = texel * 2.0 - 1.0;\n"
             "    m = vec3(m.xy * strength, m.z);\n",
             "    vec3 b = vec3(0.0);\n    vec3 m = vec3(0.0, 0.0, 1.0);\n"),
    ), (
        Mistake("no-normal-map", "the normal map ignored (the vertex normal kept)", "samplers",
                "    vec3 m = texel * 2.0 - 1.0;\n", "    vec3 m = vec3(0.0, 0.0, 1.0);\n"),
        Mistake("no-remap", "the normal texel not remapped from 0..1 to -1..1", "samplers",
                "vec3 m = texel * 2.0 - 1.0;", "vec3 m = texel;"),
        Mistake("bitangent", "the bitangent's sign flipped (the tangent's w ignored or inverted)", "samplers",
                "(v_tangent.w < 0.0 ? -1.0 : 1.0)", "(v_tangent.w < 0.0 ? 1.0 : -1.0)"),
    ), shader="scene.frag", scene="final_subpass"),
)


def exercise(step: str, path: str) -> Exercise:
    """The exercise of a step on a path; a UserError naming the ones there are."""
    from wgpurender.core.course.steps import COURSE
    from wgpurender.core.errors import UserError

    numbers = [s.number for s in COURSE]
    if step not in numbers:
        named = next((s for s in COURSE if s.stage == step), None)  # a stage's name: 3d is step 4
        hint = f"; {step!r} is step {named.number}'s stage: give {named.number}" if named else " (wgpurender stages)"
        raise UserError(f"unknown step {step!r}: the course's steps are {', '.join(numbers)}{hint}")
    if path not in PATHS:
        raise UserError(f"unknown path {path!r}: choose {' or '.join(PATHS)}")
    for ex in EXERCISES:
        if ex.step == step and ex.path == path:
            return ex
    steps = ", ".join(ex.step for ex in EXERCISES if ex.path == path)
    raise UserError(f"no exercise for step {step!r} on the {path} path: the steps with one are {steps} "
                    "(wgpurender stages lists the course)")


def exercise_command(stage: str) -> str | None:
    """``wgpurender exercise STEP`` for a stage (or scene step) that has an exercise, else None: the report's
    "try it" line."""
    from wgpurender.core.course.steps import course_step

    step = course_step(stage)
    if step is None or not any(ex.step == step.number for ex in EXERCISES):
        return None
    return f"wgpurender exercise {step.number}"
