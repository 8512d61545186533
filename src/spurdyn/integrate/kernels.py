"""Compiled kernels of the fast stepper (Numba): arrays and scalars in, arrays out.

Each kernel has a NumPy counterpart in :mod:`spurdyn.solver.reference` or
:mod:`spurdyn.contact.reference` (or, where the reference has none, the formula of
docs/solver.md written in NumPy) and is tested against it: tests/test_kernels.py, and
the splines and the contact search in tests/test_contact.py.

Conventions: ``u``-vectors stack both teeth (A's nodes first, node ``n`` owns DOFs
``2n``, ``2n+1``); ``theta``, ``omega`` are ``(2,)``; ``x = [lambda_A, lambda_B, p]``.
Model arrays are described in :class:`spurdyn.integrate.fast.Packed`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

FLANK, CORNER_A, CORNER_B = 0, 1, 2

# Indices into the per-gear flank parameter rows ``fpar[g]``.
F_T0, F_T1, F_R0, F_RTIP, F_RB, F_PSI, F_REF, F_NY, F_H, F_RA, F_RS, F_RK, F_RT = range(13)

# The contact search's safeguard (the values of spurdyn.contact.reference, repeated here
# because a compiled kernel freezes its globals and its disk cache tracks this file only).
GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)
GOLDEN_TOL = 1e-10
EDGE = 1e-9
POLISH = 1e-4


# -- small helpers --------------------------------------------------------------------------

@njit(cache=True)
def cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit(cache=True)
def bsr_matvec(indptr, indices, data, v, out):
    """``out = K v`` for ``K`` in 2 x 2 block rows (one per node): ``data (nb, 2, 2)``."""
    n = indptr.size - 1
    for i in range(n):
        a0 = 0.0
        a1 = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            v0 = v[2 * j]
            v1 = v[2 * j + 1]
            a0 += data[k, 0, 0] * v0 + data[k, 0, 1] * v1
            a1 += data[k, 1, 0] * v0 + data[k, 1, 1] * v1
        out[2 * i] = a0
        out[2 * i + 1] = a1


@njit(cache=True)
def torque(tpar, g, th):
    """Torque on gear ``g`` at its rotation ``th`` (Fig. 7), and its slope d tau / d theta."""
    amp, ts, t2 = tpar[g, 0], tpar[g, 1], tpar[g, 2]
    a = th / t2
    b = (ts - th) / t2
    f = min(a, b)
    if f <= 0.0:
        return 0.0, 0.0
    if f >= 1.0:
        return amp, 0.0
    if a <= b:
        return amp * f, amp / t2
    return amp * f, -amp / t2


# -- equations of motion ------------------------------------------------------------------

@njit(cache=True)
def elastic(theta, u, Y, node_gear, sense, indptr, indices, data, keep, w, kw, f_u, q):
    """Elastic forces ``f_u = -R K w`` and disk torques ``q = sense sum w x Kw``.

    ``w``, ``kw`` are work arrays (n_u,) left holding ``w`` and ``K w``.
    """
    nn = node_gear.size
    c = np.empty(2)
    s = np.empty(2)
    for g in range(2):
        c[g] = math.cos(sense[g] * theta[g])
        s[g] = math.sin(sense[g] * theta[g])
    for i in range(nn):
        g = node_gear[i]
        yx = Y[2 * i] + u[2 * i]
        yy = Y[2 * i + 1] + u[2 * i + 1]
        # R^T y - Y
        w[2 * i] = c[g] * yx + s[g] * yy - Y[2 * i]
        w[2 * i + 1] = -s[g] * yx + c[g] * yy - Y[2 * i + 1]
    bsr_matvec(indptr, indices, data, w, kw)
    q[0] = 0.0
    q[1] = 0.0
    for i in range(nn):
        g = node_gear[i]
        kx, ky = kw[2 * i], kw[2 * i + 1]
        f_u[2 * i] = -(c[g] * kx - s[g] * ky)
        f_u[2 * i + 1] = -(s[g] * kx + c[g] * ky)
        if keep:
            q[g] += w[2 * i] * ky - w[2 * i + 1] * kx
    q[0] *= sense[0]
    q[1] *= sense[1]


@njit(cache=True)
def accelerations(theta, u, f_th, f_u, P, w, kw, el, q, alpha, a):
    """``alpha = (tau + Q + f_theta) / J``, ``a = (f_el + f_u) / m``."""
    elastic(theta, u, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep, w, kw, el, q)
    for g in range(2):
        tau, _ = torque(P.tpar, g, theta[g])
        alpha[g] = (tau + q[g] + f_th[g]) / P.J[g]
    for i in range(a.size):
        a[i] = (el[i] + f_u[i]) / P.mass[i]


# -- constraint forces ----------------------------------------------------------------------

@njit(cache=True)
def root_phi_theta(P, theta, k):
    """``dPhi_k/dtheta`` of root node ``k``: ``-sense R Jz Y``."""
    g = P.rgear[k]
    i = P.rnode[k]
    sg = P.sense[g]
    c, s = math.cos(sg * theta[g]), math.sin(sg * theta[g])
    jx, jy = -P.Y[2 * i + 1], P.Y[2 * i]
    return -sg * (c * jx - s * jy), -sg * (s * jx + c * jy)


@njit(cache=True)
def constraint_force(P, theta, cn, cw, normal, x, f_th, f_u):
    """``G^T x``: root forces ``-lambda`` on the root nodes and their torques on the disks,
    and the contact force ``p n`` through the edge weights ``cw`` of nodes ``cn`` (A's 3, then B's 3)."""
    f_th[0] = 0.0
    f_th[1] = 0.0
    f_u[:] = 0.0
    for k in range(P.rnode.size):
        i = P.rnode[k]
        lx, ly = x[2 * k], x[2 * k + 1]
        f_u[2 * i] -= lx
        f_u[2 * i + 1] -= ly
        px, py = root_phi_theta(P, theta, k)
        f_th[P.rgear[k]] -= px * lx + py * ly
    p = x[x.size - 1]
    for j in range(6):
        sign = 1.0 if j < 3 else -1.0
        i = cn[j]
        f_u[2 * i] += sign * cw[j] * normal[0] * p
        f_u[2 * i + 1] += sign * cw[j] * normal[1] * p


@njit(cache=True)
def gram(P, theta, cn, cw, normal, C):
    """``G M^-1 G^T`` (dense, ``n_x`` square) for the constraint directions at ``theta``."""
    nr = P.rnode.size
    nx = 2 * nr + 1
    C[:, :] = 0.0
    for k in range(nr):
        pk = root_phi_theta(P, theta, k)
        gk = P.rgear[k]
        for l in range(nr):
            if P.rgear[l] != gk:
                continue
            pl = root_phi_theta(P, theta, l)
            for a in range(2):
                for b in range(2):
                    C[2 * k + a, 2 * l + b] = pk[a] * pl[b] / P.J[gk]
        i = P.rnode[k]
        C[2 * k, 2 * k] += 1.0 / P.mass[2 * i]
        C[2 * k + 1, 2 * k + 1] += 1.0 / P.mass[2 * i + 1]
        # Coupling with the contact row where a root node carries the contact (never on
        # an ordinary flank, kept for completeness).
        for j in range(6):
            if cn[j] == i:
                sign = 1.0 if j < 3 else -1.0
                for a in range(2):
                    v = -sign * cw[j] * normal[a] / P.mass[2 * i + a]
                    C[2 * k + a, nx - 1] += v
                    C[nx - 1, 2 * k + a] += v
    cpp = 0.0
    for j in range(6):
        for j2 in range(6):
            if cn[j] == cn[j2] and ((j < 3) == (j2 < 3)):
                cpp += cw[j] * cw[j2] / P.mass[2 * cn[j]]
    C[nx - 1, nx - 1] = cpp


@njit(cache=True)
def gram_contact(P, cn, cw, normal, C):
    """Refresh the contact row and column of ``G M^-1 G^T`` for new contact rows."""
    nr = P.rnode.size
    nx = 2 * nr + 1
    for k in range(nx):
        C[nx - 1, k] = 0.0
        C[k, nx - 1] = 0.0
    for k in range(nr):
        i = P.rnode[k]
        for j in range(6):
            if cn[j] == i:
                sign = 1.0 if j < 3 else -1.0
                for a in range(2):
                    v = -sign * cw[j] * normal[a] / P.mass[2 * i + a]
                    C[2 * k + a, nx - 1] += v
                    C[nx - 1, 2 * k + a] += v
    cpp = 0.0
    for j in range(6):
        for j2 in range(6):
            if cn[j] == cn[j2] and ((j < 3) == (j2 < 3)):
                cpp += cw[j] * cw[j2] / P.mass[2 * cn[j]]
    C[nx - 1, nx - 1] = cpp


# -- accelerated iteration (Appendix B) -----------------------------------------------------

@njit(cache=True)
def apply_c(C1, b, k, v, out):
    if k == 1:
        out[:] = C1 @ v
        return
    w = np.empty_like(v)
    apply_c(C1, b, k - 1, v, w)
    z = b[k] * v - w
    apply_c(C1, b, k - 1, z, out)


@njit(cache=True)
def apply_a(C1, b, n, e, out):
    if n == 1:
        out[:] = e
        return
    z = np.empty_like(e)
    apply_a(C1, b, n - 1, e, z)
    w = np.empty_like(e)
    apply_c(C1, b, n - 1, z, w)
    out[:] = b[n] * z - w


@njit(cache=True)
def accelerated_update(x, e, C, scale, n, eps_root, Cp, work):
    """One iteration ``x <- x - b_bar A_n e / ||C'||``; ``p <- min(0, p)``.

    ``C`` is ``G M^-1 G^T``; the stage's coefficient ``scale`` multiplies it. ``eps_root``
    is the smallest eigenvalue of the root block of ``G M^-1 G^T`` (constant over a
    run: the disk rotations only rotate it), so ``eps_1`` needs no eigen-solve here.
    """
    m = x.size
    active_p = e[m - 1] != 0.0
    norm = 0.0
    for i in range(m):
        acc = 0.0
        if i == m - 1 and not active_p:
            continue
        for j in range(m):
            if j == m - 1 and not active_p:
                Cp[i, j] = 0.0
                continue
            Cp[i, j] = C[i, j] * scale
            acc += abs(Cp[i, j])
        if acc > norm:
            norm = acc
    if not active_p:
        for j in range(m):
            Cp[m - 1, j] = 0.0
    lam_min = eps_root * scale
    if active_p and Cp[m - 1, m - 1] < lam_min:
        lam_min = Cp[m - 1, m - 1]
    eps1 = min(max(lam_min / norm, 1e-12), 1.0)
    for i in range(m):
        for j in range(m):
            Cp[i, j] /= norm
    b = np.zeros(n + 1)
    om, ep = 1.0, eps1
    for k in range(2, n + 1):
        b[k] = ep + om
        om, ep = b[k] * b[k] / 4.0, ep * om
    bbar = 2.0 / (om + ep)
    apply_a(Cp, b, n, e, work)
    for i in range(m):
        x[i] -= bbar * work[i] / norm
    if x[m - 1] > 0.0:
        x[m - 1] = 0.0


# -- splines and the contact search ---------------------------------------------------------

@njit(cache=True)
def spline_second(vals, h, M):
    """Second derivatives ``M (n, 2)`` of the not-a-knot cubic spline through ``vals``
    on uniform knots of spacing ``h``.

    With uniform knots, not-a-knot is ``M_0 - 2 M_1 + M_2 = 0`` (and at the other end);
    substituted into the first interior row it leaves ``6 M_1 = r_1``, so ``M_1`` and
    ``M_{n-2}`` are known and a Thomas sweep solves the rows in between.
    """
    n = vals.shape[0]
    r = np.empty((n, 2))
    for i in range(1, n - 1):
        for d in range(2):
            r[i, d] = 6.0 * (vals[i - 1, d] - 2.0 * vals[i, d] + vals[i + 1, d]) / (h * h)
    for d in range(2):
        M[1, d] = r[1, d] / 6.0
        M[n - 2, d] = r[n - 2, d] / 6.0
    # rows 2..n-3: M_{i-1} + 4 M_i + M_{i+1} = r_i
    m = n - 4
    if m > 0:
        cp = np.empty(m)
        dp = np.empty((m, 2))
        for k in range(m):
            i = k + 2
            for d in range(2):
                rhs = r[i, d]
                if k == 0:
                    rhs -= M[1, d]
                if k == m - 1:
                    rhs -= M[n - 2, d]
                if k == 0:
                    dp[k, d] = rhs / 4.0
                else:
                    dp[k, d] = (rhs - dp[k - 1, d]) / (4.0 - cp[k - 1])
            cp[k] = 1.0 / (4.0 if k == 0 else 4.0 - cp[k - 1])
        for k in range(m - 1, -1, -1):
            for d in range(2):
                if k == m - 1:
                    M[k + 2, d] = dp[k, d]
                else:
                    M[k + 2, d] = dp[k, d] - cp[k] * M[k + 3, d]
    for d in range(2):
        M[0, d] = 2.0 * M[1, d] - M[2, d]
        M[n - 1, d] = 2.0 * M[n - 2, d] - M[n - 3, d]


@njit(cache=True)
def spline_eval(vals, M, t0, h, t, out):
    """``out[0:2]`` value, ``out[2:4]`` first and ``out[4:6]`` second derivative at ``t``."""
    n = vals.shape[0]
    i = int(math.floor((t - t0) / h))
    if i < 0:
        i = 0
    if i > n - 2:
        i = n - 2
    tau = (t - (t0 + i * h)) / h
    u = 1.0 - tau
    for d in range(2):
        yi, yj, mi, mj = vals[i, d], vals[i + 1, d], M[i, d], M[i + 1, d]
        out[d] = u * yi + tau * yj + h * h / 6.0 * ((u ** 3 - u) * mi + (tau ** 3 - tau) * mj)
        out[2 + d] = (yj - yi) / h + h / 6.0 * ((1.0 - 3.0 * u * u) * mi + (3.0 * tau * tau - 1.0) * mj)
        out[4 + d] = u * mi + tau * mj


@njit(cache=True)
def newton_pair(va, Ma, vb, Mb, ta0, ha, tb0, hb, a, b):
    ea = np.empty(6)
    eb = np.empty(6)
    for _ in range(30):
        spline_eval(va, Ma, ta0, ha, a, ea)
        spline_eval(vb, Mb, tb0, hb, b, eb)
        dx, dy = ea[0] - eb[0], ea[1] - eb[1]
        f0 = cross(ea[2], ea[3], eb[2], eb[3])
        f1 = dx * ea[2] + dy * ea[3]
        j00 = cross(ea[4], ea[5], eb[2], eb[3])
        j01 = cross(ea[2], ea[3], eb[4], eb[5])
        j10 = ea[2] * ea[2] + ea[3] * ea[3] + dx * ea[4] + dy * ea[5]
        j11 = -(eb[2] * ea[2] + eb[3] * ea[3])
        det = j00 * j11 - j01 * j10
        if det == 0.0 or not math.isfinite(det):
            return a, b, False
        s0 = (f0 * j11 - j01 * f1) / det
        s1 = (j00 * f1 - j10 * f0) / det
        big = max(abs(s0), abs(s1))
        if big > 0.5:
            s0 *= 0.5 / big
            s1 *= 0.5 / big
        a -= s0
        b -= s1
        if not (math.isfinite(a) and math.isfinite(b)):
            return a, b, False
        if abs(s0) + abs(s1) < 1e-11:
            return a, b, True
    return a, b, False


@njit(cache=True)
def project(px, py, v, M, t0, h, t, lo, hi):
    e = np.empty(6)
    for _ in range(30):
        spline_eval(v, M, t0, h, t, e)
        dx, dy = e[0] - px, e[1] - py
        den = e[2] * e[2] + e[3] * e[3] + dx * e[4] + dy * e[5]
        step = (dx * e[2] + dy * e[3]) / den
        t = min(max(t - step, lo), hi)
        if abs(step) < 1e-11:
            break
    return t


@njit(cache=True)
def gap_at(va, Ma, vb, Mb, fa, fb, a, b, e, f):
    """Normal gap from A's point ``a`` to B and the foot ``b`` of the normal (warm start)."""
    ta0, ha = fa[F_T0], fa[F_H]
    tb0, tb1, hb = fb[F_T0], fb[F_T1], fb[F_H]
    spline_eval(va, Ma, ta0, ha, a, e)
    b = project(e[0], e[1], vb, Mb, tb0, hb, b, tb0, tb1)
    spline_eval(vb, Mb, tb0, hb, b, f)
    nrm = math.hypot(e[2], e[3])
    return (e[3] * (f[0] - e[0]) - e[2] * (f[1] - e[1])) / nrm, b


@njit(cache=True)
def scan(va, Ma, vb, Mb, fa, fb, b_guess):
    """A global start: the data point of A whose normal gap to B is smallest (deepest)."""
    ta0, ha = fa[F_T0], fa[F_H]
    tb0, tb1 = fb[F_T0], fb[F_T1]
    e = np.empty(6)
    f = np.empty(6)
    best = np.inf
    ba, bb = ta0, tb0
    b = min(max(b_guess, tb0), tb1)
    n = va.shape[0]
    for k in range(n):
        a = ta0 + k * ha
        gap, b = gap_at(va, Ma, vb, Mb, fa, fb, a, b, e, f)
        if gap < best:
            best, ba, bb = gap, a, b
    return ba, bb


@njit(cache=True)
def deepest(va, Ma, vb, Mb, fa, fb, a0, b0):
    """Golden-section search for the deepest point of A within one data spacing of ``a0``
    (see :func:`spurdyn.contact.reference._deepest`)."""
    ta0, ta1, ha = fa[F_T0], fa[F_T1], fa[F_H]
    e = np.empty(6)
    f = np.empty(6)
    lo, hi = max(a0 - ha, ta0), min(a0 + ha, ta1)
    x1, x2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    g1, b1 = gap_at(va, Ma, vb, Mb, fa, fb, x1, b0, e, f)
    g2, b2 = gap_at(va, Ma, vb, Mb, fa, fb, x2, b0, e, f)
    while hi - lo > GOLDEN_TOL:
        if g1 <= g2:
            hi, x2, g2, b2 = x2, x1, g1, b1
            x1 = hi - GOLDEN * (hi - lo)
            g1, b1 = gap_at(va, Ma, vb, Mb, fa, fb, x1, b2, e, f)
        else:
            lo, x1, g1, b1 = x1, x2, g2, b2
            x2 = lo + GOLDEN * (hi - lo)
            g2, b2 = gap_at(va, Ma, vb, Mb, fa, fb, x2, b1, e, f)
    if g1 <= g2:
        return x1, b1
    return x2, b2


@njit(cache=True)
def find_pair(va, Ma, vb, Mb, fa, fb, ga, gb):
    """The contact pair ``(alpha, beta, mode, nx, ny)`` of two flank splines (see
    :func:`spurdyn.contact.reference.find_contact`)."""
    ta0, ta1, ha = fa[F_T0], fa[F_T1], fa[F_H]
    tb0, tb1, hb = fb[F_T0], fb[F_T1], fb[F_H]
    a, b, ok = newton_pair(va, Ma, vb, Mb, ta0, ha, tb0, hb, ga, gb)
    na, nb = ga, gb
    if not ok or abs(a - ga) + abs(b - gb) > 1.0:
        na, nb = scan(va, Ma, vb, Mb, fa, fb, gb)
        a, b, ok = newton_pair(va, Ma, vb, Mb, ta0, ha, tb0, hb, na, nb)
        if not ok or abs(a - na) + abs(b - nb) > 1.0:
            a, b = deepest(va, Ma, vb, Mb, fa, fb, na, nb)
            na, nb = a, b
            a2, b2, ok2 = newton_pair(va, Ma, vb, Mb, ta0, ha, tb0, hb, a, b)
            if ok2 and abs(a2 - a) + abs(b2 - b) < POLISH:
                a, b = a2, b2
            ok = a < ta1 - EDGE and b < tb1 - EDGE
    e = np.empty(6)
    if ok and ta0 <= a <= ta1 and tb0 <= b <= tb1:
        mode = FLANK
    else:
        ga_ = min(max(a if ok else na, ta0), ta1)
        gb_ = min(max(b if ok else nb, tb0), tb1)
        spline_eval(vb, Mb, tb0, hb, tb1, e)
        cbx, cby = e[0], e[1]
        a_b = project(cbx, cby, va, Ma, ta0, ha, ga_, ta0, ta1)
        spline_eval(va, Ma, ta0, ha, ta1, e)
        cax, cay = e[0], e[1]
        b_a = project(cax, cay, vb, Mb, tb0, hb, gb_, tb0, tb1)
        dist_b = np.inf
        dist_a = np.inf
        if ta0 < a_b < ta1:
            spline_eval(va, Ma, ta0, ha, a_b, e)
            dist_b = math.hypot(cbx - e[0], cby - e[1])
        if tb0 < b_a < tb1:
            spline_eval(vb, Mb, tb0, hb, b_a, e)
            dist_a = math.hypot(cax - e[0], cay - e[1])
        if dist_b <= dist_a and math.isfinite(dist_b):
            a, b, mode = a_b, tb1, CORNER_B
        elif math.isfinite(dist_a):
            a, b, mode = ta1, b_a, CORNER_A
        else:
            a, b, mode = ga_, gb_, FLANK
    if mode == CORNER_A:
        spline_eval(vb, Mb, tb0, hb, b, e)
        tx, ty = e[2], e[3]
        nrm = math.hypot(tx, ty)
        nx, ny = -ty / nrm, tx / nrm          # minus B's outward normal
    else:
        spline_eval(va, Ma, ta0, ha, a, e)
        tx, ty = e[2], e[3]
        nrm = math.hypot(tx, ty)
        nx, ny = ty / nrm, -tx / nrm          # A's outward normal
    return a, b, mode, nx, ny


@njit(cache=True)
def edge_at(fpar, side, t):
    """Edge nodes (3, global) and weights of the material point at flank coordinate ``t``."""
    ny = int(fpar[F_NY])
    row = int(math.floor(t))
    if row < 0:
        row = 0
    if row > ny - 1:
        row = ny - 1
    eta = 2.0 * (t - row) - 1.0
    nodes = side[2 * row:2 * row + 3]
    w = np.empty(3)
    w[0] = 0.5 * eta * (eta - 1.0)
    w[1] = 1.0 - eta * eta
    w[2] = 0.5 * eta * (eta + 1.0)
    return nodes, w, row


@njit(cache=True)
def delta_at(fpar, sideY, t):
    """``delta(t) = Y_exact(t) - N(t) Y``: the involute's offset from the element edge."""
    ny = fpar[F_NY]
    r = fpar[F_R0] + (fpar[F_RTIP] - fpar[F_R0]) * t / ny
    al = math.acos(min(fpar[F_RB] / r, 1.0))
    chi = fpar[F_PSI] - (math.tan(al) - al)
    c, s = math.cos(fpar[F_REF]), math.sin(fpar[F_REF])
    x, y = r * math.sin(chi), r * math.cos(chi)
    if fpar[F_RA] > 0.0:
        # tip relief: move in along the involute's normal (spurdyn.geometry.relief)
        xi = math.sqrt(max(r * r - fpar[F_RB] ** 2, 0.0)) / fpar[F_RB]
        depth = fpar[F_RA] * max(0.0, (xi - fpar[F_RS]) / (fpar[F_RT] - fpar[F_RS])) ** fpar[F_RK]
        chi_t = fpar[F_PSI] - math.tan(al)
        x -= depth * math.cos(chi_t)
        y += depth * math.sin(chi_t)
    ex, ey = c * x - s * y, s * x + c * y
    row = int(math.floor(t))
    if row < 0:
        row = 0
    if row > int(ny) - 1:
        row = int(ny) - 1
    eta = 2.0 * (t - row) - 1.0
    w0, w1, w2 = 0.5 * eta * (eta - 1.0), 1.0 - eta * eta, 0.5 * eta * (eta + 1.0)
    dx = ex - (w0 * sideY[2 * row, 0] + w1 * sideY[2 * row + 1, 0] + w2 * sideY[2 * row + 2, 0])
    dy = ey - (w0 * sideY[2 * row, 1] + w1 * sideY[2 * row + 1, 1] + w2 * sideY[2 * row + 2, 1])
    return dx, dy
