"""A hand-written mutation run (issue 24, item 7): one-line changes a tired developer could make, each applied to a
copy of the repository, the tests that should notice run, the change reverted. Not collected by pytest.

    python tests/mutation_run.py [--only N,M] [--copy DIR]

Prints one line per mutation (caught / MISSED, by which test file) and a summary; docs/verification.md records
the last run. The copy is the committed tree (``git archive HEAD``), so the working tree is never touched; the
copy's modules come first on PYTHONPATH.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

API = "tests/test_api_validation.py"
CAUSES = "tests/test_reliability_causes.py"
INPUTS = "tests/test_reliability_inputs.py"
TRUST = "tests/test_trust.py"
REPORT = "tests/test_report_truth.py"
COMPARE = "tests/test_compare.py"
CLI = "tests/test_cli.py"
SAFETY = "tests/test_output_safety.py"
GLTF = CAUSES + "|gltf or node or accessor or indices or attributes"
INST = "tests/test_instancing.py"

# (file, text as committed, the tired developer's text, tests that should notice)
MUTATIONS = [
    # comparison and heatmap
    ("wgpurender/core/compare.py", "10 * np.log10(1.0 / mse)", "20 * np.log10(1.0 / mse)", [COMPARE, REPORT]),
    ("wgpurender/core/compare.py", "over_1=float(np.mean(per_pixel > 1))", "over_1=float(np.mean(per_pixel >= 1))",
     [COMPARE, REPORT]),
    ("wgpurender/core/compare.py", "max(axis=-1) * gain / 255.0", "max(axis=-1) * 32.0 / 255.0", [API, COMPARE]),
    ("wgpurender/core/compare.py", "max_abs=int(diff.max())", "max_abs=int(diff[..., 0].max())", [COMPARE, REPORT]),
    ("wgpurender/core/compare.py", 'psnr=float("inf") if mse == 0', 'psnr=0.0 if mse == 0', [COMPARE, API]),
    ("wgpurender/cli/compare.py", "return value < limit if name == \"psnr\"", "return value > limit if name == "
     "\"psnr\"", [COMPARE, CAUSES]),
    ("wgpurender/core/imageio.py", "12.92 * x, 1.055", "12.29 * x, 1.055", [API]),
    ("wgpurender/core/imageio.py", "gray = np.round(wide / 257.0)", "gray = np.round(wide / 256.0)", [INPUTS, COMPARE]),
    # the report
    ("wgpurender/report/page.py", '{_figure(files.get("wgpu"), "wgpu (WGSL', '{_figure(files.get("raw"), "wgpu (WGSL',
     [REPORT]),
    ("wgpurender/report/page.py", "<tr><th>PSNR</th><td colspan=2>{psnr}</td></tr>",
     "<tr><th>PSNR</th><td colspan=2>{c.flip_mean:.5f}</td></tr>", [REPORT]),
    ("wgpurender/report/page.py", "{100 * c.over_1:.3f}%</td></tr>", "{100 * c.over_2:.3f}%</td></tr>", [REPORT]),
    ("wgpurender/report/steps.py", "step.comparison = compare_images(step.raw, step.wgpu)",
     "step.comparison = compare_images(step.raw, step.raw)", [REPORT]),
    ("wgpurender/report/steps.py", "step.heat = heatmap(step.raw, step.wgpu, HEATMAP_GAIN)",
     "step.heat = heatmap(step.raw, step.wgpu, 1.0)", [REPORT]),
    # trust: driver class, present modes, depth, the API's path
    ("wgpurender/core/tolerances.py", 'return "lavapipe" if "llvmpipe" in device_name.lower()',
     'return "lavapipe" if "lavapipe" in device_name.lower()', [TRUST]),
    ("wgpurender/core/tolerances.py", "if metrics.changed > self.changed:", "if metrics.changed > 2 * self.changed:",
     [TRUST, "tests/test_reference_tolerances.py"]),
    ("wgpurender/raw_path/swapchain.py", '"immediate": vk.VK_PRESENT_MODE_IMMEDIATE_KHR',
     '"immediate": vk.VK_PRESENT_MODE_MAILBOX_KHR', [TRUST]),
    ("wgpurender/core/plan/build.py", 'depth_compare = "greater" if knobs.reverse_z else "less"',
     'depth_compare = "greater" if knobs.reverse_z else "less-equal"', [TRUST]),
    ("wgpurender/core/plan/build.py", 'depth_compare = "greater" if knobs.reverse_z else "less"',
     'depth_compare = "greater-equal" if knobs.reverse_z else "less"', [TRUST]),
    ("wgpurender/api.py", 'return Image(result.pixels, str(target), "wgpu"', 'return Image(result.pixels, '
     'str(target), "raw"', [TRUST]),
    ("wgpurender/api.py", "        return image.rgba8()", "        return image.pixels", [API]),
    # argument checks
    ("wgpurender/core/checks.py", "    if not math.isfinite(value):\n        raise UserError(f\"{name} must be a finite",  # noqa: E501
     "    if math.isnan(value):\n        raise UserError(f\"{name} must be a finite", [API, CAUSES]),
    ("wgpurender/core/checks.py", '    return positive(value, "gain", "32")', '    return number(value, "gain")',
     [API, COMPARE]),
    ("wgpurender/core/checks.py", "if not (0 < width <= MAX_SIZE and 0 < height <= MAX_SIZE)",
     "if not (0 <= width <= MAX_SIZE and 0 <= height <= MAX_SIZE)", [API, CLI]),
    ("wgpurender/core/checks.py", "    if count not in SAMPLE_COUNT_SHAPES:", "    if count > 64:", [API]),
    ("wgpurender/core/checks.py", "np.round(array.astype(np.float64) / 257.0)", "np.round(array.astype(np.float64)"
     " / 256.0)", [API]),
    ("wgpurender/core/checks.py", "        if not np.isfinite(array).all():", "        if np.isinf(array).all():",
     [API]),
    ("wgpurender/core/checks.py", "    elif not _is_number(value):", "    elif not isinstance(value, (int, float, "
     "str)):", [API]),
    ("wgpurender/core/checks.py", "    if array.shape[0] == 0 or array.shape[1] == 0:", "    if array.size < 0:", [API]),  # noqa: E501
    ("wgpurender/core/checks.py", "    return integer(value, \"gap\", 0, MAX_GAP)", "    return int(value)", [API]),
    ("wgpurender/api.py", "    gain = checks.gain(gain)\n", "", [API]),
    # input files and bounds
    ("wgpurender/core/input_files.py", "    kind = _kind(mode)\n    if kind is not None:",
     "    kind = _kind(mode)\n    if kind == 'never':", [CAUSES]),
    ("wgpurender/core/input_files.py", "    if err.errno == errno.ELOOP:", "    if err.errno == errno.EEXIST:", [CAUSES]),  # noqa: E501
    ("wgpurender/core/input_files.py", "    if width * height > limit:", "    if width > limit:", [CAUSES]),
    ("wgpurender/core/input_files.py", "        deepest = max(deepest, depth + 1)", "        deepest = max(deepest, "
     "depth)\n        depth = 0", [CAUSES]),
    ("wgpurender/core/input_files.py", "    if size > limit:", "    if size > limit * 4:", [CAUSES]),
    ("wgpurender/core/scene/load.py", "    except RecursionError:", "    except ValueError:", [CAUSES]),
    ("wgpurender/core/imageio.py", "    check_image_pixels(*image.size, name)\n", "", [CAUSES]),
    ("wgpurender/core/safe_write.py", "    if len(os.fsencode(name)) > _name_max(path.parent):",
     "    if len(os.fsencode(name)) > 1024:", [CAUSES]),
    ("wgpurender/core/safe_write.py", "    except OSError as err:\n        raise UserError(f\"refusing to write {link}: "  # noqa: E501
     "{os_error_reason(link, err)}\") from None", "    except OSError:\n        pass", [CAUSES + "|follow"]),
    ("wgpurender/core/safe_write.py", "    _handlers_installed = True\n    _set_handlers(signal.SIG_DFL)",
     "    _handlers_installed = True\n    _set_handlers(_on_signal)", [CAUSES + "|sigterm"]),
    ("wgpurender/core/gpu_memory.py", "BYTES_PER_PIXEL.get(fmt, 16) * max(int(samples), 1)",
     "BYTES_PER_PIXEL.get(fmt, 16)", [CAUSES + "|memory or adapter"]),
    ("wgpurender/core/gpu_memory.py", "CPU_MAX_ALLOCATION = 2**31", "CPU_MAX_ALLOCATION = 2**33", [CAUSES + "|adapter"]),  # noqa: E501
    # glTF rules
    ("wgpurender/core/gltf_rules.py", "            if child == i:", "            if child == j:", [GLTF]),
    ("wgpurender/core/gltf_rules.py", "            if node in seen:", "            if node == start and False:",
     [GLTF]),
    ("wgpurender/core/gltf_rules.py", '(r"POSITION", ("VEC3",), (FLOAT,))', '(r"POSITION", ("VEC3", "SCALAR"), '
     '(FLOAT,))', [GLTF]),
    ("wgpurender/core/gltf_rules.py", "INDEX_COMPONENTS = (UBYTE, USHORT, UINT)", "INDEX_COMPONENTS = (UBYTE, USHORT,"
     " UINT, FLOAT)", [GLTF]),
    ("wgpurender/core/gltf_rules.py", "            if count != counts[\"POSITION\"]:", "            if count < 0:",
     [GLTF]),
    # instancing and batching (issue 31.1)
    ("wgpurender/core/scene/instances.py", "axes = [(np.arange(k) - (k - 1) / 2.0) * s",
     "axes = [(np.arange(k) - k / 2.0) * s", [INST]),
    ("wgpurender/core/scene/instances.py", "z, y, x = np.meshgrid(axes[2], axes[1], axes[0], indexing=\"ij\")",
     "x, y, z = np.meshgrid(axes[0], axes[1], axes[2], indexing=\"ij\")", [INST]),
    ("wgpurender/core/scene/instances.py", "    if count > MAX_INSTANCES:", "    if count > 10 * MAX_INSTANCES:", [INST]),  # noqa: E501
    ("wgpurender/core/scene/instances.py", "    if len(forms) != 1:", "    if len(forms) > 1:", [INST]),
    ("wgpurender/core/scene/instances.py", "if \"spacing\" in t and forms[0] != \"grid\":",
     "if \"spacing\" in t and forms[0] == \"file\":", [INST]),
    ("wgpurender/core/scene/instances.py", "    if not np.isfinite(a).all():", "    if np.isinf(a).all():", [INST]),
    ("wgpurender/core/scene/instances.py", "(np.abs(transforms.determinants3(matrices)) < 1e-12).any()",
     "(np.abs(transforms.determinants3(matrices)) < 1e-12).all() and False", [INST]),
    ("wgpurender/core/scene/instances.py", "    m[:, :3, 3] = offsets", "    m[:, 3, :3] = offsets", [INST]),
    ("wgpurender/core/scene/model.py", "        return parent @ self.placements.array().astype(np.float64)",
     "        return self.placements.array().astype(np.float64) @ parent", [INST]),
    ("wgpurender/core/plan/batches.py", "    return (draw.model_path, draw.part, draw.pipeline_key, draw.material_key())",  # noqa: E501
     "    return (draw.model_path, draw.part, draw.pipeline_key)", [INST]),
    ("wgpurender/core/plan/batches.py", "        first += merged.instance_count", "        first += 1", [INST]),
    ("wgpurender/core/plan/batches.py", "out[:, :16] = worlds.transpose(0, 2, 1).reshape(-1, 16)",
     "out[:, :16] = worlds.reshape(-1, 16)", [INST]),
    ("wgpurender/core/plan/batches.py", "    return np.where((det >= 0)[:, None, None], cof, -cof)", "    return cof",
     [INST]),
    ("wgpurender/core/plan/batches.py", "out[:, 28] = np.where(determinants3(worlds) >= 0, 1.0, -1.0)",
     "out[:, 28] = 1.0", [INST]),
    ("wgpurender/core/transforms.py", "np.cross(m[..., 1, :], m[..., 2, :]))", "np.cross(m[..., 2, :], m[..., 1, :]))",
     [INST]),
    ("wgpurender/core/plan/batches.py", "        return (\"blend\", id(draw))", "        return (\"blend\",)",
     [INST]),
    ("wgpurender/core/plan/draws.py", "    return [(m, worlds[mirrored == m]) for m in dict.fromkeys(mirrored.tolist())]",  # noqa: E501
     "    return [(None, worlds)]", [INST]),
    ("wgpurender/core/plan/model.py", "        return (self.variant_key, self.textures, self.samplers, self.sampler, self.factors)",  # noqa: E501
     "        return (self.variant_key, self.textures, self.samplers, self.sampler)", [INST]),
    ("wgpurender/core/plan/explain.py", "lines.append(f\"         batch: instances {d.first_instance}..",
     "lines.append(f\"         batch: instances {d.first_instance}...", [INST]),
    ("wgpurender/core/plan/objects.py", "            materials = len({d.material_key() for d in users})",
     "            materials = len(users)", [INST]),
    ("wgpurender/wgpu_path/scene_render/scene_pass.py",
     "encoder.draw_indexed(count, draw.instance_count, first, 0, draw.first_instance)",
     "encoder.draw_indexed(count, draw.instance_count, first, 0, 0)", [INST]),
    ("wgpurender/wgpu_path/scene_render/scene_pass.py", "            if buffers is not last[3]:",
     "            if last[3] is None:", [INST]),
    ("wgpurender/wgpu_path/scene_render/scene_pass.py", "            if group is not None and group is not last[2]:",
     "            if group is not None and last[2] is None:", [INST]),
    ("wgpurender/raw_path/scene/scene_subpass.py",
     "vk.vkCmdDrawIndexed(cmd, count, draw.instance_count, first, 0, draw.first_instance)",
     "vk.vkCmdDrawIndexed(cmd, count, 1, first, 0, draw.first_instance)", [INST]),
    ("shaders_wgsl/scene.wgsl", "    let object_data = objects[instance];", "    let object_data = objects[0];", [INST]),  # noqa: E501
    ("shaders_glsl/scene.vert", "    Object object_data = objects[gl_InstanceIndex];",
     "    Object object_data = objects[gl_VertexIndex % 3];", [INST]),
    # GPU culling (issue 31.2)
    ("wgpurender/core/plan/culling.py", "    least = 2 if knob == \"gpu\" else GPU_CULL_MIN",
     "    least = 2 if knob == \"gpu\" else 2", ["tests/test_culling.py"]),
    ("wgpurender/core/plan/culling.py", "        del pipelines[key]", "        pass", ["tests/test_culling.py"]),
    ("wgpurender/wgpu_path/scene_render/culling.py", "planes = np.array([r[3] + r[0], r[3] - r[0], r[3] + r[1], r[3] - r[1],",  # noqa: E501
     "planes = np.array([r[3] + r[0], r[3] + r[0], r[3] + r[1], r[3] - r[1],", ["tests/test_culling.py"]),
    ("wgpurender/wgpu_path/scene_render/culling.py", "return centre, float(np.linalg.norm(p - centre, axis=1).max())",
     "return centre, float(np.linalg.norm(p - centre, axis=1).min())", ["tests/test_culling.py"]),
    ("wgpurender/wgpu_path/scene_render/culling.py", "(d.first_instance, d.instance_count, k * 5 + 1, 0)",
     "(d.first_instance, d.instance_count, k * 5, 0)", ["tests/test_culling.py"]),
    ("wgpurender/wgpu_path/scene_render/culling.py", "cpass.dispatch_workgroups(-(-d.instance_count // WORKGROUP))",
     "cpass.dispatch_workgroups(d.instance_count // WORKGROUP)", ["tests/test_culling.py"]),
    ("shaders_wgsl/scene_cull.wgsl", "        if (dot(plane.xyz, centre) + plane.w < -radius) {",
     "        if (dot(plane.xyz, centre) + plane.w < 0.0) {", ["tests/test_culling.py"]),
    ("shaders_wgsl/scene.wgsl", "    let object_data = objects[visible[instance]];", "    let object_data = objects[instance];",  # noqa: E501
     ["tests/test_culling.py"]),
    ("wgpurender/core/plan/objects.py", "        out.append(GpuObject(\"bind_group\", \"cull\", len(culled),",
     "        out.append(GpuObject(\"bind_group\", \"cull\", 1,", ["tests/test_plan_is_what_is_built.py|culled"]),
]


def _run(copy: Path, tests: list[str]) -> tuple[bool, str]:
    """(a test failed, which file) running the test files in the copy, stopping at the first failure."""
    env = dict(os.environ, PYTHONPATH=str(copy), LP_NUM_THREADS="1")
    for test in tests:
        try:
            file, _, select = test.partition("|")  # "FILE|EXPR": only the tests -k EXPR selects there
            argv = [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", file]
            result = subprocess.run(argv + (["-k", select] if select else []), cwd=copy, env=env,
                                    capture_output=True, text=True, timeout=240)
        except subprocess.TimeoutExpired:  # e.g. a FIFO opened for reading: the test run hangs, which is noticed
            return True, f"{Path(test.partition('|')[0]).name} (hung)"
        if result.returncode != 0:
            return True, Path(test.partition("|")[0]).name
    return False, ""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default="", help="comma-separated mutation numbers (1-based)")
    parser.add_argument("--copy", default=None, help="where to unpack the committed tree (default: a temp folder)")
    args = parser.parse_args()
    chosen = [int(n) for n in args.only.split(",") if n] or list(range(1, len(MUTATIONS) + 1))
    copy = Path(args.copy or tempfile.mkdtemp(prefix="wgpurender-mutation-"))
    if not (copy / "wgpurender").is_dir():
        copy.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "archive", "HEAD"], cwd=REPO, capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(copy)], input=archive, check=True)
        shared = REPO.parent / "shared"
        if shared.exists() and not (copy.parent / "shared").exists():
            (copy.parent / "shared").symlink_to(shared)
    caught = 0
    for number in chosen:
        path, old, new, tests = MUTATIONS[number - 1]
        source = copy / path
        text = source.read_text()
        if text.count(old) != 1:
            print(f"{number:3d} SKIPPED (the text is not in {path} exactly once)", flush=True)
            continue
        start = time.monotonic()
        source.write_text(text.replace(old, new))
        try:
            found, where = _run(copy, tests)
        finally:
            source.write_text(text)
        caught += found
        verdict = f"caught by {where}" if found else "MISSED"
        print(f"{number:3d} {verdict:40s} {time.monotonic() - start:5.0f} s  {path}: {new.strip()[:70]!r}",
              flush=True)
    print(f"{caught} of {len(chosen)} mutations caught")
    return 0


if __name__ == "__main__":
    sys.exit(main())
