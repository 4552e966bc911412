"""Per-frame caches (issue 7) never serve a stale object: post-chain bind groups and views, the scene's
camera upload and attachment views; and the one GPU cache type (wgpurender/wgpu_path/device/gpu_cache.py) is bounded,
counts hits and misses, and goes with its device.

Each check renders with a renderer or chain that has cached objects from an earlier frame and compares
with an independent result: a numpy float64 reference (rtol 2e-3 + atol 1e-3 for rgba16float outputs,
as in tests/test_post.py), or a fresh renderer that has no caches (bit-exact: same GPU arithmetic).
"""

from __future__ import annotations

import gc
import weakref
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
import wgpu
from test_post import ATOL, RTOL, ref_aces, ref_vignette, upload

from wgpurender.bench.calls import count_frame, steady_calls
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import parse_scene
from wgpurender.wgpu_path.device.gpu_cache import GpuCache, cache_stats, device_cache
from wgpurender.wgpu_path.device.targets import TARGET_USAGE, create_target, read_texture
from wgpurender.wgpu_path.post import PostChain, create_effect
from wgpurender.wgpu_path.scene import SceneRenderer, render_frame

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


def ToneMap(**params):  # noqa: N802
    return create_effect("tonemap", **params)


def Vignette(**params):  # noqa: N802
    return create_effect("vignette", **params)


def _runners(chain: PostChain):
    ((runner, _textures),) = chain._built.values()
    return runner.runners


def _reference(img: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    return ref_vignette(ref_aces(img.astype(np.float64), exposure), 0.5, 0.5, 0.5)


def test_chain_alternating_sources_and_targets_gives_each_its_own_image(ctx):
    """Two sources into two targets, alternately (A->X, B->Y, A->Y, B->X): every output is the reference of
    the source it was given, so a bind group or view cached for one texture is never used for another."""
    chain = PostChain([ToneMap(), Vignette(strength=0.5)], fuse=False)
    images = [_image(1), _image(2)]
    sources = [upload(ctx, img) for img in images]
    targets = [create_target(ctx, (32, 24), "rgba16float") for _ in range(2)]
    for s, t in [(0, 0), (1, 1), (0, 1), (1, 0), (0, 0)]:
        got = _run(ctx, chain, sources[s], targets[t])
        np.testing.assert_allclose(got, _reference(images[s]), rtol=2 * RTOL, atol=ATOL)
    tonemap = _runners(chain)[0]
    assert tonemap.groups.misses == 2, "one bind group per source, reused after that"


def test_chain_resized_renders_the_new_size_and_drops_old_entries(ctx):
    """32x24, then 16x12, then 32x24 again: each matches its reference; the resize empties the caches."""
    chain = PostChain([ToneMap(), Vignette(strength=0.5)], fuse=False)
    for w, h, seed in [(32, 24, 3), (16, 12, 4), (32, 24, 5)]:
        img = _image(seed, w, h)
        got = _run(ctx, chain, upload(ctx, img), create_target(ctx, (w, h), "rgba16float"))
        np.testing.assert_allclose(got, _reference(img), rtol=2 * RTOL, atol=ATOL)
        vignette = _runners(chain)[1]
        assert len(vignette.groups) == 1 and len(vignette.views) == 1


def test_gpu_cache_keeps_the_most_recent_entries_and_counts():
    cache: GpuCache[str] = GpuCache("test", capacity=2)
    assert cache.get("a", lambda: "A") == "A" and cache.get("b", lambda: "B") == "B"
    assert cache.get("a", lambda: "new") == "A"  # hit: "a" becomes the most recent
    cache.get("c", lambda: "C")  # evicts "b", the least recently used
    assert len(cache) == 2 and cache.get("b", lambda: "B2") == "B2"
    assert cache.stats() == {"size": 2, "capacity": 2, "hits": 1, "misses": 4, "evictions": 2}


def test_device_caches_go_with_their_device():
    """Caches hang on the device object, so no module dict keeps a device (and what it made) alive."""

    class Device:  # stands in for a GPUDevice: any object that takes attributes
        pass

    device = Device()
    made = device_cache(device, "post-pipelines", capacity=8)
    made.get("key", lambda: object())
    assert device_cache(device, "post-pipelines") is made and cache_stats(device)["post-pipelines"]["misses"] == 1
    alive = weakref.ref(device)
    del device, made
    gc.collect()
    assert alive() is None


def test_renderer_pipelines_live_in_named_device_caches(ctx, tmp_path):
    """A second renderer of the same scene on the same device compiles no post pipeline again."""
    scene = parse_scene(SCENE, tmp_path / "scene.toml")
    SceneRenderer(ctx, scene, resolve_plan(scene, None))
    before = cache_stats(ctx.device)["post-pipelines"]
    SceneRenderer(ctx, scene, resolve_plan(scene, None))
    after = cache_stats(ctx.device)["post-pipelines"]
    assert after["misses"] == before["misses"] and after["hits"] > before["hits"]


@pytest.mark.parametrize("sizes", [((64, 48), (40, 40)), ((40, 40), (64, 48))])
def test_scene_renderer_resized_equals_a_fresh_renderer(ctx, tmp_path, sizes):
    """A renderer drawn at one size, then another (new aspect: the cached camera upload must be redone; new
    attachments: cached views must be remade), gives exactly the bytes a new renderer gives at that size."""
    scene = parse_scene(SCENE, tmp_path / "scene.toml")
    reused = SceneRenderer(ctx, scene, resolve_plan(scene, None))
    first, second = sizes
    for size in (first, second):
        target = create_target(ctx, size, reused.plan.target_format, usage=TARGET_USAGE | reused.target_usage)
        got = render_frame(ctx, reused, target)[0]
        fresh_target = create_target(ctx, size, reused.plan.target_format, usage=TARGET_USAGE | reused.target_usage)
        want = render_frame(ctx, SceneRenderer(ctx, scene, resolve_plan(scene, None)), fresh_target)[0]
        np.testing.assert_array_equal(got, want)
        assert got[..., :3].max() > 0, "something was drawn"


@pytest.mark.parametrize("post_path", ["fragment", "compute"])
def test_bound_frames_draw_into_the_target_they_are_given(ctx, tmp_path, post_path):
    """The untimed frame is bound once per target (SceneRenderer._bind, issue 31.4). Two targets of one size drawn
    in turn, then a target of another size, then the first again: each read-back equals what a fresh renderer on
    the fragment post path draws into a fresh target of that size (exactly on that path; within 1/255 on the
    compute path, an independent implementation of the same chain: tests/test_post_paths.py). A frame bound to
    one target and replayed into another would leave the second one empty (or the other size's image); a stale
    attachment, view, bind group or workgroup count would differ in bytes."""
    scene = parse_scene(SCENE, tmp_path / "scene.toml")
    plan = resolve_plan(scene, ctx.adapter_facts(), post_path=post_path)
    reused = SceneRenderer(ctx, scene, plan)

    def target(size, renderer=reused):
        return create_target(ctx, size, renderer.plan.target_format, usage=TARGET_USAGE | renderer.target_usage)

    want = {}
    for size in ((96, 40), (48, 64)):
        fresh = SceneRenderer(ctx, scene, resolve_plan(scene, ctx.adapter_facts(), post_path="fragment"))
        want[size] = render_frame(ctx, fresh, target(size, fresh))[0].astype(int)
        assert (want[size][..., :3].sum(-1) > 30).mean() > 0.05, "the scene is drawn"
    # sizes whose workgroup grids (the plan's dispatch shape, core/plan/dispatch.py) are not square: a swapped
    # count shows
    tolerance = 0 if post_path == "fragment" else 1
    a, b, c = target((96, 40)), target((96, 40)), target((48, 64))
    for tex, size in ((a, (96, 40)), (b, (96, 40)), (a, (96, 40)), (c, (48, 64)), (a, (96, 40))):
        got = render_frame(ctx, reused, tex)[0].astype(int)
        assert got.shape == want[size].shape and np.abs(got - want[size]).max() <= tolerance, (tex.size, size)


def _counted(obj, name: str, calls: Counter) -> None:
    """Count calls of ``obj.name`` (an instance attribute over the real method)."""
    real = getattr(obj, name)

    def call(*args, **kwargs):
        calls[name] += 1
        return real(*args, **kwargs)

    setattr(obj, name, call)


# (post_path, output_storage, post chain): the window's plans (output_storage False: a swapchain image is no storage
# texture, so the compute path's last pass writes a scratch copied into it), an offscreen output the last dispatch
# writes directly (its bind group names the target), and a scene with no post chain (the scene pass resolves into it)
WINDOW_CASES = [("fragment", False, True), ("compute", False, True), ("compute", True, True),
                ("fragment", False, False)]


@pytest.mark.parametrize(("post_path", "storage", "post"), WINDOW_CASES)
def test_a_new_target_each_frame_reuses_the_frame_bound_for_its_size(ctx, tmp_path, post_path, storage, post):
    """A window-like loop: every frame draws into a new texture object (as a swapchain hands out), 5 at one size, 3
    at another, 3 back at the first. Each read-back equals, exactly, what a fresh renderer of the same plan draws
    into a fresh target of that size; and the frame is bound once per size (SceneRenderer._bind_size, the scene
    pass and the post chain bound once), so only what names the new texture is made per frame: the post chain's
    last step (a view, a copy's argument, or the last dispatch's bind group) or, with no chain, the scene pass."""
    text = SCENE if post else SCENE.split("[[post]]")[0]
    scene = parse_scene(text, tmp_path / "scene.toml")
    plan = resolve_plan(scene, ctx.adapter_facts(), post_path=post_path, output_storage=storage)
    assert bool(plan.post_passes) is post
    reused = SceneRenderer(ctx, scene, plan)
    calls: Counter = Counter()
    _counted(reused, "_bind_size", calls)
    _counted(reused.chain, "bind", calls)
    _counted(reused.scene_pass, "bound", calls)
    for runner in reused.chain.runners:
        _counted(runner, "bound", calls)
        if hasattr(runner, "bound_source"):  # a render pass bound but for its target
            _counted(runner, "bound_source", calls)

    def target(size, renderer=reused):
        return create_target(ctx, size, renderer.plan.target_format, usage=TARGET_USAGE | renderer.target_usage)

    want = {}
    for size in ((96, 40), (48, 64)):
        fresh = SceneRenderer(ctx, scene, plan)
        want[size] = render_frame(ctx, fresh, target(size, fresh))[0]
        assert (want[size][..., :3].astype(int).sum(-1) > 30).mean() > 0.05, "the scene is drawn"
    sizes = [(96, 40)] * 5 + [(48, 64)] * 3 + [(96, 40)] * 3
    # a dispatch writing the target is bound again for each (its bind group names it); a render pass is bound for
    # its source once per size, and only its target's view is made per frame
    late = sum(p.output == "output" and p.path == "compute" for p in plan.post_passes)
    for frame, size in enumerate(sizes):
        got = render_frame(ctx, reused, target(size))[0]
        np.testing.assert_array_equal(got, want[size], err_msg=f"frame {frame} at {size}")
    changes = 3  # the sizes drawn in turn: each size's attachments are new, so its frame is bound again
    assert calls["_bind_size"] == changes
    assert calls["bind"] == (changes if post else 0)
    scene_binds = changes if post else len(sizes)  # with no chain the scene pass writes the target itself
    assert calls["bound"] + calls["bound_source"] == (
        scene_binds + changes * (len(plan.post_passes) - late) + len(sizes) * late), dict(calls)


@pytest.mark.parametrize(("post_path", "storage"), [("fragment", False), ("compute", False), ("compute", True)])
def test_a_new_target_each_frame_makes_no_gpu_object_but_what_names_it(ctx, tmp_path, post_path, storage):
    """Counted native calls (wgpurender/bench/calls.py) of a frame into a new texture of the same size, after the
    frame was bound for that size: the device makes nothing on the window's plans (the target's view is the
    texture's own call), and one bind group where the last dispatch writes the target directly."""
    scene = parse_scene(SCENE, tmp_path / "scene.toml")
    plan = resolve_plan(scene, ctx.adapter_facts(), post_path=post_path, output_storage=storage)
    renderer = SceneRenderer(ctx, scene, plan)

    def target():
        return create_target(ctx, (64, 48), plan.target_format, usage=TARGET_USAGE | renderer.target_usage)

    steady_calls(ctx, renderer.record, target())
    same = count_frame(ctx, renderer.record, target())
    made = {k: v for k, v in same.items() if k.startswith("device.create_") and k != "device.create_command_encoder"}
    direct = any(p.path == "compute" and p.output == "output" for p in plan.post_passes)
    assert direct is storage
    assert made == ({"device.create_bind_group": 1} if direct else {}), dict(same)


@pytest.mark.parametrize("path", ["fragment", "compute"])
def test_a_chain_into_an_output_of_another_size_is_refused_in_one_line(ctx, path):
    """The pass into the output is bound per output (PostRunner.bind's late step): a 16x12 output for a 32x24
    source is refused by name and both sizes, not drawn into a corner."""
    from wgpurender.core.errors import UserError

    chain = PostChain([ToneMap(), Vignette(strength=0.5)], fuse=False, path=path)
    source = upload(ctx, _image(6))
    usage = TARGET_USAGE | wgpu.TextureUsage.STORAGE_BINDING
    with pytest.raises(UserError, match=r"vignette.*\(32, 24\).*\(16, 12\) differ"):
        _run(ctx, chain, source, create_target(ctx, (16, 12), "rgba16float", usage=usage))
