"""The sector model's run as a :class:`~spurdyn.result.Result` (docs/sector.md, 6.4): the
pairs' forces and contact rolls, the transmission error, the settled test, in the pair's
own gears A and B."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.geometry.pair import GearPair
from spurdyn.result import Result
from spurdyn.sector.system import REACH, GearBlock
from spurdyn.settings import DEFAULT_RAMP_CYCLES, RunSettings
from spurdyn.solvers.steady import cycle_figures, steady_record


def sector_result(pair: GearPair, dp: GearPair, settings: RunSettings, blocks: tuple[GearBlock, GearBlock],
            cycle: Any, teeth: NDArray[np.intp], n_kept: int, t: NDArray[np.float64],
            theta: NDArray[np.float64], omega: NDArray[np.float64], forces: NDArray[np.float64],
            gap: NDArray[np.float64], en: NDArray[np.float64] | None, per_cycle: int, cycles: int,
            max_cycles: int, h: float, torques: NDArray[np.float64], c_table: NDArray[np.float64], status: str, reason: str,
            wall: float, load: float,
            back: tuple[NDArray[np.intp], NDArray[np.float64]] | None = None,
            info: dict[str, Any] | None = None) -> Result:
    """The run as a :class:`~spurdyn.result.Result` in the pair's own A and B; ``torques`` the
    hubs' at each step (driver first), ``back`` the back flanks' driver teeth and forces where
    they are contacts, ``info`` what the integrator adds to the result's record."""
    ra, rb = dp.gear_a.base_radius, dp.gear_b.base_radius
    sel = slice(0, n_kept)
    t, theta, omega, forces, gap = t[sel], theta[sel], omega[sel], forces[sel], gap[sel]
    n = t.size
    mesh = forces.sum(axis=1)
    te = ra * theta[:, 0] - rb * theta[:, 1]
    most = forces.max(axis=1) if teeth.size else np.zeros(n)
    pitch = 2.0 * math.pi / dp.gear_a.teeth
    rolls = dp.start_roll_a + theta[:, :1] + teeth[None, :] * pitch
    top = np.argmax(forces, axis=1)
    roll_a = rolls[np.arange(n), top]
    roll = np.column_stack([roll_a, np.asarray(dp.roll_b_from_roll_a(roll_a))])
    torque = torques[sel]
    fig = cycle_figures(t, mesh, te, per_cycle, cycles, max_cycles)
    swap = pair.driver == "b"

    def ab(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return x[:, ::-1].copy() if swap else x

    reach = REACH * pitch
    on = (rolls >= dp.start_roll_a - reach) & (rolls <= dp.end_roll_a + reach)
    record: dict[str, Any] = {
        "model": "sector",
        "integrator": "implicit",
        "contact": "hertz",
        "rho_inf": settings.rho_inf,
        "n_dof": int(sum(b.n for b in blocks)),
        "case": settings.name,
        "driver": pair.driver,
        "theta_s": pair.theta_s,
        "theta_2": pair.theta_2,
        "static_force": load,
        "single_zone": (pair.theta_2, pair.theta_s - pair.theta_2),
        "teeth_per_gear": [b.count for b in blocks],
        "whole_gears": [b.whole for b in blocks],
        "rim_inner_radius_m": [b.body.mesh.inner_radius for b in blocks],
        "hub_inertia": [b.hub_inertia for b in blocks],
        "body_inertia": [b.body_inertia for b in blocks],
        # the mesh damper follows the cycle's stiffness: its mean and range over a cycle
        "mesh_damper_N_s_per_m": float(c_table[:-1].mean()),
        "mesh_damper_range_N_s_per_m": [float(c_table.min()), float(c_table.max())],
        "damping_ratio": settings.damping_ratio,
        "dt_s": h,
        "steps_per_cycle": per_cycle,
        "pair_teeth": teeth.tolist(),
        "back_flanks": back is not None,
        "backlash_normal_m": dp.backlash_normal,
        "start": settings.start,
        "ramp_cycles": (settings.ramp_cycles or DEFAULT_RAMP_CYCLES) if settings.start == "rest" else None,
        "torque_history": None if settings.torque_history is None else (settings.torque_history.source or "table"),
        "angle_end": float(theta[-1, 0]) if n else 0.0,
        "steady": steady_record(fig, per_cycle * h, float(cycle.force.max()), cycle.stiffness_mean),
    }
    back_force = None
    if back is not None:
        back_force = back[1][sel]
        record["back_pair_teeth"] = back[0].tolist()
    if en is not None:
        record["momentum"] = {"hub_momentum": en[sel, 4:6].tolist(), "contact_torque": en[sel, 6:8].tolist()}
        record["energy"] = {"kinetic_J": en[sel, 0].tolist(), "strain_J": en[sel, 1].tolist(),
                          "strip_J": en[sel, 2].tolist(), "work_J": en[sel, 3].tolist()}
    return Result(
        time=t, angle=(theta[:, 1] if swap else theta[:, 0]).copy(), contact_force=most, gap=gap,
        roll=ab(roll), theta=ab(theta), omega=ab(omega), torque=ab(torque),
        residual=np.zeros((n, 3)), iterations=np.zeros((n, 3), dtype=np.int64),
        corner=np.zeros(n, dtype=np.int8), frame_time=np.zeros(0), frame_theta=np.zeros((0, 2)),
        frame_u=np.zeros((0, 0)), status=status, reason=reason, steps=max(n - 1, 0), wall_s=wall,
        info={**record, **(info or {})}, pair_force=forces, pair_roll=np.where(on, rolls, np.nan),
        back_force=back_force, transmission_error=te)


__all__ = ["sector_result"]
