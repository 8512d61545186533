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

import hashlib
import os
import re
from pathlib import Path
from typing import Any, Callable

import numba

from spurdyn.store import cache_base

PACKAGE = Path(__file__).resolve().parent

__all__ = ["njit", "cache_folder", "compiled_sources", "imported_modules"]


def _module_file(name: str) -> Path | None:
    """The source file of ``spurdyn.a.b`` (module or package)."""
    parts = name.split(".")[1:]
    base = PACKAGE.joinpath(*parts)
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


#: ``from spurdyn.x import a, b`` (names in parentheses may span lines) and ``import
#: spurdyn.x``, wherever they stand (lazy imports in functions count too).
_FROM = re.compile(r"^[ \t]*from[ \t]+(spurdyn(?:\.\w+)*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)",
                   re.MULTILINE)
_IMPORT = re.compile(r"^[ \t]*import[ \t]+([^\n]*)", re.MULTILINE)


def imported_modules(source: str) -> list[str]:
    """The spurdyn names a source imports: each module, and each ``module.name`` taken
    from it (which may be a submodule).

    A scan of the import lines, not a parse: this runs at every start of a run, and
    parsing the compiled modules with :mod:`ast` took ~60 ms of it. A line that only looks
    like an import (in a docstring) adds a file to the key, which is harmless.
    """
    names: list[str] = []
    for module, what in _FROM.findall(source):
        names.append(module)
        for line in what.strip("()").splitlines():
            for part in line.split("#", 1)[0].split(","):
                if part.split():
                    names.append(f"{module}.{part.split()[0]}")
    for what in _IMPORT.findall(source):
        for part in what.split("#", 1)[0].split(","):
            if part.split() and part.split()[0].split(".")[0] == "spurdyn":
                names.append(part.split()[0])
    return names


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
        for name in imported_modules(path.read_text()):
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
    folder = os.path.join(cache_base(), "numba-" + digest.hexdigest()[:16])
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
