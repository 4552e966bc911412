"""The GPU context: which adapter, which device features, and how to wait for the GPU.

The course creates an instance, picks a physical device and a queue family, and
creates a logical device with the features it needs. wgpu folds those into
``request_adapter`` + ``request_device``; this module is where that happens, once
per process and backend.
"""

from __future__ import annotations

import atexit
import functools
import os
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import wgpu

from wgpurender.core.errors import UserError
from wgpurender.wgpu_path import binding
from wgpurender.wgpu_path.device import wgpu_private
from wgpurender.wgpu_path.device.driver_preload import BACKEND_ENV

if TYPE_CHECKING:
    from wgpurender.core.plan.model import AdapterFacts

VALIDATION_ENV = "WGPURENDER_VALIDATION"
DEFAULT_BACKEND = "Vulkan"
AUTO = "auto"
# The name an adapter reports (info["backend_type"]) -> wgpu-native's instance flag for that backend only.
# wgpu-native calls OpenGL "GL" and Direct3D 12 "DX12"; the adapter says "OpenGL" and "D3D12".
BACKENDS = {"Vulkan": "Vulkan", "OpenGL": "GL", "Metal": "Metal", "D3D12": "DX12"}
# "auto": every backend on the instance, the best adapter wins (GPU before CPU, then this order).
AUTO_ORDER = ("Vulkan", "Metal", "D3D12", "OpenGL")

# Features the renderer uses when the adapter offers them, and works without otherwise.
OPTIONAL_FEATURES = (
    "timestamp-query",
    "immediates",
    "clear-texture",
    "float32-filterable",
    "pipeline-cache",
    "indirect-first-instance",  # GPU-culled draws (core/plan/culling.py)
)

INSTALL_HINT = (
    "install a Vulkan driver (Debian: apt-get install mesa-vulkan-drivers libvulkan1, "
    "which gives the lavapipe CPU driver) or your GPU vendor's driver"
)


@dataclass
class GPUContext:
    """An adapter and the device made from it, plus what was negotiated."""

    adapter: wgpu.GPUAdapter
    device: wgpu.GPUDevice
    features: frozenset[str]
    _fence: wgpu.GPUBuffer | None = field(default=None, repr=False)
    # the frame loop's reusable readback (frame_loop.Readback, made there on first use; typed loosely: gpu.py
    # sits below frame_loop.py)
    frame_readback: object | None = field(default=None, repr=False)

    @property
    def queue(self) -> wgpu.GPUQueue:
        return self.device.queue

    @property
    def info(self) -> dict:
        return dict(self.adapter.info)

    @property
    def backend(self) -> str:
        return self.adapter.info["backend_type"]

    def has(self, feature: str) -> bool:
        return feature in self.features

    def adapter_facts(self) -> AdapterFacts:
        """What the plan's "auto" knobs need to know about this adapter and device (plain values)."""
        from wgpurender.core.plan.model import AdapterFacts  # lazily: the plan package costs ~0.3 s to import

        info = self.info
        limits = {**self.adapter.limits, "max-storage-buffer-binding-size":  # the device's, which binds
                  self.device.limits["max-storage-buffer-binding-size"]}
        return AdapterFacts.of(info.get("adapter_type", ""), self.features, info.get("device", ""),
                               info.get("backend_type", ""), limits,
                               info.get("description", "") if info.get("backend_type") == "OpenGL" else "")

    def use_immediates(self, requested: bool | None = None) -> bool:
        """Whether to push per-draw data as immediates: ``None`` follows the plan's rule (offered, and trusted on
        this backend: core/plan/post.py); ``True`` where the rule says no is refused with its reason."""
        from wgpurender.core.plan.post import immediates_rule

        usable, why = immediates_rule(self.adapter_facts())
        if requested and not usable:
            raise UserError(f"immediates cannot be used on {self.describe()}: {why.split('; ')[0]}; "
                            "leave them unset (or off) to use a uniform buffer")
        return usable if requested is None else bool(requested)

    def limit(self, name: str) -> int:
        return self.device.limits[name]

    def describe(self) -> str:
        info = self.adapter.info
        return f"{info['device']} ({info['backend_type']}, {info['adapter_type']}, {info['description']})"

    def wait_idle(self) -> None:
        """Block until every submitted command buffer has finished (the Vulkan analogue: vkQueueWaitIdle).

        wgpu-native's ``wgpuDevicePoll(wait=True)`` waits for the last submission, here on the calling
        thread (wgpu-py's private ``GPUDevice._poll_wait``). The public ways cost more per frame:
        ``queue.on_submitted_work_done_sync()`` raises TypeError in wgpu 0.32.0, and mapping a
        fence buffer hands the wait to wgpu-py's poll thread and back (two thread wake-ups, 0.2 ms
        to several ms on a loaded machine). Where ``_poll_wait`` is missing (another wgpu-py), we
        map a tiny buffer copied after the real work: submissions complete in order.
        """
        poll = getattr(self.device, "_poll_wait", None)
        if poll is not None:
            poll()
            return
        dev = self.device
        if self._fence is None:
            self._src = dev.create_buffer(size=4, usage=wgpu.BufferUsage.COPY_SRC, label="fence-src")
            self._fence = dev.create_buffer(
                size=4, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ, label="fence"
            )
        enc = dev.create_command_encoder(label="wait-idle")
        enc.copy_buffer_to_buffer(self._src, 0, self._fence, 0, 4)
        self.queue.submit([enc.finish()])
        self._fence.map_sync(wgpu.MapMode.READ)
        self._fence.unmap()

    def map_read(self, buffer: wgpu.GPUBuffer, offset: int = 0, size: int | None = None) -> None:
        """``buffer.map_sync(READ, ...)``, waited for on this thread: wgpu-py's poll thread is never woken.

        wgpu-py 0.32's ``GPUBuffer.map_async`` always asks the device's ``PollThread`` for a token,
        which wakes that thread; it then polls (blocking) until the map callback runs, while this
        thread waits on the promise. Two threads handing the GIL back and forth around one map cost
        ~5-10 ms stalls (the GIL switch interval) on the H100/H200 (issue 22). wgpu-py 0.32 has no
        public way to map without the thread, so the least surprising way is taken: for the one
        ``map_async`` call the device's poller is a stand-in (:class:`CallerPolls`) whose token wakes
        nothing; the device is then polled here (``wgpuDevicePoll(wait=True)``), which runs the map
        callback on this thread, and the promise is already resolved. Everything else (map state,
        ``read_mapped``, ``unmap``) stays wgpu-py's own. Where the private attributes are missing (another
        wgpu-py), this is plain ``map_sync``.
        """
        device = self.device
        poller = wgpu_private.poller(device)
        if poller is None:
            buffer.map_sync(wgpu.MapMode.READ, offset, size)
            return
        with wgpu_private.poller_replaced(device, CallerPolls(poller)):
            promise = buffer.map_async(wgpu.MapMode.READ, offset, size)
        for _ in range(3):  # one blocking poll completes every submission: the callback has run
            wgpu_private.poll_wait(device)
            if not wgpu_private.pending(promise):
                break
        else:  # never seen: hand the wait to the poll thread after all rather than block forever
            token = poller.get_token()
            promise.sync_wait()
            token.set_done()
        promise.sync_wait()

    def read_buffer(self, buffer: wgpu.GPUBuffer, offset: int = 0, size: int | None = None) -> bytes:
        """A copy of a COPY_SRC buffer's bytes, read on this thread (``queue.read_buffer`` without the poll thread).

        ``offset`` and ``size`` are multiples of 4, as WebGPU's buffer copies require."""
        size = buffer.size - offset if size is None else size
        staging = self.device.create_buffer(
            size=size, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ, label="read-buffer")
        encoder = self.device.create_command_encoder(label="read-buffer")
        encoder.copy_buffer_to_buffer(buffer, offset, staging, 0, size)
        self.queue.submit([encoder.finish()])
        self.map_read(staging)
        data = bytes(staging.read_mapped(0, size, copy=False))
        staging.unmap()
        staging.destroy()
        return data


class CallerPolls:
    """Stands in for wgpu-py's ``PollThread`` during one ``map_async``: tokens that wake no thread.

    The caller polls the device itself right after (:meth:`GPUContext.map_read`), so the map
    callback runs there; ``set_done`` (called by that callback) has nothing to release.
    """

    def __init__(self, thread: object) -> None:
        self.thread = thread

    def get_token(self) -> _QuietToken:
        return _QuietToken()


class _QuietToken:
    def set_done(self) -> None:
        pass

    def is_done(self) -> bool:
        return True


def requested_backend(backend: str | None = None) -> str:
    """The backend to use: the argument, else $WGPURENDER_BACKEND, else Vulkan; "auto" lets the machine choose.

    Names are case-insensitive: vulkan, opengl (or gl), metal, d3d12 (or dx12), auto (core/checks.py). A name
    already spelled as the adapter spells it (the default's, or one checks.backend returned) is taken as it is:
    the checks module is then not imported before the device thread starts (issue 31.5)."""
    name = backend or os.environ.get(BACKEND_ENV) or DEFAULT_BACKEND
    if name in BACKENDS or name == AUTO:
        return name
    from wgpurender.core import checks  # lazily: ~5 ms before the device thread could start

    return checks.backend(name)


_instance_backend: list[str] = []  # the backend the process's one wgpu instance was created for


def _configure_instance_once(backend: str) -> None:
    """Create the wgpu instance for ``backend`` only, with validation when $WGPURENDER_VALIDATION is set.

    wgpu-py keeps one instance per process, configured before the first adapter is enumerated. Limiting
    it to one backend means no OpenGL/EGL enumeration at start-up (the largest part of the context time
    on lavapipe and NVIDIA alike), and with validation on, NVIDIA's OpenGL backend (enumerated alongside
    Vulkan otherwise) crashed the process at exit. "auto" enables every backend. A later request for
    another backend in the same process is refused (one process, one instance): run another process.
    Validation messages from the Vulkan layer arrive through the ``wgpu`` Python logger.
    """
    if _instance_backend:
        made = _instance_backend[0]
        if made not in (backend, AUTO):
            raise UserError(f"this process already created its wgpu instance for {made} only; the {backend} "
                            f"backend needs its own process (or start with --backend auto)")
        return
    from wgpurender.core.files.runtime_dir import ensure_runtime_dir

    ensure_runtime_dir()  # before the instance: no "XDG_RUNTIME_DIR is invalid" lines from the driver
    if binding.requested() == "dawn":  # Dawn has no wgpu-native instance extras: it picks its own backends
        _instance_backend.append(backend)
        return
    _import_backend()
    from wgpu.backends.wgpu_native.extras import set_instance_extras

    validation = os.environ.get(VALIDATION_ENV, "") not in ("", "0")
    flags = ["All"] if backend == AUTO else [BACKENDS[backend]]
    set_instance_extras(backends=flags, flags=["Validation"] if validation else ["Default"])
    _instance_backend.append(backend)


def _import_backend() -> None:
    """Import wgpu-py's wgpu-native backend with wgpu.h's cached parse: Python work only (~40 ms), no driver call.

    :func:`start_context` does this in the caller's thread, so the thread it starts begins with the driver."""
    from wgpurender.wgpu_path.device.cdef_cache import cached_wgpu_header

    with cached_wgpu_header():  # wgpu.h's parse loaded from the cache of an earlier process (cdef_cache.py)
        import wgpu.backends.wgpu_native.extras  # noqa: F401

    from wgpurender.wgpu_path.device.cffi_types import install_for_wgpu

    install_for_wgpu()  # C type names parsed in microseconds, not ~0.1 s each (cffi_types.py)


@functools.cache
def _enumerate() -> tuple:
    if binding.name() == "dawn":
        adapters = _quietly(wgpu.gpu.enumerate_adapters_sync)  # Dawn prints its refusals on stderr itself
        if not adapters:
            raise UserError(binding.refusal([]))
        return tuple(adapters)
    return tuple(wgpu.gpu.enumerate_adapters_sync())


def _quietly(call):
    """``call()`` with file descriptor 2 sent to /dev/null (C code's warnings), restored after."""
    import sys

    sys.stderr.flush()
    saved, null = os.dup(2), os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 2)
    try:
        return call()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


def _adapters(backend: str | None = None) -> tuple:
    """The instance's adapters; the instance is made for ``backend`` (or the requested one) if not yet made."""
    if backend is not None or not _instance_backend:
        _configure_instance_once(requested_backend(backend))
    return _enumerate()


def available_backends() -> list[str]:
    """Backend names of the adapters this process's instance offers (only the requested one, unless auto)."""
    return sorted({a.info["backend_type"] for a in _adapters()})


def select_adapter(backend: str | None = None) -> wgpu.GPUAdapter:
    """The best adapter of the requested backend (hardware before CPU); for "auto", of any backend."""
    want = requested_backend(backend)
    adapters = _adapters(want)
    found = [a for a in adapters if want == AUTO or a.info["backend_type"] == want]
    if not found:
        others = sorted({a.info["backend_type"] for a in adapters})
        alt = f"; this machine offers: {', '.join(others)} (use --backend)" if others else ""
        if want in ("Vulkan", AUTO):
            raise UserError(f"no {'Vulkan' if want == 'Vulkan' else 'GPU'} adapter found: {INSTALL_HINT}{alt}")
        raise UserError(f"no {want} adapter found{alt}")
    order = {"DiscreteGPU": 0, "IntegratedGPU": 1, "VirtualGPU": 2, "CPU": 3}
    rank = {name: i for i, name in enumerate(AUTO_ORDER)}
    return min(found, key=lambda a: (order.get(a.info["adapter_type"], 4), rank.get(a.info["backend_type"], 9)))


def refuse_broken_gl(adapter: wgpu.GPUAdapter) -> None:
    """A GL adapter whose bindings wgpu gets wrong is refused in one line (core/plan/gl_facts.gl_binding_fault)
    rather than drawing wrong images: NVIDIA's EGL context is one (GL 3.3 with the compute extension)."""
    info = adapter.info
    if info["backend_type"] != "OpenGL":
        return
    from wgpurender.core.plan.gl_facts import CANNOT_DRAW, gl_binding_fault  # lazily: ~40 ms the rest don't need

    why = gl_binding_fault(info["description"], adapter.limits["max-compute-invocations-per-workgroup"])
    if why:
        raise UserError(f"the OpenGL adapter {info['device']} ({info['description']}) {CANNOT_DRAW}: {why}; "
                        "use --backend vulkan")


_made: dict[str, GPUContext] = {}  # the process's contexts by backend
_early: dict[str, _EarlyContext] = {}  # contexts being made on a thread (start_context), not yet taken
_made_lock = threading.Lock()


def get_context(backend: str | None = None) -> GPUContext:
    """The process-wide context for a backend, created on first use ("auto" and None resolve first).

    If :func:`start_context` began making it, this waits for that thread and returns (or raises) its result."""
    want = requested_backend(backend)
    with _made_lock:
        ctx = _made.get(want)
        early = _early.pop(want, None) if ctx is None else None
        if ctx is not None:
            return ctx
        if early is None:
            ctx = _made[want] = _make_context(want)
            return ctx
    ctx = early.result()  # outside the lock: the thread may take it (a nested get_context)
    with _made_lock:
        return _made.setdefault(want, ctx)


def start_context(backend: str | None = None) -> None:
    """Begin making the process's context for ``backend`` on a thread; :func:`get_context` takes the result.

    Making a context is mostly native work (the driver's instance and device: ~0.2 s on an NVIDIA H100) that
    holds no Python lock, so a program that starts it before importing the rest of what it draws with overlaps
    the two (issue 31.5, the first pixel). A bad backend name is refused here, in the caller's thread; an error
    while making the context is raised by the :func:`get_context` that takes it. Nothing happens if the context
    exists or is already being made."""
    want = requested_backend(backend)
    with _made_lock:
        if want in _made or want in _early:
            return
        if binding.requested() != "dawn":  # the Python part first, in this thread: on the new thread it would
            _import_backend()  # share the GIL with the caller's imports while the driver's work waited for it
        if not _early_joined:  # a process that stops early (bad input) waits for the driver, not exits mid-call
            atexit.register(_join_early)
            _early_joined.append(True)
        _early[want] = _EarlyContext(want)


_early_joined: list[bool] = []


def _join_early() -> None:
    for early in list(_early.values()):
        early.thread.join()


# Python's thread switch interval while a context is made on a thread. Making one calls wgpu-native ~140 times
# (wgpu-py asks the adapter and the device for each feature); after each call the thread waits for the GIL, up to
# the interval (5 ms by default) while the main thread imports. 0.5 ms lets it through (measured 2026-11-27:
# docs/perf-h100/2026-11-27-startup/).
EARLY_SWITCH_S = 0.0005


_switch = {"threads": 0, "before": 0.0}  # threads making a context early; the interval before the first of them
_switch_lock = threading.Lock()


@contextmanager
def _short_switch_interval() -> Iterator[None]:
    """:data:`EARLY_SWITCH_S` while any context is made on a thread; the interval from before, after the last."""
    import sys

    with _switch_lock:
        if _switch["threads"] == 0:
            _switch["before"] = sys.getswitchinterval()
            sys.setswitchinterval(min(_switch["before"], EARLY_SWITCH_S))
        _switch["threads"] += 1
    try:
        yield
    finally:
        with _switch_lock:
            _switch["threads"] -= 1
            if _switch["threads"] == 0:
                sys.setswitchinterval(_switch["before"])


class _EarlyContext:
    """A context being made on a daemon thread: its result, or the exception that stopped it."""

    def __init__(self, backend: str) -> None:
        self.ctx: GPUContext | None = None
        self.error: BaseException | None = None
        self.thread = threading.Thread(target=self._make, args=(backend,), name="wgpurender-context", daemon=True)
        self.thread.start()

    def _make(self, backend: str) -> None:
        try:
            with _short_switch_interval():
                self.ctx = _make_context(backend)
        except BaseException as exc:  # handed to the caller of get_context, which raises it there
            self.error = exc

    def result(self) -> GPUContext:
        self.thread.join()
        if self.error is not None:
            raise self.error
        return self.ctx


_making = threading.Lock()  # one context made at a time: the instance set-up and adapter list are per process


def _make_context(backend: str) -> GPUContext:
    with _making:
        return _build_context(backend)


def _build_context(backend: str) -> GPUContext:
    note = wgpu_private.version_note()
    if note:  # once per process: the private reaches may not hold on this wgpu-py
        import sys

        print(note, file=sys.stderr, flush=True)
    adapter = select_adapter(backend)
    refuse_broken_gl(adapter)
    features = frozenset(f for f in OPTIONAL_FEATURES if f in adapter.features)
    limits = {}
    if "immediates" in features:
        limits["max-immediate-size"] = adapter.limits["max-immediate-size"]
    device = adapter.request_device_sync(label="wgpurender", required_features=sorted(features), required_limits=limits)
    return GPUContext(adapter=adapter, device=device, features=features)
