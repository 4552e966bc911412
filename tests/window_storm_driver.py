"""Run by tests/test_window_storm.py in a subprocess under Xvfb: the final scene in a window while each frame
resizes (1x1 .. 3000x40), minimises, restores, unmaps (hides) and maps the window. Prints one JSON line."""

from __future__ import annotations

import json
import sys

import glfw

from wgpurender.gpu import get_context
from wgpurender.scene_render import scene_drawable_factory
from wgpurender.window import run_window

STEPS = [(1, 1), (3000, 40), "iconify", "restore", (40, 3000), "hide", "show", (97, 13), (2, 700), (320, 240),
         "hide", (5, 5), "show", "iconify", (3000, 40), "restore", (1, 1), (160, 120)]


def main(scene: str, frames: int) -> None:
    windows = []
    real_create = glfw.create_window

    def create(*args):
        windows.append(real_create(*args))
        return windows[-1]

    glfw.create_window = create  # the window.py loop stays untouched: we only learn its window
    make = scene_drawable_factory(scene, get_context())
    sizes, steps = set(), iter(STEPS * (frames // len(STEPS) + 1))

    class Storm:
        def __init__(self, fmt: str) -> None:
            self.inner = make(fmt)

        def resize(self, size):
            sizes.add(tuple(size))
            self.inner.resize(size)

        def record(self, encoder, target, t=0.0):
            (self.inner.record if hasattr(self.inner, "record") else self.inner.draw)(encoder, target, t)
            self._step()

        draw = record  # window.py has called it draw, then record

        def _step(self):
            step = next(steps)
            window = windows[-1]
            if isinstance(step, tuple):
                glfw.set_window_size(window, *step)
            else:
                {"iconify": glfw.iconify_window, "restore": glfw.restore_window, "hide": glfw.hide_window,
                 "show": glfw.show_window}[step](window)

    result = run_window(get_context(), Storm, size=(200, 150), frames=frames, fixed_time=0.0)
    print(json.dumps({"frames": result.frames, "sizes": sorted(sizes)}))


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
