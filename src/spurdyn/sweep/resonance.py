"""Where a sweep should find its main resonance: the torsional natural frequency estimate.

Two rigid disks coupled by the mesh spring have one torsional mode,
``f_n = sqrt(k / m_e) / (2 pi)`` (:func:`spurdyn.lumped.torsional_natural_frequency`).
With ``k`` the mean of the FE single-pair mesh stiffness over the path of contact
(:func:`spurdyn.lumped.mesh_stiffness_table`, the case's tooth mesh) for the paper's one
engagement, or for a steady-state run (``run.cycles``) the mean over a mesh cycle of the
stiffness of all the pairs in contact, the main
resonance is expected where the tooth mesh frequency ``z_a n / 60`` equals ``f_n``:
``n_res = 60 f_n / z_a`` rpm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from spurdyn.case.file import Case
from spurdyn.simulators import MODELS


@dataclass(frozen=True)
class ResonanceEstimate:
    """The natural-frequency estimate of a pair and the speed it predicts.

    Attributes
    ----------
    mesh_stiffness_mean
        Mean FE single-pair mesh stiffness over the path of contact, or for a steady-state
        run the mean mesh stiffness of a cycle (N/m).
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
    #: ISO 6336-1 method B for the same pair and torque (``None`` where ISO's figures do not
    #: apply: a non-standard centre distance, no torque): ``c'`` (N/m^2), the line load
    #: ``F_t / b`` (N/m), ``eps_alpha`` and the resonance speed ``n_E1`` of the pinion (rpm).
    iso_single_pair: float | None = None
    iso_line_load: float | None = None
    iso_eps_alpha: float | None = None
    iso_resonance_rpm: float | None = None

    def iso_kv(self, rpm: Any) -> Any:
        """ISO 6336-1's ``K_v`` (method B, perfect gears, no relief) at speeds of A (rpm),
        or ``None`` where ISO's figures do not apply."""
        if self.iso_resonance_rpm is None:
            return None
        from spurdyn.iso6336.dynamics import dynamic_factor

        return [dynamic_factor(float(n) / self.iso_resonance_rpm, self.iso_single_pair,
                               self.iso_line_load, self.iso_eps_alpha) for n in rpm]

    @property
    def resonance_rpm(self) -> float:
        """Speed of A (rpm) whose mesh frequency is ``f_n``."""
        return 60.0 * self.natural_frequency_hz / self.teeth_a

    def mesh_frequency(self, rpm: float) -> float:
        """Tooth mesh frequency (Hz) at speed ``rpm`` of A."""
        return self.teeth_a * rpm / 60.0

    def attrs(self) -> dict[str, Any]:
        """As global attributes of a sweep file."""
        iso = {} if self.iso_resonance_rpm is None else {"iso_resonance_rpm": self.iso_resonance_rpm}
        return iso | {"mesh_stiffness_mean": self.mesh_stiffness_mean,
                "equivalent_mass": self.equivalent_mass,
                "natural_frequency_hz": self.natural_frequency_hz,
                "resonance_rpm": self.resonance_rpm,
                "resonance_note": "f_n = sqrt(k_mean / m_e) / 2 pi with k_mean the mean FE "
                                  "single-pair mesh stiffness over the path of contact (a "
                                  "steady-state sweep: the mean over a mesh cycle of all the "
                                  "pairs in contact); resonance_rpm = 60 f_n / z_a"}


def iso_kv_grid(case: Case, rpms: Any, torques: Any) -> Any:
    """ISO 6336-1's ``K_v`` (method B, perfect gears, no relief) at each speed of A (rpm,
    rows) and driver torque (N m, columns), NaN where ISO's figures do not apply (no
    torque, a non-standard centre distance); ``None`` when they apply nowhere."""
    import numpy as np

    from spurdyn.iso6336.rating import dynamic_factor_at, iso_pair, rate

    out = np.full((len(rpms), len(torques)), np.nan)
    try:
        ip = iso_pair(case.pair)
    except ValueError:
        return None
    for j, tq in enumerate(torques):
        if tq > 0:
            r = rate(ip, float(tq))
            out[:, j] = [dynamic_factor_at(r, float(n) * 2.0 * math.pi / 60.0) for n in rpms]
    return out if np.isfinite(out).any() else None


def resonance_estimate(case: Case, model: str | None = None) -> ResonanceEstimate:
    """The estimate for the pair and tooth mesh of ``case`` (a fraction of a second; the
    sector model's, whose stiffness is its quasi-static mesh cycle, a few seconds)."""
    from spurdyn.lumped import (equivalent_mass, mesh_stiffness_table,
                                      torsional_natural_frequency)

    pair = case.pair
    table = mesh_stiffness_table(pair, case.run.nx, case.run.ny)
    entry = MODELS[model or case.model]
    if not entry.steady(case.run):
        k = table.mean(float(table.roll_a[0]), float(table.roll_a[-1]))
    else:
        # a steady-state run meshes every pair the path holds: the mean of their sum
        from spurdyn.lumped.steady import cycle_stiffness

        if entry.sector_stiffness(case.run):
            from spurdyn.lumped.sources import sector_cycle

            source: Any = sector_cycle(pair, case.run)
        else:
            source = table
        k = float(cycle_stiffness(pair, source)[1].sum(axis=0).mean())
    f_n = float(torsional_natural_frequency(pair, k))
    if not math.isfinite(f_n):  # pragma: no cover - the table refuses bad stiffness
        raise ValueError("the natural frequency is not finite")
    iso: dict[str, float] = {}
    if case.run.torque > 0:
        from spurdyn.iso6336.rating import iso_pair, rate

        try:
            r = rate(iso_pair(pair), case.run.torque)
        except ValueError:          # ISO's figures need the standard centre distance
            pass
        else:
            iso = dict(iso_single_pair=r.single_pair, iso_line_load=r.line_load,
                       iso_eps_alpha=r.eps_alpha,
                       iso_resonance_rpm=r.resonance_speed * 60.0 / (2.0 * math.pi))
    return ResonanceEstimate(mesh_stiffness_mean=k, equivalent_mass=equivalent_mass(pair),
                             natural_frequency_hz=f_n, teeth_a=pair.gear_a.teeth, **iso)
