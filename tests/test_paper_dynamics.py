"""The twins of dynamics_numpy.py and dynamics_compiled.py (and model.loading's torque schedule): each compiled function against its NumPy counterpart
(tolerances and the realistic state: tests/twin_helpers.py)."""


from dataclasses import replace

import numpy as np
import pytest

from spurdyn.solvers.paper import dynamics_compiled as dyn_c
from spurdyn.model.loading import gear_angles, gear_torques
from spurdyn.solvers.paper import dynamics_numpy as dyn_np

from twin_helpers import (  # noqa: F401
    EPS, JZ, Loaded, elastic_np, tangent_np, q_bound, tangent_q_bound, node_size, cross_size, worst, rigid_plus_noise, _synthetic_contact, _gram_ref, ROLLING,
)


def test_bsr_matvec_is_the_sparse_stiffness_product(loaded):
    """``bsr_matvec`` on the packed 2 x 2 blocks is SciPy's product with the stacked ``K``,
    to the round-off of the sums (``EPS |K| |v|``)."""
    st, P = loaded, loaded.P
    rng = np.random.default_rng(1)
    w = elastic_np(st.system, st.S.theta, st.S.u)
    for v in (w, 1e-6 * rng.standard_normal(w.size)):
        out = np.empty_like(v)
        dyn_c.bsr_matvec(P.indptr, P.indices, P.data, v, out)
        tol = 8 * EPS * (st.absK @ np.abs(v)).max()
        assert worst(out, st.K @ v) <= tol
        print(f"bsr_matvec: {worst(out, st.K @ v):.2e} N (tol {tol:.1e}, "
              f"max |Kv| {np.abs(st.K @ v).max():.1e})")
        # the block orientation matters: data[k, a, b] is row a, column b of the block
        out_t = np.empty_like(v)
        dyn_c.bsr_matvec(P.indptr, P.indices, np.ascontiguousarray(P.data.transpose(0, 2, 1)), v, out_t)
        assert worst(out_t, out) > 1e6 * tol
        # and one block changed by a part in 1e9 shows
        data = P.data.copy()
        data[P.indptr[100]] *= 1.0 + 1e-9
        dyn_c.bsr_matvec(P.indptr, P.indices, data, v, out_t)
        assert worst(out_t, out) > 10 * tol


def test_torque_follows_the_fig7_schedule(loaded):
    """``torque`` (value and slope) against :func:`spurdyn.model.loading.gear_torques`:
    values to round-off over the whole schedule (before, ramps, plateau, after, and the
    kinks), slopes against central differences of ``gear_torques`` inside each piece."""
    st, P = loaded, loaded.P
    pair, tau0 = st.system.pair, st.case.torque
    angles = gear_angles(pair)
    for g in range(2):
        ts, t2 = angles[g]
        kinks = [0.0, t2, ts - t2, ts]
        th = np.concatenate([np.linspace(-0.05, ts + 0.05, 401), kinks])
        want = gear_torques(pair, tau0, th, th)[g]
        got = np.array([dyn_c.torque(P.tpar, g, t)[0] for t in th])
        amp = abs(want).max()
        ratio = 1.0 if g == 0 else pair.gear_b.base_radius / pair.gear_a.base_radius
        assert amp == pytest.approx(tau0 * ratio)
        assert worst(got, want) <= 4 * EPS * amp
        # slopes, away from the kinks by more than the difference step
        h = 1e-6
        mids = np.array([-0.02, 0.3 * t2, 0.9 * t2, 0.5 * ts, ts - 0.7 * t2, ts - 0.1 * t2, ts + 0.02])
        fd = (gear_torques(pair, tau0, mids + h, mids + h)[g]
              - gear_torques(pair, tau0, mids - h, mids - h)[g]) / ((mids + h) - (mids - h))
        slope = np.array([dyn_c.torque(P.tpar, g, t)[1] for t in mids])
        tol = 4 * EPS * amp / h + 4 * EPS * amp / t2
        assert worst(slope, fd) <= tol
        assert np.abs(slope).max() == pytest.approx(amp / t2, rel=1e-12)   # the ramps are there
        print(f"torque gear {g}: values {worst(got, want):.1e} N m, slopes {worst(slope, fd):.1e} N m/rad "
              f"(tol {tol:.1e}, slope {amp / t2:.1f})")
        # the start of the ramp moved by 1e-9 rad shows in the values
        tpar = P.tpar.copy()
        tpar[g, 2] *= 1.0 + 1e-9
        moved = np.array([dyn_c.torque(tpar, g, t)[0] for t in th])
        assert worst(moved, got) > 100 * 4 * EPS * amp


def test_root_phi_theta_matches_reference(loaded):
    """``root_phi_theta(P, theta, k)`` is row ``k`` of :func:`spurdyn.solvers.paper.step_numpy.root_phi_theta`
    (``-s R Jz Y_i``), node by node for both gears, to ``EPS |Y|``."""
    st, P = loaded, loaded.P
    nra = st.system.gears[0].root_nodes.size
    big = 0.0
    for theta in (st.S.theta, np.array([0.3, -1.2])):
        got = np.array([dyn_c.root_phi_theta(P, theta, k) for k in range(P.rnode.size)])
        want = np.concatenate([dyn_np.root_phi_theta(gb, theta[g]) for g, gb in enumerate(st.system.gears)])
        tol = 4 * EPS * np.abs(P.Y).max()
        big = max(big, worst(got, want))
        assert worst(got, want) <= tol
        # the kernel's rows are in the order of P.rnode: A's root nodes, then B's
        assert np.array_equal(P.rnode[nra:] - st.na, st.system.gears[1].root_nodes)
        moved = np.array([dyn_c.root_phi_theta(P, theta + 1e-12, k) for k in range(P.rnode.size)])
        assert worst(moved, got) > 100 * tol
    print(f"root_phi_theta: {big:.1e} m (tol {tol:.1e})")


@pytest.mark.parametrize("where", ["stepped", "random"])
@pytest.mark.parametrize("keep", [1, 0])
def test_elastic_forces_and_disk_torques_match_reference(loaded, where, keep):
    """``elastic`` against :func:`spurdyn.solvers.paper.step_numpy.elastic` (``f_u = -R K w``,
    ``Q = s sum w x K w``), on the stepped state and on teeth turned by large angles with
    random 1e-6 m displacements, with and without the disk torque term.

    ``w``: to ``EPS |Y + u|``. ``K w`` and ``f_u`` from the kernel's ``w``: to the round-off
    of the product. ``f_u`` and ``Q`` against the reference's own ``w``: to what the
    rounding of ``w`` makes of them, ``EPS |K| |Y + u|`` and :func:`q_bound`.
    """
    st = loaded
    P = st.P._replace(keep=keep)
    if where == "stepped":
        theta, u = st.S.theta.copy(), st.S.u.copy()
    else:
        theta = np.array([0.4, -0.25])
        u = rigid_plus_noise(st, theta, 1e-6, 3)
    n = u.size
    w, kw, f, q = np.empty(n), np.empty(n), np.empty(n), np.empty(2)
    dyn_c.elastic(theta, u, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep, w, kw, f, q)
    y = np.abs(P.Y + u)
    ky = st.absK @ node_size(y)              # |K| |y|, y turned by the disk
    # w and K w
    assert worst(w, elastic_np(st.system, theta, u)) <= 4 * EPS * node_size(y).max()
    assert worst(kw, st.K @ w) <= 8 * EPS * (st.absK @ np.abs(w)).max()
    diffs = {}
    for g, gb in enumerate(st.system.gears):
        r = dyn_np.rot(gb.sense * theta[g])
        fg = st.block(g, f)
        # -R K w from the kernel's w: the product's round-off
        own = -(st.block(g, st.K @ w).reshape(-1, 2) @ r.T).ravel()
        assert worst(fg, own) <= 8 * EPS * (st.block(g, st.absK @ np.abs(w))).max()
        # the reference's own w
        q_ref, f_ref = dyn_np.elastic(gb, theta[g], st.block(g, u), bool(keep))
        tol_f = 4 * EPS * st.block(g, ky).max()
        assert worst(fg, f_ref) <= tol_f
        tol_q = q_bound(st, g, y, w, kw)
        assert abs(q[g] - q_ref) <= tol_q
        if not keep:
            assert q[g] == 0.0
        diffs[g] = (worst(fg, f_ref), tol_f, abs(q[g] - q_ref), tol_q, abs(q_ref))
        # one node 1e-9 m off (of ~1e-6 m deformations) shows in the forces and the torque
        # far beyond that (a disk rotation would not: K annihilates it to first order)
        w_, kw_, f_, q_ = np.empty(n), np.empty(n), np.empty(n), np.empty(2)
        u_ = u.copy()
        st.block(g, u_)[2 * 100] += 1e-9
        dyn_c.elastic(theta, u_, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep,
                        w_, kw_, f_, q_)
        assert worst(st.block(g, f_), fg) > 100 * tol_f
        if keep:
            assert abs(q_[g] - q[g]) > 100 * tol_q
    print(f"elastic {where} keep={keep}: (|df|, tol, |dQ|, tol, |Q|) per gear",
          {g: tuple(f"{x:.1e}" for x in d) for g, d in diffs.items()})


def test_accelerations_match_reference(loaded):
    """``accelerations`` (torque schedule, elastic forces, a given constraint force) against
    :meth:`PaperMethod.accelerations`, with the contact and root forces of the state."""
    st, P, S = loaded, loaded.P, loaded.S
    fth, fu = dyn_np.constraint_force(st.system, S.theta, st.contact, S.x)
    n = S.u.size
    w, kw, el, q, alpha, a = (np.empty(n), np.empty(n), np.empty(n), np.empty(2), np.empty(2), np.empty(n))
    dyn_c.accelerations(S.theta, S.u, fth, fu, P, w, kw, el, q, alpha, a)
    alpha_ref, a_ref = st.ref.accelerations(S.theta, S.u, fth, fu)
    y = np.abs(P.Y + S.u)
    ky = st.absK @ node_size(y)
    tol_a = 4 * EPS * ((ky + np.abs(fu)) / P.mass).max()
    # the disk: torque, elastic torque (second order, bounded as in the elastic test), force
    tau = st.ref.torques(S.theta)
    qb = np.array([q_bound(st, g, y, w, kw) for g in range(2)])
    tol_al = (4 * EPS * (np.abs(tau) + np.abs(fth)) + qb) / P.J
    assert worst(a, a_ref) <= tol_a
    assert np.all(np.abs(alpha - alpha_ref) <= tol_al)
    print(f"accelerations: a {worst(a, a_ref):.1e} m/s^2 (tol {tol_a:.1e}, max |a| {np.abs(a_ref).max():.1e}); "
          f"alpha {worst(alpha, alpha_ref):.1e} rad/s^2 (tol {tol_al.max():.1e}, "
          f"|alpha| {np.abs(alpha_ref).max():.1e})")
    # the constraint force enters: without the contact force the teeth accelerate differently
    fth0, fu0 = dyn_np.constraint_force(st.system, S.theta, st.contact, np.append(S.x[:-1], 0.0))
    a0 = np.empty(n)
    dyn_c.accelerations(S.theta, S.u, fth0, fu0, P, w, kw, el, q, np.empty(2), a0)
    assert worst(a0, a) > 100 * tol_a


def test_tangent_formula_is_the_derivative_of_the_forces(loaded):
    """The tangent ``dF/dq . (d_theta, d_u)`` (F the disk torques and tooth forces) of
    docs/solver.md, in NumPy (``tangent_np``, which ``resp_c.sparse_tangent`` is checked
    against below), against differences of the reference forces
    (:func:`spurdyn.solvers.paper.step_numpy.elastic` plus the Fig. 7 torques): along ``u`` the
    central difference is exact (``f_u`` is affine and ``Q`` quadratic in ``u``), so it
    agrees to the round-off of the forces; along ``theta`` a fourth-order difference
    agrees to its truncation error, bounded by its change when the step is doubled."""
    st, P, S = loaded, loaded.P, loaded.S
    n = S.u.size
    rng = np.random.default_rng(4)
    w, kw, el, q = np.empty(n), np.empty(n), np.empty(n), np.empty(2)
    dyn_c.elastic(S.theta, S.u, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep, w, kw, el, q)
    slopes = np.array([dyn_c.torque(P.tpar, g, S.theta[g])[1] for g in range(2)])
    assert np.all(slopes != 0.0)

    def kernel(d_th, d_u):
        oth, ou = tangent_np(st, S.theta, w, kw, d_th, d_u, True)
        return oth + slopes * d_th, ou, None

    d_u = 1e-6 * rng.standard_normal(n)
    y = np.abs(P.Y + S.u)

    def forces(theta, u):
        qf = [dyn_np.elastic(gb, theta[g], st.block(g, u), True) for g, gb in enumerate(st.system.gears)]
        return st.ref.torques(theta) + np.array([x[0] for x in qf]), np.concatenate([x[1] for x in qf])

    # along u: exact central difference
    (tp, fp), (tm, fm) = forces(S.theta, S.u + d_u), forces(S.theta, S.u - d_u)
    oth, ou, _ = kernel(np.zeros(2), d_u)
    floor_f = 4 * EPS * (st.absK @ node_size(y)).max()
    assert worst(ou, (fp - fm) / 2) <= floor_f
    # each Q to its round-off (the torques are the same at both ends and cancel), and the
    # tangent to its own: it is evaluated from the state's rounded w and K w (measured in
    # extended precision on one machine: 3e-13 from the Q's, 7e-13 from the tangent)
    floor_q = max(q_bound(st, g, y, w, kw) + tangent_q_bound(st, g, y, w, d_u) for g in range(2))
    assert worst(oth, (tp - tm) / 2) <= floor_q
    print(f"tangent along u vs central difference: {worst(ou, (fp - fm) / 2):.1e} N (tol {floor_f:.1e}), "
          f"{worst(oth, (tp - tm) / 2):.1e} N m (tol {floor_q:.1e}, {np.abs(oth).max():.1e})")
    # along theta: fourth-order differences at two steps
    dth = np.array([1.0, -0.7])

    def fd4(e):
        f = [forces(S.theta + k * e * dth, S.u) for k in (-2, -1, 1, 2)]
        return [(f[0][i] - 8 * f[1][i] + 8 * f[2][i] - f[3][i]) / (12 * e) for i in range(2)]

    e = 1e-3                       # the stencil stays on the torque ramp (theta_2 = 0.143)
    assert np.all(S.theta - 2 * e > 0) and np.all(S.theta + 2 * e < 0.14)
    (th1, u1), (th2, u2) = fd4(e), fd4(2 * e)
    oth, ou, _ = kernel(dth, np.zeros(n))
    tol_u = worst(u1, u2) + 3 * floor_f / (2 * e)
    tol_th = worst(th1, th2) + 3 * 4 * EPS * np.abs(tp).max() / (2 * e)
    assert worst(ou, u1) <= tol_u
    assert worst(oth, th1) <= tol_th
    print(f"tangent along theta vs 4th-order difference: {worst(ou, u1):.1e} N (tol {tol_u:.1e}, "
          f"max {np.abs(ou).max():.1e}), {worst(oth, th1):.1e} N m (tol {tol_th:.1e}, {np.abs(oth).max():.1e})")
    # the theta part of the tangent is well above those tolerances: a slip in it would show
    assert np.abs(ou).max() > 100 * tol_u and np.abs(oth - slopes * dth).max() > 100 * tol_th


def test_constraint_force_matches_reference(loaded):
    """``constraint_force`` (``G^T x``: ``-lambda`` on the root nodes, their moments on the
    disks, ``p n`` through the contact weights) against
    :func:`spurdyn.solvers.paper.step_numpy.constraint_force`, for the state's ``x`` and random ones."""
    st, P, S = loaded, loaded.P, loaded.S
    c = st.contact
    cn, cw = st.rows(c)
    rng = np.random.default_rng(6)
    pt = np.abs(np.array([dyn_c.root_phi_theta(P, S.theta, k) for k in range(P.rnode.size)]))
    # the state's contact, and the same with a strip's disk entries (docs/solver.md 11.3)
    for c, x in ((c, S.x), (c, np.abs(S.x).max() * rng.standard_normal(S.x.size)),
                 (replace(c, theta_row=ROLLING), S.x)):
        fth, fu = np.empty(2), np.empty(S.u.size)
        dyn_c.constraint_force(P, S.theta, cn, cw, c.normal, st.gth(c), x, fth, fu)
        rth, ru = dyn_np.constraint_force(st.system, S.theta, c, x)
        lam = np.abs(x[:-1]).reshape(-1, 2)
        tol_th = 4 * EPS * (np.array([np.sum((pt * lam)[P.rgear == g]) for g in range(2)])
                            + np.abs(st.gth(c) * x[-1]))
        tol_u = 4 * EPS * np.abs(x).max()
        assert worst(fu, ru) <= tol_u
        assert np.all(np.abs(fth - rth) <= tol_th)
        print(f"constraint_force: u {worst(fu, ru):.1e} N (tol {tol_u:.1e}), theta {worst(fth, rth):.1e} N m "
              f"(tol {tol_th.max():.1e}, |f_theta| {np.abs(rth).max():.1e})")
    # the contact force on the neighbouring material point is a different force
    fu2, fth2 = np.empty(S.u.size), np.empty(2)
    dyn_c.constraint_force(P, S.theta, cn, np.roll(cw, 1), c.normal, st.gth(c), S.x, fth2, fu2)
    assert worst(fu2, fu) > 100 * tol_u
    # and the disk entries put torques on the disks
    dyn_c.constraint_force(P, S.theta, cn, cw, c.normal, np.zeros(2), S.x, fth2, fu2)
    assert np.all(np.abs(fth2 - fth) > 100 * tol_th)


def test_gram_is_G_Minv_GT(loaded):
    """``gram`` against ``G M^-1 G^T`` from :func:`spurdyn.solvers.paper.step_numpy.jacobian`, entry
    by entry to ``EPS (|G| M^-1 |G|^T)``: at the state, at other rotations, and with the
    contact on the flank's first element row, where A's and B's root end nodes carry it
    (the coupling of root and contact rows, never met in a run)."""
    st, P, S = loaded, loaded.P, loaded.S
    m = S.x.size
    cases = [(S.theta, st.contact), (np.array([0.3, -1.2]), st.contact),
             (S.theta, _synthetic_contact(st, 2.4, 3.1, 0.3, ROLLING)),
             (S.theta, _synthetic_contact(st, 0.4, 0.7, 0.3))]
    side0 = st.system.gears[0].flank.side_nodes[0]
    assert side0 in st.system.gears[0].root_nodes          # the root end node is a root node
    for theta, c in cases:
        cn, cw = st.rows(c)
        C = np.empty((m, m))
        dyn_c.gram(P, theta, cn, cw, c.normal, st.gth(c), C)
        want, size = _gram_ref(st, theta, c)
        assert np.all(np.abs(C - want) <= 4 * EPS * size)
        print(f"gram: {worst(C, want):.1e} (max entry {np.abs(want).max():.1e}, "
              f"worst ratio to EPS |G| M^-1 |G|^T {np.max(np.abs(C - want) / (EPS * size + 1e-300)):.2f})")
    assert np.abs(C[-1, :-1]).max() > 0                    # the last case couples
    # a rotation 1e-9 rad off moves the disk part of the root blocks beyond the tolerance
    C2 = np.empty((m, m))
    dyn_c.gram(P, S.theta + 1e-9, *st.rows(st.contact), st.contact.normal, st.gth(st.contact), C2)
    want, size = _gram_ref(st, S.theta, st.contact)
    assert np.max(np.abs(C2 - want) - 4 * EPS * size) > 0


def test_gram_contact_refreshes_the_contact_row(loaded):
    """``gram_contact`` moves the contact row and column of a Gram matrix to new contact rows:
    the result is :func:`test_gram_is_G_Minv_GT`'s reference for the new pair, root block
    untouched, including a move onto a root node and back."""
    st, P, S = loaded, loaded.P, loaded.S
    m = S.x.size
    c0 = st.contact
    C = np.empty((m, m))
    dyn_c.gram(P, S.theta, *st.rows(c0), c0.normal, st.gth(c0), C)
    root = C[:-1, :-1].copy()
    for c in (_synthetic_contact(st, c0.alpha + 1.3, c0.beta - 0.7, 0.9),
              _synthetic_contact(st, c0.alpha + 0.6, c0.beta - 0.2, 0.9, ROLLING),
              _synthetic_contact(st, 0.4, 0.7, 0.3), c0):
        dyn_c.gram_contact(P, S.theta, *st.rows(c), c.normal, st.gth(c), C)
        want, size = _gram_ref(st, S.theta, c)
        assert np.array_equal(C[:-1, :-1], root)
        assert np.all(np.abs(C - want) <= 4 * EPS * size)
        print(f"gram_contact: {worst(C, want):.1e} (contact entry {want[-1, -1]:.3e})")
    # the weights matter (a refresh that kept the old row would fail here)
    dyn_c.gram_contact(P, S.theta, *st.rows(_synthetic_contact(st, c0.alpha + 0.25, c0.beta, 0.0)), c0.normal,
                       np.zeros(2), C)
    assert abs(C[-1, -1] - want[-1, -1]) > 100 * 4 * EPS * size[-1, -1]

