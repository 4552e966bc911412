"""The distinct-mesh load of `bench perf`'s scene-scale family, timed alone: N cube files, each its own model, from
the scene file to the first frame read back (bench/scale.py's ``load_ms``), and its phases. Whichever wgpurender
is first on PYTHONPATH is timed, so one call on one machine can time two trees (the device run times main's and
this branch's).

    python benchmarks/load_compare.py LABEL N OUT.csv [cold|warm] [KNOB=VALUE ...] [--split=SPLIT.csv]
        [--max-workers=M] [--scene=distinct|batched]
        appends: label, n, parse cache, knobs, wall ms, process CPU ms, worker processes, and the wall ms of
        the phases: scene file (load_scene), plan (resolve_plan), renderer (meshes, buffers, pipelines, the
        bundle), first frame (record, submit, read back)
        --split: also the inclusive wall ms (and calls) of the functions in SPLIT below during the timed load,
        appended to SPLIT.csv (they nest: each row includes the rows it calls; a tree without one skips it)
        --max-workers: the worker rule's cap (core/plan/mesh_loading.MAX_WORKERS, 16) set to M in this process
        only, to measure what fewer forks of a large process save against less parallel reading
        --scene: distinct (the default: N cube files, each its own model) or batched (N [[models]] of ONE cube
        file, each with its own transform: bench perf's scene-scale batched/N, one instanced draw), appended
        to the label as "LABEL batched"

``cold``: the parse cache (core/models/obj_cached.py) starts empty ($XDG_CACHE_HOME is pointed at a new
temporary folder: the machine's own cache is never read or written); ``warm``: the same folder after one
untimed load of the same scene. The OS file cache is warm in both (the files were just written). A tree without
the parse cache reads the same either way. ``KNOB=VALUE``: plan knobs (e.g. ``mesh_workers=off``); a tree that
lacks the knob refuses it.
"""

from __future__ import annotations

import itertools
import os
import sys
import tempfile
import time
from pathlib import Path

from wgpurender.bench import scale
from wgpurender.bench.scene import SceneRunner
from wgpurender.core.models import procedural
from wgpurender.core.plan import resolve_plan
from wgpurender.core.scene import load_scene
from wgpurender.wgpu_path.device.context import get_context
from wgpurender.wgpu_path.device.frame_loop import run_frame
from wgpurender.wgpu_path.scene.frame import SceneRenderer

SIZE = (800, 600)
PHASES = ("scene_ms", "plan_ms", "renderer_ms", "frame_ms")
SPLIT = (  # (phase, module, function or Class.method): looked up through the module at each call
    ("scene: TOML values", "wgpurender.core.scene.toml_cache", "loads"),
    ("scene: models checked (read rule included)", "wgpurender.core.scene.load", "_models"),
    ("scene: read rule", "wgpurender.core.files.read_jail", "outside"),
    ("scene: file materials and motion", "wgpurender.core.scene.load", "_with_file_data"),
    ("plan: batches", "wgpurender.core.plan.batches", "batch_draws"),
    ("renderer: meshes uploaded (reads included)", "wgpurender.wgpu_path.scene.resources",
     "SceneResources.upload_meshes"),
    ("renderer: files read by workers (forks, cache lookups)", "wgpurender.core.models.mesh_workers", "load_all"),
    ("renderer: workers' meshes unpacked", "wgpurender.core.models.mesh_workers", "_take"),
    ("renderer: buffer bytes packed", "wgpurender.wgpu_path.scene.resources", "_pair_bytes"),
    ("renderer: uniforms and object blocks", "wgpurender.wgpu_path.scene.scene_pass",
     "ScenePassRenderer._setup_uniforms"),
    ("renderer: draws (pipelines, material groups)", "wgpurender.wgpu_path.scene.scene_pass",
     "ScenePassRenderer._setup_draws"),  # load3 on: only each draw's mesh buffers and index range
    ("renderer: draws' pipelines and material groups", "wgpurender.wgpu_path.scene.scene_pass",
     "ScenePassRenderer._setup_materials"),  # while the workers read (load3 on)
    ("renderer: workers started", "wgpurender.core.models.mesh_workers", "Reading.__init__"),
    ("renderer: workers' meshes taken (waits, unpacking)", "wgpurender.core.models.mesh_workers",
     "Reading.finish"),  # load3 on: what is left of the workers' part after the blocks were made beside it
    ("renderer: pipelines created", "wgpurender.wgpu_path.scene.scene_pass", "ScenePassRenderer.pipeline"),
    ("renderer: bundle recorded", "wgpurender.wgpu_path.scene.scene_pass", "ScenePassRenderer._make_bundle"),
)


def timers(split: tuple) -> dict[str, list[float]]:
    """Wrap each SPLIT function that this tree has with a timer: {phase: [seconds, calls]}."""
    import functools
    import importlib

    spent: dict[str, list[float]] = {}
    for phase, module, name in split:
        try:
            owner = importlib.import_module(module)
        except ImportError:  # a tree without this module (main before it was added)
            continue
        *outer, attr = name.split(".")
        for part in outer:
            owner = getattr(owner, part, None)
        real = None if owner is None else getattr(owner, attr, None)
        if real is None:  # a tree without this class or function (main before load3's Reading)
            continue
        cell = spent[phase] = [0.0, 0]

        def timed(*args, _real=real, _cell=cell, **kwargs):
            start = time.perf_counter()
            try:
                return _real(*args, **kwargs)
            finally:
                _cell[0] += time.perf_counter() - start
                _cell[1] += 1

        setattr(owner, attr, functools.wraps(real)(timed))
    return spent


def timed_load(ctx, scene: Path, knobs: dict) -> tuple[list[float], int]:
    """The wall ms of each phase of load_renderer's way (scene file, plan, renderer) and the first frame."""
    marks = [time.perf_counter()]
    loaded = load_scene(scene)
    marks.append(time.perf_counter())
    plan = resolve_plan(loaded, ctx.adapter_facts(), size=SIZE, **knobs)
    marks.append(time.perf_counter())
    renderer = SceneRenderer(ctx, loaded, plan)
    marks.append(time.perf_counter())
    run_frame(ctx, renderer.record, renderer.create_output(), 0.0, label="load-compare", read_back=True)
    marks.append(time.perf_counter())
    return [(b - a) * 1e3 for a, b in itertools.pairwise(marks)], getattr(renderer.plan, "mesh_workers", 0)


USAGE = ("usage: load_compare.py LABEL N OUT.csv [cold|warm] [KNOB=VALUE ...] [--split=SPLIT.csv] [--max-workers=M] "
         "[--scene=distinct|batched]")


def batched_scene(folder: Path, n: int) -> Path:
    """bench perf's batched/N scene (bench/scale.py's ``batched_scene`` where the timed tree has it), else the
    same text made here: N models of one cube file, each at its grid place by its own ``transform``."""
    made = getattr(scale, "batched_scene", None)
    if made is not None:
        return made(folder, n, SIZE)
    procedural.write_obj(folder / "cube.obj", procedural.box(1.0))
    lines = [f'[[models]]\npath = "cube.obj"\nmaterial = "brick"\ntransform = {{ translate = [{x!r}, {y!r}, {z!r}] }}\n'
             for x, y, z in scale.grid_offsets(n).tolist()]
    path = folder / f"batched_{n}.toml"
    path.write_text(scale._head(n, SIZE, scale.brick_texture()) + "\n" + "\n".join(lines))
    return path


def arguments(argv: list[str]) -> tuple[str, int, Path, str, Path | None, int | None, dict[str, str]]:
    """(label, n, out, mode, split_to, most, knobs) from the command line; ValueError (one line) for a bad one:
    a count that is no whole number >= 1, a mode other than cold or warm, a KNOB without =, an option this
    script does not take (a misspelt --split was dropped, and the run silently wrote no split)."""
    if len(argv) < 3:
        raise ValueError(f"LABEL, N and OUT.csv are required; {USAGE}")
    label, count, out, *rest = argv
    if not label or any(c in label for c in ',"\n\r'):
        raise ValueError(f"LABEL {label!r}: give a name without commas, quotes or line breaks (a CSV cell)")
    if not count.isdecimal() or int(count) < 1:
        raise ValueError(f"N {count!r}: give the number of distinct meshes, a whole number >= 1")
    mode = rest.pop(0) if rest and "=" not in rest[0] and not rest[0].startswith("--") else "cold"
    if mode not in ("cold", "warm"):
        raise ValueError(f"cache mode {mode!r}: give cold or warm")
    split_to, most, knobs = None, None, {}
    for arg in rest:
        name, eq, value = arg.partition("=")
        if not eq or not name.strip("-") or not value:
            raise ValueError(f"{arg!r}: give KNOB=VALUE, --split=SPLIT.csv or --max-workers=M; {USAGE}")
        if name == "--split":
            split_to = Path(value)
        elif name == "--max-workers":
            if not value.isdecimal() or int(value) < 1:
                raise ValueError(f"--max-workers={value}: give a whole number >= 1")
            most = int(value)
        elif name == "--scene":
            if value not in ("distinct", "batched"):
                raise ValueError(f"--scene={value}: give distinct or batched")
            knobs[name] = value  # taken out by main: a scene, not a plan knob
        elif name.startswith("-"):
            raise ValueError(f"unknown option {name!r}; {USAGE}")
        else:
            knobs[name] = value
    return label, int(count), Path(out), mode, split_to, most, knobs


def main() -> int:
    try:
        label, n, out, mode, split_to, most, knobs = arguments(sys.argv[1:])
    except ValueError as e:
        print(f"load_compare: {e}", file=sys.stderr)
        return 2
    batched = knobs.pop("--scene", "distinct") == "batched"
    label = f"{label} batched" if batched else label
    if most is not None:  # a measurement of the rule's cap, not a knob: the plan's own rule with another bound
        from wgpurender.core.plan import mesh_loading

        mesh_loading.MAX_WORKERS = most
    ctx = get_context()
    with tempfile.TemporaryDirectory() as tmp, tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache  # never the machine's own cache
        SceneRunner(ctx, scale.distinct_scene(Path(tmp), 4, SIZE), SIZE).frame(readback=True)  # shaders, imports
        scene = batched_scene(Path(tmp), n) if batched else scale.distinct_scene(Path(tmp), n, SIZE)
        if mode == "warm":
            timed_load(ctx, scene, knobs)  # fills the parse cache
        spent = timers(SPLIT) if split_to else {}
        wall, cpu = time.perf_counter(), time.process_time()
        phases, workers = timed_load(ctx, scene, knobs)
        wall, cpu = (time.perf_counter() - wall) * 1e3, (time.process_time() - cpu) * 1e3
    new = not out.exists()
    shown = " ".join([f"{k}={v}" for k, v in knobs.items()] + ([f"max_workers={most}"] if most else [])) or "-"
    with out.open("a") as f:
        if new:
            f.write("tree,distinct_meshes,parse_cache,knobs,load_wall_ms,load_process_cpu_ms,mesh_workers,"
                    + ",".join(PHASES) + "\n")
        f.write(f"{label},{n},{mode},{shown},{wall:.1f},{cpu:.1f},{workers},"
                + ",".join(f"{p:.1f}" for p in phases) + "\n")
    if split_to:
        new_split = not split_to.exists()
        with split_to.open("a") as f:
            if new_split:
                f.write("tree,distinct_meshes,parse_cache,knobs,phase,wall_ms,calls\n")
            for phase, (seconds, calls) in spent.items():
                f.write(f'{label},{n},{mode},{shown},"{phase}",{seconds * 1e3:.1f},{calls}\n')  # names hold commas
                print(f"  {phase}: {seconds * 1e3:.1f} ms ({calls} calls)")
    split = ", ".join(f"{k} {p:.0f}" for k, p in zip(PHASES, phases, strict=True))
    what = "models of one mesh file" if batched else "distinct meshes"
    print(f"{label}: {n} {what} load in {wall:.0f} ms ({cpu:.0f} ms process CPU; parse cache {mode}, "
          f"knobs {shown}, {workers} worker processes; {split})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
