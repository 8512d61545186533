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
    keep_out_dask(sys.argv[1:])
    gc.disable()
    try:
        from spurdyn.cli.main import main

        write_apart(sys.argv[1:])
    finally:
        gc.freeze()
        gc.enable()
    code = main()
    gc.freeze()
    leave(code)


def keep_out_dask(args: list[str]) -> None:
    """Keep Dask out of a ``spurdyn run`` process.

    xarray probes for Dask when it makes its first variable, and asks for Dask's scheduler
    when it writes a NetCDF file: that imports ``dask``, ``dask.array`` and
    ``distributed`` (~170 modules, ~37 MB of the process's memory) in a process that never
    makes a Dask array. A ``None`` in :data:`sys.modules` makes ``import dask`` fail, so
    xarray takes Dask for not installed. Only in the console command's own process, and
    only for ``run``: ``spurdyn sweep`` runs on Dask, and a Python session that calls
    :func:`spurdyn.cli.main.main` keeps its Dask.

    Parameters
    ----------
    args
        The command line after the program's name.
    """
    if args[:1] == ["run"] and "dask" not in sys.modules:
        sys.modules["dask"] = None  # type: ignore[assignment]


def write_apart(args: list[str]) -> None:
    """Have ``spurdyn run`` write its folders in a process of its own.

    The libraries a run writes with (xarray, pandas, netCDF4, Matplotlib) then never load in
    the process that steps with Numba and LLVM, and the command's largest process is the
    one or the other, not both (:mod:`spurdyn.results.apart`, docs/performance.md). Only in
    the console command's own process, as :func:`keep_out_dask`.

    Parameters
    ----------
    args
        The command line after the program's name.
    """
    if args[:1] == ["run"]:
        from spurdyn.cli import run

        run.WRITE_APART = True


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


__all__ = ["entry", "keep_out_dask", "leave", "write_apart"]
