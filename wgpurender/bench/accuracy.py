"""``wgpurender bench accuracy``: what each quality knob buys in error, and what it costs in time.

Each knob (MSAA 1/4; supersampling 1x-4x; scene target rgba8unorm-srgb / rgba16float / rgba32float; texture
filtering nearest / linear / trilinear / anisotropic 4 and 16; depth depth24plus / depth32float / reverse-Z
depth32float) is swept one at a time from the highest setting, plus the combinations that matter, and every
setting gets FLIP and PSNR against a ground truth and its GPU and wall time per frame. Results: accuracy.csv,
accuracy.md and accuracy_pareto.png (error against time with the Pareto front) in --out. docs/accuracy.md
explains the choices and holds a lavapipe run.

Modules: accuracy_knobs (settings -> renderer), accuracy_downsample (the supersampling resolve),
accuracy_depth (the depth-stress scene), accuracy_run (sweep, timing, scoring, progress), accuracy_pareto,
accuracy_report (CSV, markdown, plot). This module is imported when the CLI is built: it imports nothing heavy.
"""

from __future__ import annotations

from pathlib import Path

SCENE_FILE = Path("assets/scenes/final.toml")
# The base size is the adapter's (AdapterFacts.accuracy_size: core/plan/bench_size.py), unless --size gives one.
QUICK = {"preset": "quick", "frames": 3, "warmup": 1, "rounds": 1}
FULL = {"preset": "full", "frames": 18, "warmup": 2, "rounds": 3}


def run(args) -> int:
    from wgpurender.bench.accuracy_knobs import KNOBS
    from wgpurender.bench.accuracy_report import write_reports
    from wgpurender.bench.accuracy_run import AccuracyConfig, run_accuracy
    from wgpurender.bench.perf import command_line
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.assets import resolve_scene
    from wgpurender.core.files.safe_write import output_folder
    from wgpurender.wgpu_path.device.context import get_context

    preset = QUICK if args.quick else FULL
    frames = preset["frames"] if args.frames is None else args.frames
    rounds = preset["rounds"] if args.rounds is None else args.rounds
    if frames < 1 or rounds < 1:
        raise UserError("--frames and --rounds must be at least 1")
    scene = resolve_scene(args.scene)  # a path, or a bundled scene by name (from any folder, as render does)
    if not scene.is_file():
        raise UserError(f"scene file not found: {args.scene} (give a scene file, or a bundled scene's name)")
    if args.truth == "analytic" and (args.knobs or not args.combinations):  # refused, not ignored: the
        # analytic suite has its own cases
        raise UserError("--knob and --no-combinations choose the rendered sweep's settings: leave them out "
                        "with --truth analytic")
    output_folder(args.out, "--out")  # after the refusals (they leave nothing), before any timing
    if args.truth == "analytic":
        return _run_analytic(args, preset, frames)
    knobs = tuple(k for k in KNOBS if k in (args.knobs or KNOBS))
    ctx = get_context(args.backend)
    size = args.size or ctx.adapter_facts().accuracy_size(preset["preset"])
    config = AccuracyConfig(scene_path=scene, base_size=size, frames=frames, warmup=preset["warmup"], rounds=rounds,
                            knobs=knobs, combinations=args.combinations,
                            out_dir=Path(args.out), command=command_line())
    result = run_accuracy(config, ctx)
    for kind, path in write_reports(result, config.out_dir).items():
        print(f"{kind}: {path}")
    return 0


def _run_analytic(args, preset: dict, frames: int) -> int:
    import datetime
    import sys

    from wgpurender.bench.accuracy_analytic import run_analytic, write_analytic_reports
    from wgpurender.bench.perf import command_line
    from wgpurender.wgpu_path.device.context import get_context

    ctx = get_context(args.backend)
    size = args.size or ctx.adapter_facts().accuracy_size(preset["preset"])
    rows = run_analytic(ctx, Path(args.out), size, frames, preset["warmup"],
                        progress=lambda text: print(text, file=sys.stderr, flush=True))
    header = [f"# bench accuracy --truth analytic ({size[0]}x{size[1]})", "",
              f"- adapter: {ctx.describe()}", f"- date: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC",
              f"- command: `{command_line()}`", f"- timed frames per setting: {frames} (median, p10..p90)"]
    from wgpurender.bench.accuracy_run import noise_floor

    reports = write_analytic_reports(rows, Path(args.out), header, noise_floor(ctx, frames))
    reports.update(_run_shimmer(ctx, Path(args.out), size, reports["markdown"]))
    for kind, path in reports.items():
        print(f"{kind}: {path}")
    return 0


def _run_shimmer(ctx, out: Path, size: tuple[int, int], markdown_path: Path) -> dict[str, Path]:
    """The temporal measure (accuracy_shimmer.py): its CSV, and its table appended to the analytic markdown."""
    import sys

    from wgpurender.bench import accuracy_shimmer as shimmer

    rows = shimmer.run_shimmer(ctx, out / "analytic_scenes", size,
                               progress=lambda text: print(text, file=sys.stderr, flush=True))
    with markdown_path.open("a") as f:
        f.write("\n".join(shimmer.markdown(rows, shimmer.FRAMES, size)) + "\n")
    return {"shimmer csv": shimmer.write_shimmer_csv(rows, out / "accuracy_shimmer.csv")}
