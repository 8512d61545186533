"""The one gate for compiled code: every Numba function of spurdyn is made by :func:`njit`.

Numba's own disk cache notices a change of the file a function is in, not of the files
whose functions and constants it reads. This gate keys the cache folder on the sources of
every compiled module (each imports :func:`njit` from here) and, transitively, of every
spurdyn module they import (constants, layouts), so a change to any of them starts a
fresh cache.
``NUMBA_CACHE_DIR`` (if set) or ``SPURDYN_CACHE_DIR`` choose where the cache lives.

Importing this module imports Numba: only compiled modules import it, and they are
imported lazily by the compiled stepper.
"""

from __future__ import annotations

import ast
import hashlib
import os
from pathlib import Path
from typing import Any, Callable

import numba

PACKAGE = Path(__file__).resolve().parent

__all__ = ["njit", "compiled_sources", "cache_folder"]


def _module_file(name: str) -> Path | None:
    """The source file of ``spurdyn.a.b`` (module or package)."""
    parts = name.split(".")[1:]
    base = PACKAGE.joinpath(*parts)
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def compiled_sources() -> list[Path]:
    """The compiled modules (those that import this gate) and every spurdyn module they
    import, transitively."""
    todo = [p for p in sorted(PACKAGE.rglob("*.py"))
            if "from spurdyn.jit import" in p.read_text() and p.name != "jit.py"]
    seen: set[Path] = set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        for node in ast.walk(ast.parse(path.read_text())):
            names: list[str] = []
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            for name in names:
                if name.split(".")[0] == "spurdyn":
                    found = _module_file(name)
                    if found is not None and found not in seen:
                        todo.append(found)
    return sorted(seen)


def cache_folder() -> str | None:
    """The cache folder for the current compiled sources (None: keep Numba's default)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    digest = hashlib.sha1()
    for path in compiled_sources():
        digest.update(path.relative_to(PACKAGE).as_posix().encode())
        digest.update(path.read_bytes())
    digest.update(numba.__version__.encode())
    base = os.environ.get("SPURDYN_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "spurdyn")
    folder = os.path.join(base, "numba-" + digest.hexdigest()[:16])
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return None                 # not writable: Numba keeps its default
    return folder


_folder = cache_folder()
if _folder is not None:
    numba.config.CACHE_DIR = _folder


def njit(fn: Callable[..., Any]) -> Callable[..., Any]:
    """Compile ``fn`` in nopython mode, cached on disk, releasing the GIL while it runs.

    The kernels touch no Python object, so the GIL is not needed; releasing it lets a
    thread of the command (loading the output writers, :mod:`spurdyn.results.prefetch`)
    use the second core while the time loop runs.
    """
    return numba.njit(cache=True, nogil=True)(fn)
