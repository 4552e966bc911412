"""A chain of post effects that ping-pongs between two intermediate textures.

Effect i reads the previous result and writes the next; intermediates alternate
between two textures (A, B, A, ...), and the last effect writes the caller's
target directly (an offscreen texture or the window's swapchain image, any
format), so a chain of n effects needs min(n - 1, 2) intermediates and no copy.

The chain's input is never written: it is usually the resolved scene colour.
An empty chain records nothing: the scene should then draw straight into the
output (the render plan does that), so the runner never adds a copy pass.
"""

from __future__ import annotations

from collections.abc import Sequence

import wgpu

from ..errors import UserError
from ..gpu import GPUContext
from .base import EffectDescription, PostEffect, needs_shader_encoding
from .srgb import SrgbEncode

INTERMEDIATE_USAGE = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING


def check_order(effects: Sequence[PostEffect]) -> None:
    """The srgb effect may only be last: every later effect would take encoded values for linear ones."""
    for effect in effects[:-1]:
        if isinstance(effect, SrgbEncode):
            names = ", ".join(e.name for e in effects)
            raise UserError(
                f"post effect 'srgb' must be the last effect (chain: {names}): "
                "later effects expect linear values; move it to the end or remove it"
            )


def effects_for_target(effects: Sequence[PostEffect], target_format: str) -> list[PostEffect]:
    """The effects actually run for a target: a non-empty chain ending in a plain 8-bit target gets srgb appended."""
    effects = list(effects)
    if effects and needs_shader_encoding(target_format) and not isinstance(effects[-1], SrgbEncode):
        effects.append(SrgbEncode())
    return effects


def intermediate_count(n_effects: int) -> int:
    """How many ping-pong textures n effects need: the last one writes the output."""
    return min(max(n_effects - 1, 0), 2)


class PostChain:
    """Effects run in order from a source texture to a target texture."""

    def __init__(self, effects: Sequence[PostEffect], intermediate_format: str = "rgba16float") -> None:
        check_order(effects)
        self.effects = list(effects)
        self.intermediate_format = intermediate_format
        self._intermediates: list[wgpu.GPUTexture] = []
        self._implicit_srgb = SrgbEncode()
        self._size: tuple[int, int] | None = None

    def __len__(self) -> int:
        return len(self.effects)

    def __bool__(self) -> bool:
        return bool(self.effects)

    def effects_for(self, target_format: str) -> list[PostEffect]:
        effects = effects_for_target(self.effects, target_format)
        if len(effects) > len(self.effects):
            effects[-1] = self._implicit_srgb  # keep one instance, so its pipeline/buffers are reused
        return effects

    def describe(self, input_format: str, output_format: str) -> list[EffectDescription]:
        """Each effect with the formats it reads and writes, for the plan's explain()."""
        effects = self.effects_for(output_format)
        out = []
        fmt_in = input_format
        for i, effect in enumerate(effects):
            fmt_out = output_format if i == len(effects) - 1 else self.intermediate_format
            out.append(effect.describe(fmt_in, fmt_out))
            fmt_in = fmt_out
        return out

    def clear_cache(self) -> None:
        """Forget every effect's cached bind groups and views (they refer to replaced textures)."""
        for effect in [*self.effects, self._implicit_srgb]:
            effect.clear_cache()

    def _textures(self, ctx: GPUContext, size: tuple[int, int], count: int) -> list[wgpu.GPUTexture]:
        current = self._intermediates
        if current and (tuple(current[0].size[:2]) != size or current[0].format != self.intermediate_format):
            current.clear()  # resized: the old ones are dropped (and freed by wgpu when unreferenced)
        while len(current) < count:
            current.append(
                ctx.device.create_texture(
                    label=f"post-intermediate-{'ab'[len(current)]}",
                    size=(size[0], size[1], 1),
                    format=self.intermediate_format,
                    usage=INTERMEDIATE_USAGE,
                )
            )
        return current[:count]

    def run(
        self, ctx: GPUContext, encoder: wgpu.GPUCommandEncoder, source: wgpu.GPUTexture, target: wgpu.GPUTexture,
        timer=None,
    ) -> None:
        """Record every effect into ``encoder``; the last one writes ``target``. Empty chain: records nothing.

        ``timer``: an optional :class:`wgpurender.timing.PassTimer`; each effect's pass is timed as "post:NAME".
        """
        effects = self.effects_for(target.format)
        if not effects:
            return
        size = (source.size[0], source.size[1])
        if size != self._size:  # resized: intermediates (and usually source and target) are new textures
            self.clear_cache()
            self._size = size
        temps = self._textures(ctx, size, intermediate_count(len(effects)))
        current = source
        for i, effect in enumerate(effects):
            destination = target if i == len(effects) - 1 else temps[i % 2]
            writes = timer.writes(f"post:{effect.name}") if timer is not None else None
            effect.encode(ctx.device, encoder, current, destination, timestamp_writes=writes)
            current = destination
