"""The time loop: ``simulate(pair, case) -> Result``."""

import hashlib
import os
from pathlib import Path


def _numba_cache_dir() -> None:
    """Keep the compiled kernels in a cache keyed by their source.

    Numba's own on-disk cache notices a change of the file a function is in, not of the
    files of the functions it calls; keying the folder by the sources of all compiled
    modules makes any change start a fresh cache. ``NUMBA_CACHE_DIR`` (if set) or
    ``SPURDYN_CACHE_DIR`` choose where it lives.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    import numba

    digest = hashlib.sha1()
    here = Path(__file__).parent
    for name in ("kernels.py", "fast_step.py"):
        digest.update((here / name).read_bytes())
    digest.update(numba.__version__.encode())
    base = os.environ.get("SPURDYN_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "spurdyn")
    folder = os.path.join(base, "numba-" + digest.hexdigest()[:16])
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return                      # not writable: numba keeps its default
    numba.config.CACHE_DIR = folder


_numba_cache_dir()

from spurdyn.integrate.run import simulate  # noqa: E402

__all__ = ["simulate"]
