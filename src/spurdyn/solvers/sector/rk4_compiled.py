"""The sector model's RK4 reference on modal bodies of whole gears, compiled with Numba: the
twin of the NumPy loop of :mod:`spurdyn.solvers.sector.rk4`, stage for stage the same
equations. Its pieces are the implicit compiled loop's (:mod:`spurdyn.solvers.sector.step_compiled`:
the gap table, the strip's unit load, Hertz's half-width, the complementarity problem by
active sets) and its arrays the same (per gear ``M^-1`` in place of ``S^-1``, the modes'
damping and ``omega^2``, the modes at each flank in its own frame, the static flexibility
between flanks by the teeth's distance round the ring, the flank's geometry).
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.jit import njit
from spurdyn.solvers.sector.step_compiled import (
    ORDERS,
    _flank_load,
    _half_width,
    _lcp_ordered,
    _masks_by_size,
    _modal_free,
    _table_at,
)


@njit
def _stage(tq0, tq1, q, v, held, guess_f, inv0, inv1, damp0, damp1, om0, om1, modes0, modes1, flex0, flex1,
           geo0, geo1, first0, first1, count0, count1, teeth, t_rho, t_gap, t_slope, t_ra, t_rb, consts,
           xq, wq, c_table, orders, force):
    """``(q_ddot, smallest gap, found)`` at the state ``(q, v)`` under the hubs' torques
    ``tq0, tq1``, the pairs' forces written into ``force`` (:meth:`rk4.Model.stage`): the
    strips' half-widths of ``held``, the active set of ``guess_f`` tried first, the mesh damper
    shared by the stage's forces. ``consts``: ``roll_0, roll_1, reach, pitch, r_bA, r_bB, E*,
    L, c_H``."""
    roll_0, roll_1, reach, pitch = consts[0], consts[1], consts[2], consts[3]
    ra, rb, estar, width, c_h = consts[4], consts[5], consts[6], consts[7], consts[8]
    na = inv0.shape[0]
    nb = inv1.shape[0]
    m0 = om0.size
    m1 = om1.size
    nf = modes0.shape[2]
    nt = teeth.size
    acc = _modal_free(tq0, tq1, q, v, inv0, inv1, damp0, damp1, om0, om1)
    theta = q[0]
    force[:] = 0.0
    on = np.empty(nt, np.int64)
    p = 0
    for i in range(nt):
        roll = roll_0 + theta + teeth[i] * pitch
        if roll >= roll_0 - reach and roll <= roll_1 + reach:
            on[p] = i
            p += 1
    if p == 0:
        return acc, math.nan, True
    const = np.empty(p)
    coef0 = np.empty(p)
    coef1 = np.empty(p)
    at0 = np.empty(p, np.int64)
    at1 = np.empty(p, np.int64)
    loads0 = np.empty((p, nf))
    loads1 = np.empty((p, nf))
    guess = 0
    for a in range(p):
        i = on[a]
        rho = roll_0 + theta + teeth[i] * pitch
        g0, slope, r_a, r_b = _table_at(t_rho, t_gap, t_slope, t_ra, t_rb, rho)
        hw = _half_width(held[i], r_a, r_b, geo0[3], geo1[3], estar, width)
        const[a] = g0 - slope * theta
        coef0[a] = slope - ra
        coef1[a] = rb
        k = teeth[i]
        at0[a] = (k - first0) % count0
        at1[a] = (-k - first1) % count1
        _flank_load(geo0, r_a, hw, xq, wq, loads0[a])
        _flank_load(geo1, r_b, hw, xq, wq, loads1[a])
        if guess_f[i] > 0.0:
            guess |= 1 << a
    rows0 = np.empty((p, m0))
    rows1 = np.empty((p, m1))
    for a in range(p):
        rows0[a] = loads0[a] @ modes0[at0[a], 0]
        rows1[a] = loads1[a] @ modes1[at1[a], 0]
    cs = np.zeros((p, p))
    for a in range(p):
        for c in range(p):
            d0 = (at0[a] - at0[c]) % count0
            d1 = (at1[a] - at1[c]) % count1
            cs[a, c] = (loads0[a] @ (flex0[d0, 0, 0] @ loads0[c]) + loads1[a] @ (flex1[d1, 0, 0] @ loads1[c]))
    cs -= (rows0 / om0) @ rows0.T + (rows1 / om1) @ rows1.T
    for a in range(p):
        cs[a, a] += c_h
    gaps = const + coef0 * q[0] + rows0 @ q[1:na] + coef1 * q[na] + rows1 @ q[na + 1:]
    order = orders[p, :1 << p] if p <= ORDERS else _masks_by_size(p)
    lam, found = _lcp_ordered(0.5 * (cs + cs.T), gaps, guess, order)
    if not found:
        return acc, math.nan, False
    # the mesh damper on the hubs, shared by the stage's forces (damper.damper_at)
    n_damp = c_table.size - 1
    x_d = (theta % pitch) / pitch * n_damp
    i_d = min(int(x_d), n_damp - 1)
    f_d = x_d - i_d
    c_mesh = c_table[i_d] * (1.0 - f_d) + c_table[i_d + 1] * f_d
    total = 0.0
    for a in range(p):
        total += lam[a]
    push = lam.copy()
    if c_mesh > 0.0 and total > 0.0:
        for a in range(p):
            push[a] -= c_mesh * lam[a] / total * (coef0[a] * v[0] + coef1[a] * v[na])
    # M^-1 (G^T F - D^T C D v) per gear: on the hub c^T (F - C D v), on the modes E^T F
    gen0 = np.empty(na)
    gen1 = np.empty(nb)
    gen0[0] = coef0 @ push
    gen1[0] = coef1 @ push
    gen0[1:] = rows0.T @ lam
    gen1[1:] = rows1.T @ lam
    acc[:na] += inv0 @ gen0
    acc[na:] += inv1 @ gen1
    out = gaps + cs @ lam
    for a in range(p):
        force[on[a]] = lam[a]
    return acc, out.min(), True


@njit
def run_rk4(first_step, steps, h, q, v, force, held, tq_half,
            inv0, inv1, damp0, damp1, om0, om1, modes0, modes1, flex0, flex1,
            geo0, geo1, first0, first1, count0, count1, teeth, t_rho, t_gap, t_slope, t_ra, t_rb,
            consts, xq, wq, c_table, theta_lo, theta_hi, th_out, om_out, f_out, gap_out):
    """``steps`` RK4 steps from ``first_step`` (the state ``q, v`` and the forces ``force`` at
    its start changed in place, ``held`` the forces whose half-widths the step before held;
    step ``i``'s samples written at ``i``), ``tq_half`` the hubs'
    torques at every half step. Returns ``(last step, 0)``, or the failed step and 1 (not
    finite or no solution of the contact problem), 2 (the driver left ``theta_lo .. theta_hi``)."""
    na = inv0.shape[0]
    orders = np.full((ORDERS + 1, 1 << ORDERS), -1, np.int64)
    for k in range(ORDERS + 1):
        orders[k, :1 << k] = _masks_by_size(k)
    f_tmp = np.empty_like(force)
    args = (inv0, inv1, damp0, damp1, om0, om1, modes0, modes1, flex0, flex1, geo0, geo1, first0, first1,
            count0, count1, teeth, t_rho, t_gap, t_slope, t_ra, t_rb, consts, xq, wq, c_table, orders)
    s = first_step
    a1, gap, ok = _stage(tq_half[2 * s, 0], tq_half[2 * s, 1], q, v, held, held, *args, force)
    if not ok:
        return s, 1
    if first_step == 0:
        th_out[0, 0] = q[0]
        th_out[0, 1] = q[na]
        om_out[0, 0] = v[0]
        om_out[0, 1] = v[na]
        f_out[0] = force
        gap_out[0] = gap
    for step in range(first_step, first_step + steps):
        held[:] = force       # the strips' half-widths over the step: the forces at its start
        v2 = v + 0.5 * h * a1
        a2, _, ok2 = _stage(tq_half[2 * step + 1, 0], tq_half[2 * step + 1, 1], q + 0.5 * h * v, v2,
                            held, held, *args, f_tmp)
        v3 = v + 0.5 * h * a2
        a3, _, ok3 = _stage(tq_half[2 * step + 1, 0], tq_half[2 * step + 1, 1], q + 0.5 * h * v2, v3,
                            held, held, *args, f_tmp)
        v4 = v + h * a3
        a4, _, ok4 = _stage(tq_half[2 * step + 2, 0], tq_half[2 * step + 2, 1], q + h * v3, v4,
                            held, held, *args, f_tmp)
        if not (ok2 and ok3 and ok4):
            return step + 1, 1
        q += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        for j in range(q.size):
            if not (math.isfinite(q[j]) and math.isfinite(v[j])):
                return step + 1, 1
        if q[0] < theta_lo or q[0] > theta_hi:
            return step + 1, 2
        a1, gap, ok = _stage(tq_half[2 * step + 2, 0], tq_half[2 * step + 2, 1], q, v, held, held, *args, force)
        if not ok:
            return step + 1, 1
        th_out[step + 1, 0] = q[0]
        th_out[step + 1, 1] = q[na]
        om_out[step + 1, 0] = v[0]
        om_out[step + 1, 1] = v[na]
        f_out[step + 1] = force
        gap_out[step + 1] = gap
    return first_step + steps, 0


def run_rk4_compiled(model: Any, q: NDArray[np.float64], v: NDArray[np.float64], force: NDArray[np.float64],
                     h: float, n_steps: int, outs: tuple[NDArray[np.float64], ...],
                     progress: Callable[[int, float, float], None] | None) -> tuple[int, int]:
    """:func:`run_rk4` on ``model`` (:class:`~spurdyn.solvers.sector.rk4.Model`, modal bodies
    of whole gears) in chunks of a hundredth of the run; as :func:`rk4._run_numpy`."""
    from spurdyn.contact.hertz import strip_quadrature

    if not all(b.whole for b in model.blocks):
        from spurdyn.errors import InputError

        raise InputError("backend", "the compiled RK4 reference steps whole gears only (3 cycles or more): "
                         "use backend='numpy'")
    from spurdyn.solvers.sector.stepper_compiled import gear_arrays

    (i0, d0, o0, mo0, fx0, g0, fi0, c0), (i1, d1, o1, mo1, fx1, g1, fi1, c1) = gear_arrays(
        model.gears, model.blocks)
    xq, wq = strip_quadrature()
    tq_half = np.ascontiguousarray(model.torques(np.arange(2 * n_steps + 1) * (0.5 * h)))
    consts = np.array([model.roll_0, model.roll_1, model.reach, model.pitch, model.ra, model.rb,
                       model.estar, model.width, model.c_h], dtype=float)
    table = model.table
    teeth = np.asarray(model.teeth, np.int64)
    every = max(n_steps // 100, 1)
    held = force.copy()
    step = 0
    while step < n_steps:
        chunk = min(every, n_steps - step)
        step, failed = run_rk4(step, chunk, h, q, v, force, held, tq_half, i0, i1, d0, d1, o0, o1, mo0, mo1, fx0, fx1,
                               g0, g1, fi0, fi1, c0, c1, teeth, table.rho, table.gap, table.slope, table.r_a,
                               table.r_b, consts, xq, wq, model.c_table, model.theta_lo, model.theta_hi, *outs)
        if failed:
            return step, int(failed)
        if progress is not None:
            progress(step, float(q[0]), n_steps * h * model.speed)
    return step, 0


__all__ = ["run_rk4", "run_rk4_compiled"]
