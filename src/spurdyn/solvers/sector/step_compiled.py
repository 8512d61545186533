"""The sector model's implicit time loop on modal bodies of whole gears, compiled with Numba:
the twin of :func:`spurdyn.solvers.sector.implicit_numpy.implicit_step` (docs/sector.md,
6.3), step for step the same equations (the rows, the couplings, the mesh damper by
Woodbury, the complementarity problem by active sets with the step before's first, the
generalized-alpha update).

It reads typed packs (:mod:`spurdyn.solvers.layout`): per gear a
:data:`~spurdyn.sector.packs.ModalGear` (its body's twin), the contacts
(:data:`~spurdyn.sector.packs.SectorContacts`), the rigid gap's table
(:data:`~spurdyn.sector.packs.GapArrays`) and the run's scalars
(:data:`~spurdyn.sector.packs.SectorConfig`); the rows and the other pieces it shares with
the RK4 reference are those of :mod:`spurdyn.solvers.sector.rows_compiled`. It runs
``steps`` steps from the state it is given (changed in place) and writes the saved columns.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.jit import njit
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_LCP, FAIL_NAN, OK
from spurdyn.solvers.sector.bearings_compiled import trans_back, trans_free, trans_times
from spurdyn.solvers.sector.faces_compiled import face_accelerations, face_record
from spurdyn.solvers.sector.rows_compiled import (
    damper_coefficient,
    hub_column,
    lcp_ordered,
    mask_orders,
    modal_free,
    rows_and_loads,
)


@njit
def _contact_accelerations(x0, q_hat, v_hat, last, rows, hub_cols, elastic_cols, c_mesh, cfg, orders, trans):
    """The step's accelerations with the pairs ``rows`` (of :func:`rows_and_loads`) in
    contact: ``(qdd, F, found)``, ``F`` per row. ``x0`` the accelerations without them
    (changed by the mesh damper), ``last`` the rows' forces of the step before (the damper's
    shares, the active set tried first), ``hub_cols`` per gear ``S^-1`` of a unit hub torque ``z`` and
    ``elastic_cols`` its arrow's ``(u, 1 / d)``, ``c_mesh`` the damper's coefficient,
    ``trans`` the rows' entries on the hubs' translations and their ``S_tt^-1`` (none without
    bearings)."""
    full0, full1, w0, w_gd, k_w, d_x0, w, vv, guess = _pair_blocks(x0, q_hat, v_hat, last, rows, hub_cols,
                                                                   elastic_cols, c_mesh, cfg, trans)
    lam, found = lcp_ordered(0.5 * (w + w.T), vv, guess, orders)
    qdd_new = x0.copy()
    na, nb = full0.shape[0], full1.shape[0]
    qdd_new[:na] += full0 @ lam
    qdd_new[na:na + nb] += full1 @ lam
    kd = k_w @ (d_x0 + w_gd.T @ lam)
    _damper_back(qdd_new, kd, rows, hub_cols)
    trans_back(qdd_new, na + nb, lam - kd, trans)
    return qdd_new, lam, found


@njit
def _damper_back(qdd, kd, rows, hub_cols):
    """``qdd -= S^-1 D^T kd``: the mesh damper's Woodbury part through the hubs."""
    coef0, coef1 = rows[2], rows[3]
    z0, z1 = hub_cols
    na = z0.size
    qdd[:na] -= (coef0 @ kd) * z0
    qdd[na:na + z1.size] -= (coef1 @ kd) * z1


@njit
def _pair_blocks(x0, q_hat, v_hat, last, rows, hub_cols, elastic_cols, c_mesh, cfg, trans):
    """The pairs' blocks of the step's problem (:func:`_contact_accelerations`): per gear
    ``S^-1 G^T``, ``G S^-1 G^T``, ``G S^-1 D^T``, the damper's Woodbury ``K``, ``D x0``, the
    problem's ``W`` and ``v`` and the active set tried first (the step before's, a mask);
    ``last`` the rows' forces of the step before (``held`` of :func:`rows_and_loads`); with
    bearings the translations' block ``T S_tt^-1 T^T`` in the three couplings (``T``, the
    rows' translation entries, is part of both ``G`` and ``D``)."""
    on, const, coef0, coef1, rows0, rows1, res = rows
    z0, z1 = hub_cols
    (u0, dinv0), (u1, dinv1) = elastic_cols
    bp, gp = cfg.bp, cfg.gp
    p = on.size
    na = z0.size
    nb = na + z1.size       # the bodies' coordinates; the translations after them
    tr, tinv = trans
    # couplings (docs/sector.md 6.3): per gear S^-1 G^T = z c^T + S^-1 E^T, the arrow's
    # S^-1 [0; r] = [0; r / d] - (u . r) z
    full0 = np.outer(z0, coef0 - rows0 @ u0)
    full0[1:] += (rows0 * dinv0).T
    full1 = np.outer(z1, coef1 - rows1 @ u1)
    full1[1:] += (rows1 * dinv1).T
    w0 = (np.outer(coef0, full0[0]) + rows0 @ full0[1:]
          + np.outer(coef1, full1[0]) + rows1 @ full1[1:])
    w_gd = (np.outer(coef0 * z0[0] + rows0 @ z0[1:], coef0)
            + np.outer(coef1 * z1[0] + rows1 @ z1[1:], coef1))
    w_dd = z0[0] * np.outer(coef0, coef0) + z1[0] * np.outer(coef1, coef1)
    if tinv.size:
        tt = (tr * tinv) @ tr.T
        w0 += tt
        w_gd += tt
        w_dd += tt
    # the mesh damper, shared by the forces of the step before
    shares = np.empty(p)
    total = 0.0
    guess = 0
    for a in range(p):
        shares[a] = last[a]
        total += shares[a]
        if shares[a] > 0.0:
            guess |= 1 << a
    c_pairs = np.zeros(p)
    damped = False
    if c_mesh > 0.0 and total > 0.0:
        c_pairs = c_mesh * shares / total
        for a in range(p):
            if c_pairs[a] != 0.0:
                damped = True
    if damped:
        rate = c_pairs * (coef0 * v_hat[0] + coef1 * v_hat[na] + trans_times(tr, v_hat[nb:]))
        x0[:na] -= (coef0 @ rate) * z0
        x0[na:nb] -= (coef1 @ rate) * z1
        trans_back(x0, nb, -rate, trans)
    g_x0 = coef0 * x0[0] + rows0 @ x0[1:na] + coef1 * x0[na] + rows1 @ x0[na + 1:nb] + trans_times(tr, x0[nb:])
    d_x0 = coef0 * x0[0] + coef1 * x0[na] + trans_times(tr, x0[nb:])
    if damped:
        gc = gp * c_pairs
        k_w = np.empty((p, p))
        inv_m = np.linalg.inv(np.eye(p) + w_dd * gc.reshape(1, p))
        for a in range(p):
            k_w[a] = gc[a] * inv_m[a]
    else:
        k_w = np.zeros((p, p))
    w = bp * (w0 - w_gd @ k_w @ w_gd.T) + res + cfg.c_h * np.eye(p)
    vv = (const + coef0 * q_hat[0] + rows0 @ q_hat[1:na] + coef1 * q_hat[na] + rows1 @ q_hat[na + 1:nb]
          + trans_times(tr, q_hat[nb:]) + bp * (g_x0 - w_gd @ (k_w @ d_x0)))
    return full0, full1, w0, w_gd, k_w, d_x0, w, vv, guess


@njit
def _save(out, step, q, v, force, lam, faces, rows, r_fc, c_h, na, tr):
    """Step ``step``'s samples into ``out``: turns, speeds, forces, the smallest gap of the
    rows ``rows`` near the path under their forces ``lam`` (none: left as it was; with a
    crack's ``faces`` their residual coupling ``r_fc`` with the pairs; ``tr`` their entries on
    the hubs' translations), on a sampled step ``q``, and with bearings the translations and
    rates."""
    on, const, coef0, coef1, rows0, rows1, res = rows
    nb = na + rows1.shape[1] + 1
    nt = q.size - nb
    if nt:
        out.hubs[step, :nt] = q[nb:]
        out.hubs[step, nt:] = v[nb:]
    out.theta[step, 0] = q[0]
    out.theta[step, 1] = q[na]
    out.omega[step, 0] = v[0]
    out.omega[step, 1] = v[na]
    out.force[step] = force
    if step < out.sample.size and out.sample[step] >= 0:
        out.states[out.sample[step]] = q
    p = on.size
    if p:
        fo = lam
        gaps = (const + coef0 * q[0] + rows0 @ q[1:na] + coef1 * q[na] + rows1 @ q[na + 1:nb]
                + trans_times(tr, q[nb:]) + c_h * fo + res @ fo)
        if faces.size:
            gaps += r_fc.T @ faces
        out.gap[step] = gaps.min()


@njit(entry=True)
def run_steps(first_step, steps, st, gear0, gear1, con, table, cfg, hub, out, fp, bear):
    """``steps`` steps from ``first_step`` of the state ``st`` (a
    :data:`~spurdyn.solvers.layout.SectorStepState`, changed in place), the saved columns
    ``out`` (:data:`~spurdyn.solvers.layout.SectorOut`) written at ``first_step + 1 ...``;
    ``hub`` the hubs' torques at the end of each step, ``fp`` a crack's faces
    (:data:`~spurdyn.sector.packs.FacePack`, empty without), ``bear`` the hubs' bearings
    (:data:`~spurdyn.sector.packs.BearingPack`, no translations without). The state's ``pit``
    holds each contact's pit strip's force where a pit over part of the face width splits it,
    -1 elsewhere (:func:`~spurdyn.solvers.sector.rows_compiled.split_rows`); ``force`` the
    contacts' whole forces, the sums of their rows'.

    Returns the last step done and ``OK``, or the failed step and its status of
    :mod:`spurdyn.solvers.layout`: ``FAIL_NAN`` (not finite), ``FAIL_LCP`` (the pairs'
    problem without a solution), ``FAIL_BEYOND`` (the driver left ``theta_lo .. theta_hi``
    at the step's end)."""
    q, v, acc, qdd, force, faces, pit = st.q, st.v, st.acc, st.qdd, st.force, st.faces, st.pit
    am, af, beta, gamma, h, bp, gp = cfg.am, cfg.af, cfg.beta, cfg.gamma, cfg.h, cfg.bp, cfg.gp
    na = gear0.omega2.size + 1
    n = q.size      # the bodies' coordinates, then the hubs' translations (with bearings)
    hub_cols = (hub_column(gear0), hub_column(gear1))
    elastic_cols = ((gear0.u, gear0.dinv), (gear1.u, gear1.dinv))
    orders = mask_orders()
    cracked = fp.r_ff.shape[0] > 0
    for step in range(first_step + 1, first_step + steps + 1):
        a_part = (af * qdd - am * acc) / (1.0 - am)
        q_hat = q + h * v + h * h * (0.5 - beta) * acc + h * h * beta * a_part
        v_hat = v + h * (1.0 - gamma) * acc + h * gamma * a_part
        x0 = trans_free(modal_free(hub[step, 0], hub[step, 1], q_hat, v_hat, gear0, gear1), q_hat, v_hat, bear)
        theta = q_hat[0]
        last = force.copy()
        force[:] = 0.0
        rows, lo0, lo1, sd, (kind, held) = rows_and_loads(theta, last, pit, gear0, gear1, con, table, cfg)
        pit[:] = -1.0      # read into held; this step's splits are written below
        on = rows[0]
        trans = (bear.rows[sd], bear.tinv)
        lam = np.zeros(on.size)
        r_fc = np.zeros((faces.size, on.size))
        opening = np.zeros(faces.size)
        if cracked:
            c_mesh = damper_coefficient(con.c_table, cfg.pitch, theta) if on.size else 0.0
            pairs = _pair_blocks(x0, q_hat, v_hat, held, rows, hub_cols, elastic_cols, c_mesh, cfg, trans)
            qdd_new, lam, lam_f, found, r_fc, opening = face_accelerations(x0, q_hat, faces, fp, pairs, rows, lo0,
                                                                           lo1, sd, hub_cols, cfg, trans)
            if not found:
                return step, FAIL_LCP
            faces[:] = lam_f
        elif on.size == 0:
            qdd_new = x0
        else:
            c_mesh = damper_coefficient(con.c_table, cfg.pitch, theta)
            qdd_new, lam, found = _contact_accelerations(x0, q_hat, v_hat, held, rows, hub_cols, elastic_cols,
                                                         c_mesh, cfg, orders, trans)
            if not found:
                return step, FAIL_LCP
        for a in range(on.size):    # a split contact's force the sum of its rows'
            force[on[a]] += lam[a]
            if kind[a] == 2 and pit.size:
                pit[on[a]] = lam[a]
        for j in range(n):
            if not math.isfinite(qdd_new[j]):
                return step, FAIL_NAN
        acc[:] = a_part + (1.0 - af) / (1.0 - am) * qdd_new
        q[:] = q_hat + bp * qdd_new
        v[:] = v_hat + gp * qdd_new
        qdd[:] = qdd_new
        if q[0] < cfg.theta_lo or q[0] > cfg.theta_hi:
            return step, FAIL_BEYOND
        _save(out, step, q, v, force, lam, faces, rows, r_fc, cfg.c_h, na, trans[0])
        if cracked:
            face_record(out, step, faces, opening)
    return first_step + steps, OK


__all__ = ["run_steps"]
