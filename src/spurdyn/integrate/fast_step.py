"""The paper's step, compiled, with the response to the forces superposed.

Within a step the constraint force ``G_n^T x`` is held fixed, so the RK4 result is
affine in ``x`` (to round-off: the only nonlinearity is the disk rotation, which the
forces change by ~1e-11 rad in a step). The step integrates once with the forces of the
previous step, ``x0``, and then adds the exact linear response of the RK4 map,

    dq = h^2/2 Z + h^4/24 M^-1 T3 Z,    dv = h Z + h^3/12 M^-1 (T3 + T4) Z,
    Z  = M^-1 G_n^T (x - x0),

``T3``, ``T4`` the tangent of the forces at RK4's third and fourth stage states
(docs/solver.md). Each iterate of stages 1 and 2 then costs a small dense product on the
DOFs the constraints look at (root nodes, flank nodes, rotations) instead of a
re-integration. tests/test_fast.py checks the result against the re-integrating
reference step by step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from spurdyn.integrate.kernels import (
    CORNER_A, CORNER_B, F_H, F_T0, FLANK, accelerated_update, accelerations, constraint_force,
    delta_at, edge_at, elastic, find_pair, gram, gram_contact, root_phi_theta, spline_eval, spline_second,
    torque,
)

# Constant arguments of compiled calls are written ``np.int64(0)``, ``np.bool_(True)``:
# a bare literal makes Numba compile a separate copy of the callee per literal value,
# which cost ~8 s of the first compile (measured in docs/performance.md).
OK, FAIL_DISP, FAIL_VEL, FAIL_ACC, FAIL_NAN = 0, 1, 2, 3, 4

#: Move the contact force to the contact pair found in an iteration when the pair has
#: moved by more than this (elements) from where the force acts, at most MAX_RELOCATE
#: times a step (see spurdyn.solver.reference.RELOCATE).
RELOCATE = 0.05
MAX_RELOCATE = 4


@njit(cache=True)
def _rot(P, theta, g):
    sg = P.sense[g]
    return math.cos(sg * theta[g]), math.sin(sg * theta[g])


@njit(cache=True)
def max_abs(e):
    """``max |e_i|``, NaN if any entry is NaN (Python's ``max`` would drop it)."""
    r = 0.0
    for i in range(e.size):
        a = abs(e[i])
        if a > r or a != a:
            r = a
    return r


@njit(cache=True)
def data_positions(P, g, th, omega_or_zero, uget, out, kind):
    """Positions (kind 0) or velocities (kind 1) of the data points of gear ``g``.

    ``uget`` is a full-length vector (``u`` or ``v``) of the tooth DOFs.
    """
    sg = P.sense[g]
    c, s = math.cos(sg * th), math.sin(sg * th)
    nd = P.fl_nodes.shape[1]
    cx, cy = P.centre[g, 0], P.centre[g, 1]
    for k in range(nd):
        px = 0.0
        py = 0.0
        for j in range(3):
            i = P.fl_nodes[g, k, j]
            wj = P.fl_w[g, k, j]
            if kind == 0:
                px += wj * (P.Y[2 * i] + uget[2 * i])
                py += wj * (P.Y[2 * i + 1] + uget[2 * i + 1])
            else:
                px += wj * uget[2 * i]
                py += wj * uget[2 * i + 1]
        dx, dy = P.fl_delta[g, k, 0], P.fl_delta[g, k, 1]
        rx, ry = c * dx - s * dy, s * dx + c * dy
        if kind == 0:
            out[k, 0] = cx + px + rx
            out[k, 1] = cy + py + ry
        else:
            k2 = sg * omega_or_zero
            out[k, 0] = px - k2 * ry
            out[k, 1] = py + k2 * rx


@njit(cache=True)
def material_point(P, g, t, th, uget, kind, om, al):
    """Position (kind 0), velocity (1) or acceleration (2) of the material point at ``t``."""
    nodes, w, _ = edge_at(P.fpar[g], P.side[g], t)
    dx, dy = delta_at(P.fpar[g], P.sideY[g], t)
    sg = P.sense[g]
    c, s = math.cos(sg * th), math.sin(sg * th)
    rx, ry = c * dx - s * dy, s * dx + c * dy
    px = 0.0
    py = 0.0
    for j in range(3):
        i = nodes[j]
        if kind == 0:
            px += w[j] * (P.Y[2 * i] + uget[2 * i])
            py += w[j] * (P.Y[2 * i + 1] + uget[2 * i + 1])
        else:
            px += w[j] * uget[2 * i]
            py += w[j] * uget[2 * i + 1]
    if kind == 0:
        return P.centre[g, 0] + px + rx, P.centre[g, 1] + py + ry
    if kind == 1:
        return px - sg * om * ry, py + sg * om * rx
    # sense alpha R Jz delta - omega^2 R delta
    return px - sg * al * ry - om * om * rx, py + sg * al * rx - om * om * ry


@njit(cache=True)
def search(P, theta, u, guess, va, vb, Ma, Mb):
    """Contact pair on the current flanks: ``(alpha, beta, mode, n_x, n_y, s)``."""
    data_positions(P, np.int64(0), theta[0], 0.0, u, va, np.int64(0))
    data_positions(P, np.int64(1), theta[1], 0.0, u, vb, np.int64(0))
    spline_second(va, P.fpar[0, F_H], Ma)
    spline_second(vb, P.fpar[1, F_H], Mb)
    a, b, mode, nx, ny = find_pair(va, Ma, vb, Mb, P.fpar[0], P.fpar[1], guess[0], guess[1])
    xa, ya = material_point(P, np.int64(0), a, theta[0], u, np.int64(0), 0.0, 0.0)
    xb, yb = material_point(P, np.int64(1), b, theta[1], u, np.int64(0), 0.0, 0.0)
    s = nx * (xa - xb) + ny * (ya - yb)
    return a, b, mode, nx, ny, s


@njit(cache=True)
def contact_rows(P, a, b, cn, cw):
    """Edge nodes and weights of the contact material points (A's 3 then B's 3)."""
    na, wa, _ = edge_at(P.fpar[0], P.side[0], a)
    nb, wb, _ = edge_at(P.fpar[1], P.side[1], b)
    for j in range(3):
        cn[j] = na[j]
        cw[j] = wa[j]
        cn[3 + j] = nb[j]
        cw[3 + j] = wb[j]


@njit(cache=True)
def sliding(P, theta, omega, u, v, a, b, mode, nx, ny, va, vb, Ma, Mb):
    """Appendix A terms of the relative normal acceleration at the contact pair."""
    na = va.shape[0]
    wa = np.empty((na, 2))
    wb = np.empty((na, 2))
    Wa = np.empty((na, 2))
    Wb = np.empty((na, 2))
    data_positions(P, np.int64(0), theta[0], omega[0], v, wa, np.int64(1))
    data_positions(P, np.int64(1), theta[1], omega[1], v, wb, np.int64(1))
    spline_second(wa, P.fpar[0, F_H], Wa)
    spline_second(wb, P.fpar[1, F_H], Wb)
    ea = np.empty(6)
    eb = np.empty(6)
    fa = np.empty(6)
    fb = np.empty(6)
    spline_eval(va, Ma, P.fpar[0, F_T0], P.fpar[0, F_H], a, ea)
    spline_eval(vb, Mb, P.fpar[1, F_T0], P.fpar[1, F_H], b, eb)
    spline_eval(wa, Wa, P.fpar[0, F_T0], P.fpar[0, F_H], a, fa)
    spline_eval(wb, Wb, P.fpar[1, F_T0], P.fpar[1, F_H], b, fb)
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
    extra = (2.0 * ad * (nx * fa[2] + ny * fa[3]) + ad * ad * (nx * cax + ny * cay)
             - 2.0 * bd * (nx * fb[2] + ny * fb[3]) - bd * bd * (nx * cbx + ny * cby))
    return extra


@njit(cache=True)
def sparse_tangent(P, th, w, kw, zu, nz_nodes, nnz, scratch, mark, touched, out_th, out_u, coef):
    """Add ``coef * T(0, z_u)`` to ``out_u`` and ``out_th`` for ``z_u`` nonzero only on the
    nodes ``nz_nodes[:nnz]`` (``zu`` dense (n_u,)). Returns the number of nodes written
    (listed in ``touched``); ``scratch`` (n_u,) and ``mark`` (n_nodes,) come and go back zero.
    """
    nt = 0
    dq0 = 0.0
    dq1 = 0.0
    for k in range(nnz):
        node = nz_nodes[k]
        g = P.node_gear[node]
        c, s = _rot(P, th, g)
        zx, zy = zu[2 * node], zu[2 * node + 1]
        dwx = c * zx + s * zy
        dwy = -s * zx + c * zy
        if P.keep:
            v = dwx * kw[2 * node + 1] - dwy * kw[2 * node]
            if g == 0:
                dq0 += v
            else:
                dq1 += v
        # K symmetric: block (node, r) of K's row gives K[r, node] as its transpose
        for q in range(P.indptr[node], P.indptr[node + 1]):
            r = P.indices[q]
            scratch[2 * r] += P.data[q, 0, 0] * dwx + P.data[q, 1, 0] * dwy
            scratch[2 * r + 1] += P.data[q, 0, 1] * dwx + P.data[q, 1, 1] * dwy
            if mark[r] == 0:
                mark[r] = 1
                touched[nt] = r
                nt += 1
    for k in range(nt):
        node = touched[k]
        g = P.node_gear[node]
        c, s = _rot(P, th, g)
        kx, ky = scratch[2 * node], scratch[2 * node + 1]
        out_u[2 * node] += coef * (-(c * kx - s * ky))
        out_u[2 * node + 1] += coef * (-(s * kx + c * ky))
        if P.keep:
            v = w[2 * node] * ky - w[2 * node + 1] * kx
            if g == 0:
                dq0 += v
            else:
                dq1 += v
        scratch[2 * node] = 0.0
        scratch[2 * node + 1] = 0.0
        mark[node] = 0
    out_th[0] += coef * P.sense[0] * dq0
    out_th[1] += coef * P.sense[1] * dq1
    return nt


@njit(cache=True)
def _response_full(P, th3, w3, kw3, th4, w4, kw4, sl3, sl4, zth, zu, nz_nodes, nnz, scratch,
                   mark, touched, t3th, t3u, t4th, t4u, want4):
    """``T3 Z`` (and ``T4 Z`` if ``want4``) as full vectors for ``Z = (zth, zu)``."""
    t3u[:] = 0.0
    t4u[:] = 0.0
    for g in range(2):
        t3th[g] = zth[g] * sl3[g]
        t4th[g] = zth[g] * sl4[g]
    sparse_tangent(P, th3, w3, kw3, zu, nz_nodes, nnz, scratch, mark, touched, t3th, t3u, 1.0)
    if want4:
        sparse_tangent(P, th4, w4, kw4, zu, nz_nodes, nnz, scratch, mark, touched, t4th, t4u, 1.0)


@njit(cache=True)
def _z_of(P, theta, cn, cw, normal, dx, zth, zu, nz_nodes, mark):
    """``Z = M^-1 G^T dx`` with ``G`` at ``theta`` and the contact rows ``cn, cw, normal``;
    returns the number of nodes (listed in ``nz_nodes``) where ``zu`` is nonzero."""
    constraint_force(P, theta, cn, cw, normal, dx, zth, zu)
    for g in range(2):
        zth[g] /= P.J[g]
    nnz = 0
    for k in range(P.rnode.size):
        i = P.rnode[k]
        if mark[i] == 0:
            mark[i] = 1
            nz_nodes[nnz] = i
            nnz += 1
    for j in range(6):
        i = cn[j]
        if mark[i] == 0:
            mark[i] = 1
            nz_nodes[nnz] = i
            nnz += 1
    for k in range(nnz):
        i = nz_nodes[k]
        mark[i] = 0
        zu[2 * i] /= P.mass[2 * i]
        zu[2 * i + 1] /= P.mass[2 * i + 1]
    return nnz


@njit(cache=True)
def predict(P, S, h):
    """RK4 over the step with the last step's forces held fixed (directions at ``q_n``).

    Returns the end state ``(th, u, om, v)`` and what the linear response needs: the
    third and fourth stage states' rotations, ``w`` and ``K w``, and the slopes of the
    torque schedule there.
    """
    n = S.u.size
    th, om, u, v = S.theta, S.omega, S.u, S.v
    x0 = S.x
    # -- free RK4 with the forces of the last step, directions at q_n ----------------
    fth0 = np.empty(2)
    fu0 = np.empty(n)
    constraint_force(P, th, S.cn, S.cw, S.normal, x0, fth0, fu0)
    w = np.empty(n)
    kw = np.empty(n)
    el = np.empty(n)
    qq = np.empty(2)
    a2th = np.empty(2)
    a2u = np.empty(n)
    q2th = th + 0.5 * h * om
    q2u = u + 0.5 * h * v
    v2th = om + 0.5 * h * S.alpha_n
    v2u = v + 0.5 * h * S.a_n
    accelerations(q2th, q2u, fth0, fu0, P, w, kw, el, qq, a2th, a2u)
    q3th = th + 0.5 * h * v2th
    q3u = u + 0.5 * h * v2u
    v3th = om + 0.5 * h * a2th
    v3u = v + 0.5 * h * a2u
    w3 = np.empty(n)
    kw3 = np.empty(n)
    a3th = np.empty(2)
    a3u = np.empty(n)
    accelerations(q3th, q3u, fth0, fu0, P, w3, kw3, el, qq, a3th, a3u)
    q4th = th + h * v3th
    q4u = u + h * v3u
    v4th = om + h * a3th
    v4u = v + h * a3u
    w4 = np.empty(n)
    kw4 = np.empty(n)
    a4th = np.empty(2)
    a4u = np.empty(n)
    accelerations(q4th, q4u, fth0, fu0, P, w4, kw4, el, qq, a4th, a4u)
    h6 = h / 6.0
    qs_th = th + h6 * (om + 2.0 * v2th + 2.0 * v3th + v4th)
    qs_u = u + h6 * (v + 2.0 * v2u + 2.0 * v3u + v4u)
    vs_th = om + h6 * (S.alpha_n + 2.0 * a2th + 2.0 * a3th + a4th)
    vs_u = v + h6 * (S.a_n + 2.0 * a2u + 2.0 * a3u + a4u)

    # -- the response to a disk rotation: only the torque schedule's slope is kept. The
    # elastic part, s R [K, Jz] w, moves a node by ~1e-22 m and 1e-11 m/s in a step, far
    # under round-off (docs/solver.md), and would cost two stiffness products.
    sl3 = np.empty(2)
    sl4 = np.empty(2)
    for g in range(2):
        _, sl3[g] = torque(P.tpar, g, q3th[g])
        _, sl4[g] = torque(P.tpar, g, q4th[g])
    return (qs_th, qs_u, vs_th, vs_u, q3th, w3, kw3, q4th, w4, kw4, sl3, sl4)


@njit(cache=True)
def superpose(P, S, h, pred, x, cn, cw, normal, want_v):
    """The end state of RK4 with the forces ``G^T x`` (contact row at ``cn, cw, normal``):
    ``pred`` (made with the last step's forces) plus the linear response to the change."""
    qs_th, qs_u, vs_th, vs_u, q3th, w3, kw3, q4th, w4, kw4, sl3, sl4 = pred
    n = S.u.size
    nn = n // 2
    scratch = np.zeros(n)
    mark = np.zeros(nn, dtype=np.int64)
    touched = np.empty(nn, dtype=np.int64)
    nz_nodes = np.empty(nn, dtype=np.int64)
    zth = np.empty(2)
    zu = np.zeros(n)
    zth0 = np.empty(2)
    zu0 = np.zeros(n)
    t3th = np.empty(2)
    t4th = np.empty(2)
    t3u = np.empty(n)
    t4u = np.empty(n)
    nnz = _z_of(P, S.theta, cn, cw, normal, x, zth, zu, nz_nodes, mark)
    nnz0 = _z_of(P, S.theta, S.cn, S.cw, S.normal, S.x, zth0, zu0, nz_nodes[nnz:], mark)
    for g in range(2):
        zth[g] -= zth0[g]
    zu -= zu0
    # merge the node lists (the root nodes appear in both)
    total = nnz
    for k in range(nnz0):
        i = nz_nodes[nnz + k]
        dup = False
        for l in range(nnz):
            if nz_nodes[l] == i:
                dup = True
                break
        if not dup:
            nz_nodes[total] = i
            total += 1
    _response_full(P, q3th, w3, kw3, q4th, w4, kw4, sl3, sl4, zth, zu, nz_nodes, total, scratch,
                   mark, touched, t3th, t3u, t4th, t4u, want_v)
    h2, h3, h4 = 0.5 * h * h, h ** 3 / 12.0, h ** 4 / 24.0
    th1 = np.empty(2)
    om1 = np.empty(2)
    for g in range(2):
        th1[g] = qs_th[g] + h2 * zth[g] + h4 * t3th[g] / P.J[g]
        om1[g] = vs_th[g] + h * zth[g] + h3 * (t3th[g] + t4th[g]) / P.J[g]
    u1 = qs_u + h2 * zu + h4 * t3u / P.mass
    v1 = vs_u + h * zu + h3 * (t3u + t4u) / P.mass
    return th1, u1, om1, v1


@njit(cache=True)
def _z_col(P, theta, cn, cw, normal, j, zth, zu, nz_nodes):
    """``Z = M^-1 G^T e_j``, written only where it is nonzero; returns the node count."""
    m = 2 * P.rnode.size + 1
    zth[0] = 0.0
    zth[1] = 0.0
    if j < m - 1:
        k = j // 2
        a = j % 2
        i = P.rnode[k]
        px, py = root_phi_theta(P, theta, k)
        zth[P.rgear[k]] = -(px if a == 0 else py) / P.J[P.rgear[k]]
        zu[2 * i + a] = -1.0 / P.mass[2 * i + a]
        nz_nodes[0] = i
        return 1
    nnz = 0
    for jj in range(6):
        i = cn[jj]
        sign = 1.0 if jj < 3 else -1.0
        new = True
        for l in range(nnz):
            if nz_nodes[l] == i:
                new = False
        if new:
            nz_nodes[nnz] = i
            nnz += 1
        zu[2 * i] += sign * cw[jj] * normal[0] / P.mass[2 * i]
        zu[2 * i + 1] += sign * cw[jj] * normal[1] / P.mass[2 * i + 1]
    return nnz


@njit(cache=True)
def _columns(P, h, pred, theta, cn, cw, normal, j0, j1, Wq, Wv, scratch, mark, touched,
             nz_nodes, zu, acc3, acc4):
    """Columns ``j0:j1`` of the responses of the relevant rows (positions ``Wq``, velocities
    ``Wv``) to ``x = e_j``, the constraint directions at ``theta`` and the contact rows given.

    Everything here is sparse: ``Z = M^-1 G^T e_j`` lives on one node (a root multiplier) or
    the six contact nodes, and the tangents spread it one element further.
    """
    qs_th, qs_u, vs_th, vs_u, q3th, w3, kw3, q4th, w4, kw4, sl3, sl4 = pred
    h2, h3, h4 = 0.5 * h * h, h ** 3 / 12.0, h ** 4 / 24.0
    zth = np.empty(2)
    t3th = np.empty(2)
    t4th = np.empty(2)
    for j in range(j0, j1):
        Wq[:, j] = 0.0
        Wv[:, j] = 0.0
        nnz = _z_col(P, theta, cn, cw, normal, j, zth, zu, nz_nodes)
        for g in range(2):
            t3th[g] = zth[g] * sl3[g]
            t4th[g] = zth[g] * sl4[g]
        for k in range(nnz):
            i = nz_nodes[k]
            r = P.rel_pos[i]
            if r >= 0:
                for d in range(2):
                    Wq[2 + 2 * r + d, j] += h2 * zu[2 * i + d]
                    Wv[2 + 2 * r + d, j] += h * zu[2 * i + d]
        n3 = sparse_tangent(P, q3th, w3, kw3, zu, nz_nodes, nnz, scratch, mark, touched, t3th, acc3, 1.0)
        for k in range(n3):
            i = touched[k]
            r = P.rel_pos[i]
            for d in range(2):
                dof = 2 * i + d
                if r >= 0:
                    Wq[2 + 2 * r + d, j] += h4 * acc3[dof] / P.mass[dof]
                    Wv[2 + 2 * r + d, j] += h3 * acc3[dof] / P.mass[dof]
                acc3[dof] = 0.0
        n4 = sparse_tangent(P, q4th, w4, kw4, zu, nz_nodes, nnz, scratch, mark, touched, t4th, acc4, 1.0)
        for k in range(n4):
            i = touched[k]
            r = P.rel_pos[i]
            for d in range(2):
                dof = 2 * i + d
                if r >= 0:
                    Wv[2 + 2 * r + d, j] += h3 * acc4[dof] / P.mass[dof]
                acc4[dof] = 0.0
        for g in range(2):
            Wq[g, j] += h2 * zth[g] + h4 * t3th[g] / P.J[g]
            Wv[g, j] += h * zth[g] + h3 * (t3th[g] + t4th[g]) / P.J[g]
        for k in range(nnz):
            i = nz_nodes[k]
            zu[2 * i] = 0.0
            zu[2 * i + 1] = 0.0


@njit(cache=True)
def step(P, S, cfg):
    """Advance the state ``S`` by one step of the paper's method; returns a status code.

    ``cfg = [dt, tol_disp, tol_vel, tol_acc, max_iter, levels, eps_root, pin_after]``;
    ``pin_after`` 0 is the paper's method, ``k > 0`` the ``"pinned"`` one (see
    :data:`spurdyn.solver.case.METHODS`).
    """
    h = cfg[0]
    tol1, tol2, tol3 = cfg[1], cfg[2], cfg[3]
    cap = int(cfg[4])
    nlev = int(cfg[5])
    eps_root = cfg[6]
    pin_after = int(cfg[7])
    n = S.u.size
    m = S.x.size
    nn = n // 2
    th, om, u, v = S.theta, S.omega, S.u, S.v
    x0 = S.x.copy()

    pred = predict(P, S, h)
    qs_th, qs_u, vs_th, vs_u, q3th, w3, kw3, q4th, w4, kw4, sl3, sl4 = pred
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
    _columns(P, h, pred, S.theta, S.cn, S.cw, S.normal, np.int64(0), m, Wq, Wv, scratch, mark, touched,
             nz_nodes, zu, acc3, acc4)

    # relevant rows of the free state
    qs_rel = np.empty(R)
    vs_rel = np.empty(R)
    qs_rel[0], qs_rel[1] = qs_th[0], qs_th[1]
    vs_rel[0], vs_rel[1] = vs_th[0], vs_th[1]
    for k in range(nrel):
        i = P.rel_nodes[k]
        for d in range(2):
            qs_rel[2 + 2 * k + d] = qs_u[2 * i + d]
            vs_rel[2 + 2 * k + d] = vs_u[2 * i + d]

    # The forces are G^T x with the contact row where the contact now is; the prediction
    # used the last step's forces, so rel(x) = rel* - W0 x0 + W x.
    qs_rel -= Wq @ x0
    vs_rel -= Wv @ x0
    cn_f = S.cn.copy()
    cw_f = S.cw.copy()
    n_f = S.normal.copy()
    loc_f = np.array([S.cpar[0], S.cpar[1]])
    C = S.C
    Cp = np.empty((m, m))
    work = np.empty(m)
    e = np.empty(m)
    nd = P.fl_nodes.shape[1]
    va = np.empty((nd, 2))
    vb = np.empty((nd, 2))
    Ma = np.empty((nd, 2))
    Mb = np.empty((nd, 2))
    guess = np.array([S.cpar[0], S.cpar[1]])
    u_try = qs_u.copy()
    th_try = np.empty(2)

    # -- stage 1: displacements ---------------------------------------------------------
    x = x0.copy()
    a_c, b_c, mode, nxc, nyc, sc = 0.0, 0.0, 0, 0.0, 0.0, 0.0
    it = 0
    moves = 0
    mode_f = int(S.cpar[2])
    while True:
        rel = qs_rel + Wq @ x
        th_try[0], th_try[1] = rel[0], rel[1]
        for k in range(nrel):
            i = P.rel_nodes[k]
            u_try[2 * i] = rel[2 + 2 * k]
            u_try[2 * i + 1] = rel[3 + 2 * k]
        for k in range(P.rnode.size):
            i = P.rnode[k]
            c, s = _rot(P, th_try, P.rgear[k])
            yx, yy = P.Y[2 * i], P.Y[2 * i + 1]
            e[2 * k] = -(u_try[2 * i] - (c * yx - s * yy - yx))
            e[2 * k + 1] = -(u_try[2 * i + 1] - (s * yx + c * yy - yy))
        # The search also refits the flank splines (va, vb, Ma, Mb) that the later stages'
        # sliding terms read, so it runs even when the pair is then pinned.
        a_c, b_c, mode, nxc, nyc, sc = search(P, th_try, u_try, guess, va, vb, Ma, Mb)
        if pin_after > 0 and it >= pin_after and moves >= MAX_RELOCATE:
            # "pinned": the gap where the force acts, along its normal
            a_c, b_c, mode, nxc, nyc = loc_f[0], loc_f[1], mode_f, n_f[0], n_f[1]
            xa, ya = material_point(P, np.int64(0), a_c, th_try[0], u_try, np.int64(0), 0.0, 0.0)
            xb, yb = material_point(P, np.int64(1), b_c, th_try[1], u_try, np.int64(0), 0.0, 0.0)
            sc = nxc * (xa - xb) + nyc * (ya - yb)
        guess[0], guess[1] = a_c, b_c
        e[m - 1] = sc if (x[m - 1] < 0.0 or sc > 0.0) else 0.0
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
        accelerated_update(x, e, C, h2, nlev, eps_root, Cp, work)
        if abs(a_c - loc_f[0]) + abs(b_c - loc_f[1]) > RELOCATE and moves < MAX_RELOCATE:
            # the contact force acts where the contact now is
            moves += 1
            loc_f[0], loc_f[1] = a_c, b_c
            mode_f = mode
            contact_rows(P, a_c, b_c, cn_f, cw_f)
            n_f[0], n_f[1] = nxc, nyc
            _columns(P, h, pred, S.theta, cn_f, cw_f, n_f, m - 1, m, Wq, Wv, scratch, mark,
                     touched, nz_nodes, zu, acc3, acc4)
            gram_contact(P, cn_f, cw_f, n_f, C)
        it += 1
    S.res[0] = res
    S.its[0] = it
    p_bar = x[m - 1]

    # full positions at t + dt by superposition
    th1, u1, _, _ = superpose(P, S, h, pred, x, cn_f, cw_f, n_f, np.bool_(False))
    cn1 = np.empty(6, dtype=np.int64)
    cw1 = np.empty(6)
    contact_rows(P, a_c, b_c, cn1, cw1)
    n1 = np.array([nxc, nyc])

    # -- stage 2: velocities (positions from stage 1, same force directions) ---------------
    it = 0
    v_try = vs_u.copy()
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
        pax, pay = material_point(P, np.int64(0), a_c, th1[0], v_try, np.int64(1), om_try[0], 0.0)
        pbx, pby = material_point(P, np.int64(1), b_c, th1[1], v_try, np.int64(1), om_try[1], 0.0)
        sh = nxc * (pax - pbx) + nyc * (pay - pby)
        e[m - 1] = sh if (p_bar < 0.0 and (sh > 0.0 or x[m - 1] < 0.0)) else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[1] = res
            return FAIL_NAN
        if res <= tol2:
            break
        if it >= cap:
            S.res[1] = res
            S.its[1] = it
            return FAIL_VEL
        accelerated_update(x, e, C, h, nlev, eps_root, Cp, work)
        it += 1
    S.res[1] = res
    S.its[1] = it

    _, _, om1, v1 = superpose(P, S, h, pred, x, cn_f, cw_f, n_f, np.bool_(True))

    # -- stage 3: accelerations at t + dt -----------------------------------------------
    zero2 = np.zeros(2)
    al_free = np.empty(2)
    a_free = np.empty(n)
    accelerations(th1, u1, zero2, zero_u, P, w, kw, el, qq, al_free, a_free)
    gram(P, th1, cn1, cw1, n1, C)
    extra = sliding(P, th1, om1, u1, v1, a_c, b_c, mode, nxc, nyc, va, vb, Ma, Mb)
    fth = np.empty(2)
    fu = np.empty(n)
    a_try = np.empty(n)
    al_try = np.empty(2)
    it = 0
    while True:
        constraint_force(P, th1, cn1, cw1, n1, x, fth, fu)
        for g in range(2):
            al_try[g] = al_free[g] + fth[g] / P.J[g]
        for k in range(P.rnode.size):
            i = P.rnode[k]
            g = P.rgear[k]
            px, py = root_phi_theta(P, th1, k)
            c, s = _rot(P, th1, g)
            yx, yy = P.Y[2 * i], P.Y[2 * i + 1]
            ax = a_free[2 * i] + fu[2 * i] / P.mass[2 * i]
            ay = a_free[2 * i + 1] + fu[2 * i + 1] / P.mass[2 * i + 1]
            e[2 * k] = -(ax + px * al_try[g]) - (c * yx - s * yy) * om1[g] ** 2
            e[2 * k + 1] = -(ay + py * al_try[g]) - (s * yx + c * yy) * om1[g] ** 2
        for j in range(6):
            i = cn1[j]
            a_try[2 * i] = a_free[2 * i] + fu[2 * i] / P.mass[2 * i]
            a_try[2 * i + 1] = a_free[2 * i + 1] + fu[2 * i + 1] / P.mass[2 * i + 1]
        pax, pay = material_point(P, np.int64(0), a_c, th1[0], a_try, np.int64(2), om1[0], al_try[0])
        pbx, pby = material_point(P, np.int64(1), b_c, th1[1], a_try, np.int64(2), om1[1], al_try[1])
        st = nxc * (pax - pbx) + nyc * (pay - pby) + extra
        e[m - 1] = st if (p_bar < 0.0 and (st > 0.0 or x[m - 1] < 0.0)) else 0.0
        res = max_abs(e)
        if not math.isfinite(res):
            S.res[2] = res
            return FAIL_NAN
        if res <= tol3:
            break
        if it >= cap:
            S.res[2] = res
            S.its[2] = it
            return FAIL_ACC
        accelerated_update(x, e, C, 1.0, nlev, eps_root, Cp, work)
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
    constraint_force(P, th1, cn1, cw1, n1, x, fth, fu)
    for g in range(2):
        S.alpha_n[g] = al_free[g] + fth[g] / P.J[g]
    for i in range(n):
        S.a_n[i] = a_free[i] + fu[i] / P.mass[i]
    th[:] = th1
    om[:] = om1
    u[:] = u1
    v[:] = v1
    S.x[:] = x
    S.cn[:] = cn1
    S.cw[:] = cw1
    S.normal[:] = n1
    S.cpar[0], S.cpar[1], S.cpar[2], S.cpar[3] = a_c, b_c, mode, sc
    S.t[0] += h
    return OK


@njit(cache=True)
def advance(P, S, cfg, n_steps, angle_end, save_every, rows, frames_every, frames, index0):
    """Up to ``n_steps`` steps; stops when gear A has turned ``angle_end`` or a step fails.

    Returns ``(steps, rows_written, frames_written, status)``.
    """
    nr = 0
    nf = 0
    for k in range(n_steps):
        if S.theta[0] >= angle_end:
            return k, nr, nf, 0
        status = step(P, S, cfg)
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
            frames[nf, 3:] = S.u
            nf += 1
    return n_steps, nr, nf, 0


@njit(cache=True)
def write_row(P, S, row):
    ta, _ = torque(P.tpar, np.int64(0), S.theta[0])
    tb, _ = torque(P.tpar, np.int64(1), S.theta[1])
    row[0] = S.t[0]
    row[1] = S.theta[0]
    row[2] = S.theta[1]
    row[3] = S.omega[0]
    row[4] = S.omega[1]
    row[5] = ta
    row[6] = tb
    row[7] = S.x[S.x.size - 1]
    row[8] = S.cpar[3]
    row[9] = S.cpar[0]
    row[10] = S.cpar[1]
    row[11] = S.cpar[2]
    row[12] = S.res[0]
    row[13] = S.res[1]
    row[14] = S.res[2]
    row[15] = S.its[0]
    row[16] = S.its[1]
    row[17] = S.its[2]
