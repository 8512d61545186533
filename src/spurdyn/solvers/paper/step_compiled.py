"""The paper's step compiled with Numba, the response to the forces superposed.

The twin of :meth:`spurdyn.solvers.paper.step_numpy.PaperMethod.step` (which
re-integrates every iterate); tests/test_paper_step.py checks the two step by step. The
superposition is in :mod:`spurdyn.solvers.paper.response_compiled`, the contact search
in :mod:`spurdyn.contact.search_compiled`. Constant arguments of compiled calls are
written ``np.int64(0)``, ``np.bool_(True)``: a bare literal makes Numba compile a separate
copy of the callee per literal value (docs/performance.md).
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.contact.constants import FLANK
from spurdyn.contact.search_compiled import contact_rows, material_point, search, sliding
from spurdyn.contact.strip_compiled import (
    point_offsets, roll_entries, strip_gap, strip_half_width, strip_rows, virtual_point,
)
from spurdyn.jit import njit
from spurdyn.solvers.layout import (
    CP, FAIL_ACC, FAIL_DISP, FAIL_NAN, FAIL_STRIP, FAIL_VEL, OK, HistoryRow, SparseWork,
)
from spurdyn.solvers.paper.constants import BAND_MARGIN, MAX_RELOCATE, RELOCATE
from spurdyn.solvers.paper.dynamics_compiled import (
    accelerations, assign, constraint_force, gram, gram_contact, max_abs, root_phi_theta, rotation,
    torque,
)
from spurdyn.solvers.paper.iteration_compiled import accelerated_update, band_value
from spurdyn.solvers.paper.response_compiled import response_columns, predict, superpose


@njit
def step(P, S, cfg, strip):
    """Advance the state ``S`` by one step of the paper's method; returns a status code.

    ``cfg`` is a :class:`~spurdyn.solvers.layout.Config`; ``strip`` is ``True`` for the
    distributed contact and ``None`` for the point contact. Numba removes a branch on an
    argument that is None before it compiles, so the point contact's kernel leaves the
    strip's code (:mod:`spurdyn.contact.strip_compiled`) out and compiles in less time.
    """
    h = cfg.dt
    tol1, tol2, tol3 = cfg.tol_disp, cfg.tol_vel, cfg.tol_acc
    cap = cfg.max_iter
    nlev = cfg.levels
    eps_root = cfg.eps_root
    # The distributed contact (cfg.estar > 0): strips of the force at t, compliance c_H.
    hertz = strip is not None
    c_h = cfg.c_h
    no_add = 0.0
    ns = S.cn.size // 2
    n = S.u.size
    m = S.x.size
    nn = n // 2
    th, om, u, v = S.theta, S.omega, S.u, S.v
    x0 = S.x.copy()

    pred = predict(P, S, h)
    zero_u = np.zeros(n)
    w = np.empty(n)
    kw = np.empty(n)
    el = np.empty(n)
    qq = np.empty(2)

    # -- response matrices on the rows the constraints read ----------------------------
    nrel = P.rel_nodes.size
    R = 2 + 2 * nrel
    Wq = np.zeros((R, m))
    Wv = np.zeros((R, m))
    scratch = np.zeros(n)
    mark = np.zeros(nn, dtype=np.int64)
    touched = np.empty(nn, dtype=np.int64)
    nz_nodes = np.empty(nn, dtype=np.int64)
    zu = np.zeros(n)
    acc3 = np.zeros(n)
    acc4 = np.zeros(n)
    h2 = 0.5 * h * h
    sparse = SparseWork(scratch, mark, touched, nz_nodes, zu, acc3, acc4)
    response_columns(P, h, pred, S.theta, S.cn, S.cw, S.normal, S.gth, np.int64(0), m, Wq, Wv, sparse)

    # relevant rows of the free state
    qs_rel = np.empty(R)
    vs_rel = np.empty(R)
    qs_rel[0], qs_rel[1] = pred.qs_th[0], pred.qs_th[1]
    vs_rel[0], vs_rel[1] = pred.vs_th[0], pred.vs_th[1]
    for k in range(nrel):
        i = P.rel_nodes[k]
        for d in range(2):
            qs_rel[2 + 2 * k + d] = pred.qs_u[2 * i + d]
            vs_rel[2 + 2 * k + d] = pred.vs_u[2 * i + d]

    # The forces are G^T x with the contact row where the contact now is; the prediction
    # used the last step's forces, so rel(x) = rel* - W0 x0 + W x.
    qs_rel -= Wq @ x0
    vs_rel -= Wv @ x0
    cn_f = S.cn.copy()
    cw_f = S.cw.copy()
    n_f = S.normal.copy()
    g_f = S.gth.copy()
    loc_f = np.array([S.cpar[CP.alpha], S.cpar[CP.beta]])
    C = S.C
    Cp = np.empty((m, m))
    work = np.empty(m)
    e = np.empty(m)
    e_up = np.empty(m)
    target_p = 0.0
    nd = P.fl_nodes.shape[1]
    va = np.empty((nd, 2))
    vb = np.empty((nd, 2))
    Ma = np.empty((nd, 2))
    Mb = np.empty((nd, 2))
    guess = np.array([S.cpar[CP.alpha], S.cpar[CP.beta]])
    u_try = pred.qs_u.copy()
    th_try = np.empty(2)
    load = abs(x0[m - 1]) if hertz else 0.0
    cn_t = S.cn.copy()          # the rows of the last iterate's strip
    cw_t = S.cw.copy()
    d_t = np.zeros(4)           # and its delta_bar on A, B
    hw_t = 0.0
    roll_t = np.zeros(2)        # its pair's roll with the disks, and its row's disk entries
    g_t = np.zeros(2)

    # -- stage 1: displacements ---------------------------------------------------------
    x = x0.copy()
    a_c, b_c, mode, nxc, nyc, sc = 0.0, 0.0, 0, 0.0, 0.0, 0.0
    it = 0
    moves = 0
    while True:
        rel = qs_rel + Wq @ x
        th_try[0], th_try[1] = rel[0], rel[1]
        for k in range(nrel):
            i = P.rel_nodes[k]
            u_try[2 * i] = rel[2 + 2 * k]
            u_try[2 * i + 1] = rel[3 + 2 * k]
        for k in range(P.rnode.size):
            i = P.rnode[k]
            c, s = rotation(P, th_try, P.rgear[k])
            yx, yy = P.Y[2 * i], P.Y[2 * i + 1]
            e[2 * k] = -(u_try[2 * i] - (c * yx - s * yy - yx))
            e[2 * k + 1] = -(u_try[2 * i + 1] - (s * yx + c * yy - yy))
        # The search also refits the flank splines (va, vb, Ma, Mb) that the later stages'
        # sliding terms read.
        a_c, b_c, mode, nxc, nyc, sc = search(P, th_try, u_try, guess, va, vb, Ma, Mb, hertz)
        if hertz:
            hw_t = strip_half_width(P, a_c, b_c, load, cfg.estar, cfg.face) if mode == FLANK else 0.0
            if hw_t > 0.0:
                # the gap averaged over the strip (docs/solver.md, section 11)
                d_t[0], d_t[1], fa_ok = strip_rows(P, np.int64(0), a_c, hw_t, cn_t, cw_t, np.int64(0), ns)
                d_t[2], d_t[3], fb_ok = strip_rows(P, np.int64(1), b_c, hw_t, cn_t, cw_t, ns, ns)
                if not (fa_ok and fb_ok):
                    S.its[0] = it
                    return FAIL_STRIP
                sc = strip_gap(P, cn_t, cw_t, ns, d_t[0], d_t[1], d_t[2], d_t[3], th_try, u_try, nxc, nyc)
            else:
                contact_rows(P, a_c, b_c, cn_t, cw_t)
                point_offsets(P, a_c, b_c, d_t)
        guess[0], guess[1] = a_c, b_c
        touching = x[m - 1] < 0.0 or sc > 0.0
        # the strip's mean curvature separation c_H |p| is an overlap the force allows
        e[m - 1] = sc + c_h * x[m - 1] if touching else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[0] = res
            return FAIL_NAN
        if res <= tol1:
            break
        if it >= cap:
            S.res[0] = res
            S.its[0] = it
            return FAIL_DISP
        if it == 0:
            # A penetration the band accepts is held, one outside brought just inside it:
            # removing an accepted penetration within one step is the 1/dt^2 spike. The
            # root rows aim at zero as before (their kicks do not reach the contact force).
            target_p = band_value(e[m - 1], tol1, BAND_MARGIN)
        for i in range(m - 1):
            e_up[i] = e[i]
        e_up[m - 1] = e[m - 1] - target_p if touching else 0.0
        accelerated_update(x, e_up, C, h2, nlev, eps_root, Cp, work, touching, c_h)
        if abs(a_c - loc_f[0]) + abs(b_c - loc_f[1]) > RELOCATE and moves < MAX_RELOCATE:
            # the contact force acts where the contact now is
            moves += 1
            loc_f[0], loc_f[1] = a_c, b_c
            if hertz:
                assign(cn_f, cn_t)
                assign(cw_f, cw_t)
                # the strip's pair rolls with the disks: its row's theta entries (11.3)
                _, _, g_f[0], g_f[1] = roll_entries(
                    P, th_try, u_try, a_c, b_c, mode, nxc, nyc, va, vb, Ma, Mb, hw_t, d_t[0:2], d_t[2:4])
            else:
                contact_rows(P, a_c, b_c, cn_f, cw_f)
            n_f[0], n_f[1] = nxc, nyc
            response_columns(P, h, pred, S.theta, cn_f, cw_f, n_f, g_f, m - 1, m, Wq, Wv, sparse)
            gram_contact(P, S.theta, cn_f, cw_f, n_f, g_f, C)
        it += 1
    S.res[0] = res
    S.its[0] = it
    p_bar = x[m - 1]
    if hertz:
        # the last iterate's pair's roll (its splines are the last search's)
        roll_t[0], roll_t[1], g_t[0], g_t[1] = roll_entries(
            P, th_try, u_try, a_c, b_c, mode, nxc, nyc, va, vb, Ma, Mb, hw_t, d_t[0:2], d_t[2:4])

    # full positions at t + dt by superposition
    th1, u1, _, _ = superpose(P, S, h, pred, x, cn_f, cw_f, n_f, g_f, np.bool_(False))
    cn1 = np.empty(2 * ns, dtype=np.int64)
    cw1 = np.empty(2 * ns)
    if hertz:
        assign(cn1, cn_t)
        assign(cw1, cw_t)
    else:
        contact_rows(P, a_c, b_c, cn1, cw1)
    strip1 = hw_t > 0.0          # hw_t stays 0 for the point contact
    n1 = np.array([nxc, nyc])
    g1 = g_t.copy()

    # -- stage 2: velocities (positions from stage 1, same force directions) ---------------
    it = 0
    v_try = pred.vs_u.copy()
    om_try = np.empty(2)
    while True:
        rel = vs_rel + Wv @ x
        om_try[0], om_try[1] = rel[0], rel[1]
        for k in range(nrel):
            i = P.rel_nodes[k]
            v_try[2 * i] = rel[2 + 2 * k]
            v_try[2 * i + 1] = rel[3 + 2 * k]
        for k in range(P.rnode.size):
            i = P.rnode[k]
            g = P.rgear[k]
            px, py = root_phi_theta(P, th1, k)
            e[2 * k] = -(v_try[2 * i] + px * om_try[g])
            e[2 * k + 1] = -(v_try[2 * i + 1] + py * om_try[g])
        if hertz and strip1:
            pax, pay = virtual_point(P, np.int64(0), cn1, cw1, np.int64(0), ns, d_t[0], d_t[1],
                                     th1[0], v_try, np.int64(1), om_try[0], 0.0)
            pbx, pby = virtual_point(P, np.int64(1), cn1, cw1, ns, ns, d_t[2], d_t[3],
                                     th1[1], v_try, np.int64(1), om_try[1], 0.0)
        else:
            pax, pay = material_point(P, np.int64(0), a_c, th1[0], v_try, np.int64(1), om_try[0], 0.0)
            pbx, pby = material_point(P, np.int64(1), b_c, th1[1], v_try, np.int64(1), om_try[1], 0.0)
        # the overlap c_H |p| grows with the force: its rate over this step, from the forces
        # this and the last displacement stage held, is the velocity to reach
        # and the strip re-spread at the last step's end moved the gap its rows hold by
        # cpar's jump: the secant of the gap over this step carries it too (section 11.4)
        sh = (nxc * (pax - pbx) + nyc * (pay - pby) + roll_t[0] * om_try[0] + roll_t[1] * om_try[1]
              + c_h * (p_bar - S.cpar[CP.p_held]) / h + S.cpar[CP.jump] / h)
        e[m - 1] = sh if (p_bar < 0.0 and (sh > 0.0 or x[m - 1] < 0.0)) else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[1] = res
            return FAIL_NAN
        # at least one iteration: the displacement stage's constant force leaves a velocity
        # error up to tol/dt that would carry the gap across the band next step
        if res <= tol2 and it > 0:
            break
        if it >= cap:
            S.res[1] = res
            S.its[1] = it
            return FAIL_VEL
        accelerated_update(x, e, C, h, nlev, eps_root, Cp, work, e[m - 1] != 0.0, no_add)
        it += 1
    S.res[1] = res
    S.its[1] = it

    _, _, om1, v1 = superpose(P, S, h, pred, x, cn_f, cw_f, n_f, g_f, np.bool_(True))

    # -- stage 3: accelerations at t + dt -----------------------------------------------
    zero2 = np.zeros(2)
    al_free = np.empty(2)
    a_free = np.empty(n)
    accelerations(th1, u1, zero2, zero_u, P, w, kw, el, qq, al_free, a_free)
    gram(P, th1, cn1, cw1, n1, g1, C)
    extra = sliding(P, th1, om1, u1, v1, a_c, b_c, mode, nxc, nyc, va, vb, Ma, Mb, hertz)
    fth = np.empty(2)
    fu = np.empty(n)
    a_try = np.empty(n)
    al_try = np.empty(2)
    it = 0
    while True:
        constraint_force(P, th1, cn1, cw1, n1, g1, x, fth, fu)
        for g in range(2):
            al_try[g] = al_free[g] + fth[g] / P.J[g]
        for k in range(P.rnode.size):
            i = P.rnode[k]
            g = P.rgear[k]
            px, py = root_phi_theta(P, th1, k)
            c, s = rotation(P, th1, g)
            yx, yy = P.Y[2 * i], P.Y[2 * i + 1]
            ax = a_free[2 * i] + fu[2 * i] / P.mass[2 * i]
            ay = a_free[2 * i + 1] + fu[2 * i + 1] / P.mass[2 * i + 1]
            e[2 * k] = -(ax + px * al_try[g]) - (c * yx - s * yy) * om1[g] ** 2
            e[2 * k + 1] = -(ay + py * al_try[g]) - (s * yx + c * yy) * om1[g] ** 2
        for j in range(cn1.size):
            i = cn1[j]
            a_try[2 * i] = a_free[2 * i] + fu[2 * i] / P.mass[2 * i]
            a_try[2 * i + 1] = a_free[2 * i + 1] + fu[2 * i + 1] / P.mass[2 * i + 1]
        if hertz and strip1:
            pax, pay = virtual_point(P, np.int64(0), cn1, cw1, np.int64(0), ns, d_t[0], d_t[1],
                                     th1[0], a_try, np.int64(2), om1[0], al_try[0])
            pbx, pby = virtual_point(P, np.int64(1), cn1, cw1, ns, ns, d_t[2], d_t[3],
                                     th1[1], a_try, np.int64(2), om1[1], al_try[1])
        else:
            pax, pay = material_point(P, np.int64(0), a_c, th1[0], a_try, np.int64(2), om1[0], al_try[0])
            pbx, pby = material_point(P, np.int64(1), b_c, th1[1], a_try, np.int64(2), om1[1], al_try[1])
        st = nxc * (pax - pbx) + nyc * (pay - pby) + extra + roll_t[0] * al_try[0] + roll_t[1] * al_try[1]
        e[m - 1] = st if (p_bar < 0.0 and (st > 0.0 or x[m - 1] < 0.0)) else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[2] = res
            return FAIL_NAN
        # at least one iteration: algebraic, C exact, and the force then does not lag
        if res <= tol3 and it > 0:
            break
        if it >= cap:
            S.res[2] = res
            S.its[2] = it
            return FAIL_ACC
        accelerated_update(x, e, C, 1.0, nlev, eps_root, Cp, work, e[m - 1] != 0.0, no_add)
        it += 1
    S.res[2] = res
    S.its[2] = it

    # -- the new state ------------------------------------------------------------------
    # A NaN may sit in DOFs no residual reads (the constraints see only the root and flank
    # nodes): check the whole state once before keeping it.
    total = th1[0] + th1[1] + om1[0] + om1[1]
    for i in range(n):
        total += u1[i] + v1[i]
    if not math.isfinite(total):
        return FAIL_NAN
    hw1 = 0.0
    jump = 0.0
    if hertz:
        # the next step spreads its force over the strip of the force now
        hw1 = strip_half_width(P, a_c, b_c, x[m - 1], cfg.estar, cfg.face) if mode == FLANK else 0.0
        if hw1 > 0.0:
            if strip1:
                # the gap the old rows hold, for the move re-spreading makes (section 11.4)
                jump = -strip_gap(P, cn1, cw1, ns, d_t[0], d_t[1], d_t[2], d_t[3], th1, u1, n1[0], n1[1])
            dax, day, fa_ok = strip_rows(P, np.int64(0), a_c, hw1, cn1, cw1, np.int64(0), ns)
            dbx, dby, fb_ok = strip_rows(P, np.int64(1), b_c, hw1, cn1, cw1, ns, ns)
            if not (fa_ok and fb_ok):
                return FAIL_STRIP
            if strip1:
                jump += strip_gap(P, cn1, cw1, ns, dax, day, dbx, dby, th1, u1, n1[0], n1[1])
        else:
            contact_rows(P, a_c, b_c, cn1, cw1)
        gram_contact(P, th1, cn1, cw1, n1, g1, C)
    constraint_force(P, th1, cn1, cw1, n1, g1, x, fth, fu)
    for g in range(2):
        S.alpha_n[g] = al_free[g] + fth[g] / P.J[g]
    for i in range(n):
        S.a_n[i] = a_free[i] + fu[i] / P.mass[i]
    assign(th, th1)
    assign(om, om1)
    assign(u, u1)
    assign(v, v1)
    assign(S.x, x)
    assign(S.cn, cn1)
    assign(S.cw, cw1)
    assign(S.normal, n1)
    assign(S.gth, g1)
    # the gap the constraint holds: for the strip, its mean deformed gap s_bar - c_H |p|
    S.cpar[CP.alpha], S.cpar[CP.beta], S.cpar[CP.mode], S.cpar[CP.s] = a_c, b_c, mode, sc + c_h * p_bar
    if hertz:
        S.cpar[CP.p_held] = p_bar
        S.cpar[CP.half_width] = hw1
        S.cpar[CP.jump] = jump
    S.t[0] += h
    return OK


@njit(entry=True)
def advance(P, S, cfg, strip, n_steps, angle_end, save_every, rows, frames_every, frames, index0):
    """Up to ``n_steps`` steps; stops when gear A has turned ``angle_end`` or a step fails
    (``strip`` as for :func:`step`).

    Returns ``(steps, rows_written, frames_written, status)``.
    """
    nr = 0
    nf = 0
    for k in range(n_steps):
        if S.theta[0] >= angle_end:
            return k, nr, nf, 0
        status = step(P, S, cfg, strip)
        if status != OK:
            return k, nr, nf, status
        idx = index0 + k + 1
        if idx % save_every == 0:
            write_row(P, S, rows[nr])
            nr += 1
        if frames_every > 0 and idx % frames_every == 0:
            frames[nf, 0] = S.t[0]
            frames[nf, 1] = S.theta[0]
            frames[nf, 2] = S.theta[1]
            assign(frames[nf, 3:], S.u)
            nf += 1
    return n_steps, nr, nf, 0


@njit(entry=True)
def write_row(P, S, row):
    """The history row of the state ``S``: a :class:`~spurdyn.solvers.layout.HistoryRow`
    (every column named, all floats) copied into ``row`` in field order."""
    ta, _ = torque(P.tpar, np.int64(0), S.theta[0])
    tb, _ = torque(P.tpar, np.int64(1), S.theta[1])
    values = HistoryRow(
        t=S.t[0], theta_a=S.theta[0], theta_b=S.theta[1], omega_a=S.omega[0],
        omega_b=S.omega[1], tau_a=ta, tau_b=tb, p=S.x[S.x.size - 1], s=S.cpar[CP.s],
        alpha=S.cpar[CP.alpha], beta=S.cpar[CP.beta], mode=S.cpar[CP.mode], res1=S.res[0],
        res2=S.res[1], res3=S.res[2], it1=float(S.its[0]), it2=float(S.its[1]),
        it3=float(S.its[2]), half_width=S.cpar[CP.half_width])
    for i in range(len(values)):
        row[i] = values[i]
