"""An RK4 reference for the sector model on modal bodies (issue 16; docs/sector_rk4_validation.md).

On modal bodies (docs/sector.md, 6.6) each gear's coordinates are the hub's turn and the
modal amplitudes, ``q_g = (theta_g, eta_g)``, and the residual flexibility ``R`` acts without
inertia. In contact a pair's force closes its gap (6.1),

    g_r(rho) - (r_bA theta_A - r_bB theta_B) + H q + c_s F = 0,   c_s = c_H + b_i^T R b_j,

so at a state ``q`` the forces are the solution of a small complementarity problem with no
inertia in it,

    v(q) + C_s F >= 0,  F >= 0,  F (v(q) + C_s F) = 0,   v(q) = g_r,c + G q,
    C_s = c_H I + C_res,

and the model is the ODE

    M q_ddot = f(t) - K q - C q_dot + G(q)^T F(q) - D^T C_d D q_dot,

``F(q)`` piecewise linear. This module steps it by the classical Runge-Kutta method of order
four at a fixed step (by default the paper's, 3e-8 s, shortened to a whole number of steps a
mesh cycle), each stage with its own rows at its own driver's turn (the rigid gap, its slope
and the contact radii from the run's gap table), its own forces and its own mesh damper.

The pieces are the implicit loop's: the same model
(:class:`~spurdyn.sector.model.SectorModel`, built for RK4), the same bodies
(:class:`~spurdyn.sector.bodies.ModalBody` with ``gamma' = beta' = 0``, so that its
``S`` is ``M`` and its solve ``M^-1``), the same rows (the gap table, the strips' unit loads,
the modal rows, the residual compliance), the same complementarity solver
(:func:`~spurdyn.sector.lcp.lcp`), the same mesh damper table
(:func:`~spurdyn.sector.damper.mesh_damper_table`, read by ``damper_at``), the same
torques (:func:`~spurdyn.model.loading.hub_torques`), the same static start and the same
result (:func:`~spurdyn.solvers.sector.output.sector_result`), whose settled figures and
dynamic factor are computed as the implicit run's. What differs, because an explicit
scheme takes it so:

- the strips' half-widths are held over a step at the forces of the step's start (the
  implicit loop holds them at the forces of the step before, the same lag of one step);
- the mesh damper's shares are the stage's own forces (the implicit loop: the step before's),
  so the damper acts on the pairs in contact at the stage;
- the rows are each stage's at its own turn (the implicit loop linearises the rigid gap over
  a step about the predicted turn).

It does not do what the implicit loop alone does: whole (not modal) bodies, back flanks,
torque histories, a start from another run's end, the energy record, going on until settled
(it runs the cycles asked). It refuses them by :class:`~spurdyn.errors.InputError`.
:func:`simulate_sector_rk4` steps in NumPy (:class:`Rk4Stepper`, ``backend="numpy"``) or in the
compiled twin (:mod:`spurdyn.solvers.sector.rk4_compiled`, the default where Numba is on),
the steppers of :data:`~spurdyn.solvers.sector.stepper.STEPPERS`.
"""

from __future__ import annotations

import math
import time as _time
from typing import Callable

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.result import Result
from spurdyn.sector.damper import damper_at
from spurdyn.sector.lcp import lcp
from spurdyn.sector.model import SectorModel
from spurdyn.sector.rules import back_flanks_on
from spurdyn.sector.statics import driving_pair
from spurdyn.settings import RunSettings, refuse_sector_row_grading
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_LCP, FAIL_NAN, OK, SectorRk4State
from spurdyn.solvers.sector.output import sector_result
from spurdyn.solvers.sector.stepper import SectorRecord, SectorStepper, drive, make_stepper

#: The paper's RK4 step (s): the reference's default.
PAPER_STEP = 3e-8


def refuse_rk4(pair: GearPair, settings: RunSettings, modes: bool | float | None) -> None:
    """Refuse, in one line each, what the RK4 reference does not step."""
    dp = driving_pair(pair)
    if modes is False or (modes is None and settings.bodies != "modal"):
        raise InputError("bodies", "the sector model's RK4 reference steps modal bodies only: the whole "
                         "finite-element bodies have no inertia-free part and need a step far below 3e-8 s")
    if back_flanks_on(dp, settings):
        raise InputError("back_flanks", "the sector model's RK4 reference has no back flanks: give "
                         "back_flanks=False, or a pair without backlash")
    if settings.torque_history is not None:
        raise InputError("torque_history", "the sector model's RK4 reference runs under constant torques only")
    refuse_sector_row_grading(settings.row_grading)
    if settings.start_state is not None:
        raise InputError("start_state", "the sector model's RK4 reference starts from the static "
                         "equilibrium or from rest, not from another run's end")


def rk4_stage(model: SectorModel, t: float, q: NDArray[np.float64], v: NDArray[np.float64],
              held: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], float, bool]:
    """``(q_ddot, F, smallest gap, found)`` at time ``t`` and state ``(q, v)`` of ``model``
    (built for RK4: its bodies' solve is ``M^-1``): the forces of the complementarity problem
    at ``q`` (half-widths of ``held``, whose active set is tried first), the torques, the
    bodies' forces, the pairs' ``G^T F`` and the mesh damper ``-D^T C D v`` shared by the
    forces ``F`` (twin of :func:`~spurdyn.solvers.sector.rk4_compiled.stage`)."""
    gears, parts = model.gears, model.parts
    r = np.zeros(model.n)
    r[0], r[model.na] = model.torques(np.array(t))
    for g in range(2):
        r[parts[g]] -= gears[g].forces(q[parts[g]], v[parts[g]])
    acc = np.concatenate([gears[g].solve(r[parts[g]]) for g in range(2)])
    force = np.zeros(model.c_teeth.size)
    rows = model.rows_at(float(q[0]), held)
    if rows is None:
        return acc, force, math.nan, True
    on = rows.on
    cs = model.contact_compliance(rows)
    gaps = rows.const + model.gap_rows(rows, q)
    lam, found = lcp(0.5 * (cs + cs.T), gaps, held[on] > 0.0)
    if not found:
        return acc, force, math.nan, False
    force[on] = lam
    c_mesh = damper_at(model.c_table, model.pitch, float(q[0]))
    total = lam.sum()
    rate = (c_mesh * lam / total) * model.rigid_rows(rows, v) if c_mesh > 0.0 and total > 0.0 \
        else np.zeros(on.size)
    for g, (coef, el) in enumerate(rows.sides):
        # M^-1 G^T F (hub: z c^T F; elastic: the body's columns) less M^-1 D^T C D v
        acc[parts[g]] += model.z_theta[g] * float(coef @ (lam - rate)) + gears[g].columns(el) @ lam
    return acc, force, float((gaps + cs @ lam).min()), True


class Rk4Stepper(SectorStepper):
    """The RK4 reference in NumPy, step by step: the stages' rows at their own turns, the
    strips' half-widths held at the forces of the step's start."""

    @classmethod
    def refuse(cls, model: SectorModel, energy: bool) -> None:
        super().refuse(model, energy)
        cls.refuse_crack(model)
        cls.refuse_bearings(model)

    def __init__(self, model: SectorModel, record: SectorRecord, offset: int = 0, energy: bool = False) -> None:
        super().__init__(model, record, offset, energy)
        start = model.start()
        self.state = SectorRk4State(start.q, start.v, start.force, start.force.copy())
        a1, f1, gap, found = rk4_stage(model, 0.0, start.q, start.v, start.force)
        self.a1, self.first_status = a1, OK if found else FAIL_LCP
        self.force[:] = f1
        self._write(0, gap)

    def _write(self, i: int, gap: float) -> None:
        rec, q, v, na = self.record, self.state.q, self.state.v, self.model.na
        rec.theta[i] = q[0], q[na]
        rec.omega[i] = v[0], v[na]
        rec.force[i] = self.force
        rec.gap[i] = gap
        rec.keep_state(i, q)

    def _steps(self, n: int) -> tuple[int, int]:
        if self.first_status != OK:
            return 0, self.first_status
        model, h, q, v, a1 = self.model, self.model.h, self.state.q, self.state.v, self.a1
        for k in range(n):
            step = self.index + k
            t = step * h
            held = self.force.copy()      # the strips' half-widths over the step: the forces at its start
            a2, _, _, ok2 = rk4_stage(model, t + 0.5 * h, q + 0.5 * h * v, v + 0.5 * h * a1, held)
            v2 = v + 0.5 * h * a1
            a3, _, _, ok3 = rk4_stage(model, t + 0.5 * h, q + 0.5 * h * v2, v + 0.5 * h * a2, held)
            v3 = v + 0.5 * h * a2
            a4, _, _, ok4 = rk4_stage(model, t + h, q + h * v3, v + h * a3, held)
            v4 = v + h * a3
            if not (ok2 and ok3 and ok4):
                return k, FAIL_LCP
            q += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
            v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
            if not (np.isfinite(q).all() and np.isfinite(v).all()):
                return k, FAIL_NAN
            if not model.theta_lo <= q[0] <= model.theta_hi:
                return k, FAIL_BEYOND
            a1, f1, gap, found = rk4_stage(model, t + h, q, v, held)
            if not found:
                return k, FAIL_LCP
            self.a1 = a1
            self.force[:] = f1
            self._write(step + 1, gap)
            self.reached = step + 1
        return n, OK


def simulate_sector_rk4(pair: GearPair, settings: RunSettings, dt: float = PAPER_STEP,
                        progress: Callable[[int, float, float], None] | None = None, *,
                        modes: bool | float | None = None, backend: str | None = None,
                        steps: int | None = None) -> Result:
    """Run the sector model of ``pair`` on modal bodies with ``settings`` by RK4 at the step
    ``dt`` (shortened to a whole number of steps a mesh cycle) for ``settings.cycles`` cycles
    (module docstring). ``backend`` ``"numpy"`` or ``"numba"`` (default: the settings');
    ``steps`` stops after that many steps (a short check), the cycles' arrays kept.

    Returns the :class:`~spurdyn.result.Result` of
    :func:`~spurdyn.solvers.sector.output.sector_result`, as the implicit run's, every step
    saved, ``info["integrator"] = "rk4"``.

    Raises
    ------
    InputError
        Whole bodies, back flanks, a torque history, a start from another run's end, the
        compiled backend on gears that are not whole.
    """
    wall0 = _time.perf_counter()
    refuse_rk4(pair, settings, modes)
    model = SectorModel.build(pair, settings, integrator="rk4", dt=dt, modes=modes)
    per_cycle, h, cycles = model.per_cycle, model.h, model.cycles
    n_steps = per_cycle * cycles if steps is None else min(int(steps), per_cycle * cycles)
    backend = backend or settings.backend
    record = SectorRecord(model, n_steps)
    stepper = make_stepper(model, record, "rk4", backend)
    limit = threadpool_limits(limits=1, user_api="blas")
    loop0 = _time.perf_counter()
    try:
        status, reason = drive(stepper, n_steps, max(n_steps // 100, 1), progress, n_steps * h * model.speed)
    finally:
        limit.restore_original_limits()
    loop_s = _time.perf_counter() - loop0
    n_kept = stepper.reached + 1 if reason.startswith("interrupted") else stepper.index + 1
    extra = dict(integrator="rk4", loop_s=loop_s, rayleigh=list(model.rayleigh), bodies="modal",
                 modes=[g.n - 1 for g in model.gears], coordinates=model.n, tooth_offset=0, rk4_backend=backend)
    return sector_result(model, record, n_kept=n_kept, status=status, reason=reason,
                         wall=_time.perf_counter() - wall0, most=cycles, info=extra)


def highest_frequency(pair: GearPair, settings: RunSettings, dt: float = PAPER_STEP) -> dict[str, float]:
    """The stiffest the RK4 reference meets, at the static start (its pairs in contact held
    by their compliance ``C_s``): the highest undamped frequency of ``M^-1 (K + G^T C_s^-1 G)``
    (rad/s) and of the free bodies, ``omega_max dt`` against RK4's 2.83 on the imaginary axis,
    and the largest ``|R(lambda dt)|`` of RK4's amplification over the damped system's
    eigenvalues (bodies' Rayleigh damping, the mesh damper at the start's phase)."""
    refuse_rk4(pair, settings, None)
    model = SectorModel.build(pair, settings, integrator="rk4", dt=dt)
    start = model.start()
    q, v, force = start.q, start.v, start.force
    n = model.n
    mass, stiff, damp = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    for g in range(2):
        body, s = model.gears[g], model.parts[g]
        mass[s, s] = body.mass
        w2 = body.reduced.omega2
        stiff[s, s][1:, 1:] = np.diag(w2)
        damp[s, s][1:, 1:] = np.diag(body.damp)
    free = float(np.sqrt(max(g.reduced.omega2.max() for g in model.gears)))
    rows = model.rows_at(float(q[0]), force)
    assert rows is not None
    _, f, _, _ = rk4_stage(model, 0.0, q, v, force)
    act = f[rows.on] > 0.0
    gmat = np.zeros((rows.on.size, n))
    dmat = np.zeros((rows.on.size, n))
    for g, (coef, el) in enumerate(rows.sides):
        s = model.parts[g]
        gmat[:, s.start] = coef
        dmat[:, s.start] = coef
        gmat[:, s.start + 1:s.stop] = el.modal
    ga, da = gmat[act], dmat[act]
    cs = model.contact_compliance(rows)[np.ix_(act, act)]
    stiff_c = stiff + ga.T @ np.linalg.solve(cs, ga)
    c_mesh = damper_at(model.c_table, model.pitch, float(q[0]))
    share = f[rows.on][act] / f[rows.on][act].sum()
    damp_c = damp + c_mesh * da.T @ (share[:, None] * da)
    from scipy.linalg import eigh, eigvals

    w2 = eigh(stiff_c, mass, eigvals_only=True)
    minv = np.linalg.inv(mass)
    first = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ stiff_c, -minv @ damp_c]])
    lam = eigvals(first) * dt
    amp = np.abs(1 + lam + lam**2 / 2 + lam**3 / 6 + lam**4 / 24)
    top = float(np.sqrt(w2.max()))
    return {"omega_max": top, "f_max_hz": top / (2 * math.pi), "omega_dt": top * dt,
            "free_omega_max": free, "rk4_amplification_max": float(amp.max()), "pairs_in_contact": int(act.sum())}


__all__ = ["PAPER_STEP", "Rk4Stepper", "highest_frequency", "refuse_rk4", "rk4_stage", "simulate_sector_rk4"]
