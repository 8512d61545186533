"""An on-disk store of arrays that take long to compute and are the same in every run that
asks for them: the modes of a gear's body (docs/performance.md, "The mode store").

An entry is one ``.npz`` file named by the digest of everything that determines it (the
arrays it is computed from, the settings, the source of the code that computes it and the
versions of NumPy and SciPy), so an entry that no longer matches what asks for it is never
found, and there is nothing to invalidate. An entry is written to a temporary file in the
store's folder and renamed into place, so two processes writing the same entry leave it
whole and a reader never sees half of one. Reading an entry touches it; beyond the store's
size the entries read longest ago are dropped.

``SPURDYN_MODE_CACHE`` chooses the folder (``off`` turns the store off); by default it is
``modes/`` in ``SPURDYN_CACHE_DIR`` or ``~/.cache/spurdyn``. ``SPURDYN_MODE_CACHE_SIZE`` is
its size in MB (default :data:`DEFAULT_SIZE_MB`).
"""

from __future__ import annotations

import hashlib
import os
import sys
import tempfile
import time
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import scipy
from numpy.typing import NDArray

#: The store's default size (MB): the modes of the paper's whole gear on its default mesh
#: take about 50 MB, a 19/53 design pair's a few hundred.
DEFAULT_SIZE_MB = 2000
#: The value of ``SPURDYN_MODE_CACHE`` that turns the store off.
OFF = "off"


def cache_base() -> Path:
    """spurdyn's cache folder: ``SPURDYN_CACHE_DIR`` or ``~/.cache/spurdyn``."""
    return Path(os.environ.get("SPURDYN_CACHE_DIR") or Path.home() / ".cache" / "spurdyn")


def store_folder() -> Path | None:
    """The mode store's folder (module docstring), None when it is off."""
    chosen = os.environ.get("SPURDYN_MODE_CACHE", "")
    if chosen.strip().lower() == OFF:
        return None
    return Path(chosen) if chosen else cache_base() / "modes"


def store_size() -> int:
    """The store's size in bytes (``SPURDYN_MODE_CACHE_SIZE`` MB)."""
    return int(float(os.environ.get("SPURDYN_MODE_CACHE_SIZE") or DEFAULT_SIZE_MB) * 1e6)


def digest(*parts: Any) -> str:
    """A hex digest of ``parts``: arrays (dtype, shape and bytes), sparse matrices (their
    CSR arrays), numbers and strings, in order."""
    h = hashlib.sha256()
    for part in parts:
        if hasattr(part, "tocsr"):
            csr = part.tocsr()
            parts_of = (csr.shape, csr.data, csr.indices, csr.indptr)
            h.update(digest(*parts_of).encode())
        elif isinstance(part, np.ndarray):
            h.update(f"{part.dtype.str}{part.shape}".encode())
            h.update(np.ascontiguousarray(part).tobytes())
        else:
            h.update(repr(part).encode())
        h.update(b"|")
    return h.hexdigest()


def code_revision(*modules: str) -> str:
    """A digest of the sources of the named modules and of NumPy's and SciPy's versions:
    what decides an entry's last bits besides its inputs."""
    h = hashlib.sha256(f"numpy {np.__version__} scipy {scipy.__version__}".encode())
    for name in modules:
        h.update(Path(sys.modules[name].__file__ or "").read_bytes())
    return h.hexdigest()


def load(key: str) -> dict[str, NDArray[Any]] | None:
    """The arrays stored under ``key``, or None (no store, no entry, or an entry that cannot
    be read: it is removed)."""
    folder = store_folder()
    if folder is None:
        return None
    path = folder / f"{key}.npz"
    try:
        with np.load(path, allow_pickle=False) as entry:
            arrays = {name: entry[name] for name in entry.files}
    except FileNotFoundError:
        return None
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
        try:
            path.unlink(missing_ok=True)
        except OSError:
            pass                        # a store this process may read but not change
        return None
    try:
        os.utime(path)                  # read now: dropped last
    except OSError:
        pass
    return arrays


def save(key: str, **arrays: NDArray[Any]) -> None:
    """Store ``arrays`` under ``key`` (whole or not at all; nothing if the store is off or
    cannot be written), then keep the store within its size."""
    folder = store_folder()
    if folder is None:
        return
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".part")
        with os.fdopen(fd, "wb") as out:
            np.savez(out, **arrays)
        os.replace(tmp, folder / f"{key}.npz")
    except OSError:
        return
    prune(folder, store_size())


def entries(folder: Path) -> list[Path]:
    """The store's entries, read longest ago first."""
    found = []
    for path in folder.glob("*.npz"):
        try:
            found.append((path.stat().st_mtime, path))
        except FileNotFoundError:
            pass                        # dropped by another process meanwhile
    return [path for _, path in sorted(found)]


#: A temporary file older than this (s) is the remains of a process that stopped mid-write.
STALE_PART = 3600.0


def prune(folder: Path, size: int) -> None:
    """Drop the entries read longest ago until the store holds at most ``size`` bytes, and
    the remains of writes that never finished."""
    for part in folder.glob("*.part"):
        try:
            if time.time() - part.stat().st_mtime > STALE_PART:
                part.unlink(missing_ok=True)
        except FileNotFoundError:
            pass
    listed = entries(folder)
    sizes = [p.stat().st_size if p.exists() else 0 for p in listed]
    total = sum(sizes)
    for path, bytes_ in zip(listed, sizes):
        if total <= size:
            break
        path.unlink(missing_ok=True)
        total -= bytes_


def clear() -> int:
    """Remove every entry of the store; the number removed."""
    folder = store_folder()
    if folder is None or not folder.is_dir():
        return 0
    listed = entries(folder)
    for path in listed:
        path.unlink(missing_ok=True)
    return len(listed)


__all__ = ["DEFAULT_SIZE_MB", "OFF", "cache_base", "clear", "code_revision", "digest", "entries",
           "load", "prune", "save", "store_folder", "store_size"]
