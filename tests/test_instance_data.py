"""Instance data without vertex-stage storage (issue 31, the GL regression): the plan's ``instance_data`` knob.

On NVIDIA's EGL (driver 580) every scene failed with naga's "The selected version doesn't support BUFFER_STORAGE":
the scene shader read each instance's Object block from a storage buffer in the vertex stage. The fallback reads
the same blocks as per-instance vertex attributes. Checked here: the rule per adapter (expected values from the
rule's statement: OpenGL or no storage buffers -> vertex), the same pixels from both ways on lavapipe (exactly:
one run, one machine) and against the raw path, the CPU culling the vertex way needs (its count against the
plane test written out in tests/test_culling.py), and the failure itself reproduced on llvmpipe pushed to a GL 3.3
context without SSBOs (Mesa's overrides): the storage way is refused there in one line and "auto" renders.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from test_culling import COPIES, spheres_in_view, write_scene

from wgpurender.core.errors import UserError
from wgpurender.core.plan import AdapterFacts, Knobs, resolve_knobs
from wgpurender.core.plan.culling import GPU_CULL_MIN
from wgpurender.core.plan.instance_data import resolve_instance_data
from wgpurender.core.scene import parse_scene

REPO = Path(__file__).resolve().parents[1]
VULKAN = AdapterFacts.of("CPU", ("immediates", "indirect-first-instance"), "lavapipe", "Vulkan")
GL = AdapterFacts.of("CPU", ("indirect-first-instance",), "llvmpipe", "OpenGL",
                     {"max-storage-buffers-per-shader-stage": 16, "max-compute-invocations-per-workgroup": 1024})
GLES30 = AdapterFacts.of("Other", (), "a GLES 3.0 GPU", "OpenGL",
                         {"max-storage-buffers-per-shader-stage": 0, "max-compute-invocations-per-workgroup": 0})


# -- the rule ------------------------------------------------------------------------------------------------------
def test_a_gl_context_below_4_has_neither_storage_nor_compute():
    """NVIDIA's EGL context is "3.3.0 NVIDIA 580.159.04" (the H100 run): naga writes GLSL 330 there, which has no
    buffer storage (4.00) and no compute (4.30), though the ARB extensions make the limits say otherwise."""
    limits = {"max-storage-buffers-per-shader-stage": 16, "max-compute-invocations-per-workgroup": 1024}
    nvidia = AdapterFacts.of("Other", (), "NVIDIA H100", "OpenGL", limits, "3.3.0 NVIDIA 580.159.04")
    assert (nvidia.storage, nvidia.compute) == (False, False)
    gl42 = AdapterFacts.of("CPU", (), "llvmpipe", "OpenGL", limits, "4.2 (Core Profile) Mesa 22.3.6")
    assert (gl42.storage, gl42.compute) == (True, False)
    es31 = AdapterFacts.of("Other", (), "x", "OpenGL", limits, "OpenGL ES 3.1 Mesa")
    assert (es31.storage, es31.compute) == (True, True)
    es30 = AdapterFacts.of("Other", (), "x", "OpenGL", limits, "OpenGL ES 3.0 Mesa")
    assert (es30.storage, es30.compute) == (False, False)
    assert (GL.storage, GL.compute) == (True, True)  # no version string: the limits alone


def test_an_environment_is_refused_in_one_line_without_storage(allow_assets):
    scene = REPO / "assets" / "scenes" / "metal_rough_spheres_ibl.toml"
    from wgpurender.core.plan import resolve_plan

    with pytest.raises(UserError) as err:
        resolve_plan(scene, GLES30)
    assert "\n" not in str(err.value) and "[environment]" in str(err.value) and "--backend vulkan" in str(err.value)
    assert resolve_plan(scene, GL).uses_ibl


def test_an_environment_is_refused_in_one_line_without_compute(allow_assets):
    """Storage but no compute (a GL 4.2 context): the maps are made by compute passes, so the plan refuses it rather
    than letting the device fail on 'Downlevel flags COMPUTE_SHADERS are required' (found by review)."""
    scene = REPO / "assets" / "scenes" / "metal_rough_spheres_ibl.toml"
    from wgpurender.core.plan import resolve_plan

    limits = {"max-storage-buffers-per-shader-stage": 16, "max-compute-invocations-per-workgroup": 1024}
    gl42 = AdapterFacts.of("CPU", (), "llvmpipe", "OpenGL", limits, "4.2 (Core Profile) Mesa 22.3.6")
    with pytest.raises(UserError) as err:
        resolve_plan(scene, gl42)
    assert "\n" not in str(err.value) and "compute shaders" in str(err.value)
    assert "--backend vulkan" in str(err.value)


def test_limits_become_the_storage_and_compute_facts():
    assert (GL.storage, GL.compute) == (True, True)
    assert (GLES30.storage, GLES30.compute) == (False, False)
    assert (VULKAN.storage, VULKAN.compute) == (True, True)  # no limits given: core Vulkan has both


@pytest.mark.parametrize("adapter, knob, expected", [
    (VULKAN, "auto", "storage"),
    (GL, "auto", "vertex"),      # storage offered, but the vertex stage's own count is hidden on GL
    (GLES30, "auto", "vertex"),
    (AdapterFacts("DiscreteGPU", backend="Metal", storage=False), "auto", "vertex"),
    (None, "auto", "storage"),   # not known yet: the renderer re-plans for its adapter
    (VULKAN, "vertex", "vertex"),
    (GL, "storage", "storage"),  # llvmpipe's GL 4.5 reads vertex-stage storage: allowed when asked
])
def test_the_rule_per_adapter(adapter, knob, expected):
    value, why = resolve_instance_data(knob, adapter)
    assert value == expected
    assert ("vertex buffer stepped per instance" in why) == (expected == "vertex")
    if adapter is GL and knob == "auto":
        assert "BUFFER_STORAGE" in why and "downlevel" in why


def test_storage_is_refused_in_one_line_where_there_is_none(tmp_path):
    with pytest.raises(UserError) as err:
        resolve_knobs(parse_scene(write_scene(tmp_path).read_text(), tmp_path / "row.toml"),
                      Knobs(adapter=GLES30, instance_data="storage"))
    text = str(err.value)
    assert "\n" not in text and "a GLES 3.0 GPU" in text and "instance_data = vertex" in text
    with pytest.raises(UserError, match="instance_data"):
        Knobs(instance_data="uniform").check()


def test_explain_says_which_way_and_lists_no_object_group(tmp_path):
    path = write_scene(tmp_path)
    scene = parse_scene(path.read_text(), path)
    gl = resolve_knobs(scene, Knobs(adapter=GL))
    vk = resolve_knobs(scene, Knobs(adapter=VULKAN))
    assert gl.instance_data == "vertex" and vk.instance_data == "storage"
    assert "instance_data" in gl.explain() and "BUFFER_STORAGE" in gl.explain()
    assert "vertex (step mode instance)" in dict(gl.buffers)["scene-objects"]
    assert dict(vk.buffers)["scene-objects"].startswith("storage")
    names = {(o.kind, o.name) for o in gl.objects}
    assert ("bind_group", "objects") not in names and ("bind_group_layout", "Object-layout") not in names
    assert ("bind_group", "objects") in {(o.kind, o.name) for o in vk.objects}


def test_culling_without_the_gpu_pass_is_planned_on_the_cpu(tmp_path):
    path = write_scene(tmp_path, GPU_CULL_MIN)
    scene = parse_scene(path.read_text(), path)
    gl = resolve_knobs(scene, Knobs(adapter=GL))
    assert gl.setting("culling") == "cpu" and len(gl.cpu_culled_draws) == 1 and not gl.culled_draws
    assert "culled on the CPU" in gl.explain() and f"({GPU_CULL_MIN} instances)" in gl.explain()
    no_compute = resolve_knobs(scene, Knobs(adapter=AdapterFacts("CPU", frozenset({"indirect-first-instance"}),
                                                                 backend="Vulkan", compute=False)))
    assert no_compute.instance_data == "storage" and no_compute.setting("culling") == "cpu"
    assert "no compute shaders" in no_compute.explain()
    assert resolve_knobs(scene, Knobs(adapter=VULKAN)).setting("culling") == "gpu"  # unchanged where it runs
    with pytest.raises(UserError) as err:  # the GPU pass cannot run: asked for, it is refused, not ignored
        resolve_knobs(scene, Knobs(adapter=GL, culling="gpu"))
    assert "\n" not in str(err.value) and "culling = auto or cpu" in str(err.value)
    small = resolve_knobs(parse_scene(write_scene(tmp_path).read_text(), path), Knobs(adapter=GL))
    assert small.setting("culling") == "off" and not small.cpu_culled_draws


# -- pixels on lavapipe ----------------------------------------------------------------------------------------------
def _render(ctx, path, size=None, **knobs):
    from wgpurender.wgpu_path.scene import load_renderer, render_frame

    renderer = load_renderer(path, ctx, size=size, knobs=knobs)
    return renderer, render_frame(ctx, renderer, renderer.create_output())[0]


def _mirrored_lit_scene(folder: Path) -> Path:
    """Brick cubes (albedo, normal and roughness maps, lit by a directional and a point light) as instances, two of
    them mirrored (negative scale: their own draw, first_instance > 0), plus an unlit cube of another variant."""
    from wgpurender.core.view import transforms

    bricks = REPO / "assets" / "models" / "brick_cube.obj"
    maps = {k: (REPO / "assets" / "textures" / f"brick_{k}.png").as_posix() for k in ("albedo", "normal", "roughness")}
    np.save(folder / "m.npy", np.stack([
        transforms.translate((-2.2, 0.8, 0)) @ transforms.rotate((1, 1, 0), 0.5),
        transforms.translate((0, -0.9, 0)) @ np.diag([-0.8, 0.8, 0.8, 1]),
        transforms.translate((2.3, 0.5, -1)) @ transforms.rotate((0, 1, 0), 0.9),
        transforms.translate((0.2, 1.4, -2)) @ np.diag([0.7, -0.7, 0.7, 1])]))
    (folder / "s.toml").write_text(f"""
[camera]
eye = [0, 1, 8]
target = [0, 0, 0]
fov_y = 45
[[models]]
path = "{bricks.as_posix()}"
material = {{ albedo_map = "{maps['albedo']}", normal_map = "{maps['normal']}", roughness_map = "{maps['roughness']}" }}
instances = {{ file = "m.npy" }}
[[models]]
path = "{bricks.as_posix()}"
material = {{ albedo_color = [0.2, 0.7, 0.3], unlit = true }}
transform = {{ translate = [-2.5, -1.5, 0] }}
[[lights]]
type = "directional"
direction = [-1, -1, -2]
[[lights]]
type = "point"
position = [1, 2, 3]
intensity = 4
[render]
size = [96, 64]
msaa = 1
""")
    return folder / "s.toml"


@pytest.fixture
def allow_assets(monkeypatch):
    monkeypatch.setenv("WGPURENDER_ALLOW_PATHS", str(REPO / "assets"))


@pytest.mark.parametrize("scene", ["instanced", "final.toml", "gltf_features.toml"])
def test_vertex_attributes_give_the_storage_pixels(ctx, tmp_path, allow_assets, scene):
    """The fallback forced on lavapipe against the storage way and the raw path (which reads storage)."""
    from wgpurender.raw_path.render import render_reference

    path = _mirrored_lit_scene(tmp_path) if scene == "instanced" else REPO / "assets" / "scenes" / scene
    size = (96, 64)
    storage, a = _render(ctx, path, size, instance_data="storage")
    vertex, b = _render(ctx, path, size, instance_data="vertex")
    assert storage.plan.instance_data == "storage" and vertex.plan.instance_data == "vertex"
    assert vertex.scene_pass.object_group is None  # nothing in the vertex stage reads storage
    np.testing.assert_array_equal(a, b)
    if scene == "instanced":
        draws = vertex.plan.scene_pass.draws
        assert [d.instance_count for d in draws] == [2, 2, 1] and draws[1].first_instance == 2
        assert (b[..., :3].max(axis=2) > 20).mean() > 0.05  # five cubes at 96x64: 7.8% of it here
        np.testing.assert_array_equal(b, render_reference(str(path), size=size))


@pytest.mark.parametrize("instance_data", ["vertex", "storage"])
def test_cpu_culling_draws_what_the_plane_test_keeps(ctx, tmp_path, instance_data):
    from wgpurender.raw_path.render import render_reference

    path = write_scene(tmp_path)
    culled, a = _render(ctx, path, instance_data=instance_data, culling="cpu")
    plain, b = _render(ctx, path, instance_data=instance_data, culling="off")
    assert culled.plan.setting("culling") == "cpu" and culled.scene_pass.culler is None
    (draw,) = culled.plan.cpu_culled_draws
    want = spheres_in_view(path)
    assert 0 < want < COPIES and culled.scene_pass.cpu_culler.count(draw) == want
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(a, render_reference(str(path), size=None))
    lit = a[..., :3].max(axis=2) > 200
    assert 0.05 < lit.mean() < 0.9


def test_cpu_culler_moves_the_visible_blocks_to_the_front(ctx, tmp_path):
    """The uploaded blocks of a culled draw are exactly the visible copies' blocks, in scene order."""
    from wgpurender.core.plan.batches import instance_blocks

    path = write_scene(tmp_path)
    culled, _ = _render(ctx, path, instance_data="vertex", culling="cpu")
    (draw,) = culled.plan.cpu_culled_draws
    n = culled.scene_pass.cpu_culler.count(draw)
    data = np.frombuffer(ctx.read_buffer(culled.scene_pass.object_buffer), np.float32).reshape(COPIES, 32)
    xs = data[:n, 12]  # the world matrix's translation x (column 3, row 0)
    spacing = 3.0
    full = instance_blocks((draw,))
    full[:, 27] = full[:, 28]  # the vertex way reads the mirror sign from the third normal column's padding
    kept = [k for k in range(COPIES) if full[k, 12] in set(xs.tolist())]
    assert len(kept) == n and list(np.diff(xs) > 0) == [True] * (n - 1)  # scene order: x grows
    assert kept == list(range(kept[0], kept[0] + n))  # one contiguous run of copies around the view's centre
    assert abs(xs.mean()) < spacing  # centred on the camera's axis
    np.testing.assert_array_equal(data[:n], full[kept])


# -- the regression, reproduced on llvmpipe's GL ------------------------------------------------------------------
# A GL 3.3 core context without the SSBO and compute extensions: wgpu then lacks DownlevelFlags::VERTEX_STORAGE,
# as NVIDIA's EGL context does (there naga's GLSL version refuses BUFFER_STORAGE; here wgpu-core refuses the
# vertex-stage storage binding first).
NO_VERTEX_STORAGE = {"MESA_GL_VERSION_OVERRIDE": "3.3", "MESA_GLSL_VERSION_OVERRIDE": "330",
                     "MESA_EXTENSION_OVERRIDE": "-GL_ARB_compute_shader -GL_ARB_shader_storage_buffer_object"}
CHILD = """
import sys, numpy as np
from wgpurender import api
from wgpurender.wgpu_path.device import context
from wgpurender.core.errors import UserError
if sys.argv[4] == "unchecked":  # the canary below: draw on a context the renderer refuses
    context.refuse_broken_gl = lambda adapter: None
try:
    print(context.get_context("opengl").adapter.info["description"], flush=True)
    np.save(sys.argv[2], api.render(sys.argv[1], backend="opengl", size=(96, 64), instance_data=sys.argv[3]).pixels)
except UserError as err:
    print("refused:", err)
"""


def _gl_child(path: Path, out: Path, instance_data: str, env: dict, check: str = "checked") -> list[str]:
    done = subprocess.run([sys.executable, "-c", CHILD, str(path), str(out), instance_data, check],
                          capture_output=True, text=True, timeout=300, cwd=REPO, env={**os.environ, **env})
    if "no OpenGL adapter" in done.stderr + done.stdout:
        pytest.skip("this machine has no OpenGL adapter")
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.splitlines()


def test_a_gl_context_without_vertex_storage_renders_the_same_pixels(ctx, tmp_path, allow_assets):
    path = _mirrored_lit_scene(tmp_path)
    lines = _gl_child(path, tmp_path / "old.npy", "auto", NO_VERTEX_STORAGE)
    if not lines[0].startswith("3.3") or "Mesa" not in lines[0]:
        pytest.skip(f"Mesa's version override did not apply (GL {lines[0]}): not llvmpipe")
    refused = _gl_child(path, tmp_path / "storage.npy", "storage", NO_VERTEX_STORAGE)
    assert refused[1].startswith("refused: instance_data = storage cannot run on")
    assert "max-storage-buffers-per-shader-stage is 0, or a GL context below 4.0" in refused[1]
    _gl_child(path, tmp_path / "full.npy", "auto", {})  # the same llvmpipe at its own GL 4.5
    old, full = np.load(tmp_path / "old.npy"), np.load(tmp_path / "full.npy")
    np.testing.assert_array_equal(old, full)
    _, vulkan = _render(ctx, path, (96, 64))
    assert np.abs(old.astype(int) - vulkan.astype(int)).max() <= 2  # GL against Vulkan: llvmpipe vs lavapipe


# NVIDIA's case exactly: GL 3.3 with the ARB storage and compute extensions, so wgpu's limits claim both.
GL33_WITH_EXTENSIONS = {"MESA_GL_VERSION_OVERRIDE": "3.3", "MESA_GLSL_VERSION_OVERRIDE": "330",
                        "WGPURENDER_VALIDATION": "0"}
GL42_WITH_EXTENSIONS = {**GL33_WITH_EXTENSIONS, "MESA_GL_VERSION_OVERRIDE": "4.2", "MESA_GLSL_VERSION_OVERRIDE": "420"}


def test_a_gl_42_context_with_compute_draws_like_vulkan(ctx, tmp_path, allow_assets):
    """The refusal's edge: at GL 4.2 with GL_ARB_compute_shader wgpu binds right (GLSL 420 has binding qualifiers),
    so it is not refused, and it draws what Vulkan draws, also without the tests' validation flags."""
    path = _mirrored_lit_scene(tmp_path)
    lines = _gl_child(path, tmp_path / "gl42.npy", "auto", GL42_WITH_EXTENSIONS)
    if not lines[0].startswith("4.2"):
        pytest.skip(f"Mesa's version override did not apply (GL {lines[0]})")
    _, vulkan = _render(ctx, path, (96, 64))
    assert np.abs(np.load(tmp_path / "gl42.npy").astype(int) - vulkan.astype(int)).max() <= 2


def test_a_gl_context_wgpu_binds_wrongly_is_refused_in_one_line(tmp_path):
    """GL 3.3 with GL_ARB_compute_shader (NVIDIA's EGL): wgpu then binds every uniform block and texture at 0 and
    draws wrong images with no error (the canary below); the renderer refuses it instead."""
    from helpers import one_line_refusal

    done = subprocess.run([sys.executable, "-m", "wgpurender", "render", "unlit", "--backend", "opengl", "-o",
                           str(tmp_path / "x.png")], capture_output=True, text=True, timeout=300, cwd=REPO,
                          env={**os.environ, **GL33_WITH_EXTENSIONS})
    if "no OpenGL adapter" in done.stderr:
        pytest.skip("this machine has no OpenGL adapter")
    if "(3.3" not in done.stderr:
        pytest.skip(f"Mesa's version override did not apply: {done.stderr[-300:]}")
    one_line_refusal(done.returncode, done.stderr, "cannot draw correctly", "GL_ARB_compute_shader",
                     "--backend vulkan")
    assert not (tmp_path / "x.png").exists()


def test_which_gl_contexts_wgpu_binds_wrongly():
    from wgpurender.core.plan.gl_facts import gl_binding_fault

    assert "slot 0" in gl_binding_fault("3.3.0 NVIDIA 580.159.04", 1024)  # the H100's EGL context
    assert gl_binding_fault("3.3.0 NVIDIA 580.159.04", 0) == ""  # no compute: wgpu binds by name, right
    # llvmpipe with the compute extension, unlit against Vulkan: 4.1 drew 12.04% of pixels wrong, 4.2 none
    assert "slot 0" in gl_binding_fault("4.1 (Core Profile) Mesa 22.3.6", 1024)
    assert gl_binding_fault("4.2 (Core Profile) Mesa 22.3.6", 1024) == ""  # GLSL 420 has binding qualifiers
    assert gl_binding_fault("OpenGL ES 3.1 Mesa 22.3.6", 128) == ""  # so has GLSL ES 310


def test_post_path_compute_is_refused_or_falls_back_without_compute(tmp_path):
    import dataclasses

    from wgpurender.core.plan.post import resolve_post_path

    nvidia_gl = AdapterFacts.of("DiscreteGPU", (), "NVIDIA H100", "OpenGL",
                                {"max-compute-invocations-per-workgroup": 1024}, "3.3.0 NVIDIA 580.159.04")
    scene = parse_scene(write_scene(tmp_path).read_text(), tmp_path / "row.toml")
    with pytest.raises(UserError) as err:
        resolve_post_path(scene.render, Knobs(adapter=nvidia_gl, post_path="compute"))
    assert "\n" not in str(err.value) and "post_path = fragment" in str(err.value)
    for asked in ("compute", "auto"):  # the scene's own setting, or auto on a "discrete" GPU: fragment, said why
        render = dataclasses.replace(scene.render, post_path=asked)
        path, why = resolve_post_path(render, Knobs(adapter=nvidia_gl))
        assert path == "fragment" and "no compute shaders" in why
    assert resolve_post_path(scene.render, Knobs(adapter=VULKAN, post_path="compute"))[0] == "compute"



def test_cpu_culling_of_a_later_stretched_draw(ctx, tmp_path):
    """The culled draw starts at instance 1 (a red cube is drawn first) and its copies are stretched 3x along x, so
    a copy whose centre lies outside the view still reaches into it: the sphere must grow with the largest axis
    scale, and the visible blocks must go where this draw's instances start."""
    from wgpurender.core.models import procedural

    procedural.write_obj(tmp_path / "cube.obj", procedural.box(1.0))
    procedural.write_obj(tmp_path / "other.obj", procedural.box(1.0))
    text = """
[camera]
eye = [0, 0, 12]
target = [0, 0, 0]
fov_y = 40
[[models]]
path = "other.obj"
material = { albedo_color = [1, 0, 0], unlit = true }
transform = { translate = [0, 1.5, 0], scale = 0.5 }
[[models]]
path = "cube.obj"
material = { albedo_color = [1, 1, 1], unlit = true }
transform = { scale = [3, 1, 1] }
instances = { grid = [15, 1, 1], spacing = [1.1, 1, 1] }
[render]
size = [96, 48]
msaa = 1
"""
    path = tmp_path / "s.toml"
    path.write_text(text)
    culled, a = _render(ctx, path, instance_data="vertex", culling="cpu")
    _, b = _render(ctx, path, instance_data="vertex", culling="off")
    draw = culled.plan.cpu_culled_draws[0]
    assert draw.first_instance == 1 and draw.instance_count == 15
    scene = parse_scene(text, path)
    worlds = scene.models[1].worlds()  # the scene's own copies: the plane test written out here
    m = scene.camera.projection(96 / 48) @ scene.camera.view()
    planes = np.array([m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]])
    planes /= np.linalg.norm(planes[:, :3], axis=1, keepdims=True)
    radii = np.sqrt(3) / 2 * 3.0  # the unit cube's sphere, times the stretch along x
    keep = np.all(worlds[:, :3, 3] @ planes[:, :3].T + planes[:, 3] >= -radii, axis=1)
    assert culled.scene_pass.cpu_culler.count(draw) == keep.sum() == 7
    np.testing.assert_array_equal(a, b)

    class Spy:  # what record_draws puts in the bundle: the draws' (instance count, first instance)
        def __init__(self):
            self.draws = []

        def __getattr__(self, name):
            return lambda *args: self.draws.append(args[1::3]) if name == "draw_indexed" else None

    spy = Spy()
    culled.scene_pass.record_draws(spy)
    assert spy.draws == [(1, 0), (7, 1)]  # the red cube, then the 7 visible copies from instance 1 on
    assert (a[..., 0] > 200).any() and ((a[..., 0] > 200) & (a[..., 1] < 50)).any()  # white copies and the red cube


@pytest.mark.xfail(strict=True, reason="wgpu 29's GL backend on a GL 3.3 context that has GL_ARB_compute_shader draws "
                   "no geometry (NVIDIA's EGL on the H100: unlit 12.04% of pixels off, the 3d stage 14.91%, the same "
                   "numbers as llvmpipe here): wgpu-hal trusts binding qualifiers GLSL 330 lacks "
                   "(SHADER_BINDING_LAYOUT from compute support); strict: notices the day it is fixed "
                   "(docs/backends.md)")
def test_gl_33_with_the_compute_extension_draws_like_vulkan(ctx, tmp_path):
    """Drawn past the renderer's refusal (refuse_broken_gl), with the tests' validation flags (no indirect-call
    validation). When it passes, wgpu binds right there and the refusal can go (docs/backends.md)."""
    env = {k: v for k, v in GL33_WITH_EXTENSIONS.items() if k != "WGPURENDER_VALIDATION"}
    scene = REPO / "assets" / "scenes" / "unlit.toml"
    lines = _gl_child(scene, tmp_path / "gl33.npy", "auto", env, "unchecked")
    if not lines[0].startswith("3.3"):
        pytest.skip(f"Mesa's version override did not apply (GL {lines[0]})")
    no_compute = {**env, "MESA_EXTENSION_OVERRIDE": "-GL_ARB_compute_shader"}
    without = _gl_child(scene, tmp_path / "plain.npy", "auto", no_compute)
    assert without[0].startswith("3.3")
    _, vulkan = _render(ctx, scene, (96, 64))
    np.testing.assert_array_equal(np.load(tmp_path / "plain.npy"), vulkan)  # not the xfail: 3.3 alone is fine
    np.testing.assert_array_equal(np.load(tmp_path / "gl33.npy"), vulkan)


def test_the_vertex_way_fits_beside_the_coordinate_slots(ctx, tmp_path):
    """tests/test_gltf_uv_sets.py's four-slot material (a normal map; the base colour, emissive and occlusion maps on
    slots 1-3) reads position, normal, uv, tangent and uv1..uv3 (locations 0-7); the 7 instance attributes take
    locations 9-15, after the 9 a vertex may have, inside WebGPU's 16: it renders exactly as the storage way does."""
    from test_gltf_uv_sets import write_case, write_scene

    from wgpurender.wgpu_path.scene.shader_interface import ATTRIBUTE_LOCATIONS, instance_layout

    scene = write_scene(tmp_path, write_case(tmp_path, "four_slots"))
    _, a = _render(ctx, scene, instance_data="storage")
    vertex, b = _render(ctx, scene, instance_data="vertex")
    variant = vertex.plan.variant(vertex.plan.scene_pass.draws[0].variant_key)
    assert variant.vertex_attributes == ("position", "normal", "uv", "tangent", "uv1", "uv2", "uv3")
    locations = [x["shader_location"] for x in instance_layout(variant)["attributes"]]
    assert locations == list(range(9, 16)) and max(loc for loc, _ in ATTRIBUTE_LOCATIONS.values()) == 8
    np.testing.assert_array_equal(a, b)


# -- the one storage binding's limit (review finding: a validation error past max-storage-buffer-binding-size) ----
def _bound(blocks: int) -> AdapterFacts:
    """lavapipe's facts with room for exactly ``blocks`` 128-byte Object blocks in one storage binding."""
    return AdapterFacts.of("CPU", ("immediates", "indirect-first-instance"), "lavapipe", "Vulkan",
                           {"max-storage-buffer-binding-size": 128 * blocks})


def test_auto_takes_the_vertex_way_past_the_storage_binding_limit(tmp_path):
    path = write_scene(tmp_path, copies=12)
    scene = parse_scene(path.read_text(), path)
    assert resolve_knobs(scene, Knobs(adapter=_bound(12))).instance_data == "storage"  # 12 x 128 bytes: fits
    over = resolve_knobs(scene, Knobs(adapter=_bound(11)))
    assert over.instance_data == "vertex"
    assert "12 instances' Object blocks (1536 bytes) pass the device's max-storage-buffer-binding-size (1408 bytes)" \
        in over.explain()
    with pytest.raises(UserError) as err:
        resolve_knobs(scene, Knobs(adapter=_bound(11), instance_data="storage"))
    assert "\n" not in str(err.value) and "1536 bytes" in str(err.value) and "instance_data = vertex" in str(err.value)
    assert _bound(11) == VULKAN  # the limit is no fact the raw path's plan compares


def _coincident(folder: Path, copies: int) -> Path:
    """``copies`` copies of one white triangle, all at the origin (spacing 0 in x): the image of any number of
    them is the image of one."""
    (folder / "tri.obj").write_text("v -0.8 -0.8 0\nv 0.8 -0.8 0\nv 0 0.8 0\nf 1 2 3\n")
    path = folder / f"copies{copies}.toml"
    path.write_text(f"""[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov_y = 40
[[models]]\npath = "tri.obj"\nmaterial = {{ albedo_color = [1, 1, 1], unlit = true }}
instances = {{ grid = [{copies}, 1, 1], spacing = [0, 1, 1] }}
[render]\nsize = [16, 12]\nmsaa = 1\nhdr = false\n""")
    return path


def test_more_instances_than_one_storage_binding_holds_render_or_are_refused_in_one_line(ctx, tmp_path):
    """One copy past the device's storage binding (lavapipe: 128 MiB, 1,048,576 Object blocks; a validation error
    on both paths before). The wgpu path's plan takes the vertex way and draws what one copy draws (on the raw
    path: an independent image); the raw path, which has only the storage way, refuses in one line."""
    from wgpurender.core.scene.model import MAX_INSTANCES
    from wgpurender.raw_path import render_reference
    from wgpurender.raw_path.device.context import get_vulkan
    from wgpurender.wgpu_path.scene import render_scene_file

    copies = ctx.device.limits["max-storage-buffer-binding-size"] // 128 + 1
    raw_copies = get_vulkan().limits.max_storage_buffer_range // 128 + 1  # the same as wgpu's on lavapipe
    if max(copies, raw_copies) > MAX_INSTANCES:  # NVIDIA: 2 GiB (wgpu) and 4 GiB (Vulkan) bindings
        pytest.skip(f"the adapter's storage binding holds {max(copies, raw_copies) - 1} copies, more than a model "
                    f"may have ({MAX_INSTANCES}): drawn where the binding is small (lavapipe: 1,048,576 copies)")
    one = render_reference(str(_coincident(tmp_path, 1)), (16, 12))
    assert one[..., 0].any()
    result = render_scene_file(str(_coincident(tmp_path, copies)), size=(16, 12), ctx=ctx, frames=1)
    assert result.plan.instance_data == "vertex"
    assert np.array_equal(result.pixels, one)
    with pytest.raises(UserError) as err:
        render_reference(str(_coincident(tmp_path, raw_copies)), (16, 12))
    assert "\n" not in str(err.value) and f"{raw_copies} instances" in str(err.value)
    assert f"holds {raw_copies - 1}" in str(err.value)
