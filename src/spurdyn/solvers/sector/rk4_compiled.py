"""The sector model's RK4 reference on modal bodies of whole gears, compiled with Numba: the
twin of the NumPy loop of :mod:`spurdyn.solvers.sector.rk4`, stage for stage the same
equations. Its pieces are the implicit compiled loop's
(:mod:`spurdyn.solvers.sector.rows_compiled`: the gap table, the contact rows with the
strip's unit load and Hertz's half-width, the residual compliance, the mesh damper, the
complementarity problem by active sets) and its packs the same
(:mod:`spurdyn.solvers.layout`; per gear ``M^-1`` in place of ``S^-1``).
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.jit import njit
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_LCP, FAIL_NAN, OK
from spurdyn.solvers.sector.rows_compiled import (
    arrow,
    contact_rows,
    damper_coefficient,
    lcp_ordered,
    mask_orders,
    modal_free,
)


@njit
def stage(tq0, tq1, q, v, held, gear0, gear1, con, table, cfg, orders, force):
    """``(q_ddot, smallest gap, found)`` at the state ``(q, v)`` under the hubs' torques
    ``tq0, tq1``, the pairs' forces written into ``force`` (twin of ``rk4.Rk4Model.stage``):
    the strips' half-widths of ``held``, whose active set is tried first, the mesh damper
    shared by the stage's forces."""
    na = gear0.omega2.size + 1
    nb = gear1.omega2.size + 1
    acc = modal_free(tq0, tq1, q, v, gear0, gear1)
    theta = q[0]
    force[:] = 0.0
    on, const, coef0, coef1, rows0, rows1, cs = contact_rows(theta, held, gear0, gear1, con, table, cfg)
    p = on.size
    if p == 0:
        return acc, math.nan, True
    guess = 0
    for a in range(p):
        if held[on[a]] > 0.0:
            guess |= 1 << a
    for a in range(p):
        cs[a, a] += cfg.c_h
    gaps = const + coef0 * q[0] + rows0 @ q[1:na] + coef1 * q[na] + rows1 @ q[na + 1:]
    lam, found = lcp_ordered(0.5 * (cs + cs.T), gaps, guess, orders)
    if not found:
        return acc, math.nan, False
    # the mesh damper on the hubs, shared by the stage's forces
    c_mesh = damper_coefficient(con.c_table, cfg.pitch, theta)
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
    acc[:na] += arrow(gear0, gen0)
    acc[na:] += arrow(gear1, gen1)
    out = gaps + cs @ lam
    for a in range(p):
        force[on[a]] = lam[a]
    return acc, out.min(), True


@njit
def _write(out, i, q, v, force, gap, na):
    """Step ``i``'s samples into the saved columns ``out`` (on a sampled step ``q`` too)."""
    if i < out.sample.size and out.sample[i] >= 0:
        out.states[out.sample[i]] = q
    out.theta[i, 0] = q[0]
    out.theta[i, 1] = q[na]
    out.omega[i, 0] = v[0]
    out.omega[i, 1] = v[na]
    out.force[i] = force
    out.gap[i] = gap


@njit(entry=True)
def run_rk4(first_step, steps, st, gear0, gear1, con, table, cfg, tq_half, out):
    """``steps`` RK4 steps from ``first_step`` of the state ``st`` (a
    :data:`~spurdyn.solvers.layout.SectorRk4State`: ``q, v`` and the forces at the step's
    start changed in place, ``held`` the forces whose half-widths the step before held);
    step ``i``'s samples written at ``i`` in ``out``; ``tq_half`` the hubs' torques at every
    half step. Returns ``(last step, OK)``, or the failed step and ``FAIL_NAN``,
    ``FAIL_LCP`` or ``FAIL_BEYOND`` (the driver left ``theta_lo .. theta_hi``)."""
    q, v, force, held = st.q, st.v, st.force, st.held
    h = cfg.h
    na = gear0.omega2.size + 1
    orders = mask_orders()
    f_tmp = np.empty_like(force)
    s = first_step
    a1, gap, ok = stage(tq_half[2 * s, 0], tq_half[2 * s, 1], q, v, held, gear0, gear1, con, table, cfg,
                        orders, force)
    if not ok:
        return s, FAIL_LCP
    if first_step == 0:
        _write(out, 0, q, v, force, gap, na)
    for step in range(first_step, first_step + steps):
        held[:] = force       # the strips' half-widths over the step: the forces at its start
        v2 = v + 0.5 * h * a1
        a2, _, ok2 = stage(tq_half[2 * step + 1, 0], tq_half[2 * step + 1, 1], q + 0.5 * h * v, v2,
                           held, gear0, gear1, con, table, cfg, orders, f_tmp)
        v3 = v + 0.5 * h * a2
        a3, _, ok3 = stage(tq_half[2 * step + 1, 0], tq_half[2 * step + 1, 1], q + 0.5 * h * v2, v3,
                           held, gear0, gear1, con, table, cfg, orders, f_tmp)
        v4 = v + h * a3
        a4, _, ok4 = stage(tq_half[2 * step + 2, 0], tq_half[2 * step + 2, 1], q + h * v3, v4,
                           held, gear0, gear1, con, table, cfg, orders, f_tmp)
        if not (ok2 and ok3 and ok4):
            return step + 1, FAIL_LCP
        q += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        for j in range(q.size):
            if not (math.isfinite(q[j]) and math.isfinite(v[j])):
                return step + 1, FAIL_NAN
        if q[0] < cfg.theta_lo or q[0] > cfg.theta_hi:
            return step + 1, FAIL_BEYOND
        a1, gap, ok = stage(tq_half[2 * step + 2, 0], tq_half[2 * step + 2, 1], q, v, held, gear0, gear1, con,
                            table, cfg, orders, force)
        if not ok:
            return step + 1, FAIL_LCP
        _write(out, step + 1, q, v, force, gap, na)
    return first_step + steps, OK


__all__ = ["run_rk4", "stage"]
