"""Results: the Result object, NetCDF, CSV and ParaView output, pictures.

``load_run(dir)`` reads a run folder's ``result.nc`` back as an :class:`xarray.Dataset`.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade
from spurdyn.result import STAGES, Result

__all__ = ["Result", "STAGES", "load_run"]


# xarray is imported only when a run is read (spurdyn.lazy)
__getattr__, __dir__ = lazy_facade(__name__, {"load_run": "io"}, globals())
