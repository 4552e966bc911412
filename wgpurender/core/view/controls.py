"""Mouse and keys for both demo windows, turned into orbit-camera moves (wgpurender/core/view/orbit.py).

One module for the wgpu window (wgpu_path/window/) and the raw-Vulkan one (raw_path/window/__init__.py):
the same keys, the same drag and scroll steps, the same test script, so the two windows move
their cameras identically for the same input (tests/test_raw_window.py compares their images).

=====================  ===========================================
left drag              orbit around the target
right or middle drag   pan (move the target in the view plane)
scroll                 zoom (closer / farther)
arrow keys, W A S D    orbit by 5 degrees
+ / -  (or Q / E)      zoom by one step
R or Home              reset to the scene's (or stage's) camera
F1                     show / hide the settings overlay (as in Sascha Willems' Vulkan examples)
P                      pause / resume the animation
Esc                    close the window
=====================  ===========================================

:class:`Controls` takes events in GLFW's terms (key and button codes, press/release, cursor
positions), so the window's GLFW callbacks and the tests' synthetic input
(:func:`parse_script`, ``demo --test-input``) go through the same code.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

from wgpurender.core.errors import UserError
from wgpurender.core.view.orbit import RADIANS_PER_PIXEL, Orbit

KEY_STEP_PIXELS = math.radians(5.0) / RADIANS_PER_PIXEL  # one key press orbits 5 degrees


class Controls:
    """Orbit-camera input; ``glfw`` is the glfw module (for its key and button codes)."""

    def __init__(self, glfw, orbit_of) -> None:
        """``orbit_of()`` returns the current :class:`Orbit` or None (flat stages, and across rebuilds)."""
        self.glfw = glfw
        self.orbit_of = orbit_of
        self.dragging: int | None = None  # the held mouse button
        self.cursor: tuple[float, float] | None = None
        self.close_requested = False
        self.overlay_shown = True  # F1 toggles
        self.clock = PausableClock()  # P pauses the animation time

    def _orbit(self) -> Orbit | None:
        return self.orbit_of()

    def toggles(self) -> str:
        """The line a toggle prints: what F1 and P set now."""
        return (f"overlay {'shown' if self.overlay_shown else 'hidden'} (F1), "
                f"animation {'paused' if self.clock.paused else 'running'} (P)")

    def mouse_button(self, button: int, action: int) -> None:
        g = self.glfw
        if action == g.PRESS and self.dragging is None:
            self.dragging = button
        elif action == g.RELEASE and button == self.dragging:
            self.dragging = None

    def cursor_pos(self, x: float, y: float) -> None:
        last, self.cursor = self.cursor, (x, y)
        orbit = self._orbit()
        if last is None or self.dragging is None or orbit is None:
            return
        dx, dy = x - last[0], y - last[1]
        if self.dragging == self.glfw.MOUSE_BUTTON_LEFT:
            orbit.rotate(dx, dy)
        else:
            orbit.pan(dx, dy)

    def scroll(self, dy: float) -> None:
        orbit = self._orbit()
        if orbit is not None:
            orbit.zoom(dy)

    def key(self, key: int, action: int) -> None:
        g = self.glfw
        if action not in (g.PRESS, g.REPEAT):
            return
        if key == g.KEY_ESCAPE:
            self.close_requested = True
            return
        if action == g.PRESS and key in (g.KEY_F1, g.KEY_P):  # a toggle: not on key repeat
            if key == g.KEY_F1:
                self.overlay_shown = not self.overlay_shown
            else:
                self.clock.toggle()
            print(self.toggles(), flush=True)
            return
        orbit = self._orbit()
        if orbit is None:
            return
        step = KEY_STEP_PIXELS
        moves = {
            g.KEY_LEFT: lambda: orbit.rotate(-step, 0), g.KEY_A: lambda: orbit.rotate(-step, 0),
            g.KEY_RIGHT: lambda: orbit.rotate(step, 0), g.KEY_D: lambda: orbit.rotate(step, 0),
            g.KEY_UP: lambda: orbit.rotate(0, step), g.KEY_W: lambda: orbit.rotate(0, step),
            g.KEY_DOWN: lambda: orbit.rotate(0, -step), g.KEY_S: lambda: orbit.rotate(0, -step),
            g.KEY_EQUAL: lambda: orbit.zoom(1), g.KEY_KP_ADD: lambda: orbit.zoom(1), g.KEY_Q: lambda: orbit.zoom(1),
            g.KEY_MINUS: lambda: orbit.zoom(-1), g.KEY_KP_SUBTRACT: lambda: orbit.zoom(-1),
            g.KEY_E: lambda: orbit.zoom(-1),
            g.KEY_R: orbit.reset, g.KEY_HOME: orbit.reset,
        }
        if key in moves:
            moves[key]()


class PausableClock:
    """The animation's time in seconds since the window opened, standing still while paused (P)."""

    def __init__(self, now: Callable[[], float] = time.perf_counter) -> None:
        self.now = now
        self.start = now()
        self.paused_at: float | None = None

    @property
    def paused(self) -> bool:
        return self.paused_at is not None

    def toggle(self) -> None:
        if self.paused_at is None:
            self.paused_at = self.now()
        else:  # resume where it stopped: the pause does not count
            self.start += self.now() - self.paused_at
            self.paused_at = None

    def time(self) -> float:
        return (self.paused_at if self.paused_at is not None else self.now()) - self.start


# -- synthetic input (the tests' hook) ---------------------------------------------------------


@dataclass(frozen=True)
class ScriptEvent:
    """Before frame ``frame`` is drawn: one input event, or ``wait-reload`` / ``shot PATH`` for tests."""

    frame: int
    action: str
    args: tuple[str, ...]


SCRIPT_ACTIONS = {"press": 0, "release": 0, "move": 2, "scroll": 1, "key": 1, "wait-reload": 0, "shot": 1, "click": 1}


def parse_script(text: str) -> list[ScriptEvent]:
    """``"FRAME:ACTION ARGS; ..."``, e.g. ``"1:press; 1:move 0 0; 2:move 120 0; 2:release; 3:key R"``.

    press/release act on the left mouse button (``press right`` for the right one); move
    takes cursor x y; scroll dy; key a GLFW key name without KEY_ (R, LEFT, EQUAL);
    wait-reload blocks until a watched file changed and the rebuild was tried; shot PATH
    saves the frame drawn next; click NAME clicks the settings overlay's widget NAME (``msaa=4``,
    ``reverse_z``, ``effect:0``, ...: wgpu_path/window/overlay.py) and releases on the next frame.
    """
    events = []
    for item in filter(None, (part.strip() for part in text.split(";"))):
        frame, _, rest = item.partition(":")
        words = rest.split()
        try:
            n = int(frame)
        except ValueError:
            raise UserError(f"--test-input: {item!r} must start with a frame number, e.g. '2:key R'") from None
        if not words or words[0] not in SCRIPT_ACTIONS:
            raise UserError(f"--test-input: unknown action in {item!r}: use one of {', '.join(SCRIPT_ACTIONS)}")
        action, args = words[0], tuple(words[1:])
        if action not in ("press", "release") and len(args) != SCRIPT_ACTIONS[action]:
            raise UserError(f"--test-input: {action} takes {SCRIPT_ACTIONS[action]} argument(s): {item!r}")
        events.append(ScriptEvent(n, action, args))
    return events


def install_callbacks(glfw, window, controls: Controls) -> None:
    """Route a GLFW window's key, mouse button, cursor and scroll events to ``controls``."""
    glfw.set_key_callback(window, lambda _w, key, _sc, action, _mods: controls.key(key, action))
    glfw.set_mouse_button_callback(window, lambda _w, button, action, _mods: controls.mouse_button(button, action))
    glfw.set_cursor_pos_callback(window, lambda _w, x, y: controls.cursor_pos(x, y))
    glfw.set_scroll_callback(window, lambda _w, _dx, dy: controls.scroll(dy))


def due(script: list[ScriptEvent], frame: int) -> list[ScriptEvent]:
    """Take the script's events that are due before ``frame`` is drawn (the window handles shot/wait-reload)."""
    events = []
    while script and script[0].frame <= frame:
        events.append(script.pop(0))
    return events


def send(controls: Controls, event: ScriptEvent) -> None:
    """Deliver an input event of the script as GLFW would."""
    g = controls.glfw
    button = g.MOUSE_BUTTON_RIGHT if event.args[:1] == ("right",) else g.MOUSE_BUTTON_LEFT
    if event.action == "press":
        controls.mouse_button(button, g.PRESS)
    elif event.action == "release":
        controls.mouse_button(button, g.RELEASE)
    elif event.action == "move":
        controls.cursor_pos(float(event.args[0]), float(event.args[1]))
    elif event.action == "scroll":
        controls.scroll(float(event.args[0]))
    elif event.action == "key":
        code = getattr(g, f"KEY_{event.args[0].upper()}", None)
        if code is None:
            raise UserError(f"--test-input: unknown key {event.args[0]!r}")
        controls.key(code, g.PRESS)
