"""Configuration-only quantities cached by the identity of the radar configuration.

`functools.lru_cache` keys its entries by equality, so each lookup hashes its arguments; a
`radarsim.RadarConfig` is a frozen dataclass of some forty fields and its hash costs ~5 us hot
and 10-40 us inside a frame (cold caches), several times per frame. `per_config` looks the
configuration up by identity first (a frame's chain passes the same object to every stage) and
keeps the object in the entry, so its id cannot be reused while the entry lives. Equal but
distinct configurations get entries of their own, with equal values.
"""
from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import TypeVar

__all__ = ["per_config"]

T = TypeVar("T")


def per_config(maxsize: int = 32) -> Callable[[Callable[..., T]], Callable[..., T]]:
    """Decorator: cache ``fn(cfg, *args)`` (hashable args) by the identity of `cfg`.

    At most `maxsize` entries, the oldest dropped first. `cache_clear` empties the cache.

    Examples
    --------
    >>> from pipeline.config_cache import per_config
    >>> calls = []
    >>> @per_config()
    ... def area(cfg, scale):
    ...     calls.append(scale)
    ...     return cfg[0] * cfg[1] * scale
    >>> box = (2, 3)
    >>> area(box, 2), area(box, 2), area((2, 3), 2), calls
    (12, 12, 12, [2, 2])
    """
    def decorate(fn: Callable[..., T]) -> Callable[..., T]:
        cache: dict[tuple, tuple[object, T]] = {}
        lock = threading.Lock()  # for the writes (misses) only

        @functools.wraps(fn)
        def cached(cfg, *args):
            key = (id(cfg), *args)
            hit = cache.get(key)
            if hit is not None and hit[0] is cfg:
                return hit[1]
            value = fn(cfg, *args)
            with lock:
                while len(cache) >= maxsize:
                    cache.pop(next(iter(cache)))
                cache[key] = (cfg, value)
            return value

        cached.cache_clear = cache.clear
        return cached
    return decorate
