"""A command encoder that puts GPU timestamps on every render pass someone else begins.

Stages and post effects begin their own passes; wrapping the encoder they are given
adds ``timestamp_writes`` (labelled by the pass's label, else the wrapper's) without
changing their code. Everything else is forwarded to the real encoder.
"""

from __future__ import annotations

import wgpu

from ..timing import PassTimer


class TimedEncoder:
    def __init__(self, encoder: wgpu.GPUCommandEncoder, timer: PassTimer, label: str) -> None:
        self._encoder = encoder
        self._timer = timer
        self._label = label

    def __getattr__(self, name: str):
        return getattr(self._encoder, name)

    def begin_render_pass(self, **kwargs):
        if kwargs.get("timestamp_writes") is None:
            kwargs["timestamp_writes"] = self._timer.writes(self._label)
        return self._encoder.begin_render_pass(**kwargs)
