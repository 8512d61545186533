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

The pieces are the implicit loop's (:mod:`spurdyn.solvers.sector.run`): the same bodies
(:class:`~spurdyn.solvers.sector.bodies.ModalBody` with ``gamma' = beta' = 0``, so that its
``S`` is ``M`` and its solve ``M^-1``), the same rows (the gap table, the strips' unit loads,
the modal rows, the residual compliance), the same complementarity solver
(:func:`~spurdyn.solvers.sector.lcp.lcp`), the same mesh damper table
(:func:`~spurdyn.solvers.sector.damper.mesh_damper_table`, read by ``damper_at``), the same
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
:func:`simulate_sector_rk4` steps in NumPy (``backend="numpy"``) or in the compiled twin
(:mod:`spurdyn.solvers.sector.rk4_compiled`, the default where Numba is on).
"""

from __future__ import annotations

import math
import time as _time
from typing import Callable

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from spurdyn.contact.hertz import effective_modulus
from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.iso6336.dynamics import reduced_mass
from spurdyn.model.loading import hub_torques, static_force
from spurdyn.result import Result
from spurdyn.sector.statics import _law, _solve_position, driving_pair, mesh_cycle, pairs_in_path
from spurdyn.settings import RunSettings, refuse_sector_row_grading
from spurdyn.solvers.sector.bodies import ModalBody
from spurdyn.solvers.sector.cache import _cached
from spurdyn.solvers.sector.damper import damper_at, mesh_damper_table
from spurdyn.solvers.sector.lcp import Rows, lcp
from spurdyn.solvers.sector.output import sector_result
from spurdyn.solvers.sector.reduced import reduce_gear
from spurdyn.solvers.sector.rules import (
    CYCLE_POSITIONS,
    KEEP_FREQUENCY,
    back_flanks_on,
    cover_cycles,
    body_rayleigh,
    steps_per_cycle,
)
from spurdyn.solvers.sector.system import (
    REACH,
    _half_widths,
    _half_widths_at,
    _radii,
    covered_turns,
    gap_table,
    gear_block,
    teeth_for,
)

#: The paper's RK4 step (s): the reference's default.
PAPER_STEP = 3e-8


def _refuse(pair: GearPair, settings: RunSettings, modes: bool | float | None) -> None:
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


class Model:
    """The sector model on modal bodies as the RK4 reference sees it: what
    :func:`spurdyn.solvers.sector.run.simulate_sector` builds for its run, with ``M^-1`` in
    place of ``S^-1``; :meth:`stage` is the ODE's right-hand side."""

    def __init__(self, pair: GearPair, settings: RunSettings, modes: bool | float | None = None) -> None:
        _refuse(pair, settings, modes)
        self.pair, self.settings = pair, settings
        dp = self.dp = driving_pair(pair)
        ga, gb = dp.gear_a, dp.gear_b
        self.ra, self.rb = ga.base_radius, gb.base_radius
        self.cycles = int(settings.cycles or 1)
        self.speed = float(settings.speed_a if pair.driver == "a" else settings.speed_b)
        self.pitch = pitch = 2.0 * math.pi / ga.teeth
        # the teeth the implicit run carries (cover_cycles: those of the cycles it may go on to)
        cover = cover_cycles(settings)
        (first_a, count_a), (first_b, count_b) = teeth_for(dp, cover, False, settings.teeth)
        mesh_keys = (settings.nx, settings.ny, settings.grading)
        self.blocks = blocks = tuple(
            _cached(("block", gear, sense, first, count, *mesh_keys),
                    lambda gear=gear, sense=sense, first=first, count=count:
                    gear_block(gear, sense, first, count, *mesh_keys))
            for gear, sense, first, count in ((ga, 1.0, first_a, count_a), (gb, -1.0, first_b, count_b)))
        bodies = (blocks[0].body, blocks[1].body)
        self.load = static_force(pair, settings.torque)
        self.estar = effective_modulus(ga.material.young, ga.material.poisson, gb.material.young,
                                       gb.material.poisson)
        self.width = min(ga.face_width, gb.face_width)
        n_path = pairs_in_path(dp)
        self.teeth = np.arange(-cover - 1, n_path + 1).astype(np.intp)
        self.rayleigh = rayleigh = body_rayleigh(settings)
        top = KEEP_FREQUENCY if modes in (None, True) else float(modes)
        # gamma' = beta' = 0: the body's S is M, its solve M^-1 and its columns M^-1 E^T
        self.gears = tuple(
            ModalBody(_cached(("modes", blk.gear, blk.sense, blk.first, blk.count, *mesh_keys, top),
                              lambda blk=blk: reduce_gear(blk, top)), 0.0, 0.0, rayleigh, 1)
            for blk in blocks)
        na = self.na = self.gears[0].n
        self.n = na + self.gears[1].n
        self.parts = (slice(0, na), slice(na, self.n))
        self.cycle = _cached(("cycle", pair, settings.torque, first_a, count_a, first_b, count_b, *mesh_keys),
                             lambda: mesh_cycle(pair, settings.torque, settings.nx, settings.ny,
                                                positions=CYCLE_POSITIONS, bodies=bodies))
        self.law = _law(pair, settings.torque, bodies)
        self.c_h = self.law.c_h
        self.z_theta = []
        for g in range(2):
            e = np.zeros(self.gears[g].n)
            e[0] = 1.0
            self.z_theta.append(self.gears[g].solve(e))
        self.c_table = mesh_damper_table(self.cycle, settings.damping_ratio,
                                         reduced_mass(blocks[0].inertia, blocks[1].inertia, self.ra, self.rb), pitch)
        self.reach = REACH * pitch
        self.theta_lo, self.theta_hi = covered_turns(dp, (int(self.teeth[0]), int(self.teeth[-1])), None, self.reach)
        self.table = _cached(("gaps", pair, self.reach), lambda: gap_table(dp, self.reach))
        self.roll_0, self.roll_1 = dp.start_roll_a, dp.end_roll_a

    # -- the start (simulate_sector's) ------------------------------------------------------
    def start(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``(q, v, force)`` at ``t = 0``: the static equilibrium of the loaded pair at the
        start of a cycle (as :func:`~spurdyn.solvers.sector.run.simulate_sector` starts), or
        with ``start="rest"`` the bodies undeformed; the hubs at their meshing speeds."""
        dp, n, na = self.dp, self.n, self.na
        q, v, force = np.zeros(n), np.zeros(n), np.zeros(self.teeth.size)
        v[0], v[na] = self.speed, self.speed * self.ra / self.rb
        if self.settings.start == "rest":
            return q, v, force
        js, f0, e0, _, _ = _solve_position(self.law, dp.start_roll_a)
        rolls0 = [dp.start_roll_a + j * self.pitch for j in js]
        hw0 = _half_widths(dp, rolls0, f0, self.estar, self.width)
        for g, blk in enumerate(self.blocks):
            sign = 1 if g == 0 else -1
            loads = np.zeros(blk.mass.size)
            for j, r, b, fj in zip(js, _radii(dp, rolls0)[g], hw0, f0):
                loads[blk.flank_dofs(sign * j)] += fj * blk.flank_load(sign * j, float(r), float(b))
            q[self.parts[g]][1:] = self.gears[g].static(loads)
        q[0] = e0 / self.ra
        force[np.searchsorted(self.teeth, js)] = f0
        return q, v, force

    def torques(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """The hubs' torques at times ``t`` (driver first)."""
        tq = hub_torques(self.pair, self.settings, t)
        return tq[..., ::-1].copy() if self.pair.driver == "b" else tq

    # -- the rows and the forces at a state -------------------------------------------------
    def rows_at(self, theta_a: float, held: NDArray[np.float64]) -> Rows | None:
        """The drive flanks near their paths at the driver's turn ``theta_a`` (the implicit
        loop's ``rows_at`` without back flanks), the strips' half-widths those of the forces
        ``held`` at this turn's contact radii."""
        rolls = self.roll_0 + theta_a + self.teeth * self.pitch
        on = np.flatnonzero((rolls >= self.roll_0 - self.reach) & (rolls <= self.roll_1 + self.reach))
        if not on.size:
            return None
        g0, slope, r_a, r_b = self.table.at(rolls[on])
        hw = _half_widths_at(self.dp, (r_a, r_b), held[on], self.estar, self.width)
        k = self.teeth[on]
        sides = tuple((coef, self.gears[g].rows(kg, self.blocks[g].flank_loads(r, hw)))
                      for g, (kg, coef, r) in enumerate(((k, slope - self.ra, r_a),
                                                          (-k, np.full(on.size, self.rb), r_b))))
        return Rows(on, g0 - slope * theta_a, sides)

    def gap_rows(self, rows: Rows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``G x`` (the rows' constant parts not included)."""
        return sum(coef * x[self.parts[g]][0] + self.gears[g].elastic(el, x[self.parts[g]])
                   for g, (coef, el) in enumerate(rows.sides))

    def rigid_rows(self, rows: Rows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``D x``: the rows' hub entries alone (the mesh damper's rows)."""
        return sum(coef * x[self.parts[g]][0] for g, (coef, _) in enumerate(rows.sides))

    def compliance(self, rows: Rows) -> NDArray[np.float64]:
        """``C_s = c_H I + b_i^T R b_j``: the pairs' compliance without inertia."""
        res = sum(self.gears[g].residual(el) for g, (_, el) in enumerate(rows.sides))
        return res + self.c_h * np.eye(rows.on.size)

    def stage(self, t: float, q: NDArray[np.float64], v: NDArray[np.float64], held: NDArray[np.float64],
              guess: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
        """``(q_ddot, F, smallest gap)`` at time ``t`` and state ``(q, v)``: the forces of
        the complementarity problem at ``q`` (half-widths of ``held``; ``guess`` the forces
        whose active set is tried first), the torques, the bodies' forces, the pairs'
        ``G^T F`` and the mesh damper ``-D^T C D v`` shared by the forces ``F``."""
        r = np.zeros(self.n)
        r[0], r[self.na] = self.torques(np.array(t))
        for g in range(2):
            r[self.parts[g]] -= self.gears[g].forces(q[self.parts[g]], v[self.parts[g]])
        acc = np.concatenate([self.gears[g].solve(r[self.parts[g]]) for g in range(2)])
        force = np.zeros(self.teeth.size)
        rows = self.rows_at(float(q[0]), held)
        if rows is None:
            return acc, force, math.nan
        on = rows.on
        cs = self.compliance(rows)
        gaps = rows.const + self.gap_rows(rows, q)
        lam = lcp(0.5 * (cs + cs.T), gaps, guess[on] > 0.0)
        force[on] = lam
        c_mesh = damper_at(self.c_table, self.pitch, float(q[0]))
        total = lam.sum()
        rate = (c_mesh * lam / total) * self.rigid_rows(rows, v) if c_mesh > 0.0 and total > 0.0 \
            else np.zeros(on.size)
        for g, (coef, el) in enumerate(rows.sides):
            # M^-1 G^T F (hub: z c^T F; elastic: the body's columns) less M^-1 D^T C D v
            acc[self.parts[g]] += self.z_theta[g] * float(coef @ (lam - rate)) + self.gears[g].columns(el) @ lam
        return acc, force, float((gaps + cs @ lam).min())


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
        Whole bodies, back flanks, a torque history, a start from another run's end.
    """
    wall0 = _time.perf_counter()
    model = Model(pair, settings, modes)
    per_cycle = steps_per_cycle(model.speed, model.dp.gear_a.teeth, dt)
    h = model.pitch / model.speed / per_cycle
    cycles = model.cycles
    n_steps = per_cycle * cycles if steps is None else min(int(steps), per_cycle * cycles)
    q, v, force = model.start()
    n_c = model.teeth.size
    n_out = n_steps + 1
    tq_out = model.torques(np.arange(n_out) * h)
    th_out = np.full((n_out, 2), np.nan)
    om_out = np.full((n_out, 2), np.nan)
    f_out = np.full((n_out, n_c), np.nan)
    gap_out = np.full(n_out, np.nan)
    backend = backend or settings.backend
    status, reason, step = "complete", "", 0
    limit = threadpool_limits(limits=1, user_api="blas")
    loop0 = _time.perf_counter()
    try:
        if backend == "numba":
            from spurdyn.solvers.sector.rk4_compiled import run_rk4_compiled

            step, failed = run_rk4_compiled(model, q, v, force, h, n_steps, (th_out, om_out, f_out, gap_out), progress)
        else:
            step, failed = _run_numpy(model, q, v, force, h, n_steps, (th_out, om_out, f_out, gap_out), progress)
        if failed == 1:
            status, reason = "incomplete", f"the solution became NaN at step {step}"
        elif failed == 2:
            status, reason = "incomplete", (f"at step {step} the driver left the turns its teeth cover")
    finally:
        limit.restore_original_limits()
    loop_s = _time.perf_counter() - loop0
    n_kept = step + 1 if status == "complete" else step
    result = sector_result(pair, model.dp, settings, model.blocks, model.cycle, model.teeth, n_kept,
                           np.arange(n_out) * h, th_out, om_out, f_out, gap_out, None, per_cycle, cycles,
                           cycles, h, tq_out, model.c_table, status, reason, _time.perf_counter() - wall0,
                           model.load)
    result.info.update(integrator="rk4", loop_s=loop_s, rayleigh=list(model.rayleigh), bodies="modal",
                       modes=[g.n - 1 for g in model.gears], coordinates=model.n, tooth_offset=0,
                       rk4_backend=backend)
    return result


def _run_numpy(model: Model, q: NDArray[np.float64], v: NDArray[np.float64], force: NDArray[np.float64],
               h: float, n_steps: int, outs: tuple[NDArray[np.float64], ...],
               progress: Callable[[int, float, float], None] | None) -> tuple[int, int]:
    """The RK4 loop in NumPy from the state ``(q, v)`` with the forces ``force`` at ``t = 0``
    (changed in place); step ``i``'s samples into ``outs`` (turns, speeds, forces, smallest
    gap). Returns ``(last step, 0)`` or the failed step and 1 (not finite), 2 (the driver left
    the turns the contacts cover)."""
    th_out, om_out, f_out, gap_out = outs
    na = model.na
    every = max(n_steps // 100, 1)
    a1, f1, gap = model.stage(0.0, q, v, force, force)
    force[:] = f1
    for step in range(n_steps + 1):
        th_out[step] = q[0], q[na]
        om_out[step] = v[0], v[na]
        f_out[step] = force
        gap_out[step] = gap
        if step == n_steps:
            break
        t = step * h
        held = force.copy()           # the strips' half-widths over the step: the forces at its start
        a2, _, _ = model.stage(t + 0.5 * h, q + 0.5 * h * v, v + 0.5 * h * a1, held, held)
        v2 = v + 0.5 * h * a1
        a3, _, _ = model.stage(t + 0.5 * h, q + 0.5 * h * v2, v + 0.5 * h * a2, held, held)
        v3 = v + 0.5 * h * a2
        a4, _, _ = model.stage(t + h, q + h * v3, v + h * a3, held, held)
        v4 = v + h * a3
        q += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        if not (np.isfinite(q).all() and np.isfinite(v).all()):
            return step + 1, 1
        if not model.theta_lo <= q[0] <= model.theta_hi:
            return step + 1, 2
        a1, f1, gap = model.stage(t + h, q, v, held, held)
        force[:] = f1
        if progress is not None and (step + 1) % every == 0:
            progress(step + 1, float(q[0]), n_steps * h * model.speed)
    return n_steps, 0


def highest_frequency(pair: GearPair, settings: RunSettings, dt: float = PAPER_STEP) -> dict[str, float]:
    """The stiffest the RK4 reference meets, at the static start (its pairs in contact held
    by their compliance ``C_s``): the highest undamped frequency of ``M^-1 (K + G^T C_s^-1 G)``
    (rad/s) and of the free bodies, ``omega_max dt`` against RK4's 2.83 on the imaginary axis,
    and the largest ``|R(lambda dt)|`` of RK4's amplification over the damped system's
    eigenvalues (bodies' Rayleigh damping, the mesh damper at the start's phase)."""
    model = Model(pair, settings)
    q, v, force = model.start()
    n = model.n
    mass, stiff, damp = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    for g in range(2):
        body, s = model.gears[g], model.parts[g]
        mass[s, s] = body.mass
        w2 = body.reduced.omega2
        stiff[s, s][1:, 1:] = np.diag(w2)
        damp[s, s][1:, 1:] = np.diag(body._damp)
    free = float(np.sqrt(max(g.reduced.omega2.max() for g in model.gears)))
    rows = model.rows_at(float(q[0]), force)
    assert rows is not None
    _, f, _ = model.stage(0.0, q, v, force, force)
    act = f[rows.on] > 0.0
    gmat = np.zeros((rows.on.size, n))
    dmat = np.zeros((rows.on.size, n))
    for g, (coef, el) in enumerate(rows.sides):
        s = model.parts[g]
        gmat[:, s.start] = coef
        dmat[:, s.start] = coef
        gmat[:, s.start + 1:s.stop] = el.modal
    ga, da = gmat[act], dmat[act]
    cs = model.compliance(rows)[np.ix_(act, act)]
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


__all__ = ["Model", "PAPER_STEP", "highest_frequency", "simulate_sector_rk4"]
