"""A dynamic run of the sector model (docs/sector.md, section 6; varying torques, 6.8).

The run starts from the static equilibrium of the loaded pair at the first position of a
mesh cycle (the quasi-static analysis of :mod:`spurdyn.sector.statics` on the same bodies),
or from rest, or from another run's end, the hubs at their nominal speeds, and lasts
``cycles`` mesh cycles. It steps the equations of
:mod:`spurdyn.solvers.sector.system` by generalized-alpha (docs/implicit.md, section 1):
with the equations of motion linear and the contact rows held over a step, a step is one
solve per gear with the factor of ``S = M + gamma' C + beta' K`` (constant: factorised once
a run) and a complementarity problem of as many unknowns as pairs on the path,

    W F + v >= 0,  F >= 0,  F (W F + v) = 0,   W = beta' G S^-1 G^T + c_H I,

``v`` the pairs' gaps at the end of the step without their forces, ``c_H`` the strip's
curvature compliance (and on modal bodies their residual compliance). Its solution is unique
(``W`` is positive definite) and found by trying the active sets, the fewest contacts first
(two or three pairs). The columns ``S^-1 G^T`` come from each gear's response to unit loads
where a pair's load enters its coordinates (:mod:`spurdyn.solvers.sector.bodies`), needed
only at the hub and the rows' coordinates. The strips' half-widths follow the forces of the
step before.

The mesh damper ``c = 2 zeta sqrt(k(phi) m_e)`` (``k(phi)`` the quasi-static cycle's mesh
stiffness at the driver's phase, ``m_e`` the pair's reduced mass) acts along the line of
action on the rate of the pairs' whole deflection, ``-D q_dot`` with ``D`` the rows' hub
entries, for the pairs in contact at the step before, shared by their forces; its
``gamma' D^T C D`` is taken by Woodbury's formula, so the factors stay the run's
(docs/sector.md, 6.3).
"""

from __future__ import annotations

import math
import time as _time
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from spurdyn.contact.hertz import effective_modulus
from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.iso6336.dynamics import reduced_mass
from spurdyn.model.loading import check_history, hub_torques, static_force
from spurdyn.result import Result
from spurdyn.sector.statics import (
    _law,
    _solve_position,
    driving_pair,
    mesh_cycle,
    pairs_in_path,
)
from spurdyn.settings import RunSettings, refuse_sector_row_grading
from spurdyn.solvers.implicit.alpha import GeneralizedAlpha
from spurdyn.solvers.sector.bodies import FullBody
from spurdyn.solvers.sector.cache import _cached
from spurdyn.solvers.sector.damper import damper_at, mesh_damper_table
from spurdyn.solvers.sector.lcp import Rows, lcp
from spurdyn.solvers.sector.output import sector_result
from spurdyn.solvers.sector.rules import (
    BACKLASH_FLOOR,
    BODY_DAMPING_FREQUENCY,
    BODY_DAMPING_RATIO,
    CYCLE_POSITIONS,
    KEEP_FREQUENCY,
    SECTOR_REVISION,
    STEPS_PER_MESH_PERIOD,
    back_flanks_on,
    body_rayleigh,
    cover_cycles,
    cycles_limit,
    steps_per_cycle,
)
from spurdyn.solvers.sector.state import (
    SectorState,
    common_rotation,
    pack_state,
    unpack_state,
)
from spurdyn.solvers.sector.system import (
    REACH,
    WHOLE_FROM_CYCLES,
    _half_widths,
    _half_widths_at,
    _radii,
    back_roll_sum,
    back_teeth,
    covered_turns,
    gap_table,
    gear_block,
    teeth_for,
)
from spurdyn.solvers.steady import settled_after


def simulate_sector(pair: GearPair, settings: RunSettings,
                    progress: Callable[[int, float, float], None] | None = None, *,
                    dt: float | None = None, energy: bool = False,
                    modes: bool | float | None = None) -> Result:
    """Run the sector model of ``pair`` with ``settings`` (module docstring).

    Parameters
    ----------
    pair, settings
        The pair and the run: its ``torque`` (on the driver), speeds, ``cycles`` (1 if not
        given), mesh (``nx``, ``ny``, ``grading``), ``damping_ratio`` (the mesh damper),
        ``rayleigh_mass``/``rayleigh_stiffness`` (the bodies; :func:`body_rayleigh` if
        neither is given) and ``rho_inf``.
    progress
        Called as ``progress(step, angle_reached, angle_total)`` (rad) about a hundred times.
    dt
        The time step (s); by default the one of :func:`steps_per_cycle`. It is shortened
        to a whole number of steps per mesh cycle.
    energy
        Keep the energy balance per sample in ``info["energy"]`` (kinetic, strain,
        strip, the torques' work, J), and the hubs' momenta with the pairs' torques on
        them in ``info["momentum"]``.
    modes
        Reduce each body to its modes (:mod:`spurdyn.solvers.sector.reduced`): ``True``
        keeps those below :data:`KEEP_FREQUENCY`, a number those below it (Hz); ``False`` steps the whole
        finite-element bodies; ``None`` as ``settings.bodies`` says.

    Returns
    -------
    Result
        ``contact_force`` the most loaded pair's force, ``gap`` the smallest gap of a pair
        on the path, ``pair_force`` every pair's, ``transmission_error``
        ``r_bA theta_A - r_bB theta_B`` (the driver's), ``info["steady"]`` the settled test.
    """
    wall0 = _time.perf_counter()
    refuse_sector_row_grading(settings.row_grading)
    dp = driving_pair(pair)
    ga, gb = dp.gear_a, dp.gear_b
    ra, rb = ga.base_radius, gb.base_radius
    cycles = int(settings.cycles or 1)
    most = cycles_limit(settings)
    speed = float(settings.speed_a if pair.driver == "a" else settings.speed_b)
    pitch = 2.0 * math.pi / ga.teeth
    per_cycle = steps_per_cycle(speed, ga.teeth, dt)
    h = pitch / speed / per_cycle
    n_steps = per_cycle * cycles
    check_history(pair, settings)
    # the cycles' worth of teeth the run carries (a guard stops the run where they are left)
    cover = cover_cycles(settings)
    back = back_flanks_on(dp, settings)
    (first_a, count_a), (first_b, count_b) = teeth_for(dp, cover, back, settings.teeth)
    mesh_keys = (settings.nx, settings.ny, settings.grading)
    blocks = tuple(_cached(("block", gear, sense, first, count, *mesh_keys),
                           lambda gear=gear, sense=sense, first=first, count=count:
                           gear_block(gear, sense, first, count, *mesh_keys))
                   for gear, sense, first, count in ((ga, 1.0, first_a, count_a), (gb, -1.0, first_b, count_b)))
    bodies = (blocks[0].body, blocks[1].body)
    load = static_force(pair, settings.torque)

    def torques_at(steps: NDArray[np.intp]) -> NDArray[np.float64]:
        """The hubs' torques at the ends of ``steps`` (driver first, as ``dp``'s A and B)."""
        tq = hub_torques(pair, settings, steps * h)
        return tq[:, ::-1].copy() if pair.driver == "b" else tq
    estar = effective_modulus(ga.material.young, ga.material.poisson, gb.material.young, gb.material.poisson)
    width = min(ga.face_width, gb.face_width)
    n_path = pairs_in_path(dp)
    # the driver's teeth that come near the path: 0 .. P at the start, one more a cycle (of
    # as many as the run may go on to; the result keeps those of the cycles it ran)
    k_lo = -cover - 1
    teeth = np.arange(k_lo, n_path + 1)
    # the contacts: the drive flanks of those teeth, and with the back flanks those of the
    # driver's teeth that come near the back path (each on the driven gear's tooth -k + 1)
    jn = dp.backlash_normal
    sigma = back_roll_sum(dp)
    back_lo, back_hi = back_teeth(dp, cover, REACH * pitch) if back else (0, -1)
    back_k = np.arange(back_lo, back_hi + 1)
    c_teeth = np.concatenate([teeth, back_k]).astype(np.intp)
    c_side = np.concatenate([np.zeros(teeth.size, np.intp), np.ones(back_k.size, np.intp)])
    n_c = c_teeth.size

    # -- the scheme, the bodies as the loop sees them ------------------------------------
    scheme = GeneralizedAlpha(settings.rho_inf)
    bp, gp = scheme.beta_prime(h), scheme.gamma_prime(h)
    am, af, beta, gamma = scheme.alpha_m, scheme.alpha_f, scheme.beta, scheme.gamma
    rayleigh = body_rayleigh(settings)
    if modes is None:
        modes = settings.bodies == "modal"
    if modes:
        from spurdyn.solvers.sector.bodies import ModalBody
        from spurdyn.solvers.sector.reduced import reduce_gear

        top = KEEP_FREQUENCY if modes is True else float(modes)
        gears: tuple[Any, Any] = tuple(
            ModalBody(_cached(("modes", blk.gear, blk.sense, blk.first, blk.count, *mesh_keys, top),
                              lambda blk=blk: reduce_gear(blk, top)), gp, bp, rayleigh, 2 if back else 1)
            for blk in blocks)
    else:
        gears = tuple(FullBody(blk, gp, bp, rayleigh) for blk in blocks)
    na = gears[0].n
    n = na + gears[1].n
    parts = (slice(0, na), slice(na, n))

    # -- the quasi-static cycle and the static start -------------------------------------
    cycle = _cached(("cycle", pair, settings.torque, first_a, count_a, first_b, count_b, *mesh_keys),
                    lambda: mesh_cycle(pair, settings.torque, settings.nx, settings.ny,
                                       positions=CYCLE_POSITIONS, bodies=bodies))
    law = _law(pair, settings.torque, bodies)
    start = settings.start_state
    if start is not None:
        # another run's end (a sweep's continuation): its state per angle at this speed
        if not (blocks[0].whole and blocks[1].whole):
            raise InputError("start_state", "a sector run starts from another's end only on whole "
                             f"gears: give {WHOLE_FROM_CYCLES} cycles or more, and no fewer teeth than "
                             "the gears have")
        st = unpack_state(start, n)
        offset = st.offset
        q, v, acc, qdd = st.q.copy(), speed * st.dq, speed**2 * st.ddq, speed**2 * st.qdd
        force = np.zeros(n_c)
        at = dict(zip(zip(st.teeth.tolist(), st.sides.tolist()), st.forces))
        force[:] = [at.get((int(k) + offset, int(sd)), 0.0) for k, sd in zip(c_teeth, c_side)]
        # the pair's common rotation at this point's speed (a chain's drift not carried on)
        common = common_rotation(tuple(gears[g].momentum(v[parts[g]]) for g in range(2)),
                                 (blocks[0].inertia, blocks[1].inertia), ra / rb, speed)
        v[0] += common
        v[na] += common * ra / rb
        reset = common / speed
    elif settings.start == "rest":
        # the bodies undeformed at their nominal speeds, the torques ramped up from zero
        offset = 0
        q, qdd, acc, force = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n_c)
        v = np.zeros(n)
        v[0], v[na] = speed, speed * ra / rb
    else:
        offset = 0
        js, f0, e0, _, _ = _solve_position(law, dp.start_roll_a)
        q = np.zeros(n)
        rolls0 = [dp.start_roll_a + j * pitch for j in js]
        hw0 = _half_widths(dp, rolls0, f0, estar, width)     # the strips of the static forces
        for g, blk in enumerate(blocks):
            sign = 1 if g == 0 else -1
            loads = np.zeros(blk.mass.size)
            for j, r, b, fj in zip(js, _radii(dp, rolls0)[g], hw0, f0):
                loads[blk.flank_dofs(sign * j)] += fj * blk.flank_load(sign * j, float(r), float(b))
            q[parts[g]][1:] = gears[g].static(loads)
        q[0] = e0 / ra
        force = np.zeros(n_c)
        force[np.searchsorted(teeth, js)] = f0      # the drive flanks come first
        v = np.zeros(n)
        v[0], v[na] = speed, speed * ra / rb
        qdd = np.zeros(n)
        acc = np.zeros(n)

    z_theta = []
    for g in range(2):
        e = np.zeros(gears[g].n)
        e[0] = 1.0
        z_theta.append(gears[g].solve(e))
    j_a, j_b = blocks[0].inertia, blocks[1].inertia
    c_table = mesh_damper_table(cycle, settings.damping_ratio, reduced_mass(j_a, j_b, ra, rb), pitch)
    c_h = law.c_h
    reach = REACH * pitch
    theta_lo, theta_hi = covered_turns(dp, (int(teeth[0]), int(teeth[-1])),
                                       (back_lo, back_hi) if back else None, reach)

    table = _cached(("gaps", pair, reach), lambda: gap_table(dp, reach))
    roll_0, roll_1 = dp.start_roll_a, dp.end_roll_a

    def rows_at(theta_a: float, f: NDArray[np.float64]) -> Rows | None:
        """The contacts near their paths at the driver's turn ``theta_a``: their indices in
        ``c_teeth``, the constant part of their gaps, and per gear the rows' coefficients on
        the hub and their elastic parts (:meth:`~spurdyn.solvers.sector.bodies.FullBody.rows`).
        A back flank's roll is ``Sigma - rho`` (:func:`~spurdyn.solvers.sector.system.back_roll_sum`),
        running backwards as the driver turns, and its gap the mirror image's plus the
        backlash, opening as the driver runs ahead (docs/sector.md, 6.7)."""
        rolls = roll_0 + theta_a + c_teeth * pitch
        rolls = np.where(c_side == 1, sigma - rolls, rolls)
        on = np.flatnonzero((rolls >= roll_0 - reach) & (rolls <= roll_1 + reach))
        if not on.size:
            return None
        g0, slope, r_a, r_b = table.at(rolls[on])
        hw = _half_widths_at(dp, (r_a, r_b), f[on], estar, width)
        sd = c_side[on]
        sgn = np.where(sd == 1, -1.0, 1.0)        # d roll / d theta_A
        k = c_teeth[on] + offset          # the driver's body teeth (a continuation runs on)
        # d gap / d theta: the base circles' and, off the path, the corner's
        sides = tuple((coef, gears[g].rows(kg, blocks[g].flank_loads(r, hw), sd))
                      for g, (kg, coef, r) in enumerate(((k, sgn * (slope - ra), r_a),
                                                          (-k + sd, sgn * rb, r_b))))
        return Rows(on, g0 - sgn * slope * theta_a + jn * sd, sides)

    def gap_rows(rows: Rows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``G x`` for the pairs ``rows`` (their constant parts not included)."""
        return sum(coef * x[parts[g]][0] + gears[g].elastic(elastic, x[parts[g]])
                   for g, (coef, elastic) in enumerate(rows.sides))

    def rigid_rows(rows: Rows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``D x``: the rows' rigid part alone, their entries on the hubs (the mesh damper's
        rows: ``-D q_dot`` is the rate of the pairs' whole approach, the bodies' and the
        strips' compliance together, while they touch)."""
        return sum(coef * x[parts[g]][0] for g, (coef, _) in enumerate(rows.sides))

    def compliance(rows: Rows) -> tuple[Any, ...]:
        """``(G S^-1 G^T, G S^-1 D^T, D S^-1 D^T, C_res, S^-1 G^T)``: the pairs' coupling
        through each gear, by their whole rows ``G`` and their rigid parts ``D`` (the
        damper's rows: ``S^-1 D^T`` is the hub's response ``z`` times the rows' hub
        coefficients); the bodies' residual compliance between the pairs' loads; and the
        columns (per gear)."""
        m = rows.on.size
        w, w_gd, w_dd, res = (np.zeros((m, m)) for _ in range(4))
        cols = []
        for g, (coef, elastic) in enumerate(rows.sides):
            z = z_theta[g]
            full = np.outer(z, coef) + gears[g].columns(elastic)       # S^-1 G^T
            w += coef[:, None] * full[0][None, :] + gears[g].elastic(elastic, full)
            w_gd += np.outer(coef * z[0] + gears[g].elastic(elastic, z), coef)
            w_dd += z[0] * np.outer(coef, coef)
            res += gears[g].residual(elastic)
            cols.append(full)
        return w, w_gd, w_dd, res, cols

    def columns_times(cols: list[NDArray[np.float64]], lam: NDArray[np.float64]) -> NDArray[np.float64]:
        """``S^-1 G^T lam`` from the per-gear columns ``cols``."""
        return np.concatenate([c @ lam for c in cols])

    def rigid_columns_times(rows: Rows, lam: NDArray[np.float64]) -> NDArray[np.float64]:
        """``S^-1 D^T lam``: the responses to the hub torques of the rows' rigid parts."""
        return np.concatenate([float(coef @ lam) * z_theta[g] for g, (coef, _) in enumerate(rows.sides)])

    def beyond(step: int) -> str:
        """Why a run stopped where the driver left the turns its teeth cover."""
        return (f"at step {step} the driver had turned {q[0] / pitch:.2f} pitches, beyond the "
                f"{theta_lo / pitch:.2f} to {theta_hi / pitch:.2f} its teeth cover (its speed "
                f"left {speed * 60 / (2 * math.pi):,.0f} rpm by too much)")

    # -- the time loop -------------------------------------------------------------------
    n_out = n_steps + 1
    tq_out = torques_at(np.arange(n_out))
    th_out = np.full((n_out, 2), np.nan)
    om_out = np.full((n_out, 2), np.nan)
    f_out = np.full((n_out, n_c), np.nan)
    gap_out = np.full(n_out, np.nan)
    en_out = np.full((n_out, 8), np.nan) if energy else None
    c_res = np.zeros((0, 0))
    damper_torque = [0.0, 0.0]       # the mesh damper's torques on the hubs at the last step
    # the torques' work (J), by the trapezoid rule between saved steps (exact for constant ones)
    work = [float(tq_out[0] @ np.array([q[0], q[na]])), q[0], q[na]]

    def save(i: int, rows: Rows | None) -> None:
        th_out[i] = q[0], q[na]
        om_out[i] = v[0], v[na]
        f_out[i] = force
        fo = force[rows.on] if rows is not None else np.zeros(0)
        if rows is not None:
            gaps = gap_rows(rows, q) + rows.const + c_h * fo + c_res @ fo
            gap_out[i] = float(gaps.min())
        if en_out is not None:
            if i > 0:
                work[0] += 0.5 * float((tq_out[i - 1] + tq_out[i]) @ np.array([q[0] - work[1], q[na] - work[2]]))
                work[1:] = q[0], q[na]
            res = 0.5 * float(fo @ c_res @ fo) if rows is not None else 0.0
            en_out[i] = (sum(gears[g].kinetic(v[parts[g]]) for g in range(2)),
                         sum(gears[g].strain(q[parts[g]]) for g in range(2)) + res,
                         0.5 * c_h * float(force @ force), work[0],
                         *(gears[g].momentum(v[parts[g]]) for g in range(2)),
                         # the pairs' generalised forces on the hubs: the rows' hub entries,
                         # and the mesh damper's torques (it acts on the hubs)
                         *((float(rows.sides[g][0] @ fo) if rows is not None else 0.0) + damper_torque[g]
                           for g in range(2)))

    rows0 = rows_at(0.0, force)
    if rows0 is not None:
        c_res = compliance(rows0)[3]
    save(0, rows0)
    status, reason, step = "complete", "", 0
    every = max(n_steps // 100, 1)
    # BLAS on one thread: the products are small and another process may hold the other core
    # (as the implicit integrator's steps, docs/implicit.md)
    limit = threadpool_limits(limits=1, user_api="blas")
    compiled = (settings.backend == "numba" and modes and not energy
                and blocks[0].whole and blocks[1].whole)
    done = [0]          # the compiled loop's last finished step (an interrupt comes between chunks)
    target = cycles     # the cycles the run goes to: more, one at a time, until it settles
    try:
        while True:     # a segment of cycles, then the settled test
            first = step
            if compiled:        # the same loop, compiled (step_compiled.py), in chunks for progress
                from spurdyn.solvers.sector.stepper_compiled import run_compiled

                step, failed = run_compiled(gears, blocks, (q, v, acc, qdd, force), c_teeth, c_side, offset, table,
                                            (roll_0, roll_1, reach, pitch, ra, rb, estar, width, c_h,
                                             am, af, beta, gamma, h, bp, gp, sigma, jn, theta_lo, theta_hi),
                                            tq_out, c_table, (th_out, om_out, f_out, gap_out), first, n_steps, every,
                                            progress, target * pitch, done)
                if failed == 1:
                    status, reason = "incomplete", f"the solution became NaN at step {step}"
                elif failed == 2:
                    status, reason = "incomplete", beyond(step)
            else:
                for step in range(first + 1, n_steps + 1):
                    a_part = (af * qdd - am * acc) / (1.0 - am)
                    q_hat = q + h * v + h * h * (0.5 - beta) * acc + h * h * beta * a_part
                    v_hat = v + h * (1.0 - gamma) * acc + h * gamma * a_part
                    r = np.zeros(n)
                    r[0], r[na] = tq_out[step]
                    for g in range(2):
                        r[parts[g]] -= gears[g].forces(q_hat[parts[g]], v_hat[parts[g]])
                    x0 = np.concatenate([gears[g].solve(r[parts[g]]) for g in range(2)])
                    rows = rows_at(float(q_hat[0]), force)
                    last = force
                    force = np.zeros(n_c)
                    if rows is not None:
                        on = rows.on
                        w0, w_gd, w_dd, c_res, cols = compliance(rows)
                        m = on.size
                        # the mesh damper on the rate of the whole approach of the pairs in contact at
                        # the step before (the rows' rigid part D: bodies and strips together, in
                        # parallel with the mesh stiffness), shared by their forces:
                        # S + gamma' D^T C D, by Woodbury through the pairs' couplings
                        shares = last[on]
                        c_mesh = damper_at(c_table, pitch, float(q_hat[0]))
                        c_pairs = c_mesh * shares / shares.sum() if c_mesh > 0.0 and shares.sum() > 0.0 \
                            else np.zeros(m)
                        if c_pairs.any():
                            x0 -= rigid_columns_times(rows, c_pairs * rigid_rows(rows, v_hat))
                        g_x0, d_x0 = gap_rows(rows, x0), rigid_rows(rows, x0)
                        k_w = (gp * c_pairs)[:, None] * np.linalg.inv(np.eye(m) + w_dd * (gp * c_pairs)[None, :]) \
                            if c_pairs.any() else np.zeros((m, m))
                        w = bp * (w0 - w_gd @ k_w @ w_gd.T) + c_res + c_h * np.eye(m)
                        vv = rows.const + gap_rows(rows, q_hat) + bp * (g_x0 - w_gd @ k_w @ d_x0)
                        lam = lcp(0.5 * (w + w.T), vv, shares > 0.0)
                        qdd_new = x0 + columns_times(cols, lam) - rigid_columns_times(rows, k_w @ (d_x0 + w_gd.T @ lam))
                        force[on] = lam
                    else:
                        qdd_new = x0
                    if not np.isfinite(qdd_new).all():
                        status, reason = "incomplete", f"the solution became NaN at step {step}"
                        break
                    acc = a_part + (1.0 - af) / (1.0 - am) * qdd_new
                    q = q_hat + bp * qdd_new
                    v = v_hat + gp * qdd_new
                    qdd = qdd_new
                    if not theta_lo <= q[0] <= theta_hi:
                        status, reason = "incomplete", beyond(step)
                        break
                    if energy:
                        damper_torque[:] = [0.0, 0.0]
                        if rows is not None and c_pairs.any():
                            rate = c_pairs * rigid_rows(rows, v)
                            damper_torque[:] = [-float(coef @ rate) for coef, _ in rows.sides]
                    save(step, rows)
                    if progress is not None and step % every == 0:
                        progress(step, float(q[0]), target * pitch)
            lo, hi = max(target - 2, 0) * per_cycle, n_steps + 1       # the last two cycles
            if status != "complete" or target >= most or settled_after(
                    f_out[lo:hi].sum(axis=1), ra * th_out[lo:hi, 0] - rb * th_out[lo:hi, 1], per_cycle,
                    min(target, 2)):
                break
            # not settled, and it may go on: one more cycle
            target += 1
            n_steps += per_cycle
            th_out, om_out, f_out, gap_out = (np.concatenate([x, np.full((per_cycle,) + x.shape[1:], np.nan)])
                                              for x in (th_out, om_out, f_out, gap_out))
            tq_out = np.concatenate([tq_out, torques_at(np.arange(n_steps - per_cycle + 1, n_steps + 1))])
            if en_out is not None:
                en_out = np.concatenate([en_out, np.full((per_cycle, 8), np.nan)])
    except KeyboardInterrupt:
        if compiled:
            step = done[0] + 1
        status, reason = "incomplete", f"interrupted by the user at step {step}"
        step -= 1
    finally:
        limit.restore_original_limits()
    n_kept = step + 1 if status == "complete" or "interrupted" in reason else step
    # the teeth of the cycles run (those of the cycles it might have gone on to never came)
    keep = teeth >= -target - 1
    back_keep = back_k >= back_teeth(dp, target, REACH * pitch)[0] if back else np.zeros(0, bool)
    result = sector_result(pair, dp, settings, blocks, cycle, teeth[keep], n_kept, np.arange(th_out.shape[0]) * h,
                           th_out, om_out, f_out[:, :teeth.size][:, keep], gap_out, en_out, per_cycle, cycles, most, h,
                           tq_out, c_table, status, reason, _time.perf_counter() - wall0, load,
                           back=(back_k[back_keep], f_out[:, teeth.size:][:, back_keep]) if back else None)
    if status == "complete" and blocks[0].whole and blocks[1].whole:
        # where the next speed of a continuation starts: this end, the teeth N on
        # (the pitches the driver turned: the cycles run, give or take its transmission error)
        turned = int(round(q[0] / pitch))
        q_end = q.copy()
        q_end[0] -= turned * pitch
        q_end[na] -= turned * 2.0 * math.pi / gb.teeth
        loaded = np.flatnonzero(force > 0.0)
        result.info["sector_end_state"] = pack_state(SectorState(
            offset - turned, q_end, v / speed, acc / speed**2, qdd / speed**2,
            c_teeth[loaded] + offset, force[loaded], c_side[loaded]))
    result.info["tooth_offset"] = offset
    # how far a continuation's start turned from its speed, and was set to it (a fraction)
    result.info["common_rotation_reset"] = reset if start is not None else None
    result.info["rayleigh"] = list(rayleigh)
    # the bodies' damping was the model's default (BODY_DAMPING_RATIO), not the run's
    result.info["rayleigh_default"] = settings.rayleigh_mass is None and settings.rayleigh_stiffness is None
    result.info["bodies"] = "modal" if modes else "full"
    result.info["modes"] = [g.n - 1 for g in gears] if modes else None
    result.info["coordinates"] = n
    return result


__all__ = ["BACKLASH_FLOOR", "BODY_DAMPING_FREQUENCY", "BODY_DAMPING_RATIO", "SECTOR_REVISION", "back_flanks_on", "KEEP_FREQUENCY", "STEPS_PER_MESH_PERIOD", "body_rayleigh",
           "cycles_limit", "simulate_sector", "steps_per_cycle"]
