"""pygfx 0.17's image of a glTF file posed at ``t`` seconds of its first animation (the peer for anim-after/).

As ../pygfx_shot.py (same camera, lights, background), plus pygfx's own animation player: the file's first
AnimationClip played by an AnimationMixer advanced once by ``t`` seconds (skins are posed by pygfx on the GPU).

Usage: python pygfx_pose.py MODEL OUT.png CAMERA_JSON SIZE T
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pygfx as gfx
from PIL import Image
from rendercanvas.offscreen import RenderCanvas

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from lighting import BACKGROUND_SRGB, LIGHT_DIRECTION, pygfx_lights  # noqa: E402


def main(model: str, out: str, cam_json: str, size: int, t: float) -> None:
    cam = json.loads(cam_json)
    canvas = RenderCanvas(size=(size, size), pixel_ratio=1)
    renderer = gfx.WgpuRenderer(canvas)
    scene = gfx.Scene()
    scene.add(gfx.Background.from_color(BACKGROUND_SRGB))
    loaded = gfx.load_gltf(model, quiet=True, remote_ok=False)
    scene.add(loaded.scene)
    mixer = gfx.AnimationMixer()
    action = mixer.clip_action(loaded.animations[0])
    action.play()
    mixer.update(t)
    for light in pygfx_lights(np.array(cam["target"]), LIGHT_DIRECTION):
        scene.add(light)
    camera = gfx.PerspectiveCamera(cam["fov_y"], 1, depth_range=(cam["near"], cam["far"]))
    camera.local.position = cam["eye"]
    camera.look_at(cam["target"])
    canvas.request_draw(lambda: renderer.render(scene, camera))
    Image.fromarray(np.asarray(canvas.draw())[:, :, :3]).save(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), float(sys.argv[5]))
