"""Render one glTF file with pygfx 0.17 (offscreen canvas) from a given camera: the peer's image.

Usage: python pygfx_shot.py MODEL OUT.png CAMERA_JSON SIZE
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pygfx as gfx
from lighting import BACKGROUND_SRGB, LIGHT_DIRECTION, pygfx_lights
from PIL import Image
from rendercanvas.offscreen import RenderCanvas


def main(model: str, out: str, cam_json: str, size: int) -> None:
    cam = json.loads(cam_json)
    canvas = RenderCanvas(size=(size, size), pixel_ratio=1)
    renderer = gfx.WgpuRenderer(canvas)
    scene = gfx.Scene()
    scene.add(gfx.Background.from_color(BACKGROUND_SRGB))
    loaded = gfx.load_gltf(model, quiet=True, remote_ok=False)
    scene.add(loaded.scene)
    for light in pygfx_lights(np.array(cam["target"]), LIGHT_DIRECTION):
        scene.add(light)
    camera = gfx.PerspectiveCamera(cam["fov_y"], 1, depth_range=(cam["near"], cam["far"]))
    camera.local.position = cam["eye"]
    camera.look_at(cam["target"])
    canvas.request_draw(lambda: renderer.render(scene, camera))
    Image.fromarray(np.asarray(canvas.draw())[:, :, :3]).save(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]))
