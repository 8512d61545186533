"""Where a sweep should find its main resonance: the torsional natural frequency estimate.

Two rigid disks coupled by the mesh spring have one torsional mode,
``f_n = sqrt(k / m_e) / (2 pi)`` (:func:`spurdyn.lumped.torsional_natural_frequency`).
With ``k`` the mean of the FE single-pair mesh stiffness over the path of contact
(:func:`spurdyn.lumped.mesh_stiffness_table`, the case's tooth mesh), the main
resonance is expected where the tooth mesh frequency ``z_a n / 60`` equals ``f_n``:
``n_res = 60 f_n / z_a`` rpm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from spurdyn.casefile import Case


@dataclass(frozen=True)
class ResonanceEstimate:
    """The natural-frequency estimate of a pair and the speed it predicts.

    Attributes
    ----------
    mesh_stiffness_mean
        Mean FE single-pair mesh stiffness over the path of contact (N/m).
    equivalent_mass
        Disk inertias reduced to the line of action (kg).
    natural_frequency_hz
        ``f_n`` (Hz).
    teeth_a
        Teeth of gear A (the speeds of a sweep are A's).
    """

    mesh_stiffness_mean: float
    equivalent_mass: float
    natural_frequency_hz: float
    teeth_a: int

    @property
    def resonance_rpm(self) -> float:
        """Speed of A (rpm) whose mesh frequency is ``f_n``."""
        return 60.0 * self.natural_frequency_hz / self.teeth_a

    def mesh_frequency(self, rpm: float) -> float:
        """Tooth mesh frequency (Hz) at speed ``rpm`` of A."""
        return self.teeth_a * rpm / 60.0

    def attrs(self) -> dict[str, Any]:
        """As global attributes of a sweep file."""
        return {"mesh_stiffness_mean": self.mesh_stiffness_mean,
                "equivalent_mass": self.equivalent_mass,
                "natural_frequency_hz": self.natural_frequency_hz,
                "resonance_rpm": self.resonance_rpm,
                "resonance_note": "f_n = sqrt(k_mean / m_e) / 2 pi with k_mean the mean FE "
                                  "single-pair mesh stiffness over the path of contact; "
                                  "resonance_rpm = 60 f_n / z_a"}


def resonance_estimate(case: Case) -> ResonanceEstimate:
    """The estimate for the pair and tooth mesh of ``case`` (a fraction of a second)."""
    from spurdyn.lumped import (equivalent_mass, mesh_stiffness_table,
                                      torsional_natural_frequency)

    pair = case.pair
    table = mesh_stiffness_table(pair, case.run.nx, case.run.ny)
    k = table.mean(float(table.roll_a[0]), float(table.roll_a[-1]))
    f_n = float(torsional_natural_frequency(pair, k))
    if not math.isfinite(f_n):  # pragma: no cover - the table refuses bad stiffness
        raise ValueError("the natural frequency is not finite")
    return ResonanceEstimate(mesh_stiffness_mean=k, equivalent_mass=equivalent_mass(pair),
                             natural_frequency_hz=f_n, teeth_a=pair.gear_a.teeth)
