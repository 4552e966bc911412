"""wgpurender bench: benchmark suites, one sub-subcommand each: perf and accuracy.

The parsers live here; the suites run in wgpurender/bench/perf.py and wgpurender/bench/accuracy.py
(bench/ never imports cli/).
"""

from __future__ import annotations

from pathlib import Path

from wgpurender.cli._args import add_anisotropy_arg, add_backend_arg, size_arg
from wgpurender.core.plan.anisotropy import DEFAULT_ANISOTROPY

# Every suite with the few words the top-level --help shows for it (the suites' own --help says more).
SUITES = {"perf": "speed against the raw-Vulkan path", "accuracy": "error against time per quality knob",
          "post-roofline": "each post pass against a copy of the same bytes"}


def register(subparsers) -> None:
    listed = "; ".join(f"{name} ({words})" for name, words in SUITES.items())
    p = subparsers.add_parser("bench", help=f"benchmark suites: {listed}",
                              description="Run a benchmark suite and write its results (CSV, markdown, plots).")
    suites = p.add_subparsers(dest="suite", required=True, metavar="SUITE")
    _register_perf(suites)
    _register_accuracy(suites)
    _register_roofline(suites)


def _register_perf(suites) -> None:
    p = suites.add_parser(
        "perf",
        help="frame, CPU, readback, post, many-objects and first-frame times, wgpu against raw Vulkan",
        description="Measure every stage and the final scene (final_subpass.toml on both paths) on the wgpu and "
        "the raw-Vulkan path, post effects, many objects and first-frame time; write results.csv, report.md "
        "and perf_*.png (plots need matplotlib: pip install 'wgpurender[bench]').",
    )
    p.add_argument("--quick", action="store_true", help="tiny sizes and few repeats: checks the harness in < 60 s")
    p.add_argument("--out", type=Path, default=Path("bench-results"), metavar="DIR",
                   help="where results go (default ./bench-results)")
    p.add_argument("--only", "--families", dest="only", action="append", default=None, metavar="FAMILY",
                   help="run only these families (repeatable, or comma-separated): frames, scene, post, msaa-post, "
                   "objects, scene-scale, control, startup")
    p.add_argument("--counts", default=None, metavar="N,N",
                   help="scene-scale's counts, comma-separated, each within a scene's bound on copies of one "
                   "model (default 1000,10000,100000,1000000; 50,200 with --quick)")
    big = p.add_mutually_exclusive_group()
    big.add_argument("--big", dest="big", action="store_true", default=None,
                     help="add 3840x2160 (default: when the adapter is not a CPU)")
    big.add_argument("--no-big", dest="big", action="store_false")
    p.add_argument("--no-raw", dest="raw", action="store_false", help="skip the raw-Vulkan peer")
    p.add_argument("--frames", type=int, default=None, metavar="N",
                   help="timed frames per case (default 20; 100 in the frames, scene and scene-scale families on "
                   "a GPU, whose p99 is judged; 4 with --quick)")
    p.add_argument("--docs-img", type=Path, default=None, metavar="DIR", help="also copy the plots here")
    add_anisotropy_arg(p)
    add_backend_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.bench.perf import FAMILIES, PerfConfig, command_line, run_perf, write_reports
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.safe_write import output_folder
    from wgpurender.wgpu_path.device.context import get_context

    families = tuple(f.strip() for arg in (args.only or FAMILIES) for f in arg.split(",") if f.strip())
    unknown = [f for f in families if f not in FAMILIES]
    if unknown:
        raise UserError(f"unknown benchmark family {unknown[0]!r}: choose from {', '.join(FAMILIES)}")
    if args.frames is not None and args.frames < 1:
        raise UserError("--frames must be at least 1")
    if args.frames is not None and set(families) <= {"startup"}:  # its rounds are fresh processes, not frames
        raise UserError("--frames sets the timed frames of the frame families; the startup family times first "
                        "pixels over fresh processes: add another family with --only, or leave --frames out")
    if args.anisotropy != DEFAULT_ANISOTROPY and "scene" not in families:
        raise UserError("--anisotropy applies to the scene family: add --only scene, or leave it out")
    counts = _counts(args.counts, families)
    output_folder(args.out, "--out")  # before any timing
    if args.docs_img is not None:
        output_folder(args.docs_img, "--docs-img")
    config = PerfConfig(quick=args.quick, out_dir=args.out, families=families, big=args.big, raw=args.raw,
                        frames=args.frames, command=command_line(), anisotropy=args.anisotropy, counts=counts)
    run_ = run_perf(config, get_context(args.backend))
    paths = write_reports(run_, args.out, args.docs_img)
    for kind, path in paths.items():
        print(f"{kind}: {path}")
    return 0


def _counts(text: str | None, families: tuple[str, ...]) -> tuple[int, ...] | None:
    """--counts as positive integers up to the scene's own bound on copies of one model (a count is an
    instanced/N scene: its N offsets are made before the scene is read); refused where scene-scale does not run."""
    from wgpurender.core.errors import UserError
    from wgpurender.core.scene.model import MAX_INSTANCES

    if text is None:
        return None
    if "scene-scale" not in families:
        raise UserError("--counts sets the scene-scale family's counts: add --only scene-scale, or leave it out")
    parts = [p.strip() for p in text.split(",") if p.strip()]
    # ASCII digits only: str.isdigit also passes "²", which int() refuses
    if not parts or not all(p.isascii() and p.isdigit() and p.strip("0") for p in parts):
        raise UserError(f"--counts {text!r}: give positive whole numbers, comma-separated (e.g. --counts 1000,10000)")
    big = next((p for p in parts if len(p.lstrip("0")) > len(str(MAX_INSTANCES)) or int(p) > MAX_INSTANCES), None)
    if big is not None:  # the length first: int() refuses a string of over 4300 digits
        shown = big if len(big) <= 20 else f"{big[:8]}... ({len(big)} digits)"
        raise UserError(f"--counts {shown}: at most {MAX_INSTANCES} (copies of one model a scene may hold); "
                        "give smaller counts")
    return tuple(int(p) for p in parts)


def _sizes(preset: str) -> str:
    from wgpurender.core.plan.bench_size import HARDWARE, SOFTWARE

    (sw, sh), (hw, hh) = SOFTWARE[preset], HARDWARE[preset]
    return f"lavapipe {sw}x{sh}, a GPU {hw}x{hh}"


def _register_accuracy(suites) -> None:
    """``wgpurender bench accuracy``: wgpurender/bench/accuracy.py runs it."""
    from wgpurender.bench.accuracy import QUICK, SCENE_FILE, run
    from wgpurender.bench.accuracy_knobs import KNOBS

    p = suites.add_parser(
        "accuracy",
        help="error (FLIP, PSNR against a ground truth) against time for each quality knob",
        description="Sweep MSAA, supersampling, the scene target format, texture filtering and the depth setup; "
        "write accuracy.csv, accuracy.md and accuracy_pareto.png (the plot needs matplotlib: "
        "pip install 'wgpurender[bench]').",
    )
    p.add_argument("scene", nargs="?", type=Path, default=SCENE_FILE, metavar="SCENE",
                   help=f"scene file with a post chain, or a bundled scene's name (default {SCENE_FILE})")
    p.add_argument("--quick", action="store_true",
                   help=f"the adapter's quick base size ({_sizes('quick')}), {QUICK['frames']} timed frames, 1 round")
    p.add_argument("--out", type=Path, default=Path("bench-results/accuracy"), metavar="DIR",
                   help="where results go (default ./bench-results/accuracy)")
    p.add_argument("--size", type=size_arg, default=None, metavar="WxH",
                   help=f"base size (default the adapter's: {_sizes('full')}; the ground truth renders 8x it)")
    p.add_argument("--frames", type=int, default=None, metavar="N", help="timed frames per setting")
    p.add_argument("--rounds", type=int, default=None, metavar="R",
                   help="split the timed frames over R passes through all settings (default 3; --quick 1)")
    p.add_argument("--knob", action="append", default=None, choices=KNOBS, dest="knobs",
                   help="sweep only these knobs (repeatable; default all)")
    p.add_argument("--no-combinations", dest="combinations", action="store_false",
                   help="only the one-knob-at-a-time sweeps")
    p.add_argument("--truth", choices=("rendered", "analytic"), default="rendered",
                   help="rendered (default): every knob on SCENE against the same renderer at 8x; analytic: "
                   "anti-aliasing (none, FXAA, MSAA 4, SSAA 2x/4x), texture filtering and depth on test scenes "
                   "against float64 ground truths no renderer made (accuracy_analytic.csv/.md)")
    add_backend_arg(p)
    p.set_defaults(func=run)


def _register_roofline(suites) -> None:
    """``wgpurender bench post-roofline``: wgpurender/bench/post_roofline.py runs it."""
    p = suites.add_parser(
        "post-roofline",
        help="every post pass: bytes moved, time, GB/s and %% of a copy moving the same bytes",
        description="Time each post pass of a scene (fragment and compute path, fused and unfused) with GPU "
        "timestamps against a compute copy of the same bytes measured in the same run; write "
        "post-roofline-SCENE.md and .csv for each scene.",
    )
    p.add_argument("scenes", nargs="*", type=Path, metavar="SCENE",
                   default=[Path("assets/scenes/final.toml"), Path("assets/scenes/final_subpass.toml")],
                   help="scene files with a post chain (default: final.toml, whose fused pass is fxaa+vignette, "
                   "and final_subpass.toml, whose whole chain is one per-pixel pass)")
    p.add_argument("--size", type=size_arg, default=(3840, 2160), metavar="WxH", help="default 3840x2160")
    p.add_argument("--frames", type=int, default=20, metavar="N", help="timed frames per variant (default 20)")
    p.add_argument("--shapes", nargs="?", const="all", default=None, metavar="WxHxR,...",
                   help="also time the fused compute passes with each dispatch shape (workgroup width x height x "
                   "rows per invocation): the built-in list, or the shapes given, e.g. 16x8x2,32x8x4")
    p.add_argument("--out", type=Path, default=Path("bench-results"), metavar="DIR",
                   help="where results go (default ./bench-results)")
    add_backend_arg(p)
    p.set_defaults(func=_run_roofline)


def _run_roofline(args) -> int:
    from wgpurender.bench.perf import command_line
    from wgpurender.bench.post_roofline import csv_text, markdown, record_bandwidth, run_roofline
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.safe_write import atomic_write, output_folder
    from wgpurender.core.plan.dispatch import parse_shapes
    from wgpurender.wgpu_path.device.context import get_context

    if args.frames < 1:
        raise UserError("--frames must be at least 1")
    shapes = None if args.shapes in (None, "all") else parse_shapes(args.shapes)
    ctx = get_context(args.backend)
    if not ctx.has("timestamp-query"):
        raise UserError(f"{ctx.describe()} has no timestamp queries: post-roofline times passes with them")
    output_folder(args.out, "--out")  # before any timing
    for scene in args.scenes:
        rows = run_roofline(ctx, scene, args.size, args.frames, shapes=args.shapes is not None, sweep=shapes)
        record_bandwidth(ctx, scene, args.size, rows, command_line())
        text = markdown(rows, ctx, scene, args.size, args.frames, command_line())
        md, csv = args.out / f"post-roofline-{scene.stem}.md", args.out / f"post-roofline-{scene.stem}.csv"
        atomic_write(md, text.encode())
        atomic_write(csv, csv_text(rows).encode())
        print(text, end="")
        print(f"wrote {md} and {csv}")
    return 0
