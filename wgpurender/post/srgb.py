"""sRGB output encoding, and the rule that keeps a chain from encoding twice.

Rule: float textures hold linear values; 8-bit textures hold sRGB-encoded values.
Who applies the curve depends only on the format written:

- ``rgba8unorm-srgb`` / ``bgra8unorm-srgb``: the hardware encodes on write. A
  shader that also encoded would encode twice (too bright, washed out), so this
  effect passes linear values through there.
- ``rgba8unorm`` / ``bgra8unorm`` (e.g. a swapchain without an -srgb view): nobody
  else encodes, so this effect applies the curve in the shader.
- float formats: stay linear (imageio.to_uint8 encodes float images when saving).

Every effect before this one reads and writes linear values, so it must be last
(the chain enforces it), and :class:`~wgpurender.post.chain.PostChain` appends it
by itself when a non-empty chain ends in a plain 8-bit target. The pipeline is
cached per target format, so the choice is made once per format, not per pixel:
the WGSL override constant ENCODE selects it.
"""

from __future__ import annotations

from .base import PostEffect, encoding_of, needs_shader_encoding


class SrgbEncode(PostEffect):
    name = "srgb"
    summary = "linear -> sRGB output encoding (in the shader only where the target format does not encode)"
    shader = "post_srgb.wgsl"

    def constants(self, target_format: str) -> dict[str, float]:
        return {"0": 1.0 if needs_shader_encoding(target_format) else 0.0}

    def notes(self, input_format: str, output_format: str) -> tuple[str, ...]:
        return {
            "hardware": (f"{output_format} encodes on write: the shader passes linear values through",),
            "shader": (f"{output_format} does not encode: the shader applies the sRGB curve",),
            "none": (f"{output_format} holds linear values: the shader copies",),
        }[encoding_of(output_format)]
