"""Preloaded by the worker processes of the local cluster (``distributed`` preload).

Ctrl-C at the terminal reaches every process of the foreground group; the client stops
the sweep and closes the cluster, so its workers ignore SIGINT instead of printing a
``KeyboardInterrupt`` traceback each.
"""

from __future__ import annotations

from typing import Any

from spurdyn.signals import ignore_interrupts


def dask_setup(worker: Any = None) -> None:
    """Ignore SIGINT in this worker process (a no-op outside the main thread)."""
    ignore_interrupts()
