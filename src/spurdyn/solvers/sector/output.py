"""The sector model's run as a :class:`~spurdyn.result.Result` (docs/sector.md, 6.4): the
pairs' forces and contact rolls, the transmission error, the settled test, in the pair's
own gears A and B."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.result import Result, ToothStress
from spurdyn.sector.rules import mesh_damping
from spurdyn.sector.system import REACH
from spurdyn.settings import DEFAULT_RAMP_CYCLES
from spurdyn.solvers.sector.teeth import SPLIT_PRESSURE_NOTE, pair_pressures, root_stress, split_anywhere
from spurdyn.solvers.sector.crack_faces import face_openings
from spurdyn.solvers.steady import cycle_figures, steady_record

if TYPE_CHECKING:  # annotations only
    from spurdyn.sector.model import SectorModel
    from spurdyn.solvers.sector.stepper import SectorRecord


def sector_result(model: SectorModel, record: SectorRecord, *, n_kept: int, status: str, reason: str,
                  wall: float, most: int, keep: NDArray[np.bool_] | None = None,
                  back_keep: NDArray[np.bool_] | None = None, info: dict[str, Any] | None = None,
                  offset: int = 0) -> Result:
    """The run of ``model`` written in ``record`` as a :class:`~spurdyn.result.Result` in the
    pair's own A and B.

    Parameters
    ----------
    model, record
        The run's model and its samples (the hubs' torques at each step, driver first).
    n_kept
        The rows of ``record`` the result keeps (those written).
    status, reason
        The run's status and why it stopped where it is incomplete.
    wall
        The run's wall time (s).
    most
        The most cycles the run could go on to (the settled test's limit).
    keep
        Which of the model's drive-flank teeth the result keeps (those of the cycles run);
        ``None`` keeps every contact column of the record.
    back_keep
        Which of the back flanks' driver teeth the result keeps; ``None`` where the run has
        no back flanks.
    info
        What the integrator adds to the result's record.
    offset
        The driver's body tooth of pair 0 (a continuation runs on).

    Returns
    -------
    Result
        The run, its ``info`` the model's record (:func:`sector_record`) and ``info``.
    """
    teeth, forces = model.teeth, record.force
    if keep is not None:
        teeth, forces = teeth[keep], forces[:, :model.teeth.size][:, keep]
    back = None
    if back_keep is not None:
        back = (model.back_k[back_keep], record.force[:, model.teeth.size:][:, back_keep])
    dp, pair, h, per_cycle = model.dp, model.pair, model.h, model.per_cycle
    t = np.arange(record.theta.shape[0]) * h
    sel = slice(0, n_kept)
    t, theta, omega, forces, gap = t[sel], record.theta[sel], record.omega[sel], forces[sel], record.gap[sel]
    n = t.size
    mesh = forces.sum(axis=1)
    te = model.ra * theta[:, 0] - model.rb * theta[:, 1]
    most_force = forces.max(axis=1) if teeth.size else np.zeros(n)
    pitch = 2.0 * math.pi / dp.gear_a.teeth
    rolls = dp.start_roll_a + theta[:, :1] + teeth[None, :] * pitch
    top = np.argmax(forces, axis=1)
    roll_a = rolls[np.arange(n), top]
    roll = np.column_stack([roll_a, np.asarray(dp.roll_b_from_roll_a(roll_a))])
    torque = record.torque[sel]
    # a faulty pair repeats after its period (a revolution): its settled test and window by periods
    period = model.period
    fig = cycle_figures(t, mesh, te, per_cycle * period, -(-model.cycles // period),
                        None if most is None else -(-most // period))
    swap = pair.driver == "b"

    def ab(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return x[:, ::-1].copy() if swap else x

    reach = REACH * pitch
    on = (rolls >= dp.start_roll_a - reach) & (rolls <= dp.end_roll_a + reach)
    out = sector_record(model, teeth, back is not None, float(theta[-1, 0]) if n else 0.0,
                        steady_record(fig, per_cycle * h, float(model.cycle.force.max()), model.cycle.stiffness_mean))
    back_force = None
    if back is not None:
        back_force = back[1][sel]
        out["back_pair_teeth"] = back[0].tolist()
    contact = pair_pressures(model, record.theta[sel, 0], record.force[sel], keep, offset)
    if split_anywhere(model, record.theta[sel, 0], record.force[sel], offset):
        out["contact_pressure_note"] = SPLIT_PRESSURE_NOTE
    # a faulty gear's fillets differ tooth by tooth (missing, cracked): not recovered yet
    stress = None if model.faults else root_stress(model, record, n_kept, offset)
    _fault_records(model, out, record, n_kept, most)
    en = record.energy
    if en is not None:
        out["momentum"] = {"hub_momentum": en[sel, 4:6].tolist(), "contact_torque": en[sel, 6:8].tolist()}
        out["energy"] = {"kinetic_J": en[sel, 0].tolist(), "strain_J": en[sel, 1].tolist(),
                         "strip_J": en[sel, 2].tolist(), "work_J": en[sel, 3].tolist()}
    hubs = None
    if model.bear is not None:      # the translations in A's and B's order (the record's: driver first)
        hubs = record.hubs[sel]
        if swap:
            hubs = hubs[:, [2, 3, 0, 1, 6, 7, 4, 5]]
        out["bearings"] = bearing_record(model, swap)
    if stress is not None and swap:
        stress = ToothStress(stress.time, stress.teeth[::-1], stress.values[::-1], stress.per_cycle)
    return Result(
        time=t, angle=(theta[:, 1] if swap else theta[:, 0]).copy(), contact_force=most_force, gap=gap,
        roll=ab(roll), theta=ab(theta), omega=ab(omega), torque=ab(torque),
        frame_time=np.zeros(0), frame_theta=np.zeros((0, 2)),
        frame_u=np.zeros((0, 0)), status=status, reason=reason, steps=max(n - 1, 0), wall_s=wall,
        info={**out, **(info or {}), "static_cycle": static_cycle(model)}, pair_force=forces,
        pair_roll=np.where(on, rolls, np.nan), back_force=back_force, transmission_error=te, tooth_stress=stress,
        hub_translation=hubs, **contact)


def bearing_record(model: SectorModel, swap: bool) -> list[dict[str, float] | None]:
    """Gear A's and gear B's bearing as the result's record keeps it: its stiffness (N/m),
    damping (N s/m) and the gear's translating mass (kg); ``None`` for a hub whose centre is
    held."""
    bear, given = model.bear, model.settings.bearings
    mass = bear.mass[::2][::-1] if swap else bear.mass[::2]
    return [None if b is None else {"stiffness": b.stiffness, "damping": b.damping, "mass_kg": float(m)}
            for b, m in zip(given, mass)]


def _fault_records(model: SectorModel, out: dict[str, Any], record: SectorRecord, n_kept: int,
                   most: int | None) -> None:
    """A faulty run's own in its record ``out``: its steady figures in mesh cycles as every
    run's (their lists per period, a revolution, which it names) and how far a crack's
    faces opened and how hard they were pressed together."""
    if model.period > 1:
        st = out["steady"]
        st.update(cycles=model.cycles, cycles_done=max(n_kept - 1, 0) // model.per_cycle, max_cycles=most,
                  last_cycles=st["last_cycles"] * model.period, period_mesh_cycles=model.period)
    faces = face_openings(model, record, n_kept)
    if faces is not None:
        out["crack_faces"] = faces


def static_cycle(model: SectorModel) -> dict[str, NDArray[np.float64]]:
    """The run's quasi-static mesh cycle (``model.cycle``) as the result keeps it beside the
    dynamic one (:func:`spurdyn.results.pairs.pair_variables`): the driver's roll of the first
    pair at each position (rad), each pair's force (N) and the static transmission error (m)."""
    c = model.cycle
    return {"roll": c.roll.copy(), "force": c.force.copy(), "transmission_error": c.transmission_error.copy()}


def sector_record(model: SectorModel, teeth: NDArray[np.intp], back: bool, angle_end: float,
                  steady: dict[str, Any]) -> dict[str, Any]:
    """The result's record of a run of ``model``: the model, its pair and loading, its bodies,
    the mesh damper, the step, the drive flanks' ``teeth`` kept, whether ``back`` flanks are
    contacts, the driver's turn at the end and the settled test's ``steady`` record."""
    pair, settings, blocks, c_table = model.pair, model.settings, model.blocks, model.c_table
    zeta, zeta_source = mesh_damping(settings)
    return {
        "model": "sector",
        "integrator": "implicit",
        "contact": "hertz",
        "rho_inf": settings.rho_inf,
        "n_dof": int(sum(b.n for b in blocks)),
        "case": settings.name,
        "driver": pair.driver,
        "theta_s": pair.theta_s,
        "theta_2": pair.theta_2,
        "static_force": model.load,
        "single_zone": (pair.theta_2, pair.theta_s - pair.theta_2),
        "teeth_per_gear": [b.count for b in blocks],
        "whole_gears": [b.whole for b in blocks],
        "rim_inner_radius_m": [b.body.mesh.inner_radius for b in blocks],
        "hub_inertia": [b.hub_inertia for b in blocks],
        "body_inertia": [b.body_inertia for b in blocks],
        # the mesh damper follows the cycle's stiffness: its mean and range over a cycle
        "mesh_damper_N_s_per_m": float(c_table[:-1].mean()),
        "mesh_damper_range_N_s_per_m": [float(c_table.min()), float(c_table.max())],
        "damping_ratio": zeta,
        "damping_ratio_source": zeta_source,
        "dt_s": model.h,
        "steps_per_cycle": model.per_cycle,
        "pair_teeth": teeth.tolist(),
        "back_flanks": back,
        "backlash_normal_m": model.dp.backlash_normal,
        "start": settings.start,
        "ramp_cycles": (settings.ramp_cycles or DEFAULT_RAMP_CYCLES) if settings.start == "rest" else None,
        "torque_history": None if settings.torque_history is None else (settings.torque_history.source or "table"),
        "angle_end": angle_end,
        "steady": steady,
    }


__all__ = ["bearing_record", "sector_record", "sector_result", "static_cycle"]
