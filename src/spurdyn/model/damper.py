"""The mesh damper's coefficient (docs/implicit.md, section 3; docs/sector.md, 6.3).

The mesh damper is a dashpot along the line of action between the two base circles, acting
while the teeth are in contact, with ``c_m = 2 zeta sqrt(k m_e)`` for a damping ratio
``zeta`` of the pair's torsional mode. The formula is data of a run's settings, not of a
step: the implicit integrator (:mod:`spurdyn.solvers.implicit.step_numpy`) reads it at the
pitch point, the sector model (:mod:`spurdyn.sector.damper`) along its mesh cycle.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike


def mesh_damper_coefficient(zeta: float, stiffness: ArrayLike, reduced_mass: float) -> Any:
    """``c_m = 2 zeta sqrt(k m_e)`` (N s/m) of a torsional mode ``k``, ``m_e`` (a float for a
    float ``k``, an array for an array of them)."""
    c = 2.0 * zeta * np.sqrt(np.asarray(stiffness, dtype=float) * reduced_mass)
    return float(c) if c.ndim == 0 else c


__all__ = ["mesh_damper_coefficient"]
