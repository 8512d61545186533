"""Load the output writers in a thread while the solver runs.

Writing a run folder first imports xarray (whose first ``Variable`` probes for duck-array
libraries and so imports ``dask.array``), netCDF4 and Matplotlib, and the first NetCDF file
and picture of a process start their libraries: about 2 s of a command's time outside the
time loop (docs/performance.md). The compiled time loop
releases the GIL (:func:`spurdyn.jit.njit`), so these imports can run on the other core
meanwhile: :func:`start` before the run, :func:`wait` before writing. (The console command
writes in a process of its own, :mod:`spurdyn.results.apart`, which calls :func:`load`
once the loop has begun, instead.)
"""

from __future__ import annotations

import sys
import threading

#: Python's thread switch interval (s) while the writers load: the time loop's thread takes
#: the GIL back after each chunk of steps within this, not Python's default 5 ms.
SWITCH_INTERVAL = 2e-4


def load() -> None:
    """Import the writers and write a small NetCDF file and picture in a scratch folder,
    removed after (in :func:`start`'s thread, or in a writer process,
    :mod:`spurdyn.results.apart`)."""
    import json
    import os
    import tempfile

    import numpy as np
    import xarray as xr

    import spurdyn.iso6336.rating  # noqa: F401 - the summary's ISO figures
    import spurdyn.results.io  # noqa: F401
    from spurdyn.results.plots import plot_contact_force

    # What the first use of each writer costs once per process, paid here: xarray's probe
    # for duck arrays, its search for NetCDF backends and the netCDF4 library's start
    # (~0.7 s), Matplotlib's fonts, Agg canvas, and the first picture of the run's kind
    # (zones, arrows, legend, layout: ~0.04 s less for the real one, which a forked child
    # draws with what this process has loaded; spurdyn.results.beside).
    tiny = xr.Dataset({"x": (("time",), np.zeros(2))})
    angle = np.linspace(0.0, 20.0, 50)
    picture = xr.Dataset(
        {"angle_deg": ("time", angle), "contact_force": ("time", 500.0 + 50.0 * np.sin(angle))},
        attrs={"case_name": "prefetch", "status": "complete", "theta_s_deg": 21.0,
               "angle_target_deg": 21.0, "single_zone_deg": np.array([8.0, 13.0]),
               "static_force_N": 500.0,
               "case": json.dumps({"run": {"speed_a_rpm": 1.0, "speed_b_rpm": 1.0}})})
    folder = tempfile.mkdtemp(prefix="spurdyn-prefetch-")
    try:
        tiny.to_netcdf(os.path.join(folder, "x.nc"), engine="netcdf4",
                       encoding={"x": {"zlib": True, "complevel": 4}})
        plot_contact_force([picture], os.path.join(folder, "x.png"))
    finally:
        for name in os.listdir(folder):
            os.remove(os.path.join(folder, name))
        os.rmdir(folder)


#: How many loading threads run, and the switch interval before the first of them (the one
#: to restore when the last ends): overlapping starts must not restore each other's 0.2 ms.
_LOADING = {"count": 0, "interval": 0.0}
_LOCK = threading.Lock()


def _shorten() -> None:
    with _LOCK:
        if _LOADING["count"] == 0:
            _LOADING["interval"] = sys.getswitchinterval()
            sys.setswitchinterval(min(_LOADING["interval"], SWITCH_INTERVAL))
        _LOADING["count"] += 1


def _restore() -> None:
    with _LOCK:
        _LOADING["count"] -= 1
        if _LOADING["count"] == 0:
            sys.setswitchinterval(_LOADING["interval"])


def start() -> threading.Thread:
    """Start loading the writers in a daemon thread; errors surface at the real import.

    The loading holds the GIL (imports are Python), the time loop runs without it and needs
    it back between its chunks of steps (~100 a run, ~10 ms apart on the design pair): at
    Python's default switch interval the loop's thread waited up to 5 ms at each, so the
    interval is shortened while a loading thread runs, and restored when the last of them
    ends (docs/performance.md).
    """
    def run() -> None:
        try:
            load()
        except Exception:  # noqa: BLE001 - the writer's own import reports it
            pass
        finally:
            _restore()
    thread = threading.Thread(target=run, name="spurdyn-prefetch", daemon=True)
    _shorten()
    try:
        thread.start()
    except BaseException:
        _restore()
        raise
    return thread


def wait(thread: threading.Thread | None) -> None:
    """Wait for :func:`start`'s thread (imports are not safe to race with)."""
    if thread is not None:
        thread.join()
