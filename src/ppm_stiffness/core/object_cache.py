"""Values computed once per (immutable) object and kept while the object lives.

Designs and legs are frozen pydantic models: what is derived from one (a leg's reduced
form, its constant directions) cannot change while it lives. :func:`per_object` caches
such a derived value under the object's identity (not its value: a design's hash would
cost more than some of the values) and drops it when the object is garbage-collected,
so that maps, sweeps and the optimiser reuse it call after call without a cache that
grows with every design a sweep creates.
"""

from __future__ import annotations

import functools
import weakref
from collections.abc import Callable
from typing import Any, TypeVar

R = TypeVar("R")


def per_object(fn: Callable[[Any], R]) -> Callable[[Any], R]:
    """Decorate ``fn(obj)`` so that it runs once per live object ``obj``.

    The object must not change while it lives (a frozen model); the cached value is
    shared by every caller, so it must not be changed either. An object that cannot be
    weakly referenced is not cached. ``wrapper.cache_size()`` gives the number of
    objects held (tests).
    """
    cache: dict[int, tuple[weakref.ref[Any], R]] = {}

    @functools.wraps(fn)
    def wrapper(obj: Any) -> R:
        key = id(obj)
        hit = cache.get(key)
        if hit is not None and hit[0]() is obj:
            return hit[1]
        value = fn(obj)

        def forget(ref: weakref.ref[Any], key: int = key) -> None:
            entry = cache.get(key)
            if entry is not None and entry[0] is ref:
                del cache[key]

        try:
            cache[key] = (weakref.ref(obj, forget), value)
        except TypeError:  # not weakly referenceable: computed every time
            pass
        return value

    wrapper.cache_size = lambda: len(cache)  # type: ignore[attr-defined]
    return wrapper
