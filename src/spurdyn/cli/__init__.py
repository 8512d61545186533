"""The ``spurdyn`` command line.

``command``: the console entry point; ``main``: the parser and the subcommands;
``run``, ``sweep``, ``stiffness``: ``spurdyn run``, ``spurdyn sweep``, ``spurdyn
stiffness``; ``inputs``: the commands' common inputs (CASE, a picture's target);
``options``: option parsing shared by the subcommands; ``report``: what ``spurdyn info``
reports.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

#: Public names and the module each comes from, imported when first asked for
#: (so that ``import spurdyn.cli`` costs nothing before a command is parsed).
_EXPORTS = {
    "entry": "command", "build_parser": "main",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    """Serve a public name from its module, importing the module when first asked."""
    if name in _EXPORTS:
        return getattr(import_module(f"spurdyn.cli.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module 'spurdyn.cli' has no attribute {name!r}")
