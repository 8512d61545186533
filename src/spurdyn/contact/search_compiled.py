"""The contact search compiled with Numba: the twin of :mod:`spurdyn.contact.search_numpy`.

Arrays and scalars in, arrays and scalars out. Each function has a NumPy counterpart
(the search, the splines and the sliding terms in :mod:`spurdyn.contact.search_numpy`,
the material points in :class:`spurdyn.model.flank.Flank`) and is tested against it
in tests/test_contact_search.py. A flank is given by its parameter row ``fpar``
(columns :data:`spurdyn.contact.constants.F`), its outline nodes ``side`` and their
initial offsets ``sideY``; the functions at the end read the packed model
(:class:`spurdyn.solvers.layout.Packed`: ``fl_nodes``, ``fl_w``, ``fl_delta``, ``fpar``,
``side``, ``sideY``, ``Y``, ``centre``, ``sense``).
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.contact.constants import CORNER_A, CORNER_B, EDGE, FLANK, GOLDEN, GOLDEN_TOL, POLISH, F
from spurdyn.jit import njit


# -- small helpers --------------------------------------------------------------------------

@njit
def cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit
def edge_shape(eta):
    """Quadratic edge shape functions (root, middle, tip) at ``eta``: the compiled twin
    of :func:`spurdyn.fem.element.edge_weights`."""
    return 0.5 * eta * (eta - 1.0), 1.0 - eta * eta, 0.5 * eta * (eta + 1.0)


@njit
def edge_at(fpar, side, t):
    """Edge nodes (3, global) and weights of the material point at flank coordinate ``t``."""
    ny = int(fpar[F.ny])
    row = int(math.floor(t))
    if row < 0:
        row = 0
    if row > ny - 1:
        row = ny - 1
    eta = 2.0 * (t - row) - 1.0
    nodes = side[2 * row:2 * row + 3]
    w = np.empty(3)
    w[0], w[1], w[2] = edge_shape(eta)
    return nodes, w, row


@njit
def exact_at(fpar, t):
    """Initial position (from the centre) of the exact involute point at ``t``: the twin
    of :meth:`spurdyn.model.flank.Flank.exact`."""
    ny = fpar[F.ny]
    r = fpar[F.r0] + (fpar[F.r_tip] - fpar[F.r0]) * t / ny
    al = math.acos(min(fpar[F.base_radius] / r, 1.0))
    chi = fpar[F.psi_base] - (math.tan(al) - al)
    c, s = math.cos(fpar[F.ref_angle]), math.sin(fpar[F.ref_angle])
    x, y = r * math.sin(chi), r * math.cos(chi)
    if fpar[F.relief_amount] > 0.0:
        # tip relief: move in along the involute's normal (twin of
        # spurdyn.geometry.relief.relief_depth)
        xi = math.sqrt(max(r * r - fpar[F.base_radius] ** 2, 0.0)) / fpar[F.base_radius]
        depth = fpar[F.relief_amount] * max(0.0, (xi - fpar[F.relief_start]) / (fpar[F.relief_tip] - fpar[F.relief_start])) ** fpar[F.relief_exponent]
        chi_t = fpar[F.psi_base] - math.tan(al)
        x -= depth * math.cos(chi_t)
        y += depth * math.sin(chi_t)
    return c * x - s * y, s * x + c * y


@njit
def delta_at(fpar, sideY, t):
    """``delta(t) = Y_exact(t) - N(t) Y``: the involute's offset from the element edge."""
    ny = fpar[F.ny]
    ex, ey = exact_at(fpar, t)
    row = int(math.floor(t))
    if row < 0:
        row = 0
    if row > int(ny) - 1:
        row = int(ny) - 1
    eta = 2.0 * (t - row) - 1.0
    w0, w1, w2 = edge_shape(eta)
    dx = ex - (w0 * sideY[2 * row, 0] + w1 * sideY[2 * row + 1, 0] + w2 * sideY[2 * row + 2, 0])
    dy = ey - (w0 * sideY[2 * row, 1] + w1 * sideY[2 * row + 1, 1] + w2 * sideY[2 * row + 2, 1])
    return dx, dy


# -- splines -------------------------------------------------------------------------------

@njit
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


@njit
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


# -- the contact search (twin of spurdyn.contact.search_numpy) -------------------------------

@njit
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


@njit
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


@njit
def gap_at(va, Ma, vb, Mb, fa, fb, a, b, e, f):
    """Normal gap from A's point ``a`` to B and the foot ``b`` of the normal (warm start)."""
    ta0, ha = fa[F.t0], fa[F.h]
    tb0, tb1, hb = fb[F.t0], fb[F.t1], fb[F.h]
    spline_eval(va, Ma, ta0, ha, a, e)
    b = project(e[0], e[1], vb, Mb, tb0, hb, b, tb0, tb1)
    spline_eval(vb, Mb, tb0, hb, b, f)
    nrm = math.hypot(e[2], e[3])
    return (e[3] * (f[0] - e[0]) - e[2] * (f[1] - e[1])) / nrm, b


@njit
def scan(va, Ma, vb, Mb, fa, fb, b_guess):
    """A global start: the data point of A whose normal gap to B is smallest (deepest)."""
    ta0, ha = fa[F.t0], fa[F.h]
    tb0, tb1 = fb[F.t0], fb[F.t1]
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


@njit
def deepest(va, Ma, vb, Mb, fa, fb, a0, b0):
    """Golden-section search for the deepest point of A within one data spacing of ``a0``
    (see :func:`spurdyn.contact.search_numpy._deepest`)."""
    ta0, ta1, ha = fa[F.t0], fa[F.t1], fa[F.h]
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


@njit
def find_pair(va, Ma, vb, Mb, fa, fb, ga, gb):
    """The contact pair ``(alpha, beta, mode, nx, ny)`` of two flank splines (see
    :func:`spurdyn.contact.search_numpy.find_contact`)."""
    ta0, ta1, ha = fa[F.t0], fa[F.t1], fa[F.h]
    tb0, tb1, hb = fb[F.t0], fb[F.t1], fb[F.h]
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


# -- on the packed model (spurdyn.solvers.layout.Packed) ------------------------------------

@njit
def data_positions(P, g, th, omega_or_zero, uget, out, kind):
    """Positions (kind 0) or velocities (kind 1) of the data points of gear ``g``; with
    kind 2 (3) the positions (velocities) of the tooth turned rigidly with its disk, on
    which a strip's pair is located (docs/solver.md, section 11.2; ``uget`` unread).

    ``uget`` is a full-length vector (``u`` or ``v``) of the tooth DOFs.
    """
    sg = P.sense[g]
    c, s = math.cos(sg * th), math.sin(sg * th)
    nd = P.fl_nodes.shape[1]
    cx, cy = P.centre[g, 0], P.centre[g, 1]
    rigid = kind >= 2
    for k in range(nd):
        px = 0.0
        py = 0.0
        for j in range(3):
            i = P.fl_nodes[g, k, j]
            wj = P.fl_w[g, k, j]
            if kind == 0:
                px += wj * (P.Y[2 * i] + uget[2 * i])
                py += wj * (P.Y[2 * i + 1] + uget[2 * i + 1])
            elif rigid:
                px += wj * P.Y[2 * i]
                py += wj * P.Y[2 * i + 1]
            else:
                px += wj * uget[2 * i]
                py += wj * uget[2 * i + 1]
        dx, dy = P.fl_delta[g, k, 0], P.fl_delta[g, k, 1]
        if rigid:       # the involute point itself, turned with the disk
            dx += px
            dy += py
            px = 0.0
            py = 0.0
        rx, ry = c * dx - s * dy, s * dx + c * dy
        if kind == 0 or kind == 2:
            out[k, 0] = cx + px + rx
            out[k, 1] = cy + py + ry
        else:
            k2 = sg * omega_or_zero
            out[k, 0] = px - k2 * ry
            out[k, 1] = py + k2 * rx


@njit
def material_point(P, g, t, th, uget, kind, om, al):
    """Position (kind 0), velocity (1) or acceleration (2) of the material point at ``t``."""
    nodes, w, _ = edge_at(P.fpar[g], P.side[g], t)
    dx, dy = delta_at(P.fpar[g], P.sideY[g], t)
    return weighted_point(P, g, nodes, w, 0, 3, dx, dy, th, uget, kind, om, al)


@njit
def weighted_point(P, g, nodes, w, off, n, dx, dy, th, uget, kind, om, al):
    """Position (kind 0), velocity (1) or acceleration (2) of ``c + sum_j w_j (Y + u)_j +
    R delta`` of gear ``g``, over the nodes ``nodes[off:off + n]`` with weights
    ``w[off:off + n]``: one material point (three edge nodes) or a strip's virtual point."""
    sg = P.sense[g]
    c, s = math.cos(sg * th), math.sin(sg * th)
    rx, ry = c * dx - s * dy, s * dx + c * dy
    px = 0.0
    py = 0.0
    for j in range(n):
        i = nodes[off + j]
        wj = w[off + j]
        if kind == 0:
            px += wj * (P.Y[2 * i] + uget[2 * i])
            py += wj * (P.Y[2 * i + 1] + uget[2 * i + 1])
        else:
            px += wj * uget[2 * i]
            py += wj * uget[2 * i + 1]
    if kind == 0:
        return P.centre[g, 0] + px + rx, P.centre[g, 1] + py + ry
    if kind == 1:
        return px - sg * om * ry, py + sg * om * rx
    # sense alpha R Jz delta - omega^2 R delta
    return px - sg * al * ry - om * om * rx, py + sg * al * rx - om * om * ry


@njit
def search(P, theta, u, guess, va, vb, Ma, Mb, rigid=False):
    """Contact pair on the current flanks: ``(alpha, beta, mode, n_x, n_y, s)``; with
    ``rigid`` the pair, its mode and normal are those of the rigidly turned flanks (the
    strip's, docs/solver.md section 11.2; ``va`` ... ``Mb`` then hold their splines) and
    ``s`` the deformed flanks' gap there."""
    kind = np.int64(2) if rigid else np.int64(0)
    data_positions(P, np.int64(0), theta[0], 0.0, u, va, kind)
    data_positions(P, np.int64(1), theta[1], 0.0, u, vb, kind)
    spline_second(va, P.fpar[0, F.h], Ma)
    spline_second(vb, P.fpar[1, F.h], Mb)
    a, b, mode, nx, ny = find_pair(va, Ma, vb, Mb, P.fpar[0], P.fpar[1], guess[0], guess[1])
    xa, ya = material_point(P, np.int64(0), a, theta[0], u, np.int64(0), 0.0, 0.0)
    xb, yb = material_point(P, np.int64(1), b, theta[1], u, np.int64(0), 0.0, 0.0)
    s = nx * (xa - xb) + ny * (ya - yb)
    return a, b, mode, nx, ny, s


@njit
def contact_rows(P, a, b, cn, cw):
    """Edge nodes and weights of the contact material points: A's in the first half of
    ``cn``, ``cw``, B's in the second, each three and, past them, zero weights on A's (B's)
    first node (the slots a distributed contact's strip may fill)."""
    na, wa, _ = edge_at(P.fpar[0], P.side[0], a)
    nb, wb, _ = edge_at(P.fpar[1], P.side[1], b)
    half = cn.size // 2
    for j in range(half):
        cn[j] = na[j] if j < 3 else na[0]
        cw[j] = wa[j] if j < 3 else 0.0
        cn[half + j] = nb[j] if j < 3 else nb[0]
        cw[half + j] = wb[j] if j < 3 else 0.0


@njit
def _splined_at(P, g, th, om, uget, kind, t, out):
    """Value and first two derivatives (``out``, 6) at ``t`` of gear ``g``'s flank spline
    through the data points of ``kind`` (:func:`data_positions`)."""
    nd = P.fl_nodes.shape[1]
    vals = np.empty((nd, 2))
    M = np.empty((nd, 2))
    data_positions(P, g, th, om, uget, vals, kind)
    spline_second(vals, P.fpar[g, F.h], M)
    spline_eval(vals, M, P.fpar[g, F.t0], P.fpar[g, F.h], t, out)


@njit
def sliding(P, theta, omega, u, v, a, b, mode, nx, ny, va, vb, Ma, Mb, rigid=False):
    """Appendix A terms of the relative normal acceleration at the contact pair. With
    ``rigid`` (``va`` ... ``Mb`` the rigidly turned flanks' splines, as :func:`search` left
    them) the pair's rates are the rigid flanks' and the terms the deformed ones'."""
    ea = np.empty(6)
    eb = np.empty(6)
    fa = np.empty(6)
    fb = np.empty(6)
    spline_eval(va, Ma, P.fpar[0, F.t0], P.fpar[0, F.h], a, ea)
    spline_eval(vb, Mb, P.fpar[1, F.t0], P.fpar[1, F.h], b, eb)
    if rigid:
        _splined_at(P, np.int64(0), theta[0], omega[0], v, np.int64(3), a, fa)
        _splined_at(P, np.int64(1), theta[1], omega[1], v, np.int64(3), b, fb)
        ad, bd = pair_rates(ea, eb, fa, fb, mode)
        _splined_at(P, np.int64(0), theta[0], 0.0, u, np.int64(0), a, ea)
        _splined_at(P, np.int64(1), theta[1], 0.0, u, np.int64(0), b, eb)
    _splined_at(P, np.int64(0), theta[0], omega[0], v, np.int64(1), a, fa)
    _splined_at(P, np.int64(1), theta[1], omega[1], v, np.int64(1), b, fb)
    if not rigid:
        ad, bd = pair_rates(ea, eb, fa, fb, mode)
    cax, cay = ea[4], ea[5]
    cbx, cby = eb[4], eb[5]
    return (2.0 * ad * (nx * fa[2] + ny * fa[3]) + ad * ad * (nx * cax + ny * cay)
            - 2.0 * bd * (nx * fb[2] + ny * fb[3]) - bd * bd * (nx * cbx + ny * cby))


@njit
def pair_rates(ea, eb, fa, fb, mode):
    """``(d alpha/dt, d beta/dt)`` from the position (``ea``, ``eb``) and velocity (``fa``,
    ``fb``) splines' values at the pair (the twin of ``search_numpy.pair_rates``)."""
    tax, tay, cax, cay = ea[2], ea[3], ea[4], ea[5]
    tbx, tby, cbx, cby = eb[2], eb[3], eb[4], eb[5]
    ta2 = tax * tax + tay * tay
    tb2 = tbx * tbx + tby * tby
    if mode == FLANK:
        nt = math.sqrt(ta2)
        hx, hy = tax / nt, tay / nt
        m00 = hx * tax + hy * tay
        m01 = -(hx * tbx + hy * tby)
        m10 = (tax * cay - tay * cax) / ta2
        m11 = -(tbx * cby - tby * cbx) / tb2
        r0 = hx * (fb[0] - fa[0]) + hy * (fb[1] - fa[1])
        r1 = (tbx * fb[3] - tby * fb[2]) / tb2 - (tax * fa[3] - tay * fa[2]) / ta2
        det = m00 * m11 - m01 * m10
        ad = (r0 * m11 - m01 * r1) / det
        bd = (m00 * r1 - m10 * r0) / det
    elif mode == CORNER_A:
        ad = 0.0
        bd = (tbx * (fa[0] - fb[0]) + tby * (fa[1] - fb[1])) / tb2
    else:
        ad = (tax * (fb[0] - fa[0]) + tay * (fb[1] - fa[1])) / ta2
        bd = 0.0
    return ad, bd
