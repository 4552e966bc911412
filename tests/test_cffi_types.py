"""wgpu_path/device/cffi_types.py: the fast answer for a typedef equals cffi's own parse, for every typedef of wgpu.h.

The reference is cffi's real parser (pycparser), not the module under test: for each typedef name and each
of the three shapes (a sample of the names: each real parse takes ~0.1 s), both answers must be equal model
types with equal qualifiers, and the ctype cffi makes from them must be the same object. Other strings must be
left to the parser.
"""

from __future__ import annotations

import pytest

from wgpurender.wgpu_path.device import cffi_types


@pytest.fixture(scope="module")
def parser():
    from wgpu.backends.wgpu_native._ffi import ffi

    cffi_types.install(ffi)
    real = getattr(ffi._parser.parse_type_and_quals, "original", ffi._parser.parse_type_and_quals)
    return ffi, real


def test_every_typedef_shape_matches_cffis_parser(parser):
    ffi, real = parser
    names = sorted(k.split(" ", 1)[1] for k in ffi._parser._declarations if k.startswith("typedef "))
    assert len(names) > 100
    # every 7th name (the whole set parses for minutes), plus the ones a frame uses
    sample = set(names[::7]) | {n for n in names if n in ("WGPURenderPassDescriptor", "WGPUColor", "WGPUBool")}
    sample |= {"uint8_t", "uint32_t", "intptr_t", "uintptr_t", "int", "float", "double"}  # primitives wgpu-py uses
    for name in sorted(sample):
        for cdecl in (name, f"{name} *", f"{name}[]"):
            fast = cffi_types.fast_parse_type_and_quals(ffi._parser, cdecl)
            assert fast is not None, cdecl
            expected = real(cdecl)
            assert fast == expected, cdecl
            with ffi._lock:  # cffi keys its ctype cache by the model type: equal types, one ctype
                assert ffi._get_cached_btype(fast[0]) is ffi._get_cached_btype(expected[0])


def test_void_pointer_matches_cffis_parser(parser):
    ffi, real = parser
    assert cffi_types.fast_parse_type_and_quals(ffi._parser, "void *") == real("void *")


# every callback signature wgpu-py 0.32 hands to ffi.callback (each real parse re-reads wgpu.h's typedefs)
CALLBACKS = [
    "void(WGPULogLevel, WGPUStringView, void *)",
    "void(WGPUQueueWorkDoneStatus, void *, void *)",
    "void(WGPUMapAsyncStatus, WGPUStringView, void *, void *)",
    "void(WGPUCompilationInfoRequestStatus, WGPUCompilationInfo*, void*)",
    "void(WGPURequestAdapterStatus, WGPUAdapter, WGPUStringView, void *, void *)",
    "void(WGPUDevice const *, WGPUDeviceLostReason, WGPUStringView, void *, void *)",
    "void(WGPUDevice const *, WGPUErrorType, WGPUStringView, void *, void *)",
    "void(WGPURequestDeviceStatus, WGPUDevice, WGPUStringView, void *, void *)",
    "void(WGPUCreatePipelineAsyncStatus, WGPUComputePipeline, char *, void *, void *)",
    "void(WGPUCreatePipelineAsyncStatus, WGPURenderPipeline, WGPUStringView, void *, void *)",
    "int(void)", "void()", "WGPUColor const *",
]


@pytest.mark.parametrize("cdecl", CALLBACKS)
def test_callback_signatures_match_cffis_parser(parser, cdecl):
    ffi, real = parser
    fast = cffi_types.fast_parse_type_and_quals(ffi._parser, cdecl)
    expected = real(cdecl)
    assert fast is not None and fast == expected, cdecl
    # ffi.callback makes a function-pointer ctype of a function type, as cffi's _typeof does
    def as_ctype(t):
        return (t.as_function_pointer() if t.is_raw_function else t)
    with ffi._lock:
        assert ffi._get_cached_btype(as_ctype(fast[0])) is ffi._get_cached_btype(as_ctype(expected[0]))


@pytest.mark.parametrize("cdecl", ["char[4]", "WGPUColor **", "struct WGPUColor *", "int (*)(int)",
                                   "int(int, ...)", "void(int (*)(int))"])
def test_other_shapes_go_to_the_parser(parser, cdecl):
    ffi, _ = parser
    assert cffi_types.fast_parse_type_and_quals(ffi._parser, cdecl) is None
