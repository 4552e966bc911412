"""``wgpurender demo --raw``: the demo's flags, run by the raw-Vulkan window (wgpurender/raw_path/window/__init__.py).

Every demo flag either works here as it does for the wgpu window or is refused with one line (exit 2):
``--backend`` (a wgpu choice) is refused; the orbit camera, keys, FPS title, ``--test-input`` and the
``--benchmark`` CSV are the wgpu window's, from the core (core/view/controls.py, core/view/frame_times.py);
``--anisotropy`` is resolved for the raw device by the same function (core/plan/resolve.py);
``--validation`` turns on the Vulkan validation layer and counts its messages.
"""

from __future__ import annotations

import os

REFUSED = {  # dest -> why it cannot apply to the raw window
    "backend": "--backend picks a wgpu backend: the raw path is Vulkan only, leave it out with --raw",
    "no_overlay": "--no-overlay hides the wgpu window's settings overlay: the raw window has none, leave it out",
}


def run_raw(args, benchmark, size: tuple[int, int], video=None) -> int:
    """``benchmark``: the demo's BenchmarkSpec (None without --benchmark), checked by the caller; ``size``: the
    window size the demo chose (--size, else a scene's [render] size); ``video``: the --record FrameWriter (None
    without it)."""
    from wgpurender.core.errors import UserError
    from wgpurender.core.files.imageio import check_writable, image_format, save_image
    from wgpurender.core.view.controls import parse_script
    from wgpurender.raw_path.device.validation import ENV
    from wgpurender.raw_path.window import run_raw_window

    for dest, why in REFUSED.items():
        if getattr(args, dest):
            raise UserError(why)
    if args.screenshot:
        image_format(args.screenshot)  # the suffix picks the format; refuse an unknown one before a window
        check_writable(args.screenshot)
    if args.validation:
        os.environ[ENV] = "1"  # read when the window's Vulkan context is made
    script = parse_script(args.test_input)
    result = run_raw_window(args.target, size=size, present_mode=args.present_mode, frames=args.frames,
                            screenshot=bool(args.screenshot), msaa=args.msaa, fixed_time=args.time,
                            benchmark=benchmark, script=script, anisotropy=args.anisotropy, video=video)
    print(f"surface offers: {result.offered}")
    print(f"swapchain: {result.swapchain_format}, present mode {result.present_mode}, "
          f"re-created {result.recreated} time(s)")
    for event in result.events:
        print(f"  {event}")
    print(f"frames: {result.frames}, mean frame time {result.mean_frame_ms:.2f} ms")
    if result.benchmark is not None:
        print(result.benchmark.summary())
        print(f"wrote {result.benchmark.write_csv()}")
    if args.screenshot and result.last_frame is not None:
        print(f"wrote {save_image(args.screenshot, result.last_frame)}")
    if result.validation_messages is not None:
        print(f"validation messages: {result.validation_messages}")
    return 0
