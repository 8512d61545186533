"""Results: the Result object, NetCDF, CSV and ParaView output, pictures.

``load_run(dir)`` reads a run folder's ``result.nc`` back as an :class:`xarray.Dataset`.
"""

from __future__ import annotations

from typing import Any

from spurdyn.result import STAGES, Result

__all__ = ["Result", "STAGES", "load_run"]


def __getattr__(name: str) -> Any:
    # xarray is imported only when a run is read.
    if name == "load_run":
        from spurdyn.results.io import load_run

        return load_run
    raise AttributeError(f"module 'spurdyn.results' has no attribute {name!r}")
