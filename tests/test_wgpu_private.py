"""Each reach into wgpu-py's private parts (wgpurender/wgpu_path/device/wgpu_private.py) holds on the installed wgpu-py,
and a different wgpu-py gets one line saying what to do."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np

from wgpurender.wgpu_path.device import wgpu_private


def test_the_version_check_says_in_one_line_what_to_do():
    assert wgpu_private.version_note() == ""  # the wgpu-py this was written for is the one installed
    note = wgpu_private.version_note("0.33.0")
    assert "\n" not in note and "wgpu-py 0.33.0" in note and "pip install 'wgpu==0.32.*'" in note
    assert "wgpu_private.py" in note and "tests/test_wgpu_private.py" in note


def test_reach_1_the_native_library_and_the_handles(ctx):
    ffi, lib = wgpu_private.native()
    assert float(lib.wgpuQueueGetTimestampPeriod(wgpu_private.handle(ctx.queue))) > 0
    assert ffi.typeof(wgpu_private.handle(ctx.device)).kind == "pointer"
    from wgpurender.wgpu_path.device.native import timestamp_period_ns

    assert timestamp_period_ns(ctx) > 0


def test_reach_2_the_backend_module_parses_wgpu_h():
    """BACKEND_FFI names the module whose import runs the cdef that cdef_cache.py and cffi_types.py take over."""
    module = importlib.import_module(wgpu_private.BACKEND_FFI)
    assert module.ffi is wgpu_private.native()[0]
    assert "WGPUTextureDescriptor" in {name.split(" ")[-1] for name in module.ffi._parser._declarations}


def test_reach_2_in_a_fresh_process_the_cache_patch_comes_before_the_backend():
    code = ("import sys; from wgpurender.wgpu_path.device import wgpu_private; "
            f"print({wgpu_private.BACKEND_FFI!r} in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"  # importing the reach module does not load wgpu's backend


def test_reach_3_the_poll_thread_readback(ctx):
    """The device's poller is found and swapped back; a readback through it returns the uploaded bytes."""
    import wgpu

    device = ctx.device
    real = wgpu_private.poller(device)
    assert real is not None
    with wgpu_private.poller_replaced(device, "stand-in") as before:
        assert device._poller == "stand-in" and before is real
    assert wgpu_private.poller(device) is real
    data = np.arange(64, dtype=np.uint8).tobytes()
    buffer = device.create_buffer_with_data(data=data, usage=wgpu.BufferUsage.MAP_READ)
    ctx.map_read(buffer, 0, 64)  # maps on this thread through the swapped poller
    assert bytes(buffer.read_mapped()) == data
    buffer.unmap()


def test_reach_4_a_surface_handle_is_none_before_the_surface():
    class Context:
        pass

    assert wgpu_private.surface_handle(Context()) is None
