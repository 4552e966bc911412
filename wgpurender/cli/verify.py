"""wgpurender verify: the cross-driver equivalence matrix (wgpurender/verify.py) on this adapter."""

from __future__ import annotations

from pathlib import Path

from wgpurender.cli._args import size_arg

IMPLEMENTATIONS_SIZE = (160, 120)  # --implementations' default: the smallest size class of its bounds


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "verify",
        help="render every stage and scene on both paths; compare wgpu vs raw and this device vs the references",
        description="Render every stage and every repository scene on the wgpu and the raw-Vulkan path on this "
        "adapter; compare wgpu vs raw (exact, or the explained post-chain bound), the raw renders against "
        "assets/reference/*.png and the tutorial scenes against the C++ frames in ../shared/anchors, with the "
        "calibrated tolerances of assets/reference/tolerances.toml. Writes verify.csv, verify.md, heatmaps/ and "
        "tolerances.toml (the table re-calibrated for this driver class). Exits 1 when a bound is exceeded.",
    )
    p.add_argument("--out", type=Path, default=Path("out/verify"), metavar="DIR",
                   help="output folder (default out/verify)")
    p.add_argument("--quick", action="store_true", help="a subset: stages triangle and 3d, scene unlit")
    p.add_argument("--implementations", metavar="LIST", default=None,
                   help="the implementation matrix instead: a comma list of raw, wgpu-vulkan, wgpu-gl, browser, "
                   "wgpu-dawn, or 'all' (every one available here); each renders every stage and scene at --size, "
                   "every pair is compared (max, share over 1/255, PSNR, FLIP) and each against wgpu-vulkan is bounded "
                   "by assets/reference/implementations.toml. Writes implementations.md/.csv and heatmaps/impl-*.png")
    p.add_argument("--size", type=size_arg, default=None, metavar="WxH",
                   help="size for --implementations (default 160x120); the bounds hold up to the largest size class "
                   "calibrated in assets/reference/implementations.toml (640x480), a larger size fails as uncalibrated")
    p.add_argument("--calibrate", action="store_true",
                   help="with --implementations: rewrite the measured implementations' rows of "
                   "assets/reference/implementations.toml from this run (at --size only; the other size classes' "
                   "rows are kept, and the size-free bounds stay no lower than theirs: calibrate several size "
                   "classes in one run with docs/runs/2026-11-27-size-free-bounds/calibrate.py)")
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.core.errors import UserError
    from wgpurender.verify import run_verify

    if args.implementations is None and args.calibrate:
        raise UserError("--calibrate applies to --implementations only (the driver table is written to --out)")
    if args.implementations is None and args.size is not None:  # refused, not ignored
        raise UserError("--size applies to --implementations only (verify renders at the references' sizes)")
    if args.out.exists() and not args.out.is_dir():
        raise UserError(f"--out {args.out}: exists and is not a folder")
    try:
        (args.out / "heatmaps").mkdir(parents=True, exist_ok=True)  # before any rendering
    except OSError as err:
        raise UserError(f"--out {args.out}: cannot create it ({err.strerror or err})") from None
    if args.implementations is not None:
        return run_implementations(args)
    report = run_verify(args.out, quick=args.quick)
    for row in report.rows:
        detail = row.note if row.status in ("skipped", "FAIL") else (row.metrics.summary() if row.metrics else "")
        print(f"{row.status:>9}  {row.kind:<8} {row.name:<20} {row.comparison:<18} {detail}")
    print(f"{report.device}; {report.cpu}; driver class {report.driver_class}")
    if report.differs:
        print(f"unlike `wgpurender render T`: {report.differs}")
    print(f"wrote {args.out / 'verify.csv'}, {args.out / 'verify.md'}, {args.out / 'heatmaps'}/, "
          f"{args.out / 'tolerances.toml'}")
    return _summary(report.rows, report.failed)


def _summary(rows, failed) -> int:
    """The last line: how many comparisons passed, failed and were skipped, and the exit status it means."""
    skipped = sum(1 for row in rows if row.status == "skipped")
    passed = len(rows) - len(failed) - skipped
    verdict = "FAIL" if failed else "ok"
    print(f"verify: {verdict}: {passed} passed, {len(failed)} over their bound, {skipped} skipped")
    return 1 if failed else 0


def run_implementations(args) -> int:
    from wgpurender.core.errors import UserError
    from wgpurender.implementations import QUICK, all_targets, available
    from wgpurender.verify_matrix import run_matrix

    wanted = None if args.implementations in ("", "all") else [x.strip() for x in args.implementations.split(",")]
    impls, missing = available(wanted)
    if len(impls) < 2:
        raise UserError(f"--implementations needs two available implementations, have {', '.join(impls) or 'none'}"
                        + "".join(f"; {k}: {v}" for k, v in missing.items()))
    targets = [t for t in all_targets() if not args.quick or t in QUICK]
    size = tuple(args.size or IMPLEMENTATIONS_SIZE)
    report = run_matrix(args.out, impls, missing, targets, size, calibrate=args.calibrate)
    for c in report.cells:
        m = c.comparison
        detail = c.note if m is None else (f"max {m.max_abs}/255, >1/255 {100 * m.over_1:.2f}%, PSNR {m.psnr:.1f}, "
                                           f"FLIP {m.flip_mean:.4f}" + (f" ({c.note})" if c.note else ""))
        print(f"{c.status:>9}  {c.target:<20} {c.a + ' / ' + c.b:<24} {detail}")
    for impl, why in missing.items():
        print(f"  not available: {impl} ({why})")
    if report.differs:
        print(f"unlike `wgpurender render T`: {report.differs}")
    print(f"wrote {args.out / 'implementations.md'}, {args.out / 'implementations.csv'}, {args.out / 'heatmaps'}/")
    return _summary(report.cells, report.failed)
