"""A small bounded cache of per-frame GPU objects (bind groups, texture views) keyed by the objects they use.

Keys hold the textures themselves (wgpu objects hash by identity), not ``id()``: a freed
texture's id can be reused by a new one, a held reference cannot. The bound keeps a
caller that hands in a new texture object every frame (a swapchain image) from growing
the cache; such a caller pays what it paid before the cache, nothing more. Entries for
textures that were replaced (a resize) are dropped by :meth:`clear` or pushed out by new ones.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

V = TypeVar("V")


class BoundedCache(Generic[V]):
    """Least-recently-used mapping with at most ``capacity`` entries; :meth:`get` makes missing values."""

    def __init__(self, capacity: int = 4) -> None:
        self.capacity = capacity
        self._items: OrderedDict[Hashable, V] = OrderedDict()
        self.misses = 0  # values made so far (tests read it to check reuse)

    def __len__(self) -> int:
        return len(self._items)

    def get(self, key: Hashable, make: Callable[[], V]) -> V:
        items = self._items
        value = items.get(key)
        if value is None:
            value = make()
            self.misses += 1
            items[key] = value
            if len(items) > self.capacity:
                items.popitem(last=False)
        else:
            items.move_to_end(key)
        return value

    def clear(self) -> None:
        self._items.clear()
