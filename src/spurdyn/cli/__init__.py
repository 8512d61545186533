"""The ``spurdyn`` command line.

``command``: the console entry point; ``main``: the parser and the subcommands;
``run``, ``sweep``, ``stiffness``: ``spurdyn run``, ``spurdyn sweep``, ``spurdyn
stiffness``; ``inputs``: the commands' common inputs (CASE, a picture's target);
``options``: option parsing shared by the subcommands; ``report``: what ``spurdyn info``
reports.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for
#: (so that ``import spurdyn.cli`` costs nothing before a command is parsed).
_EXPORTS = {
    "entry": "command", "build_parser": "main",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
