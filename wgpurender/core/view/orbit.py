"""An orbit camera for the demo window: the eye moves on a sphere around a target point.

API-free (numpy only). The window turns mouse and key input into :meth:`Orbit.rotate`,
:meth:`Orbit.zoom` and :meth:`Orbit.pan`; the stage or scene it shows takes :meth:`Orbit.eye`
and :attr:`Orbit.target` as its look-at camera. The start pose is the scene file's camera
(or the 3d stage's constants), so :meth:`Orbit.reset` always returns to what a headless
render shows.

The sphere is laid out around the camera's own ``up`` vector (the Vulkan tutorial's scene
uses +z up, the course's own scenes +y), in an orthonormal basis ``(a, b, up)`` where ``a``
points from the target towards the start eye: ``eye = target + r (cos p (cos y a + sin y b)
+ sin p up)`` with yaw ``y`` and pitch ``p``. Pitch stays inside +-89 degrees so the view
never looks straight along ``up`` (where look-at is undefined).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

MAX_PITCH = math.radians(89.0)
MIN_DISTANCE = 1e-3
RADIANS_PER_PIXEL = math.radians(0.4)  # mouse drag: 0.4 degrees per pixel
ZOOM_PER_STEP = 0.9  # one scroll step or key press: 10 % closer


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    n = np.linalg.norm(v)
    if n == 0.0:
        raise ValueError("zero-length vector")
    return v / n


@dataclass
class Orbit:
    """Yaw/pitch/distance around ``target``; build one with :meth:`from_look_at`."""

    target: np.ndarray
    up: np.ndarray
    a: np.ndarray  # horizontal axis towards the start eye
    b: np.ndarray  # up x a
    distance: float
    yaw: float = 0.0
    pitch: float = 0.0
    _start: tuple = field(default=(), repr=False)

    @classmethod
    def from_look_at(cls, eye, target, up=(0.0, 1.0, 0.0)) -> Orbit:
        """The orbit whose :meth:`eye` is ``eye`` (to float64 rounding)."""
        eye, target, u = np.asarray(eye, np.float64), np.asarray(target, np.float64), _unit(up)
        offset = eye - target
        distance = max(float(np.linalg.norm(offset)), MIN_DISTANCE)
        horizontal = offset - np.dot(offset, u) * u
        if np.linalg.norm(horizontal) < 1e-9 * distance:  # looking along up: any horizontal axis will do
            horizontal = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 0.0, 1.0])
        a = _unit(horizontal)
        b = np.cross(u, a)
        pitch = math.asin(float(np.clip(np.dot(offset, u) / distance, -1.0, 1.0)))
        orbit = cls(target.copy(), u, a, b, distance, 0.0, float(np.clip(pitch, -MAX_PITCH, MAX_PITCH)))
        orbit._start = (target.copy(), distance, 0.0, orbit.pitch)
        return orbit

    def eye(self) -> tuple[float, float, float]:
        cp = math.cos(self.pitch)
        direction = cp * (math.cos(self.yaw) * self.a + math.sin(self.yaw) * self.b) + math.sin(self.pitch) * self.up
        return tuple(float(v) for v in self.target + self.distance * direction)

    def rotate(self, dx: float, dy: float) -> None:
        """Drag by (dx, dy) pixels: right turns the camera around the target, down raises it."""
        self.yaw -= dx * RADIANS_PER_PIXEL
        self.pitch = float(np.clip(self.pitch + dy * RADIANS_PER_PIXEL, -MAX_PITCH, MAX_PITCH))

    def zoom(self, steps: float) -> None:
        """Positive steps move closer (scroll up), negative ones away."""
        self.distance = max(self.distance * ZOOM_PER_STEP**steps, MIN_DISTANCE)

    def pan(self, dx: float, dy: float) -> None:
        """Move target and eye together in the view plane, by (dx, dy) pixels scaled with the distance."""
        forward = _unit(np.asarray(self.target) - np.asarray(self.eye()))
        right = np.cross(forward, self.up)
        if np.linalg.norm(right) < 1e-9:
            return
        right = _unit(right)
        view_up = np.cross(right, forward)
        scale = self.distance * 0.002
        self.target = self.target + scale * (-dx * right + dy * view_up)

    def reset(self) -> None:
        target, self.distance, self.yaw, self.pitch = self._start
        self.target = target.copy()

    def pose(self) -> tuple:
        """A hashable summary: the window redraws the camera only when it changed."""
        return (*self.eye(), *(float(v) for v in self.target))


def moved_camera(camera, orbit: Orbit):
    """``camera`` (any dataclass with ``eye`` and ``target``) at the orbit's eye and target; the same object when
    nothing moved, so a window can skip re-uploading it."""
    eye, target = orbit.eye(), tuple(float(v) for v in orbit.target)
    if (tuple(camera.eye), tuple(camera.target)) == (eye, target):
        return camera
    return dataclasses.replace(camera, eye=eye, target=target)


def follow(orbit: Orbit | None, seen: tuple | None, camera) -> tuple[Orbit | None, tuple | None]:
    """(orbit, seen) after a frame's ``play(t)``: a file camera an animation moved (its eye, target and up differ
    from ``seen``, the pose last followed) restarts the orbit where it now is; otherwise, a still camera or a
    paused clock, the user's orbit stays (core/scene/playback.py places the file camera again each frame)."""
    pose = (tuple(camera.eye), tuple(camera.target), tuple(camera.up))
    if orbit is None or getattr(camera, "file_camera", None) is None or pose == seen:
        return orbit, seen
    return Orbit.from_look_at(*pose), pose
