"""Python's garbage collector and the frames that follow a load: what the load made is frozen.

A scene's load leaves tens of thousands of long-lived objects (the plan, meshes, wgpu-py wrappers); every full
collection during the frames walks them all again, and such a collection paused a frame by 4-5 ms (issue 22, the
p99 tails of issue 31.4). :func:`settle`, once a new drawable has drawn its first frame: the objects frozen after
an earlier load go back under the collector (the drawable they belonged to may be garbage now: a live reload, a
knob turned, a resize), one collection frees what is garbage, and ``gc.freeze()`` moves the survivors to the
permanent generation, which later collections skip. The collector stays on for what the frames themselves make.
Both windows call it; the benchmark's frames do the same (wgpurender/bench/frames.py, ``settle_garbage``).

Only our own freeze is ever undone. CPython has ONE permanent generation and ``gc.unfreeze()`` empties all of it,
so it cannot give back our objects alone: an application embedding the renderer may have frozen its own (before
forking workers, say), and unfreezing them would let a collection free or touch what it froze. So we unfreeze only
while nobody else has frozen anything: nothing was frozen before our first freeze, and a canary made right after
our last freeze is still outside the permanent generation (any later ``gc.freeze()`` moves it in; the frozen
count cannot tell, since frozen objects that die by reference count leave the generation). Otherwise
:func:`settle` only collects: nothing is unfrozen and nothing more is frozen (freezing then would mix our drawable
with theirs for good, and a reload would never free the old one); the frames then pay the collector's walks, as
without this module.

Python 3.12 keeps some of the interpreter's own objects in the permanent generation (``gc.get_freeze_count()`` is
375 in a fresh 3.12.1 process and again after every full collection; 0 on 3.11 and 3.13), so "nobody froze" is a
count no larger than that one, measured when this module is imported. A ``gc.freeze()`` by anyone moves every tracked
object (thousands), so a count of 1000 or more at import is someone's freeze, and then only 0 counts as nobody's.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator


class _Canary:
    """Made in the youngest generation right after our freeze: frozen only by someone else's gc.freeze()."""


_canary: _Canary | None = None  # None: we hold no freeze
_INTERPRETER = gc.get_freeze_count() if gc.get_freeze_count() < 1000 else 0  # the interpreter's own (3.12)


@contextlib.contextmanager
def paused() -> Iterator[None]:
    """No automatic collection while a load makes its objects (a decorator too): a scene of 10k models makes
    ~10^5 long-lived objects, none of them garbage, and each full collection on the way walked all made so far
    (issue 31.3). Whatever the load leaves unreachable is collected by the next collection after it; the collector
    is on again after the load only if it was on before (a caller that turned it off keeps it off)."""
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_on:
            gc.enable()


def only_ours_frozen() -> bool:
    """Whether the permanent generation holds nothing but what our last freeze put there (or nothing at all)."""
    if _canary is None:
        return gc.get_freeze_count() <= _INTERPRETER
    return any(o is _canary for o in gc.get_objects())  # ~1 ms once a load is frozen; settle collects anyway


def settle() -> int:
    """Unfreeze what we froze, collect, freeze; the number of objects frozen (0 when someone else's frozen objects
    are there: then only a collection)."""
    global _canary
    if not only_ours_frozen():
        gc.collect()
        return 0
    gc.unfreeze()
    gc.collect()
    gc.freeze()
    _canary = _Canary()
    return gc.get_freeze_count()


def thaw() -> None:
    """Give what :func:`settle` froze back to the collector; someone else's frozen objects stay frozen."""
    global _canary
    if only_ours_frozen():
        gc.unfreeze()
        _canary = _Canary()  # nobody has frozen anything since: a later freeze of theirs moves it in
