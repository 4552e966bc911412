"""The plan's knobs as a window turns them live: their current values, their choices, and the plan they resolve to.

The demo's overlay (wgpu_path/window/overlay.py) shows one widget per knob: MSAA, the anisotropy rule, each
post effect of the scene on or off, post fusion, the post path, the depth format and reverse-Z. A change goes
through :func:`~wgpurender.core.plan.resolve.resolve_plan`, the one resolution function every entry point uses;
:func:`changed` says which parts of the plan differ, so the window rebuilds only when the plan did change and
says what changed. API-free.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from wgpurender.core.course.formats import POST_PATHS
from wgpurender.core.plan.anisotropy import ANISOTROPY_RULES, DEFAULT_ANISOTROPY
from wgpurender.core.plan.model import DEPTH_FORMATS, RenderPlan
from wgpurender.core.scene import Scene

MSAA_CHOICES = (1, 4)
FUSE_CHOICES = (None, True, False)  # None: the scene's render.post_fuse


@dataclass
class LiveKnobs:
    """The knobs' current values; ``effects`` says per [[post]] entry whether it runs."""

    msaa: int | None = None  # None: the scene's
    anisotropy: str = DEFAULT_ANISOTROPY
    depth_format: str = DEPTH_FORMATS[0]
    reverse_z: bool = False
    post_fuse: bool | None = None
    post_path: str = "auto"
    effects: list[bool] = field(default_factory=list)

    @classmethod
    def for_scene(cls, scene: Scene, msaa: int | None = None, anisotropy: str = DEFAULT_ANISOTROPY) -> LiveKnobs:
        return cls(msaa=msaa, anisotropy=anisotropy, effects=[True] * len(scene.post))

    def scene(self, scene: Scene) -> Scene:
        """``scene`` with the switched-off effects left out of its post chain."""
        kept = tuple(step for step, on in zip(scene.post, self.effects, strict=False) if on)
        return scene if len(kept) == len(scene.post) else dataclasses.replace(scene, post=kept)

    def resolve(self, scene: Scene, adapter, output_format: str, output_storage: bool = False) -> RenderPlan:
        """The plan for these values, through the one resolution function."""
        from wgpurender.core.plan.resolve import resolve_plan

        knobs = {"depth_format": self.depth_format, "reverse_z": self.reverse_z, "post_fuse": self.post_fuse,
                 "post_path": None if self.post_path == "auto" else self.post_path, "output_storage": output_storage}
        return resolve_plan(self.scene(scene), adapter, output_format=output_format, msaa=self.msaa,
                            anisotropy=self.anisotropy, **knobs)


CHOICES = {  # knob -> the values a widget offers
    "msaa": MSAA_CHOICES,
    "anisotropy": ANISOTROPY_RULES,
    "depth_format": DEPTH_FORMATS,
    "post_fuse": FUSE_CHOICES,
    "post_path": POST_PATHS,
}


def changed(old: RenderPlan, new: RenderPlan) -> list[str]:
    """What differs between two plans, in the plan's own words: knobs, passes, attachments, pipelines, textures."""
    out = []
    if old.msaa != new.msaa:
        out.append(f"msaa {old.msaa} -> {new.msaa}")
    for name in ("depth_format", "reverse_z", "post_fuse", "post_path", "anisotropy"):
        a, b = getattr(old.knobs, name), getattr(new.knobs, name)
        if a != b:
            out.append(f"{name} {a} -> {b}")
    for part in ("passes", "attachments", "pipelines", "post_pipelines", "samplers"):
        if getattr(old, part) != getattr(new, part):
            out.append(f"{part} ({len(getattr(old, part))} -> {len(getattr(new, part))})")
    return out
