"""What sector runs in one process share: the bodies, their modes, the quasi-static cycle
and the gap table (seconds each to build), kept by what they are built from, so that the
points of a sweep on one worker build them once."""

from __future__ import annotations

from typing import Any, Callable

#: What the last runs built, by what it is built from: the two bodies, their modes and the
#: quasi-static cycle (seconds each), which the points of a sweep share.
_CACHE: dict[Any, Any] = {}
#: Entries kept (a body of the paper's gear on 4 x 14 teeth holds about 60 MB).
CACHE_SIZE = 6


def cached(key: Any, build: Callable[[], Any]) -> Any:
    """``build()``, kept under ``key`` (the oldest entry dropped beyond :data:`CACHE_SIZE`;
    nothing kept for an unhashable key)."""
    try:
        found = _CACHE.get(key)
    except TypeError:
        return build()
    if found is None:
        found = build()
        if len(_CACHE) >= CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = found
    return found


__all__ = ["CACHE_SIZE", "cached"]
