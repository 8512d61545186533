"""Load the output writers in a thread while the solver runs.

Writing a run folder first imports xarray (whose first ``Variable`` probes for duck-array
libraries and so imports ``dask.array``), netCDF4 and Matplotlib, and the first NetCDF file
and picture of a process start their libraries: about 2 s of a command's time outside the
time loop (docs/performance.md). The compiled time loop
releases the GIL (:func:`spurdyn.jit.njit`), so these imports can run on the other core
meanwhile: :func:`start` before the run, :func:`wait` before writing.
"""

from __future__ import annotations

import threading


def _load() -> None:
    import io
    import os
    import tempfile

    import numpy as np
    import xarray as xr
    from matplotlib.figure import Figure

    import spurdyn.results.io  # noqa: F401
    import spurdyn.results.plots  # noqa: F401

    # What the first use of each writer costs once per process, paid here: xarray's probe
    # for duck arrays, its search for NetCDF backends and the netCDF4 library's start
    # (~0.7 s), Matplotlib's fonts and Agg canvas.
    tiny = xr.Dataset({"x": (("time",), np.zeros(2))})
    fd, name = tempfile.mkstemp(suffix=".nc")
    os.close(fd)
    try:
        tiny.to_netcdf(name, engine="netcdf4", encoding={"x": {"zlib": True, "complevel": 4}})
    finally:
        os.remove(name)
    fig = Figure(figsize=(1, 1))
    fig.subplots().plot([0, 1], [0, 1])
    fig.savefig(io.BytesIO(), format="png")


def start() -> threading.Thread:
    """Start loading the writers in a daemon thread; errors surface at the real import."""
    def run() -> None:
        try:
            _load()
        except Exception:  # noqa: BLE001 - the writer's own import reports it
            pass
    thread = threading.Thread(target=run, name="spurdyn-prefetch", daemon=True)
    thread.start()
    return thread


def wait(thread: threading.Thread | None) -> None:
    """Wait for :func:`start`'s thread (imports are not safe to race with)."""
    if thread is not None:
        thread.join()
