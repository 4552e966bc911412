"""The implementations the course runs on, and one way to render every target on each.

A *target* is a stage (by name) or a repository scene (assets/scenes/NAME.toml, by stem). An
*implementation* is one WebGPU/Vulkan stack that draws it:

- ``wgpu-vulkan``: wgpu-native over Vulkan (the default of ``wgpurender render``);
- ``wgpu-gl``: wgpu-native over OpenGL (``--backend opengl``);
- ``raw``: the raw-Vulkan reference path (wgpurender/raw_path);
- ``browser``: the exported page (``wgpurender export``) in headless Chromium's WebGPU (Dawn);
- ``wgpu-dawn``: the wgpu path on Dawn through wgpudawn (``$WGPURENDER_BINDING=dawn``, wgpu_path/binding.py),
  a GPU driver only: Dawn refuses lavapipe.

wgpu-py keeps one wgpu instance per process, made for one backend (gpu.py), so a second wgpu backend
renders in a child process: ``python -m wgpurender.implementations IMPL DIR --size WxH [TARGET ...]``
writes DIR/TARGET.png. Outer tool: imports both paths.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.assets import scene_dir
from wgpurender.core.plan.gl_facts import CANNOT_DRAW

REPO = Path(__file__).resolve().parent.parent
SCENE_DIR = scene_dir()  # the checkout's assets/scenes, or the wheel's copy
WGPU_IMPLEMENTATIONS = {"wgpu-vulkan": "vulkan", "wgpu-gl": "opengl", "wgpu-dawn": "vulkan"}
IMPLEMENTATIONS = ("raw", "wgpu-vulkan", "wgpu-gl", "browser", "wgpu-dawn")
CHILD_ENV = {"wgpu-dawn": {"WGPURENDER_BINDING": "dawn"}}  # what a child process needs to be that implementation
QUICK = ("triangle", "3d", "unlit")  # verify --quick


def scene_files() -> dict[str, Path]:
    """The repository scenes by stem, in name order (those reading ../shared/anchors only where it exists)."""
    files = {}
    for path in sorted(SCENE_DIR.glob("*.toml")):
        text = path.read_text()
        if "shared/anchors" in text and not (REPO.parent / "shared" / "anchors").is_dir():
            continue
        files[path.stem] = path
    return files


def stage_names() -> list[str]:
    from wgpurender.wgpu_path.stages import all_stages

    return list(all_stages())


def all_targets() -> list[str]:
    """Every stage, then every repository scene."""
    return [*stage_names(), *scene_files()]


def target_path(name: str) -> str:
    """What ``wgpurender render`` takes for a target: the stage name, or the scene file."""
    scenes = scene_files()
    return str(scenes[name]) if name in scenes else name


def render_wgpu(name: str, size: tuple[int, int], backend: str | None = None, t: float = 0.0) -> np.ndarray:
    """One target on this process's wgpu backend: 8-bit RGBA, top row first; drawn with the browser page's
    anisotropy (REFERENCE_ANISOTROPY: the matrix's note says what that changes against ``render T``)."""
    from wgpurender.core.files.imageio import to_uint8
    from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
    from wgpurender.wgpu_path.render import render_any

    return to_uint8(render_any(target_path(name), size=size, t=t, backend=backend,
                               anisotropy=REFERENCE_ANISOTROPY).pixels)


def render_raw(name: str, size: tuple[int, int]) -> np.ndarray:
    from wgpurender.core.files.imageio import to_uint8
    from wgpurender.core.plan.anisotropy import REFERENCE_ANISOTROPY
    from wgpurender.raw_path import render_reference

    return to_uint8(render_reference(target_path(name), size, anisotropy=REFERENCE_ANISOTROPY))


def render_browser(names: list[str], size: tuple[int, int], work: Path) -> tuple[dict, dict, str]:
    """Export each target to ``work/NAME`` and read its frame back in headless Chromium (one browser):
    (images by name, reasons for the targets that could not be drawn, the browser and adapter)."""
    from wgpurender.webpage import export
    from wgpurender.webpage.chromium import Chromium

    images, skipped, pages = {}, {}, {}
    work.mkdir(parents=True, exist_ok=True)  # export makes the page's own folder, never a missing parent
    for name in names:
        try:
            pages[name] = export(target_path(name), work / name, size).page
        except UserError as err:
            skipped[name] = str(err)
    with Chromium(webgpu=True) as browser:
        who = browser.version()
        for name, page in pages.items():
            tab = browser.open(page)
            try:
                images[name] = tab.capture()
            except RuntimeError as err:
                skipped[name] = f"the page failed: {err}"
            adapter = tab.evaluate("window.wgpurender.adapter") or {}
            tab.close()
        who += " / " + " ".join(str(v) for v in adapter.values() if v) if pages else ""
    return images, skipped, who


def available(wanted: list[str] | None = None) -> tuple[list[str], dict[str, str]]:
    """The implementations this machine has (of ``wanted``, default all) and why each other one is missing."""
    import shutil

    from wgpurender.webpage.chromium import find_chromium

    missing = {}
    for name in wanted or IMPLEMENTATIONS:
        if name not in IMPLEMENTATIONS:
            raise UserError(f"unknown implementation {name!r}: choose from {', '.join(IMPLEMENTATIONS)}")
        if name == "browser" and find_chromium() is None:
            missing[name] = "chromium is not installed (apt-get install chromium)"
        elif name == "raw" and shutil.which("glslc") is None:
            missing[name] = "glslc is not on PATH (the raw path compiles its GLSL with it)"
        elif name == "wgpu-gl" and (why := _gl_missing()):
            missing[name] = why
        elif name == "wgpu-dawn":
            why = _dawn_missing()
            if why:
                missing[name] = why
    return [n for n in (wanted or IMPLEMENTATIONS) if n not in missing], missing


def _gl_missing() -> str:
    """Why wgpu-gl cannot render here ('' when it can): no OpenGL adapter, or its one-line refusal (a GL context
    wgpu binds wrongly: wgpu_path/device/context.refuse_broken_gl)."""
    env = {**os.environ, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR") or "/tmp"}
    probe = subprocess.run([sys.executable, "-m", "wgpurender", "info", "--backend", "opengl"], capture_output=True,
                           text=True, env=env, timeout=120)
    if probe.returncode == 0:
        return ""
    refusal = [line for line in probe.stderr.splitlines() if CANNOT_DRAW in line]
    return refusal[-1].split("error: ", 1)[-1] if refusal else "no OpenGL adapter (wgpurender info --backend opengl)"


def _dawn_missing() -> str:
    """Why the Dawn binding cannot render here ('' when it can): not installed, or its one-line refusal."""
    import importlib.util

    if importlib.util.find_spec("wgpudawn") is None:
        return "wgpudawn is not installed (pip install 'wgpurender[dawn]')"
    env = {**os.environ, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR") or "/tmp", **CHILD_ENV["wgpu-dawn"]}
    probe = subprocess.run([sys.executable, "-m", "wgpurender", "info"], capture_output=True, text=True, env=env,
                           timeout=120)
    return "" if probe.returncode == 0 else (probe.stderr.strip().splitlines() or ["Dawn failed"])[-1]


def render_in_child(implementation: str, names: list[str], size: tuple[int, int], out: Path,
                    timeout: float = 600) -> dict[str, np.ndarray]:
    """Render ``names`` on a wgpu implementation in a child process (its own wgpu instance); a target the
    implementation refuses is left out (:func:`child_skipped` says why)."""
    from wgpurender.core.files.imageio import load_png

    out.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, "-m", "wgpurender.implementations", "--size", f"{size[0]}x{size[1]}", implementation,
           str(out), *names]
    env = {**os.environ, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR") or "/tmp",
           **CHILD_ENV.get(implementation, {})}
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=REPO)
    if done.returncode != 0:
        tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["(no output)"]
        raise UserError(f"{implementation} renderer failed: {tail[0]}")
    return {name: load_png(out / f"{name}.png") for name in names if (out / f"{name}.png").is_file()}


def child_skipped(out: Path) -> dict[str, str]:
    """The targets a child process refused, with its one line each (``skipped.txt``)."""
    path = out / "skipped.txt"
    lines = path.read_text().splitlines() if path.is_file() else []
    return dict(line.split("\t", 1) for line in lines if "\t" in line)


def calibrate(implementation: str, measured: dict, bounded_by: str, cls: str = "lavapipe") -> Path:
    """Rewrite ``implementation``'s rows of assets/reference/implementations.toml from one run (the other
    implementations' rows are kept). ``measured``: {"WxH": {target: (Metrics, Structure)}} at one size or more.

    The smallest size gives the rows' max, changed and FLIP (the CPU-driver rule of tolerances.calibrate); each
    larger size its own class of the three (``sizes``: max grows with the pixel count). The size-free bounds
    come from the worst over every size (tolerances.calibrate_structure). What the run did not measure is kept
    (``verify --calibrate --size S`` measures one size class): the other size classes' rows and targets, with
    size-free bounds no lower than before where a kept class shared them, and ``kept`` saying where they came from;
    rows of another driver class bound nothing on this one and are replaced."""
    from wgpurender.core.verdict import tolerances as tol

    table = tol.load_table(tol.IMPLEMENTATIONS_PATH) if tol.IMPLEMENTATIONS_PATH.is_file() else {}
    old = table.get("implementations", {}).get(implementation, {})
    old = old if old.get("driver_class", "lavapipe") == cls else {}
    rows, structure = _size_rows(old), {n: {k: r[k] for k in STRUCTURE if k in r} for n, r in _targets(old)}
    sizes = sorted(measured, key=tol.size_pixels)
    for name in {n for size in sizes for n in measured[size]}:
        ran = [size for size in sizes if name in measured[size]]
        for size in ran:
            metrics = measured[size][name][0]
            rows.setdefault(name, {})[size] = {**tol.calibrate([metrics], "lavapipe"), "measured": metrics.summary()}
        fresh = tol.calibrate_structure([measured[size][name][1] for size in ran], ran)
        structure[name] = _widened(fresh, structure.get(name, {}), sorted(set(rows[name]) - set(ran)))
    base = min((size for by_size in rows.values() for size in by_size), key=tol.size_pixels)
    lacking = sorted(name for name, by_size in rows.items() if base not in by_size)
    if lacking:
        raise UserError(f"--calibrate at {base} makes it the smallest size class, but {len(lacking)} kept "
                        f"{implementation} target(s) ({', '.join(lacking)}) have no row there: calibrate every "
                        "target at once, or each size class with docs/runs/2026-11-27-size-free-bounds/calibrate.py")
    targets = {}
    for name, by_size in rows.items():
        larger = {size: by_size[size] for size in sorted(by_size, key=tol.size_pixels) if size != base}
        targets[name] = {**by_size[base], **({"sizes": larger} if larger else {}), **structure.get(name, {})}
    entry = {"bounded_by": bounded_by, "driver_class": cls, "size": base}
    kept = sorted({size for by_size in _size_rows(old).values() for size in by_size} - set(sizes),
                  key=tol.size_pixels)
    if kept:
        entry["kept"] = (f"{', '.join(kept)} and unmeasured targets kept from an earlier run: {old['bounded_by']}"
                         + (f"; {old['kept']}" if "kept" in old else ""))
    table.setdefault("implementations", {})[implementation] = {**entry, "targets": targets}
    tol.IMPLEMENTATIONS_PATH.write_text(tol.format_implementation_table(table))
    return tol.IMPLEMENTATIONS_PATH


THREE = ("max_abs", "changed", "flip_mean", "measured")  # a size class's row
STRUCTURE = ("radial", "detail", "structure_measured")  # the size-free bounds, one per target


def _targets(entry: dict):
    return entry.get("targets", {}).items()


def _size_rows(entry: dict) -> dict[str, dict[str, dict]]:
    """{target: {"WxH": its three bounds and measured}} of an implementation's table entry, every size class."""
    return {name: {entry["size"]: {k: row[k] for k in THREE if k in row}, **row.get("sizes", {})}
            for name, row in _targets(entry)}


def _widened(fresh: dict, old: dict, kept: list[str]) -> dict:
    """This run's size-free bounds, no lower than the earlier ones when those also covered ``kept`` sizes (which
    this run did not measure: their worst may be in the earlier bounds)."""
    if not kept or not {"radial", "detail"} <= old.keys():
        return fresh
    radial, detail = max(fresh["radial"], old["radial"]), max(fresh["detail"], old["detail"])
    note = (f"; no lower than the earlier radial {old['radial']:g}, detail {old['detail']:g}, which covered "
            f"{', '.join(kept)}")
    return {"radial": radial, "detail": detail, "structure_measured": fresh["structure_measured"] + note}


def _main(argv: list[str] | None = None) -> int:
    from wgpurender.cli._args import size_arg
    from wgpurender.core.files.imageio import save_png

    p = argparse.ArgumentParser(prog="python -m wgpurender.implementations")
    p.add_argument("implementation", choices=sorted(WGPU_IMPLEMENTATIONS))
    p.add_argument("out", type=Path)
    p.add_argument("--size", type=size_arg, default=(160, 120))
    p.add_argument("targets", nargs="*")
    args = p.parse_args(argv)
    backend = WGPU_IMPLEMENTATIONS[args.implementation]
    args.out.mkdir(parents=True, exist_ok=True)
    skipped = []
    for name in args.targets or all_targets():
        try:
            save_png(args.out / f"{name}.png", render_wgpu(name, args.size, backend))
        except UserError as err:  # this implementation cannot draw it (e.g. Dawn has no clear-texture): said why
            skipped.append(f"{name}\t{err}")
    (args.out / "skipped.txt").write_text("".join(f"{line}\n" for line in skipped))
    from wgpurender.wgpu_path.device.context import get_context

    (args.out / "adapter.txt").write_text(get_context(backend).describe())
    return 0


if __name__ == "__main__":
    sys.exit(_main())
