"""Whether the compiled solver still has to be compiled (a first run, an empty cache).

The command says so before it starts a run: compiling takes up to a minute with nothing
else to show. Looks at Numba's on-disk cache index of the stepping kernel; when that
cannot be read it says nothing rather than something untrue.
"""

from __future__ import annotations


def needs_compiling() -> bool:
    """True when neither this process nor the on-disk cache holds the compiled kernel."""
    from spurdyn.solvers.paper import step_compiled

    kernel = step_compiled.advance
    if kernel.signatures:  # compiled in this process already
        return False
    try:
        index = kernel._cache._cache_file._load_index()  # Numba's cache index (private)
    except Exception:  # noqa: BLE001 - another Numba version: say nothing
        return False
    return not index


__all__ = ["needs_compiling"]
