"""The twins of response_compiled.py against the RK4 response formula of docs/solver.md: each compiled function against its NumPy counterpart
(tolerances and the realistic state: tests/twin_helpers.py)."""


from dataclasses import replace

import numpy as np

from spurdyn.solvers.paper import dynamics_compiled as dyn_c
from spurdyn.solvers.paper import response_compiled as resp_c
from spurdyn.solvers.paper import dynamics_numpy as dyn_np
from spurdyn.solvers.layout import SparseWork

from twin_helpers import (  # noqa: F401
    EPS, JZ, Loaded, elastic_np, tangent_np, q_bound, node_size, cross_size, worst, rigid_plus_noise, _synthetic_contact, _gram_ref, ROLLING,
)


def test_sparse_tangent_is_the_tangent_on_a_few_nodes(loaded):
    """``resp_c.sparse_tangent`` adds ``coef T(0, z_u)`` for a ``z_u`` living on a few nodes
    (as ``M^-1 G^T x`` does: the root and contact nodes), which is ``tangent``'s NumPy
    formula with ``d_theta = 0``; its work arrays come back zero and ``touched`` lists the
    nodes of the stiffness rows reached."""
    st, P, S = loaded, loaded.P, loaded.S
    n, nn = S.u.size, S.u.size // 2
    rng = np.random.default_rng(5)
    w, kw, el, q = np.empty(n), np.empty(n), np.empty(n), np.empty(2)
    dyn_c.elastic(S.theta, S.u, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep, w, kw, el, q)
    nodes = np.unique(np.concatenate([P.rnode, st.rows(st.contact)[0]])).astype(np.int64)
    zu = np.zeros(n)
    zu[np.ravel(np.column_stack([2 * nodes, 2 * nodes + 1]))] = 1e5 * rng.standard_normal(2 * nodes.size)
    out_th0, out_u0 = rng.standard_normal(2), rng.standard_normal(n)
    out_th, out_u = out_th0.copy(), out_u0.copy()
    scratch, mark = np.zeros(n), np.zeros(nn, np.int64)
    touched = np.empty(nn, np.int64)
    coef = 0.7
    nt = resp_c.sparse_tangent(P, S.theta, w, kw, zu, nodes, nodes.size, scratch, mark, touched,
                                  out_th, out_u, coef)
    rth, ru = tangent_np(st, S.theta, w, kw, np.zeros(2), zu)
    tol_u = 8 * EPS * coef * (st.absK @ node_size(zu)).max() + 4 * EPS * np.abs(out_u0).max()
    tol_th = 8 * EPS * coef * (cross_size(zu, kw) + cross_size(w, st.absK @ node_size(zu)))
    assert worst(out_u, out_u0 + coef * ru) <= tol_u
    assert worst(out_th, out_th0 + coef * rth) <= tol_th + 4 * EPS * np.abs(out_th0).max()
    reached = np.unique((st.K[np.ravel(np.column_stack([2 * nodes, 2 * nodes + 1]))].nonzero()[1]) // 2)
    assert np.array_equal(np.sort(touched[:nt]), reached)
    assert not scratch.any() and not mark.any()
    print(f"sparse_tangent: u {worst(out_u, out_u0 + coef * ru):.1e} N (tol {tol_u:.1e}, "
          f"max {np.abs(coef * ru).max():.1e}); theta {worst(out_th, out_th0 + coef * rth):.1e} N m "
          f"(tol {tol_th:.1e}, {np.abs(coef * rth).max():.1e})")
    # a change of z_u by a part in 1e9 on one node shows
    zu2 = zu.copy()
    zu2[2 * nodes[3]] *= 1.0 + 1e-9
    o2 = out_u0.copy()
    resp_c.sparse_tangent(P, S.theta, w, kw, zu2, nodes, nodes.size, scratch, mark, touched,
                             out_th0.copy(), o2, coef)
    assert worst(o2, out_u) > 10 * tol_u


def test_z_and_response_columns_match_the_rk4_response_formula(loaded):
    """``_z_of``/``_z_col`` (``Z = M^-1 G^T x``, nonzero on the root and contact nodes) against
    ``inverse_mass * jacobian^T x``; and ``_columns``, the response of the relevant rows to
    ``x = e_j``, against docs/solver.md section 7/8 written in NumPy:
    ``dq = h^2/2 Z + h^4/24 M^-1 T3 Z``, ``dv = h Z + h^3/12 M^-1 (T3 + T4) Z``, ``T3``, ``T4``
    the force tangents at RK4's third and fourth stage states with the disk part reduced to
    the torque schedule's slope (``tangent_np`` with ``d_theta = 0``, plus ``tau' Z_theta``)."""
    st, P, S = loaded, loaded.P, loaded.S
    m, n, nn = S.x.size, S.u.size, S.u.size // 2
    h = st.case.dt
    # the contact row with a strip's disk entries (docs/solver.md 11.3): their torques go
    # through Z and the response columns too
    c = replace(st.contact, theta_row=ROLLING)
    cn, cw = st.rows(c)
    gmat = dyn_np.jacobian(st.system, S.theta, c)
    minv = dyn_np.inverse_mass(st.system)
    # Z for the state's x
    zth, zu, nz, mark = np.empty(2), np.zeros(n), np.empty(nn, np.int64), np.zeros(nn, np.int64)
    nnz = resp_c._z_of(P, S.theta, cn, cw, c.normal, st.gth(c), S.x, zth, zu, nz, mark)
    want = minv * (gmat.T @ S.x)
    size = minv * (np.abs(gmat.T) @ np.abs(S.x))
    assert np.all(np.abs(np.concatenate([zth, zu]) - want) <= 4 * EPS * size)
    assert np.array_equal(np.sort(nz[:nnz]), np.unique(np.concatenate([P.rnode, cn])))
    assert not mark.any()
    # response columns
    pred = resp_c.predict(P, S, h)
    q3th, w3, kw3, q4th, w4, kw4, sl3, sl4 = pred[4:]
    rel = P.rel_nodes
    R = 2 + 2 * rel.size
    Wq, Wv = np.zeros((R, m)), np.zeros((R, m))
    scratch, touched, acc3, acc4 = np.zeros(n), np.empty(nn, np.int64), np.zeros(n), np.zeros(n)
    zu = np.zeros(n)
    resp_c.response_columns(P, h, pred, S.theta, cn, cw, c.normal, st.gth(c), 0, m, Wq, Wv,
                            SparseWork(scratch, mark, touched, nz, zu, acc3, acc4))
    assert not (scratch.any() or mark.any() or zu.any() or acc3.any() or acc4.any())
    rows = np.concatenate([[0, 1], 2 + np.ravel(np.column_stack([2 * rel, 2 * rel + 1]))])
    mass = np.concatenate([[P.J[0], P.J[1]], P.mass])
    big = np.zeros(2)
    for j in range(m):
        z = minv * gmat[j]                       # M^-1 G^T e_j
        zcol_th, zcol_u, nzc = np.empty(2), np.zeros(n), np.empty(nn, np.int64)
        k = resp_c._z_col(P, S.theta, cn, cw, c.normal, st.gth(c), j, zcol_th, zcol_u, nzc)
        assert np.all(np.abs(np.concatenate([zcol_th, zcol_u]) - z) <= 4 * EPS * np.abs(z))
        assert set(nzc[:k]) == set(np.flatnonzero(z[2:]) // 2)
        t3th, t3u = tangent_np(st, q3th, w3, kw3, np.zeros(2), z[2:])
        t4th, t4u = tangent_np(st, q4th, w4, kw4, np.zeros(2), z[2:])
        t3 = np.concatenate([t3th + sl3 * z[:2], t3u])
        t4 = np.concatenate([t4th + sl4 * z[:2], t4u])
        dq = 0.5 * h * h * z + h**4 / 24 * t3 / mass
        dv = h * z + h**3 / 12 * (t3 + t4) / mass
        # round-off: of Z, and of the tangent products (|K| |z|, and the disk sums)
        kz = st.absK @ node_size(z[2:])
        t3size, t4size = (np.concatenate([[cross_size(z[2:], kw_) + cross_size(w_, kz)
                                           + np.abs(sl_ * z[:2]).max()] * 2, kz])
                          for w_, kw_, sl_ in ((w3, kw3, sl3), (w4, kw4, sl4)))
        tq = 8 * EPS * (0.5 * h * h * np.abs(z) + h**4 / 24 * t3size / mass)
        tv = 8 * EPS * (h * np.abs(z) + h**3 / 12 * (t3size + t4size) / mass)
        assert np.all(np.abs(Wq[:, j] - dq[rows]) <= tq[rows])
        assert np.all(np.abs(Wv[:, j] - dv[rows]) <= tv[rows])
        big = np.maximum(big, [np.max(np.abs(Wq[:, j] - dq[rows]) / np.abs(dq[rows]).max()),
                               np.max(np.abs(Wv[:, j] - dv[rows]) / np.abs(dv[rows]).max())])
        # the stiffness term is resolved: dropping it would fail
        stiff = h**4 / 24 * t3 / mass
        assert np.max(np.abs(stiff[rows]) - tq[rows]) > 0
    print(f"_columns: worst difference relative to the column (positions, velocities): {big}")

