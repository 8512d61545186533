"""The ``spurdyn`` console command: :func:`spurdyn.cli.main.main` in a process that starts
and ends quickly.

A command's process ends when its work is done, so the objects of the libraries it loads
(NumPy, SciPy, Numba, xarray, Matplotlib: ~2,000 modules) are never garbage. The garbage
collector would still walk them: in the collections that the imports trigger, in every
full collection while the case is built and the files are written, and once more at exit,
where the interpreter's teardown spent ~0.5 s on them (docs/performance.md). So the
collector is off while the command's modules are imported, and what is loaded by then, and
at the end, is frozen (:func:`gc.freeze`). The process then leaves without the teardown
(:func:`leave`).

This module imports nothing else at its top, so that the collector is off before the
command's imports begin.
"""

from __future__ import annotations

import atexit
import gc
import os
import sys
import threading
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
    leave(code)


def leave(code: int) -> NoReturn:
    """Exit with ``code``, without the interpreter's teardown when nothing needs it.

    The teardown frees the objects of every module one by one (~0.1 s, even frozen); the
    operating system takes the whole process back at once. What an exit must do is done
    first: the exit handlers (:mod:`atexit`: logging, multiprocessing, Dask) and flushing
    the standard streams. Every file the command writes is closed when it is complete.
    With another thread still running (an exit joins it), or without CPython's runner of
    the exit handlers, the process exits the ordinary way.
    """
    run_exit_handlers = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_handlers is None or threading.active_count() > 1 or not isinstance(code, int):
        sys.exit(code)
    run_exit_handlers()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):    # closed, or a reader gone: as an exit would
            pass
    os._exit(code)


__all__ = ["entry", "leave"]
