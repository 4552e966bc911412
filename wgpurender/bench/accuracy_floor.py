"""The noise floor of ``bench accuracy``'s timings: a time below it says nothing about the setting.

Measured in each run, on the same context (accuracy_run.noise_floor): a frame that draws nothing (a camera-only
scene, whose pass only clears, at 8x8) is timed like every setting. Its median is the fixed cost of any frame:
submitting, waiting, the timestamp queries themselves. A setting whose median is below FLOOR_FACTOR times that floor
is mostly that fixed cost, so the tables print "below timer resolution" instead of a number that would rank settings
by noise (on an H100 at 160x120 every setting read 0.1 ms: the floor itself). The CSV keeps the number and says so
in its ``timing`` column.
"""

from __future__ import annotations

from dataclasses import dataclass

BELOW = "below timer resolution"
FLOOR_FACTOR = 2.0
EMPTY_SCENE = ('description = "bench accuracy: a frame that draws nothing (the timer\'s noise floor)"\n\n'
               "[camera]\neye = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n\n"
               '[render]\nsize = [8, 8]\nmsaa = 1\noutput_format = "rgba8unorm-srgb"\n')


@dataclass(frozen=True)
class Floor:
    """Medians (ms) of the empty frame: ``gpu`` None where the adapter has no timestamps."""

    gpu: float | None
    wall: float

    def below(self, gpu_ms: float | None, wall_ms: float) -> bool:
        """Whether a setting's time (GPU where measured, else wall) is under FLOOR_FACTOR x the empty frame's."""
        if gpu_ms is not None and self.gpu is not None:
            return gpu_ms < FLOOR_FACTOR * self.gpu
        return wall_ms < FLOOR_FACTOR * self.wall

    def describe(self) -> str:
        gpu = f"GPU {self.gpu:.3f} ms, " if self.gpu is not None else ""
        return (f"noise floor: a frame that draws nothing takes {gpu}wall {self.wall:.3f} ms (median); times under "
                f"{FLOOR_FACTOR:g}x that read \"{BELOW}\"")
