"""The ``spurdyn`` console command: :func:`spurdyn.cli.main.main` in a process that starts
and ends quickly.

A command's process ends when its work is done, so the objects of the libraries it loads
(NumPy, SciPy, Numba, xarray, Matplotlib: ~2,000 modules) are never garbage. The garbage
collector would still walk them: in the collections that the imports trigger, in every
full collection while the case is built and the files are written, and once more at exit,
where the interpreter's teardown spent ~0.5 s on them (docs/performance.md). So the
collector is off while the command's modules are imported, and what is loaded by then, and
at the end, is frozen (:func:`gc.freeze`): left to the operating system. Exit handlers
and the flushing of the streams still run.

This module imports nothing else at its top, so that the collector is off before the
command's imports begin.
"""

from __future__ import annotations

import gc
import sys
from typing import NoReturn


def entry() -> NoReturn:
    """Run the command line (``sys.argv``) and exit with its status."""
    gc.disable()
    try:
        from spurdyn.cli.main import main
    finally:
        gc.freeze()
        gc.enable()
    code = main()
    gc.freeze()
    sys.exit(code)


__all__ = ["entry"]
