"""The browser's numbers (issue 22.6): first pixel and frame time of exported pages in headless Chromium, beside
wgpu-native on this machine, for the same targets and size.

    python benchmarks/bench_browser.py [--targets triangle,3d,assets/scenes/final.toml] [--size 800x600]
                                       [--frames 60] [--runs 3] [--out FILE.md]

Per target: ``wgpurender export`` writes the page (wgpurender/webpage/); a fresh headless Chromium
(``--enable-unsafe-webgpu``: Dawn on SwiftShader here, no GPU) opens it, and the page reports

- **first pixel**: ``performance.now()`` (ms since the navigation started) when the player's first frame is done:
  page load, adapter and device, the replayed set-up (shader modules, pipelines, uploads) and one frame;
- **frame**: the player's own ``frameMs`` per animation frame (replay of the frame's calls, GPU work, present),
  median and spread over ``--frames`` frames.

wgpu-native beside it, same target and size: first pixel = ``wgpurender.bench.startup``'s fresh-process child
(process start to the first frame's pixels read back) for a stage, and the wall time of a fresh
``wgpurender render`` for a scene; frame = record + submit + wait of the bench's runner (bench/frames.py,
bench/scene.py). Not the same measurement at the edges (the browser's excludes starting the browser, wgpu-native's
includes starting Python); both include device creation, pipelines and the first frame. Markdown to stdout
(and ``--out``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FIRST_FRAME_JS = """new Promise((resolve, reject) => {
  const poll = () => {
    const w = window.wgpurender;
    if (w && w.error) return reject(new Error(w.error));
    if (w && w.frames > 0) return resolve(performance.now());
    setTimeout(poll, 1);
  };
  poll();
})"""
FRAMES_JS = """new Promise((resolve) => {
  const out = []; let seen = window.wgpurender.frames;
  const step = () => {
    const w = window.wgpurender;
    if (w.frames !== seen) { out.push(w.frameMs); seen = w.frames; }
    if (out.length >= %d) resolve(out); else requestAnimationFrame(step);
  };
  requestAnimationFrame(step);
})"""


def browser_numbers(page: Path, frames: int, runs: int) -> tuple[list[float], list[float], str]:
    from wgpurender.webpage.chromium import Chromium

    firsts, frame_ms, version = [], [], ""
    for _ in range(runs):
        with Chromium() as browser:
            version = browser.version()
            tab = browser.open(page)
            firsts.append(float(tab.evaluate(FIRST_FRAME_JS)))
            frame_ms += [float(v) for v in tab.evaluate(FRAMES_JS % frames)]
    return firsts, frame_ms, version


def native_numbers(target: str, size: tuple[int, int], frames: int, runs: int) -> tuple[list[float], list[float]]:
    from wgpurender.bench.frames import measure
    from wgpurender.bench.startup import run_child
    from wgpurender.wgpu_path.device.context import get_context

    env = dict(os.environ, WGPURENDER_VALIDATION="0")
    is_scene = target.endswith(".toml")
    firsts = []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(runs):
            if is_scene:
                start = time.perf_counter()
                subprocess.run([sys.executable, "-m", "wgpurender", "render", target, "--size", f"{size[0]}x{size[1]}",
                                "-o", str(Path(tmp) / "f.png")], env=env, check=True, capture_output=True)
                firsts.append((time.perf_counter() - start) * 1e3)
            else:
                firsts.append(run_child("wgpu", target, size, env)["total_ms"])
    ctx = get_context()
    if is_scene:
        from wgpurender.bench.scene import SceneRunner

        runner = SceneRunner(ctx, Path(target), size)
    else:
        from wgpurender.bench.frames import WgpuStageRunner

        runner = WgpuStageRunner(ctx, target, size)
    return firsts, measure(runner, frames).frame


def spread(values: list[float]) -> str:
    q = statistics.quantiles(values, n=10) if len(values) > 1 else [values[0]] * 9
    return f"{statistics.median(values):.1f} [{q[0]:.1f}..{q[-1]:.1f}]"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--targets", default="triangle,3d,assets/scenes/final.toml")
    p.add_argument("--size", default="800x600")
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--out", type=Path)
    args = p.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    from wgpurender.webpage import export

    rows, version = [], ""
    with tempfile.TemporaryDirectory(prefix="wgpurender-browser-bench-") as tmp:
        for target in args.targets.split(","):
            page = export(target, Path(tmp) / Path(target).stem, size).page
            b_first, b_frames, version = browser_numbers(page, args.frames, args.runs)
            n_first, n_frames = native_numbers(target, size, min(args.frames, 20), args.runs)
            ratio_first = statistics.median(b_first) / statistics.median(n_first)
            ratio_frame = statistics.median(b_frames) / statistics.median(n_frames)
            rows.append((target, spread(b_first), spread(n_first), ratio_first, spread(b_frames), spread(n_frames),
                         ratio_frame))
            print(f"  {target}: done", file=sys.stderr)
    from wgpurender.wgpu_path.device.context import get_context

    lines = [f"Browser: {version}, headless, --enable-unsafe-webgpu (Dawn on SwiftShader); wgpu-native: "
             f"{get_context().describe()}; size {size[0]}x{size[1]}; {args.runs} fresh runs per target, "
             f"{args.frames} browser frames / 20 native frames per run; ms, median [p10..p90].", "",
             "| target | first pixel, browser | first pixel, wgpu-native | browser / native | frame, browser | "
             "frame, wgpu-native | browser / native |", "| --- | --- | --- | --- | --- | --- | --- |"]
    lines += [f"| {t} | {bf} | {nf} | {qf:.2f}x | {bfr} | {nfr} | {qfr:.2f}x |"
              for t, bf, nf, qf, bfr, nfr, qfr in rows]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        args.out.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
