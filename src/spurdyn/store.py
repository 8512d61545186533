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
import inspect
import math
import os
import platform
import sys
import tempfile
import time
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import scipy
from numpy.typing import NDArray
from threadpoolctl import threadpool_info

from spurdyn.errors import InputError

#: The store's default size (MB): the modes of the paper's whole gear on its default mesh
#: take about 50 MB, a 19/53 design pair's a few hundred.
DEFAULT_SIZE_MB = 2000
#: The value of ``SPURDYN_MODE_CACHE`` that turns the store off.
OFF = "off"


def cache_base() -> Path:
    """spurdyn's cache folder: ``SPURDYN_CACHE_DIR`` or ``~/.cache/spurdyn``."""
    return Path(os.environ.get("SPURDYN_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "spurdyn"))


def store_folder() -> Path | None:
    """The mode store's folder (module docstring), None when it is off.

    Raises
    ------
    InputError
        ``SPURDYN_MODE_CACHE`` names something that is not a folder.
    """
    chosen = os.environ.get("SPURDYN_MODE_CACHE", "")
    if chosen.strip().lower() == OFF:
        return None
    folder = Path(chosen) if chosen else cache_base() / "modes"
    if folder.exists() and not folder.is_dir():
        raise InputError("SPURDYN_MODE_CACHE", f"{folder} is not a folder: name a folder, or "
                         f"'{OFF}' to keep no modes on disk")
    return folder


def store_size() -> int:
    """The store's size in bytes (``SPURDYN_MODE_CACHE_SIZE`` MB).

    Raises
    ------
    InputError
        ``SPURDYN_MODE_CACHE_SIZE`` is not a number of MB, 0 or more.
    """
    given = os.environ.get("SPURDYN_MODE_CACHE_SIZE") or str(DEFAULT_SIZE_MB)
    try:
        size = float(given)
    except ValueError:
        size = math.nan
    if not (math.isfinite(size) and size >= 0.0):
        raise InputError("SPURDYN_MODE_CACHE_SIZE", f"must be a number of MB, 0 or more (got {given!r})")
    return int(size * 1e6)


def check() -> None:
    """Refuse a store the environment describes wrongly (:func:`store_folder`,
    :func:`store_size`), before a run computes anything."""
    if store_folder() is not None:
        store_size()


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
    """A digest of the sources of the named modules, NumPy's and SciPy's versions, the BLAS
    libraries and the machine's architecture: what decides an entry's last bits besides its
    inputs."""
    h = hashlib.sha256(f"numpy {np.__version__} scipy {scipy.__version__} {platform.machine()}".encode())
    # sorted: threadpoolctl lists the libraries in the order the process happened to load them
    libs = sorted(repr([lib.get(k) for k in ("internal_api", "version", "architecture", "num_threads")])
                  for lib in threadpool_info())
    for lib in libs:
        h.update(lib.encode())
    for name in modules:
        module = sys.modules[name]
        try:
            h.update(Path(module.__file__ or "").read_bytes())
        except OSError:
            h.update(inspect.getsource(module).encode())
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
    except OSError:
        return None                     # absent, or not ours to read: leave it
    except (ValueError, EOFError, KeyError, zipfile.BadZipFile):
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
    size = store_size()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".part")
    except OSError:
        return
    try:
        with os.fdopen(fd, "wb") as out:
            np.savez(out, **arrays)
        # readable by whoever may read the folder, as a file written with open() would be
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, folder / f"{key}.npz")
    except BaseException as err:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(err, OSError):
            return                      # a full disk or a folder not ours: keep computing
        raise
    try:
        prune(folder, size)
    except OSError:
        pass                            # another process's entries: its own prune keeps them


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


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
    listed = []
    for path in entries(folder):
        try:
            listed.append((path, path.stat().st_size))
        except FileNotFoundError:
            pass                        # dropped by another process meanwhile
    total = sum(bytes_ for _, bytes_ in listed)
    for path, bytes_ in listed:
        if total <= size:
            break
        path.unlink(missing_ok=True)
        total -= bytes_


def clear() -> int:
    """Remove every entry of the store; the number removed."""
    folder = store_folder()
    if folder is None or not folder.is_dir():
        return 0
    removed = 0
    for path in entries(folder):
        try:
            path.unlink()
            removed += 1
        except OSError:
            pass                        # gone meanwhile, or not ours to remove
    return removed


__all__ = ["DEFAULT_SIZE_MB", "OFF", "cache_base", "check", "clear", "code_revision", "digest", "entries",
           "load", "prune", "save", "store_folder", "store_size"]
