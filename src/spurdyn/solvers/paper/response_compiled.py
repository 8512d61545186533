"""The response of the compiled RK4 step to a change of the constraint forces.

Within a step the constraint force ``G_n^T x`` is held fixed, so the RK4 result is
affine in ``x`` (to round-off: the only nonlinearity is the disk rotation, which the
forces change by ~1e-11 rad in a step). The step integrates once with the forces of the
previous step, ``x0`` (:func:`predict`), and then adds the exact linear response of the
RK4 map,

    dq = h^2/2 Z + h^4/24 M^-1 T3 Z,    dv = h Z + h^3/12 M^-1 (T3 + T4) Z,
    Z  = M^-1 G_n^T (x - x0),

``T3``, ``T4`` the tangent of the forces at RK4's third and fourth stage states
(docs/solver.md). Its NumPy twin is the re-integration of
:meth:`spurdyn.solvers.paper.step_numpy.PaperMethod.rk4`; tests/test_paper_step.py
checks the whole step against it, tests/test_paper_dynamics.py the tangent.
"""

from __future__ import annotations

import numpy as np

from spurdyn.jit import njit
from spurdyn.solvers.layout import Prediction, SparseWork, StepResponse
from spurdyn.solvers.paper.dynamics_compiled import (
    accelerations, constraint_force, root_phi_theta, rotation, torque,
)


@njit
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
        c, s = rotation(P, th, g)
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
        c, s = rotation(P, th, g)
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


@njit
def _response_full(P, pred, zth, zu, nz_nodes, nnz, scratch, mark, touched, t3th, t3u, t4th, t4u,
                   want4):
    """``T3 Z`` (and ``T4 Z`` if ``want4``) as full vectors for ``Z = (zth, zu)``, the
    tangents those of the prediction ``pred``."""
    t3u[:] = 0.0
    t4u[:] = 0.0
    for g in range(2):
        t3th[g] = zth[g] * pred.sl3[g]
        t4th[g] = zth[g] * pred.sl4[g]
    sparse_tangent(P, pred.q3th, pred.w3, pred.kw3, zu, nz_nodes, nnz, scratch, mark, touched, t3th, t3u, 1.0)
    if want4:
        sparse_tangent(P, pred.q4th, pred.w4, pred.kw4, zu, nz_nodes, nnz, scratch, mark, touched, t4th, t4u,
                       1.0)


@njit
def _z_of(P, theta, cn, cw, normal, gth, dx, zth, zu, nz_nodes, mark):
    """``Z = M^-1 G^T dx`` with ``G`` at ``theta`` and the contact rows ``cn, cw, normal,
    gth``; returns the number of nodes (listed in ``nz_nodes``) where ``zu`` is nonzero."""
    constraint_force(P, theta, cn, cw, normal, gth, dx, zth, zu)
    for g in range(2):
        zth[g] /= P.J[g]
    nnz = 0
    for k in range(P.rnode.size):
        i = P.rnode[k]
        if mark[i] == 0:
            mark[i] = 1
            nz_nodes[nnz] = i
            nnz += 1
    for j in range(cn.size):
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


@njit
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
    constraint_force(P, th, S.cn, S.cw, S.normal, S.gth, x0, fth0, fu0)
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
    return Prediction(qs_th, qs_u, vs_th, vs_u, q3th, w3, kw3, q4th, w4, kw4, sl3, sl4)


@njit
def superpose(P, S, h, pred, x, cn, cw, normal, gth, want_v):
    """The end state of RK4 with the forces ``G^T x`` (contact row at ``cn, cw, normal, gth``):
    ``pred`` (made with the last step's forces) plus the linear response to the change."""
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
    nnz = _z_of(P, S.theta, cn, cw, normal, gth, x, zth, zu, nz_nodes, mark)
    nnz0 = _z_of(P, S.theta, S.cn, S.cw, S.normal, S.gth, S.x, zth0, zu0, nz_nodes[nnz:], mark)
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
    _response_full(P, pred, zth, zu, nz_nodes, total, scratch, mark, touched, t3th, t3u, t4th, t4u, want_v)
    h2, h3, h4 = 0.5 * h * h, h ** 3 / 12.0, h ** 4 / 24.0
    th1 = np.empty(2)
    om1 = np.empty(2)
    for g in range(2):
        th1[g] = pred.qs_th[g] + h2 * zth[g] + h4 * t3th[g] / P.J[g]
        om1[g] = pred.vs_th[g] + h * zth[g] + h3 * (t3th[g] + t4th[g]) / P.J[g]
    u1 = pred.qs_u + h2 * zu + h4 * t3u / P.mass
    v1 = pred.vs_u + h * zu + h3 * (t3u + t4u) / P.mass
    return th1, u1, om1, v1


@njit
def _z_col(P, theta, cn, cw, normal, gth, j, zth, zu, nz_nodes):
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
    zth[0] = gth[0] / P.J[0]
    zth[1] = gth[1] / P.J[1]
    nnz = 0
    half = cn.size // 2
    for jj in range(cn.size):
        i = cn[jj]
        sign = 1.0 if jj < half else -1.0
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


@njit
def response_columns(P, h, pred, theta, cn, cw, normal, gth, j0, j1, Wq, Wv, work):
    """Columns ``j0:j1`` of the responses of the relevant rows (positions ``Wq``, velocities
    ``Wv``) to ``x = e_j``, the constraint directions at ``theta`` and the contact rows given;
    ``work`` the sparse workspace (:data:`~spurdyn.solvers.layout.SparseWork`), left clean.

    Everything here is sparse: ``Z = M^-1 G^T e_j`` lives on one node (a root multiplier) or
    the six contact nodes, and the tangents spread it one element further.
    """
    scratch, mark, touched, nz_nodes = work.scratch, work.mark, work.touched, work.nz_nodes
    zu, acc3, acc4 = work.zu, work.acc3, work.acc4
    h2, h3, h4 = 0.5 * h * h, h ** 3 / 12.0, h ** 4 / 24.0
    zth = np.empty(2)
    t3th = np.empty(2)
    t4th = np.empty(2)
    for j in range(j0, j1):
        Wq[:, j] = 0.0
        Wv[:, j] = 0.0
        nnz = _z_col(P, theta, cn, cw, normal, gth, j, zth, zu, nz_nodes)
        for g in range(2):
            t3th[g] = zth[g] * pred.sl3[g]
            t4th[g] = zth[g] * pred.sl4[g]
        for k in range(nnz):
            i = nz_nodes[k]
            r = P.rel_pos[i]
            if r >= 0:
                for d in range(2):
                    Wq[2 + 2 * r + d, j] += h2 * zu[2 * i + d]
                    Wv[2 + 2 * r + d, j] += h * zu[2 * i + d]
        n3 = sparse_tangent(P, pred.q3th, pred.w3, pred.kw3, zu, nz_nodes, nnz, scratch, mark, touched, t3th, acc3, 1.0)
        for k in range(n3):
            i = touched[k]
            r = P.rel_pos[i]
            for d in range(2):
                dof = 2 * i + d
                if r >= 0:
                    Wq[2 + 2 * r + d, j] += h4 * acc3[dof] / P.mass[dof]
                    Wv[2 + 2 * r + d, j] += h3 * acc3[dof] / P.mass[dof]
                acc3[dof] = 0.0
        n4 = sparse_tangent(P, pred.q4th, pred.w4, pred.kw4, zu, nz_nodes, nnz, scratch, mark, touched, t4th, acc4, 1.0)
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


@njit
def free_rows(P, S, h, pred):
    """The response matrices on the rows the constraints read, for the forces on the last
    step's contact rows, and the free state there (a
    :class:`~spurdyn.solvers.layout.StepResponse`)."""
    m = S.x.size
    n = S.u.size
    nn = n // 2
    nrel = P.rel_nodes.size
    R = 2 + 2 * nrel
    Wq = np.zeros((R, m))
    Wv = np.zeros((R, m))
    sparse = SparseWork(np.zeros(n), np.zeros(nn, dtype=np.int64), np.empty(nn, dtype=np.int64),
                        np.empty(nn, dtype=np.int64), np.zeros(n), np.zeros(n), np.zeros(n))
    response_columns(P, h, pred, S.theta, S.cn, S.cw, S.normal, S.gth, np.int64(0), m, Wq, Wv, sparse)
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
    x0 = S.x.copy()
    qs_rel -= Wq @ x0
    vs_rel -= Wv @ x0
    return StepResponse(Wq, Wv, qs_rel, vs_rel, sparse)
