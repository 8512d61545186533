"""The sector model's mesh damper along the cycle (docs/sector.md, 6.3): its coefficient
``c(phi) = 2 zeta sqrt(k(phi) m_e)`` tabulated over a pitch of the driver, and read as the
NumPy loops read it (the compiled loops' twin:
:func:`~spurdyn.solvers.sector.rows_compiled.damper_coefficient`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.model.damper import mesh_damper_coefficient

#: Phases over a mesh cycle at which the mesh damper's coefficient is tabulated.
DAMPER_SAMPLES = 512

def mesh_damper_table(cycle: Any, zeta: float, m_e: float, pitch: float) -> NDArray[np.float64]:
    """The mesh damper's ``c(phi) = 2 zeta sqrt(k(phi) m_e)`` (N s/m) at
    :data:`DAMPER_SAMPLES` + 1 even phases ``phi`` of the driver over a pitch from the start
    of the path (the last the first again: the cycle repeats), ``k(phi)`` the quasi-static
    mesh stiffness of ``cycle`` (:meth:`~spurdyn.sector.statics.MeshCycle.effective`, its
    pairs' entries and exits sharp)."""
    k = cycle.effective(np.arange(DAMPER_SAMPLES) * (pitch / DAMPER_SAMPLES)).sum(axis=0)
    return np.asarray(mesh_damper_coefficient(zeta, np.append(k, k[0]), m_e), dtype=float)


def damper_at(table: NDArray[np.float64], pitch: float, theta: float) -> float:
    """The mesh damper's coefficient at the driver's turn ``theta`` (rad from the start):
    ``table`` (:func:`mesh_damper_table`) linear between its phases (twin of
    :func:`~spurdyn.solvers.sector.rows_compiled.damper_coefficient`)."""
    n = table.size - 1
    x = (theta % pitch) / pitch * n
    i = min(int(x), n - 1)
    f = x - i
    return float(table[i] * (1.0 - f) + table[i + 1] * f)


__all__ = ["DAMPER_SAMPLES", "damper_at", "mesh_damper_table"]
