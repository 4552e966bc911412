"""Render one glTF file with pygfx 0.17 (offscreen canvas) from a given camera: the peer's image.

Usage: python pygfx_shot.py MODEL OUT.png CAMERA_JSON SIZE [T]
T (anim-after/run_anim.py): the file's first animation played by pygfx's AnimationMixer, advanced once by T
seconds (skins posed by pygfx on the GPU); without it the file as written, as the held-out run drew it.
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pygfx as gfx
from lighting import BACKGROUND_SRGB, LIGHT_DIRECTION, pygfx_lights
from PIL import Image
from rendercanvas.offscreen import RenderCanvas


def main(model: str, out: str, cam_json: str, size: int, t: float | None = None) -> None:
    cam = json.loads(cam_json)
    canvas = RenderCanvas(size=(size, size), pixel_ratio=1)
    renderer = gfx.WgpuRenderer(canvas)
    scene = gfx.Scene()
    scene.add(gfx.Background.from_color(BACKGROUND_SRGB))
    loaded = gfx.load_gltf(model, quiet=True, remote_ok=False)
    scene.add(loaded.scene)
    if t is not None:
        mixer = gfx.AnimationMixer()
        mixer.clip_action(loaded.animations[0]).play()
        mixer.update(t)
    for light in pygfx_lights(np.array(cam["target"]), LIGHT_DIRECTION):
        scene.add(light)
    camera = gfx.PerspectiveCamera(cam["fov_y"], 1, depth_range=(cam["near"], cam["far"]))
    camera.local.position = cam["eye"]
    camera.look_at(cam["target"])
    canvas.request_draw(lambda: renderer.render(scene, camera))
    Image.fromarray(np.asarray(canvas.draw())[:, :, :3]).save(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), float(sys.argv[5]) if len(sys.argv) > 5 else None)
