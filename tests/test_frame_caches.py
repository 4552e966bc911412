"""Per-frame caches (issue 7) never serve a stale object: post-chain bind groups and views, effect
parameter uploads, the scene's camera upload and attachment views.

Each check renders with a renderer or chain that has cached objects from an earlier frame and compares
with an independent result: a numpy float64 reference (rtol 2e-3 + atol 1e-3 for rgba16float outputs,
as in tests/test_post.py), or a fresh renderer that has no caches (bit-exact: same GPU arithmetic).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_post import ATOL, RTOL, ref_aces, ref_vignette, upload

from wgpurender.plan import build_plan
from wgpurender.post import PostChain, ToneMap, Vignette
from wgpurender.post.cache import BoundedCache
from wgpurender.scene import parse_scene
from wgpurender.scene_render import SceneRenderer, render_frame
from wgpurender.targets import create_target, read_texture

CUBE = Path(__file__).resolve().parents[1] / "assets" / "models" / "brick_cube.obj"
SCENE = f"""
[camera]
eye = [2.0, 1.6, 2.6]
target = [0.0, 0.0, 0.0]

[[models]]
path = "{CUBE}"
material = {{ albedo_color = [0.8, 0.5, 0.3] }}

[[lights]]
type = "directional"
direction = [-0.3, -1.0, -0.5]

[render]
size = [64, 48]
msaa = 4
hdr = true

[[post]]
effect = "tonemap"

[[post]]
effect = "vignette"
"""


def _image(seed: int, w: int = 32, h: int = 24) -> np.ndarray:
    rng = np.random.default_rng(seed)
    img = rng.uniform(0.0, 4.0, (h, w, 4))
    img[..., 3] = 1.0
    return img.astype(np.float16)


def _run(ctx, chain: PostChain, src, dst) -> np.ndarray:
    encoder = ctx.device.create_command_encoder()
    chain.run(ctx, encoder, src, dst)
    ctx.queue.submit([encoder.finish()])
    return read_texture(ctx, dst).astype(np.float64)


def _reference(img: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    return ref_vignette(ref_aces(img.astype(np.float64), exposure), 0.5, 0.5, 0.5)


def test_chain_alternating_sources_and_targets_gives_each_its_own_image(ctx):
    """Two sources into two targets, alternately (A->X, B->Y, A->Y, B->X): every output is the reference of
    the source it was given, so a bind group or view cached for one texture is never used for another."""
    chain = PostChain([ToneMap(), Vignette(strength=0.5)])
    images = [_image(1), _image(2)]
    sources = [upload(ctx, img) for img in images]
    targets = [create_target(ctx, (32, 24), "rgba16float") for _ in range(2)]
    for s, t in [(0, 0), (1, 1), (0, 1), (1, 0), (0, 0)]:
        got = _run(ctx, chain, sources[s], targets[t])
        np.testing.assert_allclose(got, _reference(images[s]), rtol=2 * RTOL, atol=ATOL)
    tonemap = chain.effects[0]
    assert tonemap._groups.misses == 2, "one bind group per source, reused after that"


def test_chain_resized_renders_the_new_size_and_drops_old_entries(ctx):
    """32x24, then 16x12, then 32x24 again: each matches its reference; the resize empties the caches."""
    chain = PostChain([ToneMap(), Vignette(strength=0.5)])
    for w, h, seed in [(32, 24, 3), (16, 12, 4), (32, 24, 5)]:
        img = _image(seed, w, h)
        got = _run(ctx, chain, upload(ctx, img), create_target(ctx, (w, h), "rgba16float"))
        np.testing.assert_allclose(got, _reference(img), rtol=2 * RTOL, atol=ATOL)
        assert len(chain.effects[1]._groups) == 1 and len(chain.effects[1]._target_views) == 1


def test_changed_parameter_is_uploaded_next_frame(ctx):
    """The parameter buffer is rewritten only on change: exposure 1 -> 2.5 between frames must show."""
    tonemap = ToneMap(exposure=1.0)
    chain = PostChain([tonemap, Vignette(strength=0.5)])
    img = _image(6)
    src, dst = upload(ctx, img), create_target(ctx, (32, 24), "rgba16float")
    np.testing.assert_allclose(_run(ctx, chain, src, dst), _reference(img, 1.0), rtol=2 * RTOL, atol=ATOL)
    tonemap.params["exposure"] = 2.5
    np.testing.assert_allclose(_run(ctx, chain, src, dst), _reference(img, 2.5), rtol=2 * RTOL, atol=ATOL)


def test_bounded_cache_keeps_the_most_recent_entries():
    cache: BoundedCache[str] = BoundedCache(capacity=2)
    assert cache.get("a", lambda: "A") == "A" and cache.get("b", lambda: "B") == "B"
    assert cache.get("a", lambda: "new") == "A"  # hit: "a" becomes the most recent
    cache.get("c", lambda: "C")  # evicts "b", the least recently used
    assert len(cache) == 2 and cache.get("b", lambda: "B2") == "B2" and cache.misses == 4


@pytest.mark.parametrize("sizes", [((64, 48), (40, 40)), ((40, 40), (64, 48))])
def test_scene_renderer_resized_equals_a_fresh_renderer(ctx, tmp_path, sizes):
    """A renderer drawn at one size, then another (new aspect: the cached camera upload must be redone; new
    attachments: cached views must be remade), gives exactly the bytes a new renderer gives at that size."""
    scene = parse_scene(SCENE, tmp_path / "scene.toml")
    reused = SceneRenderer(ctx, scene, build_plan(scene))
    first, second = sizes
    for size in (first, second):
        target = create_target(ctx, size, reused.plan.output_format)
        got = render_frame(ctx, reused, target)[0]
        fresh_target = create_target(ctx, size, reused.plan.output_format)
        want = render_frame(ctx, SceneRenderer(ctx, scene, build_plan(scene)), fresh_target)[0]
        np.testing.assert_array_equal(got, want)
        assert got[..., :3].max() > 0, "something was drawn"
