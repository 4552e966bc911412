"""``wgpurender export STAGE|SCENE -o DIR``: a static page that renders the target live with the browser's WebGPU.

No second renderer: the wgpu path renders the target once on this machine's device through a recording
proxy (recorder.py), and the page's generic player (player.js, shipped with the package) replays what it
created and recorded with the browser's ``navigator.gpu``: the same specialised WGSL strings, pipelines, uniform
bytes, textures and meshes. What changes per frame is recorded too:

- an animated stage (its uploads depend on ``t``) is recorded at ``FPS`` frames per second over one period of its
  motion (core/course/loops.py: the frame at the period is the frame at 0), so the page's loop has no jump;
  the page plays those uploads back in a loop (frame ``k`` shows ``t = k / FPS``);
- a 3D scene gets the window demo's orbit camera: the page packs the view matrix and eye into the scene's
  Camera uniform with the field offsets generated from the same ``Struct`` that packs it in Python
  (scene_render/shader_interface.CAMERA).

The page: ``index.html`` + ``player.js`` + ``data.js`` (the recording; textures and the reference frame as PNG,
other bytes as base64: packing.py). Plain classic scripts,
not ES modules: Chromium refuses module scripts and ``fetch`` from ``file://``, and the page must open from
disk. ``window.wgpurender.capture()`` resolves to ``{width, height, rgba}`` (base64 RGBA8, top row first) of the
frame at ``t = 0`` and the default camera: the frame ``wgpurender render TARGET --size WxH --anisotropy scene``
makes here (docs/backends.md).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from wgpurender.core.errors import UserError

FPS = 30
SECONDS = 4.0
PLAYER = Path(__file__).with_name("player.js")
NOT_EXPORTABLE = {"clear": "the browser's WebGPU has no clearTexture (a wgpu-native feature): export clear-pass, "
                           "which clears through a render pass"}


@dataclass
class Export:
    """What was written: the page and what it replays."""

    page: Path
    target: str
    size: tuple[int, int]
    calls: int
    page_bytes: int  # the three files on disk together: what a reader downloads
    animated: bool


def export(target: str, out: str | Path, size: tuple[int, int] = (800, 600), force: bool = False) -> Export:
    """Write the page for a stage (by name) or a scene file into ``out`` (made if missing; its parent must exist).

    ``out`` is checked before anything is recorded: new, empty, or holding an earlier wgpurender output (its
    manifest, core/files/owned_files.py); ``force`` writes beside other files. Each file is written atomically."""
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.course.loops import loop_seconds
    from wgpurender.core.files.owned_files import OwnedFolder
    from wgpurender.webpage.record import record_scene, record_stage
    from wgpurender.wgpu_path.device.context import get_context

    if target in NOT_EXPORTABLE:
        raise UserError(f"cannot export {target}: {NOT_EXPORTABLE[target]}")
    folder = OwnedFolder(out, "export", force, "cannot export to")
    folder.check_names(EXPORT_FILES)
    ctx = get_context()
    data = (record_scene if is_scene_file(target) else record_stage)(ctx, target, tuple(size), FPS,
                                                                     loop_seconds(target) or SECONDS)
    folder.claim(EXPORT_FILES)
    folder.write("data.js", ("window.WGPURENDER_EXPORT = " + json.dumps(data, separators=(",", ":")) + ";\n").encode())
    folder.write("player.js", PLAYER.read_bytes())
    page = folder.write("index.html", page_html(data["meta"]).encode())
    folder.finish()
    written = sum((page.parent / name).stat().st_size for name in EXPORT_FILES)  # what a reader downloads
    return Export(page, target, tuple(size), len(data["setup"]) + len(data["frame"]), written,
                  data["meta"]["frames"] > 1)


EXPORT_FILES = ("data.js", "player.js", "index.html")


def page_html(meta: dict) -> str:
    from html import escape

    title = escape(f"wgpurender: {meta['name']}")
    return f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #222; }}
canvas {{ border: 1px solid #999; image-rendering: pixelated; cursor: grab; touch-action: none; }}
#message {{ color: #a00; font-weight: bold; }}
pre {{ background: #f4f4f4; padding: .6em; overflow: auto; max-height: 28em; font-size: 12px; }}
dt {{ font-weight: bold; float: left; clear: left; width: 9em; }} dd {{ margin-left: 9.5em; }}
</style></head>
<body>
<h1>{title}</h1>
<p>{escape(meta['summary'])}</p>
{"".join(f'<p class="credit"><small>Credit: {escape(line)}</small></p>' for line in meta.get("credits", []))}
<p id="message"></p>
<canvas id="view" width="{meta['size'][0]}" height="{meta['size'][1]}"></canvas>
<p>{escape(meta['controls'])}</p>
<dl>
<dt>adapter</dt><dd id="adapter">(starting)</dd>
<dt>frame time</dt><dd id="frametime">-</dd>
<dt>vs wgpu-native</dt><dd id="difference">-</dd>
<dt>exported</dt><dd>{escape(meta['exported'])}</dd>
</dl>
<h2>Plan</h2>
<pre id="plan">{escape(meta['plan'])}</pre>
<script src="data.js"></script>
<script src="player.js"></script>
</body></html>
"""
