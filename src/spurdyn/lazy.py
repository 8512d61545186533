"""Lazy package facades: a package's public names served from their modules when first asked.

A facade (a package's ``__init__.py``) lists its public names and the module each lives in;
:func:`lazy_facade` makes the module-level ``__getattr__`` and ``__dir__`` (PEP 562) that
import the module only when a name is first asked for. This keeps ``import spurdyn.x``
cheap (no Numba, xarray or Matplotlib before they are needed) and lets a facade name what
sits on a higher floor without an import circle (docs/architecture.md).

This module is on the ground floor: it imports nothing of spurdyn.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any, Callable, Mapping

__all__ = ["lazy_facade"]

#: The top-level package: a module named from it is named whole.
ROOT = __name__.split(".")[0]


def lazy_facade(package: str, exports: Mapping[str, str],
                namespace: Mapping[str, Any]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of the facade of ``package``.

    Parameters
    ----------
    package
        The package's full name (the facade's ``__name__``).
    exports
        Each public name and the module it comes from, relative to ``package``
        (``"check"`` for ``package.check``, ``"solvers.check"`` from ``spurdyn``), or whole
        (``"spurdyn.model.alpha"``) for a module outside the package.
    namespace
        The facade's own globals, listed by ``__dir__`` with the exported names.

    Returns
    -------
    tuple
        ``(__getattr__, __dir__)``: the first serves a name of ``exports`` from its module,
        importing the module when first asked, and raises :class:`AttributeError` for any
        other; the second lists the facade's names and the exported ones, sorted.
    """

    def __getattr__(name: str) -> Any:
        """Serve a public name from its module, importing the module when first asked."""
        if name in exports:
            home = exports[name]
            whole = home.startswith(f"{ROOT}.")
            return getattr(import_module(home if whole else f"{package}.{home}"), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted({*namespace, *exports})

    return __getattr__, __dir__
