"""wgpurender verify: the cross-driver equivalence matrix (wgpurender/verify.py) on this adapter."""

from __future__ import annotations

from pathlib import Path


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
    p.set_defaults(func=run)


def run(args) -> int:
    from wgpurender.core.errors import UserError
    from wgpurender.verify import run_verify

    if args.out.exists() and not args.out.is_dir():
        raise UserError(f"--out {args.out}: exists and is not a folder")
    try:
        (args.out / "heatmaps").mkdir(parents=True, exist_ok=True)  # before any rendering
    except OSError as err:
        raise UserError(f"--out {args.out}: cannot create it ({err.strerror or err})") from None
    report = run_verify(args.out, quick=args.quick)
    for row in report.rows:
        detail = row.note if row.status in ("skipped", "FAIL") else (row.metrics.summary() if row.metrics else "")
        print(f"{row.status:>9}  {row.kind:<8} {row.name:<20} {row.comparison:<18} {detail}")
    print(f"{report.device}; {report.cpu}; driver class {report.driver_class}")
    print(f"wrote {args.out / 'verify.csv'}, {args.out / 'verify.md'}, {args.out / 'heatmaps'}/, "
          f"{args.out / 'tolerances.toml'}")
    if report.failed:
        print(f"{len(report.failed)} comparison(s) exceed their bound")
        return 1
    return 0
