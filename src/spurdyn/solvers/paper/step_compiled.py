"""The paper's step compiled with Numba, the response to the forces superposed.

The twin of :meth:`spurdyn.solvers.paper.step_numpy.PaperMethod.step` (which
re-integrates every iterate); tests/test_paper_step_twins.py checks the two step by step. The
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
    CP, FAIL_ACC, FAIL_DISP, FAIL_NAN, FAIL_STRIP, FAIL_VEL, OK, ContactFound, ContactRows,
    HistoryRow, IterateStrip, StepEnd, StepWork,
)
from spurdyn.solvers.paper.constants import BAND_MARGIN, MAX_RELOCATE, RELOCATE
from spurdyn.solvers.paper.dynamics_compiled import (
    accelerations, assign, constraint_force, gram, gram_contact, max_abs, root_phi_theta, rotation,
    torque,
)
from spurdyn.solvers.paper.iteration_compiled import accelerated_update, band_value
from spurdyn.solvers.paper.response_compiled import free_rows, predict, response_columns, superpose


@njit
def step(P, S, cfg, strip):
    """Advance the state ``S`` by one step of the paper's method; returns a status code.

    ``cfg`` is a :class:`~spurdyn.solvers.layout.Config`; ``strip`` is ``True`` for the
    distributed contact and ``None`` for the point contact. Numba removes a branch on an
    argument that is None before it compiles, so the point contact's kernel leaves the
    strip's code (:mod:`spurdyn.contact.strip_compiled`) out and compiles in less time;
    each phase below takes ``strip`` for the same reason.
    """
    h = cfg.dt
    m = S.x.size
    n = S.u.size
    pred = predict(P, S, h)
    resp = free_rows(P, S, h, pred)
    # the forces act on the contact rows of the last step until the contact moves
    force = ContactRows(S.cn.copy(), S.cw.copy(), S.normal.copy(), S.gth.copy())
    last = IterateStrip(S.cn.copy(), S.cw.copy(), np.zeros(4), np.zeros(2), np.zeros(2))
    nd = P.fl_nodes.shape[1]
    wk = StepWork(np.empty(m), np.empty(m), np.empty((m, m)), np.empty(m), np.empty((nd, 2)),
                  np.empty((nd, 2)), np.empty((nd, 2)), np.empty((nd, 2)))
    x = S.x.copy()
    status, pair = displacement_stage(P, S, cfg, strip, pred, resp, x, force, last, wk)
    if status != OK:
        return status
    p_bar = x[m - 1]
    # full positions at t + dt by superposition
    th1, u1, _, _ = superpose(P, S, h, pred, x, force.cn, force.cw, force.normal, force.gth,
                              np.bool_(False))
    # the contact rows at t + dt: the last iterate's strip, or its material points
    ns = last.cn.size // 2
    rows1 = ContactRows(np.empty(2 * ns, dtype=np.int64), np.empty(2 * ns),
                        np.array([pair.nx, pair.ny]), last.gth.copy())
    if strip is not None:
        assign(rows1.cn, last.cn)
        assign(rows1.cw, last.cw)
    else:
        contact_rows(P, pair.alpha, pair.beta, rows1.cn, rows1.cw)
    status = velocity_stage(P, S, cfg, strip, pred, resp, x, th1, rows1, pair, last, p_bar, wk)
    if status != OK:
        return status
    _, _, om1, v1 = superpose(P, S, h, pred, x, force.cn, force.cw, force.normal, force.gth,
                              np.bool_(True))
    end = StepEnd(th1, u1, om1, v1)
    al_free = np.empty(2)
    a_free = np.empty(n)
    fth = np.empty(2)
    fu = np.empty(n)
    status = acceleration_stage(P, S, cfg, strip, x, end, rows1, pair, last, p_bar, wk,
                                al_free, a_free, fth, fu)
    if status != OK:
        return status
    return end_of_step(P, S, cfg, strip, x, end, rows1, pair, last, p_bar, al_free, a_free,
                       fth, fu)


@njit
def displacement_stage(P, S, cfg, strip, pred, resp, x, force, last, wk):
    """Stage 1: iterate the forces ``x`` (in place) until the positions at ``t + dt`` meet the
    constraints; returns ``(status, the pair found)``. The force moves with the pair (``force``'s
    rows, ``S.C``); ``last`` and ``wk``'s splines are left as the last iterate's."""
    hertz = strip is not None
    m = S.x.size
    e, e_up = wk.e, wk.e_up
    h2 = 0.5 * cfg.dt * cfg.dt
    c_h = cfg.c_h
    loc_f = np.array([S.cpar[CP.alpha], S.cpar[CP.beta]])
    guess = np.array([S.cpar[CP.alpha], S.cpar[CP.beta]])
    u_try = pred.qs_u.copy()
    th_try = np.empty(2)
    load = abs(x[m - 1]) if hertz else 0.0
    target_p = 0.0
    it = 0
    moves = 0
    while True:
        rel = resp.qs_rel + resp.Wq @ x
        root_position_errors(P, rel, th_try, u_try, e)
        fits, pair = find_contact(P, cfg, strip, th_try, u_try, guess, load, last, wk)
        if not fits:
            S.its[0] = it
            return FAIL_STRIP, pair
        guess[0], guess[1] = pair.alpha, pair.beta
        touching = x[m - 1] < 0.0 or pair.s > 0.0
        # the strip's mean curvature separation c_H |p| is an overlap the force allows
        e[m - 1] = pair.s + c_h * x[m - 1] if touching else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[0] = res
            return FAIL_NAN, pair
        if res <= cfg.tol_disp:
            break
        if it >= cfg.max_iter:
            S.res[0] = res
            S.its[0] = it
            return FAIL_DISP, pair
        if it == 0:
            # A penetration the band accepts is held, one outside brought just inside it:
            # removing an accepted penetration within one step is the 1/dt^2 spike. The
            # root rows aim at zero as before (their kicks do not reach the contact force).
            target_p = band_value(e[m - 1], cfg.tol_disp, BAND_MARGIN)
        for i in range(m - 1):
            e_up[i] = e[i]
        e_up[m - 1] = e[m - 1] - target_p if touching else 0.0
        accelerated_update(x, e_up, S.C, h2, cfg.levels, cfg.eps_root, wk.Cp, wk.work, touching, c_h)
        if abs(pair.alpha - loc_f[0]) + abs(pair.beta - loc_f[1]) > RELOCATE and moves < MAX_RELOCATE:
            moves += 1
            loc_f[0], loc_f[1] = pair.alpha, pair.beta
            move_force(P, S, cfg.dt, strip, pred, resp, pair, th_try, u_try, force, last, wk)
        it += 1
    S.res[0] = res
    S.its[0] = it
    if hertz:
        # the last iterate's pair's roll (its splines are the last search's)
        last.roll[0], last.roll[1], last.gth[0], last.gth[1] = roll_entries(
            P, th_try, u_try, pair.alpha, pair.beta, pair.mode, pair.nx, pair.ny, wk.va, wk.vb,
            wk.Ma, wk.Mb, pair.half_width, last.delta[0:2], last.delta[2:4])
    return OK, pair


@njit
def rows_into(P, rel, disks, nodes):
    """The rows the constraints read (``rel``: the two disks, then each read node's two
    DOFs) written into the full arrays ``disks`` and ``nodes``: positions or velocities."""
    disks[0], disks[1] = rel[0], rel[1]
    for k in range(P.rel_nodes.size):
        i = P.rel_nodes[k]
        nodes[2 * i] = rel[2 + 2 * k]
        nodes[2 * i + 1] = rel[3 + 2 * k]


@njit
def root_position_errors(P, rel, th_try, u_try, e):
    """The iterate's rows the constraints read (``rel``) into ``th_try``, ``u_try``, and the
    root nodes' position errors into ``e``."""
    rows_into(P, rel, th_try, u_try)
    for k in range(P.rnode.size):
        i = P.rnode[k]
        c, s = rotation(P, th_try, P.rgear[k])
        yx, yy = P.Y[2 * i], P.Y[2 * i + 1]
        e[2 * k] = -(u_try[2 * i] - (c * yx - s * yy - yx))
        e[2 * k + 1] = -(u_try[2 * i + 1] - (s * yx + c * yy - yy))


@njit
def find_contact(P, cfg, strip, th_try, u_try, guess, load, last, wk):
    """The contact pair of an iterate, and for the strip its rows into ``last``; returns
    ``(fits, pair)``, ``fits`` False when the strip is wider than its slots. The search
    also refits the flank splines (``wk``'s) that the later stages' sliding terms read."""
    hertz = strip is not None
    ns = last.cn.size // 2
    d_t = last.delta
    a_c, b_c, mode, nxc, nyc, sc = search(P, th_try, u_try, guess, wk.va, wk.vb, wk.Ma, wk.Mb, hertz)
    hw_t = 0.0
    fits = True
    if hertz:
        hw_t = strip_half_width(P, a_c, b_c, load, cfg.estar, cfg.face) if mode == FLANK else 0.0
        if hw_t > 0.0:
            # the gap averaged over the strip (docs/solver.md, section 11)
            d_t[0], d_t[1], fa_ok = strip_rows(P, np.int64(0), a_c, hw_t, last.cn, last.cw, np.int64(0), ns)
            d_t[2], d_t[3], fb_ok = strip_rows(P, np.int64(1), b_c, hw_t, last.cn, last.cw, ns, ns)
            fits = fa_ok and fb_ok
            if fits:
                sc = strip_gap(P, last.cn, last.cw, ns, d_t[0], d_t[1], d_t[2], d_t[3], th_try,
                               u_try, nxc, nyc)
        else:
            contact_rows(P, a_c, b_c, last.cn, last.cw)
            point_offsets(P, a_c, b_c, d_t)
    return fits, ContactFound(a_c, b_c, mode, nxc, nyc, sc, hw_t)


@njit
def move_force(P, S, h, strip, pred, resp, pair, th_try, u_try, force, last, wk):
    """The contact force acts where the contact now is: ``force``'s rows moved to ``pair``,
    with their response columns and ``S.C``'s contact row and column."""
    m = S.x.size
    if strip is not None:
        assign(force.cn, last.cn)
        assign(force.cw, last.cw)
        # the strip's pair rolls with the disks: its row's theta entries (11.3)
        _, _, force.gth[0], force.gth[1] = roll_entries(
            P, th_try, u_try, pair.alpha, pair.beta, pair.mode, pair.nx, pair.ny, wk.va, wk.vb,
            wk.Ma, wk.Mb, pair.half_width, last.delta[0:2], last.delta[2:4])
    else:
        contact_rows(P, pair.alpha, pair.beta, force.cn, force.cw)
    force.normal[0], force.normal[1] = pair.nx, pair.ny
    response_columns(P, h, pred, S.theta, force.cn, force.cw, force.normal, force.gth, m - 1, m,
                     resp.Wq, resp.Wv, resp.sparse)
    gram_contact(P, S.theta, force.cn, force.cw, force.normal, force.gth, S.C)


@njit
def velocity_stage(P, S, cfg, strip, pred, resp, x, th1, rows1, pair, last, p_bar, wk):
    """Stage 2: iterate ``x`` (in place) until the velocities at ``t + dt`` meet the
    constraints (positions from stage 1, same force directions); returns a status."""
    h = cfg.dt
    m = S.x.size
    e = wk.e
    it = 0
    v_try = pred.vs_u.copy()
    om_try = np.empty(2)
    no_al = np.zeros(2)
    while True:
        rel = resp.vs_rel + resp.Wv @ x
        rows_into(P, rel, om_try, v_try)
        for k in range(P.rnode.size):
            i = P.rnode[k]
            g = P.rgear[k]
            px, py = root_phi_theta(P, th1, k)
            e[2 * k] = -(v_try[2 * i] + px * om_try[g])
            e[2 * k + 1] = -(v_try[2 * i + 1] + py * om_try[g])
        dx, dy = contact_motion(P, strip, rows1, pair, last, th1, v_try, np.int64(1), om_try, no_al)
        # the overlap c_H |p| grows with the force: its rate over this step, from the forces
        # this and the last displacement stage held, is the velocity to reach
        # and the strip re-spread at the last step's end moved the gap its rows hold by
        # cpar's jump: the secant of the gap over this step carries it too (section 11.4)
        sh = (pair.nx * dx + pair.ny * dy + last.roll[0] * om_try[0] + last.roll[1] * om_try[1]
              + cfg.c_h * (p_bar - S.cpar[CP.p_held]) / h + S.cpar[CP.jump] / h)
        e[m - 1] = sh if (p_bar < 0.0 and (sh > 0.0 or x[m - 1] < 0.0)) else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[1] = res
            return FAIL_NAN
        # at least one iteration: the displacement stage's constant force leaves a velocity
        # error up to tol/dt that would carry the gap across the band next step
        if res <= cfg.tol_vel and it > 0:
            break
        if it >= cfg.max_iter:
            S.res[1] = res
            S.its[1] = it
            return FAIL_VEL
        accelerated_update(x, e, S.C, h, cfg.levels, cfg.eps_root, wk.Cp, wk.work, e[m - 1] != 0.0, 0.0)
        it += 1
    S.res[1] = res
    S.its[1] = it
    return OK


@njit
def contact_motion(P, strip, rows1, pair, last, th1, vec, kind, om, al):
    """The contact points' velocity (``kind`` 1, ``vec`` the nodal velocities) or
    acceleration (2) at ``t + dt``, A's less B's: the strip-averaged points, or the
    material points; ``om``, ``al`` the disks' speeds and accelerations."""
    ns = rows1.cn.size // 2
    d = last.delta
    if strip is not None and pair.half_width > 0.0:
        pax, pay = virtual_point(P, np.int64(0), rows1.cn, rows1.cw, np.int64(0), ns, d[0], d[1],
                                 th1[0], vec, kind, om[0], al[0])
        pbx, pby = virtual_point(P, np.int64(1), rows1.cn, rows1.cw, ns, ns, d[2], d[3],
                                 th1[1], vec, kind, om[1], al[1])
    else:
        pax, pay = material_point(P, np.int64(0), pair.alpha, th1[0], vec, kind, om[0], al[0])
        pbx, pby = material_point(P, np.int64(1), pair.beta, th1[1], vec, kind, om[1], al[1])
    return pax - pbx, pay - pby


@njit
def acceleration_stage(P, S, cfg, strip, x, end, rows1, pair, last, p_bar, wk, al_free,
                       a_free, fth, fu):
    """Stage 3: iterate ``x`` (in place) until the accelerations at ``t + dt`` meet the
    constraints, ``S.C`` rebuilt there; returns a status. Leaves the free accelerations in
    ``al_free``, ``a_free`` and the last iterate's constraint force in ``fth``, ``fu``."""
    hertz = strip is not None
    m = S.x.size
    n = S.u.size
    e = wk.e
    th1, om1 = end.theta, end.omega
    accelerations(th1, end.u, np.zeros(2), np.zeros(n), P, np.empty(n), np.empty(n), np.empty(n),
                  np.empty(2), al_free, a_free)
    gram(P, th1, rows1.cn, rows1.cw, rows1.normal, rows1.gth, S.C)
    extra = sliding(P, th1, om1, end.u, end.v, pair.alpha, pair.beta, pair.mode, pair.nx, pair.ny,
                    wk.va, wk.vb, wk.Ma, wk.Mb, hertz)
    a_try = np.empty(n)
    al_try = np.empty(2)
    it = 0
    while True:
        constraint_force(P, th1, rows1.cn, rows1.cw, rows1.normal, rows1.gth, x, fth, fu)
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
        for j in range(rows1.cn.size):
            i = rows1.cn[j]
            a_try[2 * i] = a_free[2 * i] + fu[2 * i] / P.mass[2 * i]
            a_try[2 * i + 1] = a_free[2 * i + 1] + fu[2 * i + 1] / P.mass[2 * i + 1]
        dx, dy = contact_motion(P, strip, rows1, pair, last, th1, a_try, np.int64(2), om1, al_try)
        st = pair.nx * dx + pair.ny * dy + extra + last.roll[0] * al_try[0] + last.roll[1] * al_try[1]
        e[m - 1] = st if (p_bar < 0.0 and (st > 0.0 or x[m - 1] < 0.0)) else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[2] = res
            return FAIL_NAN
        # at least one iteration: algebraic, C exact, and the force then does not lag
        if res <= cfg.tol_acc and it > 0:
            break
        if it >= cfg.max_iter:
            S.res[2] = res
            S.its[2] = it
            return FAIL_ACC
        accelerated_update(x, e, S.C, 1.0, cfg.levels, cfg.eps_root, wk.Cp, wk.work, e[m - 1] != 0.0, 0.0)
        it += 1
    S.res[2] = res
    S.its[2] = it
    return OK


@njit
def end_of_step(P, S, cfg, strip, x, end, rows1, pair, last, p_bar, al_free, a_free, fth, fu):
    """The new state into ``S``: the motion at ``t + dt``, the forces ``x`` and the
    accelerations they give, the contact rows the next step starts from (for the strip,
    re-spread over the strip of the force now); returns a status."""
    n = S.u.size
    th1, om1, u1, v1 = end.theta, end.omega, end.u, end.v
    # A NaN may sit in DOFs no residual reads (the constraints see only the root and flank
    # nodes): check the whole state once before keeping it.
    total = th1[0] + th1[1] + om1[0] + om1[1]
    for i in range(n):
        total += u1[i] + v1[i]
    if not math.isfinite(total):
        return FAIL_NAN
    hw1 = 0.0
    jump = 0.0
    if strip is not None:
        fits, hw1, jump = respread(P, cfg, x, end, rows1, pair, last, S.C)
        if not fits:
            return FAIL_STRIP
    constraint_force(P, th1, rows1.cn, rows1.cw, rows1.normal, rows1.gth, x, fth, fu)
    for g in range(2):
        S.alpha_n[g] = al_free[g] + fth[g] / P.J[g]
    for i in range(n):
        S.a_n[i] = a_free[i] + fu[i] / P.mass[i]
    assign(S.theta, th1)
    assign(S.omega, om1)
    assign(S.u, u1)
    assign(S.v, v1)
    assign(S.x, x)
    assign(S.cn, rows1.cn)
    assign(S.cw, rows1.cw)
    assign(S.normal, rows1.normal)
    assign(S.gth, rows1.gth)
    # the gap the constraint holds: for the strip, its mean deformed gap s_bar - c_H |p|
    S.cpar[CP.alpha], S.cpar[CP.beta], S.cpar[CP.mode], S.cpar[CP.s] = (
        pair.alpha, pair.beta, pair.mode, pair.s + cfg.c_h * p_bar)
    if strip is not None:
        S.cpar[CP.p_held] = p_bar
        S.cpar[CP.half_width] = hw1
        S.cpar[CP.jump] = jump
    S.t[0] += cfg.dt
    return OK


@njit
def respread(P, cfg, x, end, rows1, pair, last, C):
    """The strip's rows ``rows1`` re-spread over the strip of the force ``x`` now (the next
    step's), and ``C``'s contact row; returns ``(fits, half-width, jump)``, the jump the
    move of the gap the rows hold (section 11.4)."""
    m = x.size
    ns = rows1.cn.size // 2
    d_t = last.delta
    th1, u1, n1 = end.theta, end.u, rows1.normal
    cn1, cw1 = rows1.cn, rows1.cw
    strip1 = pair.half_width > 0.0
    hw1 = strip_half_width(P, pair.alpha, pair.beta, x[m - 1], cfg.estar, cfg.face) if pair.mode == FLANK else 0.0
    jump = 0.0
    if hw1 > 0.0:
        if strip1:
            # the gap the old rows hold, for the move re-spreading makes (section 11.4)
            jump = -strip_gap(P, cn1, cw1, ns, d_t[0], d_t[1], d_t[2], d_t[3], th1, u1, n1[0], n1[1])
        dax, day, fa_ok = strip_rows(P, np.int64(0), pair.alpha, hw1, cn1, cw1, np.int64(0), ns)
        dbx, dby, fb_ok = strip_rows(P, np.int64(1), pair.beta, hw1, cn1, cw1, ns, ns)
        if not (fa_ok and fb_ok):
            return False, hw1, jump
        if strip1:
            jump += strip_gap(P, cn1, cw1, ns, dax, day, dbx, dby, th1, u1, n1[0], n1[1])
    else:
        contact_rows(P, pair.alpha, pair.beta, cn1, cw1)
    gram_contact(P, th1, cn1, cw1, n1, rows1.gth, C)
    return True, hw1, jump


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
