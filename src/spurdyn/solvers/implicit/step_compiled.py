"""The implicit step compiled with Numba: the twin of
:meth:`spurdyn.solvers.implicit.step_numpy.ImplicitMethod.step` (docs/implicit.md, section 2).

The same Newton iteration on ``(q_{n+1}, x_{n+1})`` with the contact's semismooth active
set, the force held where the first iterate found the contact pair (relocated as the
paper's step does), the secant on the point contact's row, and the teeth's constant
iteration blocks: here one banded Cholesky factor of both teeth's DOFs (reverse
Cuthill-McKee order), solved by :func:`band_solve`. ``I`` is the
:class:`~spurdyn.solvers.layout.ImplicitPack`, ``P`` the paper's
:class:`~spurdyn.solvers.layout.Packed`. Constant arguments of compiled calls are written
``np.int64(0)`` so that Numba compiles one copy of each callee.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.contact.constants import FLANK
from spurdyn.contact.search_compiled import contact_rows, search
from spurdyn.contact.strip_compiled import point_offsets, roll_entries, strip_gap, strip_half_width, strip_rows
from spurdyn.jit import njit
from spurdyn.solvers.layout import CP, FAIL_NAN, FAIL_NEWTON, FAIL_STRIP, OK
from spurdyn.solvers.paper.constants import MAX_RELOCATE, RELOCATE
from spurdyn.solvers.paper.dynamics_compiled import (
    bsr_matvec, constraint_force, elastic, root_phi_theta, torque,
)


@njit
def band_solve(band, perm, b, out, work):
    """``out = A^-1 b`` for ``A[perm][:, perm] = U^T U``, ``U`` stored by columns:
    ``band[j, bw + i - j] = U[i, j]`` (each column's band contiguous, so both sweeps run
    along memory)."""
    bw = band.shape[1] - 1
    n = b.size
    for j in range(n):                       # U^T z = b[perm]: z_j from the column of U above it
        acc = b[perm[j]]
        lo = max(0, j - bw)
        for i in range(lo, j):
            acc -= band[j, bw + i - j] * work[i]
        work[j] = acc / band[j, bw]
    for j in range(n - 1, -1, -1):           # U y = z, column by column
        y = work[j] / band[j, bw]
        work[j] = y
        lo = max(0, j - bw)
        for i in range(lo, j):
            work[i] -= band[j, bw + i - j] * y
    for k in range(n):
        out[perm[k]] = work[k]


@njit
def solve_u(P, I, theta, b, out, loc, work):
    """``S_u^-1 b``: each node's pair turned into its disk's frame, solved, turned back."""
    c0, s0 = math.cos(P.sense[0] * theta[0]), math.sin(P.sense[0] * theta[0])
    c1, s1 = math.cos(P.sense[1] * theta[1]), math.sin(P.sense[1] * theta[1])
    for i in range(P.node_gear.size):
        c, s = (c0, s0) if P.node_gear[i] == 0 else (c1, s1)
        loc[2 * i] = c * b[2 * i] + s * b[2 * i + 1]
        loc[2 * i + 1] = -s * b[2 * i] + c * b[2 * i + 1]
    band_solve(I.band, I.perm, loc, loc, work)
    for i in range(P.node_gear.size):
        c, s = (c0, s0) if P.node_gear[i] == 0 else (c1, s1)
        lx, ly = loc[2 * i], loc[2 * i + 1]
        out[2 * i] = c * lx - s * ly
        out[2 * i + 1] = s * lx + c * ly


@njit
def theta_block(P, I, touching):
    """The disks' 2 x 2 block of ``S`` and its inverse."""
    s = np.zeros((2, 2))
    s[0, 0] = I.mq[0] / I.bp
    s[1, 1] = I.mq[1] / I.bp
    if touching and I.c_mesh > 0.0:
        k = (I.gp / I.bp) * I.c_mesh
        for a in range(2):
            for b in range(2):
                s[a, b] += k * I.base[a] * I.base[b]
    det = s[0, 0] * s[1, 1] - s[0, 1] * s[1, 0]
    inv = np.empty((2, 2))
    inv[0, 0], inv[1, 1] = s[1, 1] / det, s[0, 0] / det
    inv[0, 1], inv[1, 0] = -s[0, 1] / det, -s[1, 0] / det
    return inv


@njit
def root_columns(P, I, theta, touching, z):
    """``S^-1 G_root^T`` into ``z[:, :2 n_root]`` (rows ``[theta_A, theta_B, u]``)."""
    inv = theta_block(P, I, touching)
    nr = P.rnode.size
    n_u = P.mass.size
    for col in range(2 * nr):
        for r in range(z.shape[0]):
            z[r, col] = 0.0
    for k in range(nr):
        g = P.rgear[k]
        px, py = root_phi_theta(P, theta, k)
        c, s = math.cos(P.sense[g] * theta[g]), math.sin(P.sense[g] * theta[g])
        for d in range(2):
            col = 2 * k + d
            pt = -(px if d == 0 else py)          # G[col, g]
            z[0, col] = inv[0, g] * pt
            z[1, col] = inv[1, g] * pt
            # A^-1 R^T e_(k,d) = sum_e root_inv[:, 2k + e] R[d, e], turned by R, times -1
            r0 = c if d == 0 else s
            r1 = -s if d == 0 else c
            for i in range(n_u // 2):
                if P.node_gear[i] != g:
                    continue
                vx = I.root_inv[2 * i, 2 * k] * r0 + I.root_inv[2 * i, 2 * k + 1] * r1
                vy = I.root_inv[2 * i + 1, 2 * k] * r0 + I.root_inv[2 * i + 1, 2 * k + 1] * r1
                z[2 + 2 * i, col] = -(c * vx - s * vy)
                z[3 + 2 * i, col] = -(s * vx + c * vy)


@njit
def g_times(P, theta, cn, cw, normal, gth, row, vec):
    """Row ``row`` of ``G`` times ``vec`` (stacked like ``q``): a root row or the contact row
    (its disk entries ``gth``)."""
    nr = P.rnode.size
    if row < 2 * nr:
        k, d = row // 2, row % 2
        px, py = root_phi_theta(P, theta, k)
        return -(px if d == 0 else py) * vec[P.rgear[k]] - vec[2 + 2 * P.rnode[k] + d]
    half = cn.size // 2
    acc = gth[0] * vec[0] + gth[1] * vec[1]
    for j in range(cn.size):
        sign = 1.0 if j < half else -1.0
        i = cn[j]
        acc += sign * cw[j] * (normal[0] * vec[2 + 2 * i] + normal[1] * vec[3 + 2 * i])
    return acc


@njit
def forces(P, I, theta, omega, u, v, touching, out, w, kw, el, q, wd, cwd):
    """``F(q, qdot)``: torques, elastic forces, Rayleigh's and the mesh damper's."""
    elastic(theta, u, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep, w, kw, el, q)
    for g in range(2):
        tau, _ = torque(P.tpar, g, theta[g])
        out[g] = tau + q[g]
    for i in range(el.size):
        out[2 + i] = el[i]
    if I.ray_a > 0.0 or I.ray_b > 0.0:
        cs = np.empty((2, 2))
        for g in range(2):
            cs[g, 0] = math.cos(P.sense[g] * theta[g])
            cs[g, 1] = math.sin(P.sense[g] * theta[g])
        nn = P.node_gear.size
        for i in range(nn):          # w_dot = R^T u_dot - s theta_dot Jz (w + Y)
            g = P.node_gear[i]
            c, s = cs[g, 0], cs[g, 1]
            wx, wy = w[2 * i] + P.Y[2 * i], w[2 * i + 1] + P.Y[2 * i + 1]
            wd[2 * i] = c * v[2 * i] + s * v[2 * i + 1] + P.sense[g] * omega[g] * wy
            wd[2 * i + 1] = -s * v[2 * i] + c * v[2 * i + 1] - P.sense[g] * omega[g] * wx
        bsr_matvec(P.indptr, P.indices, P.data, wd, cwd)
        for i in range(nn):
            g = P.node_gear[i]
            c, s = cs[g, 0], cs[g, 1]
            dx = I.ray_a * P.mass[2 * i] * wd[2 * i] + I.ray_b * cwd[2 * i]
            dy = I.ray_a * P.mass[2 * i + 1] * wd[2 * i + 1] + I.ray_b * cwd[2 * i + 1]
            out[2 + 2 * i] -= c * dx - s * dy
            out[3 + 2 * i] -= s * dx + c * dy
            wx, wy = w[2 * i] + P.Y[2 * i], w[2 * i + 1] + P.Y[2 * i + 1]
            out[g] += P.sense[g] * (wx * dy - wy * dx)
    if touching and I.c_mesh > 0.0:
        rate = I.base[0] * omega[0] + I.base[1] * omega[1]
        out[0] -= I.c_mesh * rate * I.base[0]
        out[1] -= I.c_mesh * rate * I.base[1]


@njit
def contact(P, I, strip, theta, u, guess, load, cn, cw, d, buf):
    """The contact pair at ``(theta, u)``: ``(alpha, beta, mode, nx, ny, s, half_width, ok)``
    with its rows written into ``cn``, ``cw`` and their offsets ``delta`` into ``d`` (the
    strip of ``load`` for the distributed contact, ``strip`` True; None for the point
    contact, whose kernel Numba then compiles without the strip's code)."""
    ns = I.ns
    hertz = strip is not None
    a, b, mode, nx, ny, s = search(P, theta, u, guess, buf[0], buf[1], buf[2], buf[3], hertz)
    hw = 0.0
    if hertz:
        if mode == FLANK:
            hw = strip_half_width(P, a, b, load, I.estar, I.face)
        if hw > 0.0:
            dax, day, ok_a = strip_rows(P, np.int64(0), a, hw, cn, cw, np.int64(0), ns)
            dbx, dby, ok_b = strip_rows(P, np.int64(1), b, hw, cn, cw, ns, ns)
            if not (ok_a and ok_b):
                return a, b, mode, nx, ny, s, hw, False
            s = strip_gap(P, cn, cw, ns, dax, day, dbx, dby, theta, u, nx, ny)
            d[0], d[1], d[2], d[3] = dax, day, dbx, dby
            return a, b, mode, nx, ny, s, hw, True
    contact_rows(P, a, b, cn, cw)
    point_offsets(P, a, b, d)
    return a, b, mode, nx, ny, s, hw, True


@njit(entry=True)
def step(P, I, strip, theta, omega, u, v, x, qdd, acc, cpar, cn, cw, normal, res):
    """One implicit step in place (state at ``t`` in, at ``t + h`` out); returns the status.

    ``cpar`` (columns :data:`~spurdyn.solvers.layout.CP`) holds the contact pair; ``cn``,
    ``cw``, ``normal`` its rows; ``res[0]``, ``res[1]`` receive the Newton iteration's last
    residual (m) and its iterations. ``strip`` is True for the distributed contact and None for
    the point contact (Numba leaves the strip's branches out of the point contact's kernel).
    """
    hertz = strip is not None
    n_u = u.size
    n_q = 2 + n_u
    nr2 = 2 * P.rnode.size
    nx_ = nr2 + 1
    h, am, af, beta, gamma, bp, gp = I.h, I.am, I.af, I.beta, I.gamma, I.bp, I.gp
    # the predictor: the accelerations of the step before
    q = np.empty(n_q)
    qd = np.empty(n_q)
    q[0], q[1] = theta[0], theta[1]
    qd[0], qd[1] = omega[0], omega[1]
    q[2:] = u
    qd[2:] = v
    qdd1 = qdd.copy()
    a1 = ((1.0 - af) * qdd1 + af * qdd - am * acc) / (1.0 - am)
    q += h * qd + h * h * ((0.5 - beta) * acc + beta * a1)
    qd += h * ((1.0 - gamma) * acc + gamma * a1)
    xs = x.copy()
    load = abs(x[nx_ - 1]) if hertz else 0.0
    guess = np.array([cpar[CP.alpha], cpar[CP.beta]])
    radius = 0.0
    for i in range(P.Y.size):
        radius = max(radius, abs(P.Y[i]))
    # work arrays
    buf = np.empty((4, P.fl_nodes.shape[1], 2))
    cn_c, cw_c = cn.copy(), cw.copy()          # the rows of this iterate's pair
    cn_f, cw_f = cn.copy(), cw.copy()          # where the force acts
    nrm_f = normal.copy()
    d_c = np.zeros(4)                          # this iterate's offsets delta on A, B
    g_f = np.zeros(2)                          # the force's row's disk entries (11.3)
    a_f, b_f = 0.0, 0.0
    w, kw, el, wd, cwd = (np.empty(n_u), np.empty(n_u), np.empty(n_u), np.empty(n_u),
                          np.empty(n_u))
    qel = np.empty(2)
    f = np.empty(n_q)
    r = np.empty(n_q)
    s_r = np.empty(n_q)
    loc = np.empty(n_u)
    work = np.empty(n_u)
    z = np.empty((n_q, nx_))
    gtx_th, gtx_u = np.empty(2), np.empty(n_u)
    e = np.empty(nx_)
    col = np.zeros(n_q)
    zc = np.empty(n_q)
    was = -1
    z_touch = False
    residual = math.inf
    phi, predicted, gap_before = 1.0, math.nan, 0.0
    moves = 0
    a_c, b_c, mode, nxc, nyc, sc, hw = 0.0, 0.0, 0, 0.0, 0.0, 0.0, 0.0
    it = 0
    while True:
        th = q[:2]
        uu = q[2:]
        a_c, b_c, mode, nxc, nyc, sc, hw, ok = contact(P, I, strip, th, uu, guess, load, cn_c, cw_c,
                                                       d_c, buf)
        if not ok:
            res[1] = it
            return FAIL_STRIP
        guess[0], guess[1] = a_c, b_c
        if it == 0 or (abs(a_c - a_f) + abs(b_c - b_f) > RELOCATE and moves < MAX_RELOCATE):
            if it > 0:
                moves += 1
            a_f, b_f = a_c, b_c
            cn_f[:] = cn_c
            cw_f[:] = cw_c
            nrm_f[0], nrm_f[1] = nxc, nyc
            if hertz:
                # the strip's pair rolls with the disks: its row's theta entries (solver.md
                # 11.3), from the rigid flanks' splines the search just left in buf
                _, _, g_f[0], g_f[1] = roll_entries(P, th, uu, a_c, b_c, mode, nxc, nyc, buf[0], buf[1],
                                                    buf[2], buf[3], hw, d_c[0:2], d_c[2:4])
        gap = sc + I.c_h * xs[nx_ - 1]
        was_touching = xs[nx_ - 1] < 0.0
        if it == 0 or was_touching != z_touch:
            root_columns(P, I, th, was_touching, z)
            z_touch = was_touching
        # the contact column: S^-1 G_c^T (its disk entries g_f through the disks' block)
        inv = theta_block(P, I, was_touching)
        col[:] = 0.0
        half = cn_f.size // 2
        for j in range(cn_f.size):
            sign = 1.0 if j < half else -1.0
            i = cn_f[j]
            col[2 + 2 * i] += sign * cw_f[j] * nrm_f[0]
            col[3 + 2 * i] += sign * cw_f[j] * nrm_f[1]
        zc[0] = inv[0, 0] * g_f[0] + inv[0, 1] * g_f[1]
        zc[1] = inv[1, 0] * g_f[0] + inv[1, 1] * g_f[1]
        solve_u(P, I, th, col[2:], zc[2:], loc, work)
        for rr in range(n_q):
            z[rr, nx_ - 1] = zc[rr]
        kappa = 1.0 / (g_times(P, th, cn_f, cw_f, nrm_f, g_f, nx_ - 1, zc) + I.c_h)
        touching = xs[nx_ - 1] - kappa * gap < 0.0
        forces(P, I, th, qd[:2], uu, qd[2:], touching, f, w, kw, el, qel, wd, cwd)
        constraint_force(P, th, cn_f, cw_f, nrm_f, g_f, xs, gtx_th, gtx_u)
        r[0] = I.mq[0] * qdd1[0] - f[0] - gtx_th[0]
        r[1] = I.mq[1] * qdd1[1] - f[1] - gtx_th[1]
        for i in range(n_u):
            r[2 + i] = I.mq[2 + i] * qdd1[2 + i] - f[2 + i] - gtx_u[i]
        # minus the constraints c = [-Phi; gap]
        for k in range(P.rnode.size):
            g = P.rgear[k]
            i = P.rnode[k]
            c, s = math.cos(P.sense[g] * th[g]), math.sin(P.sense[g] * th[g])
            yx, yy = P.Y[2 * i], P.Y[2 * i + 1]
            e[2 * k] = uu[2 * i] - (c * yx - s * yy - yx)
            e[2 * k + 1] = uu[2 * i + 1] - (s * yx + c * yy - yy)
        e[nx_ - 1] = -gap
        rows = nx_ if touching else nr2
        if not touching:                          # the force goes to zero
            r[0] += g_f[0] * xs[nx_ - 1]
            r[1] += g_f[1] * xs[nx_ - 1]
            for j in range(cn_f.size):
                sign = 1.0 if j < half else -1.0
                i = cn_f[j]
                r[2 + 2 * i] += sign * cw_f[j] * nrm_f[0] * xs[nx_ - 1]
                r[3 + 2 * i] += sign * cw_f[j] * nrm_f[1] * xs[nx_ - 1]
        s_r[0] = inv[0, 0] * r[0] + inv[0, 1] * r[1]
        s_r[1] = inv[1, 0] * r[0] + inv[1, 1] * r[1]
        solve_u(P, I, th, r[2:], s_r[2:], loc, work)
        res_u = 0.0
        for i in range(n_u):
            res_u = max(res_u, abs(s_r[2 + i]))
        residual = max(res_u, max(abs(s_r[0]), abs(s_r[1])) * radius)
        for k in range(rows):
            residual = max(residual, abs(e[k]))
        if not touching:
            residual = max(residual, abs(xs[nx_ - 1]) / kappa)
        if residual != residual:
            res[1] = it
            res[0] = residual
            return FAIL_NAN
        if residual <= I.tol and (1 if touching else 0) == was:
            break
        if it == I.max_iter:
            res[1] = it
            res[0] = residual
            return FAIL_NEWTON
        if touching and was == 1 and predicted == predicted and abs(predicted) > 1e-18:
            phi = min(max((gap - gap_before) / predicted, 0.1), 10.0)
        was = 1 if touching else 0
        # the Schur complement (G S^-1 G^T + D) dx = e + G S^-1 r, the contact row scaled by phi
        cmat = np.empty((rows, rows))
        rhs = np.empty(rows)
        for a in range(rows):
            scale = phi if (touching and a == nx_ - 1) else 1.0
            for b in range(rows):
                cmat[a, b] = scale * g_times(P, th, cn_f, cw_f, nrm_f, g_f, a, z[:, b])
            rhs[a] = e[a] + scale * g_times(P, th, cn_f, cw_f, nrm_f, g_f, a, s_r)
        if touching:
            cmat[rows - 1, rows - 1] += I.c_h
        if not (np.isfinite(cmat).all() and np.isfinite(rhs).all()):
            res[1] = it
            res[0] = math.nan
            return FAIL_NAN
        dx = np.linalg.solve(cmat, rhs)
        dq = -s_r
        for b in range(rows):
            dq += z[:, b] * dx[b]
        for b in range(rows):
            xs[b] += dx[b]
        if touching:
            predicted = g_times(P, th, cn_f, cw_f, nrm_f, g_f, nx_ - 1, dq) + I.c_h * dx[rows - 1]
        else:
            xs[nx_ - 1] = 0.0
            predicted = math.nan
        gap_before = gap
        q += dq
        qdd1 += dq / bp
        qd += dq * (gp / bp)
        it += 1
    res[0] = residual
    res[1] = it
    acc[:] = ((1.0 - af) * qdd1 + af * qdd - am * acc) / (1.0 - am)
    qdd[:] = qdd1
    theta[0], theta[1] = q[0], q[1]
    omega[0], omega[1] = qd[0], qd[1]
    u[:] = q[2:]
    v[:] = qd[2:]
    x[:] = xs
    if hertz:
        # the next step's strip is the one of the force now; the gap kept is the one the
        # constraint holds, the strip's mean deformed gap s_bar - c_H |p|
        a_c, b_c, mode, nxc, nyc, sc, hw, ok = contact(P, I, strip, theta, u, guess,
                                                       abs(x[nx_ - 1]), cn_c, cw_c, d_c, buf)
        if not ok:
            return FAIL_STRIP
        sc += I.c_h * x[nx_ - 1]
    cn[:] = cn_c
    cw[:] = cw_c
    normal[0], normal[1] = nxc, nyc
    cpar[CP.alpha], cpar[CP.beta], cpar[CP.mode], cpar[CP.s] = a_c, b_c, float(mode), sc
    cpar[CP.half_width] = hw
    return OK
