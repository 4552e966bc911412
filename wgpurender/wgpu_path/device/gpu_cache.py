"""One cache type for GPU objects: named, keyed, bounded, and released with its device.

Every GPU object the wgpu path makes once and reuses (pipelines, layouts, samplers, bind groups, views)
lives in a :class:`GpuCache`. Rules, after pygfx's ``GpuCache`` (named caches with hit/miss counts):

- **keyed**: by plain values (formats, shader text, a plan's pass) or by the GPU objects a value uses
  (wgpu objects hash by identity; a held reference cannot be reused by a new object, an ``id()`` can);
- **bounded**: least recently used entries go first, so a caller that hands in a new texture every
  frame (a swapchain image) cannot grow a cache; such a caller pays what it paid without one;
- **released with its device**: :func:`device_cache` hangs a device's caches on the device object
  itself, never in a module dict keyed by devices (which would hold every device, and all it made,
  for the life of the process);
- **named, counted**: ``hits``, ``misses`` and ``evictions`` per cache; :func:`cache_stats` lists them.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

V = TypeVar("V")
_ATTRIBUTE = "_wgpurender_caches"


class GpuCache(Generic[V]):
    """Least-recently-used mapping with at most ``capacity`` entries; :meth:`get` makes missing values."""

    def __init__(self, name: str, capacity: int = 64) -> None:
        self.name = name
        self.capacity = capacity
        self._items: OrderedDict[Hashable, V] = OrderedDict()
        self.hits = self.misses = self.evictions = 0

    def __len__(self) -> int:
        return len(self._items)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._items

    def get(self, key: Hashable, make: Callable[[], V]) -> V:
        """The value for ``key``, made by ``make()`` on a miss (a value of None is not cached: wrap it)."""
        items = self._items
        value = items.get(key)
        if value is None:
            value = make()
            self.misses += 1
            items[key] = value
            if len(items) > self.capacity:
                items.popitem(last=False)
                self.evictions += 1
        else:
            self.hits += 1
            items.move_to_end(key)
        return value

    def clear(self) -> None:
        self._items.clear()

    def stats(self) -> dict[str, int]:
        return {"size": len(self), "capacity": self.capacity, "hits": self.hits, "misses": self.misses,
                "evictions": self.evictions}

    def __repr__(self) -> str:
        return f"GpuCache({self.name!r}, {len(self)}/{self.capacity}, hits {self.hits}, misses {self.misses})"


def device_cache(device: Any, name: str, capacity: int = 64) -> GpuCache:
    """The device's cache called ``name`` (made on first use), stored on the device object itself."""
    caches = getattr(device, _ATTRIBUTE, None)
    if caches is None:
        caches = {}
        setattr(device, _ATTRIBUTE, caches)
    cache = caches.get(name)
    if cache is None:
        cache = caches[name] = GpuCache(name, capacity)
    return cache


def clear_caches(device: Any) -> None:
    """Empty every named cache of a device (the demo's live reload: shader files changed on disk)."""
    for cache in getattr(device, _ATTRIBUTE, {}).values():
        cache.clear()


def cache_stats(device: Any) -> dict[str, dict[str, int]]:
    """Every named cache of a device with its counts (for benchmarks and tests)."""
    return {name: cache.stats() for name, cache in getattr(device, _ATTRIBUTE, {}).items()}
