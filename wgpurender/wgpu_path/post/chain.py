"""Running a plan's post passes: each pass's small runner (wgpurender/wgpu_path/post/passes.py) in order.

:class:`PostRunner` runs the passes of a :class:`~wgpurender.core.plan.RenderPlan` between textures the
caller owns (the scene renderer makes every attachment the plan lists). :class:`PostChain` is the same
for a bare list of effect steps (tests, benchmarks, the window's experiments): it plans the passes with
the plan's own rule (:func:`wgpurender.core.plan.plan_post_passes`) and keeps its own intermediates.

Why separate passes at all, not subpasses: WebGPU has no subpasses or input attachments (Metal and
D3D12 do not expose them), so each pass samples the previous image as a texture and the image makes
a full trip through memory per pass. Fusing per-pixel effects into one pass (the plan's default)
removes those trips where no effect needs its neighbours; the raw path's subpass composes them the
same way. On desktop GPUs and lavapipe subpasses are not tile-local anyway; the bandwidth a tiler's
subpass would save is a mobile one. What separate passes allow: an effect may read neighbouring
pixels (FXAA, sharpen), which an input attachment forbids.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping, Sequence

import wgpu

from wgpurender.core.course.effects import EffectStep, check_order, steps_for_target
from wgpurender.core.plan import STORAGE_FORMATS, Attachment, PostPass, plan_post_passes
from wgpurender.wgpu_path.device.context import GPUContext
from wgpurender.wgpu_path.post.passes import ComputePass, FragmentPass, planned_pass

POST_USAGE = {
    "post-intermediate": wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING,
    "post-mask": wgpu.TextureUsage.RENDER_ATTACHMENT,
    "post-scratch": wgpu.TextureUsage.STORAGE_BINDING | wgpu.TextureUsage.COPY_SRC,
}


def attachment_usage(a: Attachment, passes: Sequence[PostPass]) -> int:
    """The usage a post attachment needs: storage where a compute pass writes it, a copy's destination where a
    compute pass's scratch is copied into it (an -srgb intermediate)."""
    usage = POST_USAGE.get(a.role, 0)
    if any(p.path == "compute" and p.output == a.name for p in passes):
        usage |= wgpu.TextureUsage.STORAGE_BINDING
    if any(p.copy_to == a.name for p in passes):
        usage |= wgpu.TextureUsage.COPY_DST
    return usage


def output_usage(passes: Sequence[PostPass]) -> int:
    """Extra usage the caller's output texture needs: STORAGE_BINDING when a compute pass writes it directly."""
    last = passes[-1] if passes else None
    if last is not None and last.path == "compute" and last.output == "output":
        return wgpu.TextureUsage.STORAGE_BINDING
    return 0


class PostRunner:
    """The runners of a list of planned post passes, made once (pipelines compiled now, not at frame 1)."""

    def __init__(self, ctx: GPUContext, passes: Sequence[PostPass]) -> None:
        self.ctx = ctx
        self.passes = tuple(passes)
        self.runners: list[FragmentPass | ComputePass] = [planned_pass(ctx.device, p) for p in self.passes]

    def __len__(self) -> int:
        return len(self.passes)

    def __bool__(self) -> bool:
        return bool(self.passes)

    def run(self, encoder: wgpu.GPUCommandEncoder, textures: Mapping[str, wgpu.GPUTexture], timer=None) -> None:
        """Record every pass; ``textures``: attachment name -> texture ("output" included).

        ``timer``: an optional :class:`wgpurender.wgpu_path.device.timing.PassTimer`; each pass is timed as
        "post:EFFECTS".
        """
        if timer is None:
            self._run_untimed(encoder, textures)
            return
        for p, runner in zip(self.passes, self.runners, strict=True):
            writes = timer.writes(f"post:{p.effect}")
            source, target = textures[p.input], textures[p.output]
            if isinstance(runner, ComputePass):
                copy_to = textures[p.copy_to] if p.copy_to else None
                runner.encode(encoder, source, target, copy_to, timestamp_writes=writes)
            else:
                runner.encode(encoder, source, target, textures[p.mask] if p.mask else None,
                              timestamp_writes=writes)

    def _run_untimed(self, encoder: wgpu.GPUCommandEncoder, textures: Mapping[str, wgpu.GPUTexture]) -> None:
        self.bind(textures)(textures["output"])(encoder)

    def bind(self, textures: Mapping[str, wgpu.GPUTexture]) -> Callable[[wgpu.GPUTexture], Callable]:
        """The untimed chain between ``textures`` (every attachment but "output"), made once:
        ``bind(textures)(output)(encoder)`` records every pass into ``output``.

        Each pass is checked and its views, bind group and workgroup count are looked up here, so a frame pays
        only for the wgpu calls (issue 31.4; a caller that keeps the textures keeps the result). Only the steps
        that name the output (:func:`names_output`: the last pass's target or its copy) are finished per output
        texture, so a swapchain's new image each frame costs one view (or one copy's argument), not the chain.
        Consecutive compute passes share one compute pass (each dispatch is its own usage scope in WebGPU, so a
        dispatch reading what the one before it wrote is ordered by wgpu): two calls fewer per pass.
        """
        steps: list[tuple[str, Callable]] = []  # ("render", encode) | ("dispatch", dispatch) | ("copy", copy)
        late: list[tuple[int, str, Callable]] = []  # (index in steps, kind, output -> step): the output's steps
        for p, runner in zip(self.passes, self.runners, strict=True):
            source = textures[p.input]
            mask = textures[p.mask] if p.mask else None
            if p.output == "output":
                kind = "dispatch" if isinstance(runner, ComputePass) else "render"
                late.append((len(steps), kind, _late_pass(runner, source, mask)))
                steps.append((kind, None))
            elif isinstance(runner, ComputePass):
                steps.append(("dispatch", runner.bound(source, textures[p.output])))
            else:
                steps.append(("render", runner.bound(source, textures[p.output], mask)))
            if p.copy_to and names_output(p):
                late.append((len(steps), "copy", functools.partial(_copy_into, runner, textures, p)))
                steps.append(("copy", None))
            elif p.copy_to:
                steps.append(("copy", functools.partial(runner.copy, target=textures[p.output],
                                                        copy_to=textures[p.copy_to])))
        return functools.partial(_finish, tuple(steps), tuple(late))


def names_output(p: PostPass) -> bool:
    """Whether a planned pass writes the caller's output texture (its target, or its copy's destination)."""
    return p.output == "output" or p.copy_to == "output"


def _late_pass(runner: FragmentPass | ComputePass, source: wgpu.GPUTexture,
               mask: wgpu.GPUTexture | None) -> Callable[[wgpu.GPUTexture], Callable]:
    """``step(output)``: the pass into ``output``, with all that does not name it made now (a render pass: its
    bundle and mask, then per output its view; a dispatch's bind group names its target, so it is made per output).
    Views and bind groups per output live in the runner's caches of 4: a swapchain's new image cannot grow them."""
    if isinstance(runner, ComputePass):
        return functools.partial(runner.bound, source)
    into = runner.bound_source(source, mask)

    def step(output: wgpu.GPUTexture) -> Callable:
        runner.check(source, output)
        return into(output, runner.views.get(output, output.create_view))

    return step


def _copy_into(runner, textures: Mapping[str, wgpu.GPUTexture], p: PostPass, output: wgpu.GPUTexture) -> Callable:
    def texture(name: str) -> wgpu.GPUTexture:
        return output if name == "output" else textures[name]

    return functools.partial(runner.copy, target=texture(p.output), copy_to=texture(p.copy_to))


def _finish(steps: tuple, late: tuple, output: wgpu.GPUTexture) -> Callable[[wgpu.GPUCommandEncoder], None]:
    """The bound chain finished for ``output``: only its late steps are made now."""
    if late:
        steps = list(steps)
        for index, kind, make in late:
            steps[index] = (kind, make(output))
        steps = tuple(steps)
    return functools.partial(_record_steps, steps)


def _record_steps(steps: tuple[tuple[str, Callable], ...], encoder: wgpu.GPUCommandEncoder) -> None:
    """Record bound post steps: dispatches in one open compute pass until a render pass or a copy comes."""
    open_pass = None
    for kind, step in steps:
        if kind == "dispatch":
            if open_pass is None:
                open_pass = encoder.begin_compute_pass(label="post-compute")
            step(open_pass)
            continue
        if open_pass is not None:
            open_pass.end()
            open_pass = None
        step(encoder)
    if open_pass is not None:
        open_pass.end()


class PostChain:
    """Effect steps run from a source texture to a target texture, planned like a scene's chain.

    ``fuse`` and ``path`` are the plan's knobs (post_fuse, post_path "fragment" | "compute");
    ``intermediate_format``: the ping-pong textures' format (the plan uses the scene image's).
    """

    def __init__(self, steps: Sequence[EffectStep], intermediate_format: str = "rgba16float", *, fuse: bool = True,
                 path: str = "fragment") -> None:
        check_order([s.effect for s in steps])
        self.steps = list(steps)
        self.intermediate_format, self.fuse, self.path = intermediate_format, fuse, path
        self._built: dict[tuple, tuple[PostRunner, dict[str, wgpu.GPUTexture]]] = {}

    def __len__(self) -> int:
        return len(self.steps)

    def __bool__(self) -> bool:
        return bool(self.steps)

    def plan(self, input_format: str, output_format: str, size: tuple[int, int]):
        """(passes, attachments) as the plan would list them for this chain."""
        steps = steps_for_target(self.steps, output_format)
        return plan_post_passes(steps, self.fuse, self.path, "input", self.intermediate_format, output_format,
                                size, output_twin=False)  # the caller's target exists: never its twin

    def _build(self, ctx: GPUContext, source: wgpu.GPUTexture, target: wgpu.GPUTexture):
        size = (source.size[0], source.size[1])
        key = (ctx.device, size, source.format, target.format)
        if key not in self._built:
            self._built.clear()  # a resize or a new format: the old textures go
            passes, attachments = self.plan(self.intermediate_format, target.format, size)
            textures = {a.name: ctx.device.create_texture(
                label=a.name, size=(size[0], size[1], 1), format=a.format, usage=attachment_usage(a, passes))
                for a in attachments}
            self._built[key] = (PostRunner(ctx, passes), textures)
        return self._built[key]

    def run(self, ctx: GPUContext, encoder: wgpu.GPUCommandEncoder, source: wgpu.GPUTexture,
            target: wgpu.GPUTexture, timer=None) -> None:
        """Record every pass into ``encoder``; the last one writes ``target``. Empty chain: records nothing.

        On the compute path a pass that writes ``target`` directly needs it to have STORAGE_BINDING usage
        (:func:`output_usage`); -srgb targets are written through a scratch and a copy instead.
        """
        if not self.steps:
            return
        runner, textures = self._build(ctx, source, target)
        runner.run(encoder, {**textures, "input": source, "output": target}, timer=timer)


__all__ = ["STORAGE_FORMATS", "PostChain", "PostRunner", "attachment_usage", "names_output", "output_usage"]
