"""Run by tests/test_window_storm.py in a subprocess under Xvfb: the final scene in a window while each frame
resizes (1x1 .. 3000x40), minimises, restores, unmaps (hides) and maps the window. Prints one JSON line."""

from __future__ import annotations

import json
import sys

import glfw

from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.window import run_window
from wgpurender.wgpu_path.window.view import DemoView

STEPS = [(1, 1), (3000, 40), "iconify", "restore", (40, 3000), "hide", "show", (97, 13), (2, 700), (320, 240),
         "hide", (5, 5), "show", "iconify", (3000, 40), "restore", (1, 1), (160, 120)]


def main(scene: str, frames: int) -> None:
    windows = []
    real_create = glfw.create_window

    def create(*args):
        windows.append(real_create(*args))
        return windows[-1]

    glfw.create_window = create  # the window loop stays untouched: we only learn its window
    sizes, steps = set(), iter(STEPS * (frames // len(STEPS) + 1))

    class Storm:
        def __init__(self, inner) -> None:
            self.inner = inner

        def resize(self, size):
            sizes.add(tuple(size))
            self.inner.resize(size)

        def record(self, encoder, target, t=0.0):
            self.inner.record(encoder, target, t)
            self._step()

        def _step(self):
            step = next(steps)
            window = windows[-1]
            if isinstance(step, tuple):
                glfw.set_window_size(window, *step)
            else:
                {"iconify": glfw.iconify_window, "restore": glfw.restore_window, "hide": glfw.hide_window,
                 "show": glfw.show_window}[step](window)

    class StormView(DemoView):  # the demo's own view (files, reload), each drawable wrapped in the storm
        def _make(self, fmt: str):
            return Storm(super()._make(fmt))

    ctx = get_context()
    result = run_window(ctx, StormView(ctx, scene), size=(200, 150), frames=frames, fixed_time=0.0)
    print(json.dumps({"frames": result.frames, "sizes": sorted(sizes)}))


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
