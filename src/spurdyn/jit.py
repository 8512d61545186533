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

import functools
import hashlib
import os
import re
import types
from pathlib import Path
from typing import Any, Callable

import numba
from numba.core.typing.typeof import typeof_impl

from spurdyn.linking import linked_njit
from spurdyn.store import cache_base

PACKAGE = Path(__file__).resolve().parent

__all__ = ["Kernel", "njit", "cache_folder", "compiled_sources", "imported_modules"]


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


_OPTIONS = {"cache": True, "nogil": True}


def _renamed(fn: Callable[..., Any], suffix: str) -> Callable[..., Any]:
    """A copy of ``fn`` whose qualified name ends in ``suffix``: Numba names a function's
    disk cache by its qualified name, so two builds of one function need two names."""
    copy = types.FunctionType(fn.__code__, fn.__globals__, fn.__name__, fn.__defaults__,
                              fn.__closure__)
    functools.update_wrapper(copy, fn)
    copy.__qualname__ = fn.__qualname__ + suffix
    del copy.__wrapped__
    return copy


class Kernel:
    """A compiled function in two builds: one for the kernels that call it, one for Python.

    Numba gives every compiled function a CPython wrapper (unboxing each argument, the
    packed model's twenty arrays among them) and a C wrapper, optimised and emitted to
    machine code with it, and the function once more in each kernel that calls it. A
    kernel that only other kernels call needs neither: the build they link
    (:attr:`internal`) has none, which takes a fifth off a first run's compile
    (docs/performance.md, "The first run's compile"). A call from Python (the tests of the
    NumPy twins, a stepper's single step) compiles :attr:`public`, the same code with its
    wrappers, on its first call; attributes not found here are that build's (``overloads``,
    ``signatures``).
    """

    def __init__(self, fn: Callable[..., Any]) -> None:
        self.py_func = fn
        self.internal = linked_njit(_renamed(fn, "__internal"), **_OPTIONS)
        self._public: Any = None
        functools.update_wrapper(self, fn)

    @property
    def public(self) -> Any:
        """The build called from Python (its dispatcher, made on first use)."""
        if self._public is None:
            self._public = numba.njit(**_OPTIONS)(self.py_func)
        return self._public

    def __call__(self, *args: Any) -> Any:
        return self.public(*args)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(self.public, name)


@typeof_impl.register(Kernel)
def _typeof_kernel(value: Kernel, context: Any) -> Any:
    """A kernel seen from another kernel is its wrapper-less build."""
    return numba.types.Dispatcher(value.internal)


def njit(fn: Callable[..., Any] | None = None, *, entry: bool = False) -> Any:
    """Compile ``fn`` in nopython mode, cached on disk, releasing the GIL while it runs.

    The kernels touch no Python object, so the GIL is not needed; releasing it lets a
    thread of the command (loading the output writers, :mod:`spurdyn.results.prefetch`)
    use the second core while the time loop runs.

    A :class:`Kernel` (other kernels link a build without Python's wrappers), or with
    ``entry=True`` (as ``@njit(entry=True)``) one Numba dispatcher: for the functions a
    solver calls from Python (its time loop), which would otherwise compile twice when
    kernels call them too.
    """
    if fn is None:
        return lambda f: njit(f, entry=entry)
    if entry:
        return numba.njit(**_OPTIONS)(fn)
    return Kernel(fn)
