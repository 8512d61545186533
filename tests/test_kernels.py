"""The compiled kernels one by one against their NumPy counterparts.

Each test calls one kernel of :mod:`spurdyn.integrate.kernels` or
:mod:`spurdyn.solvers.paper.step_compiled` on a realistic state of the paper's pair (1,500 steps
of the 20,000 rpm run: the torque is on its ramp and the teeth carry ~200 N) and compares
it with the same quantity computed by :mod:`spurdyn.solvers.paper.step_numpy`,
:mod:`spurdyn.contact.search_numpy`, :mod:`spurdyn.solvers.paper.iteration_numpy`,
:mod:`spurdyn.model.loading`, or, where there is no NumPy counterpart, by the formula of
docs/solver.md written out here in NumPy/SciPy. (The spline kernels, ``delta_at`` and the
contact search are compared in tests/test_contact.py; ``predict``/``superpose`` in
tests/test_fast.py.)

The tolerances are round-off bounds of the computation compared, never fitted: ``EPS``
times the size of the terms that are summed (``|K| |v|`` for a product with the
stiffness, ``|G| M^-1 |G|^T`` for the Gram matrix...). Where a quantity is a difference of
large numbers the bound is set by those: the elastic displacement ``w = R^T (Y + u) - Y``
is a difference of ~5 cm positions leaving micrometres, so two correct codes that round
``w`` differently part by ``EPS |Y|`` in ``w`` and ``EPS |K| |Y|`` in the forces (a part in
1e9 of them; tests/test_fast.py's module docstring). Those comparisons are also made with
the kernel's own ``w`` fed to the NumPy side, where the bound is the plain product's. Each
test checks too that a small change of an input moves the kernel's output by much more
than its tolerance, so a tolerance that hid a real error would show.
"""

import dataclasses
import math

import numpy as np
import pytest
import scipy.sparse as sp

from spurdyn.contact import search_numpy as cref
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.solvers.paper import dynamics_compiled as dyn_c
from spurdyn.solvers.paper import iteration_compiled as it_c
from spurdyn.solvers.paper import response_compiled as resp_c
from spurdyn.contact import search_compiled as search_c
from spurdyn.contact.constants import F
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper
from spurdyn.model.loading import gear_angles, gear_torques
from spurdyn.solvers.paper import iteration_numpy as iteration
from spurdyn.solvers.paper import dynamics_numpy as dyn_np
from spurdyn.solvers.paper import step_numpy as sref
from spurdyn.settings import RPM, RunSettings
from spurdyn.model.system import build_system

EPS = np.finfo(float).eps
JZ = np.array([[0.0, -1.0], [1.0, 0.0]])


class Loaded:
    """A loaded state of the paper's pair and everything the comparisons need."""

    def __init__(self, steps: int = 1500) -> None:
        self.case = RunSettings(speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE)
        self.system = build_system(paper_pair(), self.case)
        self.fast = CompiledStepper(self.system, self.case)
        for _ in range(steps):
            assert self.fast.step() == 0
        self.S, self.P = self.fast.S, self.fast.P
        self.ref = sref.PaperMethod(self.system, self.case)
        self.na = self.system.gears[0].mesh.n_nodes          # nodes of A (B's are offset by it)
        self.K = sp.block_diag([g.stiffness for g in self.system.gears], format="csr")
        self.absK = abs(self.K)
        self.contact = self.ref.contact_at(self.S.theta, self.S.u, (self.S.cpar[0], self.S.cpar[1]))

    def rows(self, c):
        """``cn, cw`` (stacked node numbers, weights) of a reference contact pair."""
        cn = np.concatenate([c.nodes_a, c.nodes_b + self.na]).astype(np.int64)
        return cn, np.concatenate([c.weights_a, c.weights_b])

    def block(self, g, vec):
        o = self.system.offsets
        return vec[o[g]:o[g + 1]]


@pytest.fixture(scope="module")
def loaded():
    st = Loaded()
    assert st.S.x[-1] < -100.0                    # pressed together by ~200 N
    assert st.contact.mode == cref.FLANK
    assert 0.05 < st.S.theta[0] < 0.14            # on the torque ramp (non-zero slope)
    return st


def elastic_np(system, theta, u):
    """``w``, ``K w`` of both teeth in NumPy (docs/solver.md section 2)."""
    w = np.empty_like(u)
    for g, gb in enumerate(system.gears):
        o = system.offsets
        r = dyn_np.rot(gb.sense * theta[g])
        w[o[g]:o[g + 1]] = ((gb.Y + u[o[g]:o[g + 1]]).reshape(-1, 2) @ r).ravel() - gb.Y
    return w


def tangent_np(st, theta, w, kw, d_th, d_u, keep=True):
    """``dF/dq . (d_th, d_u)`` without the torque schedule's slope, from the formulas of
    docs/solver.md (the tangent of the forces): ``dw = R^T du - s d_th Jz (w + Y)``,
    ``df = -s d_th R Jz K w - R K dw``, ``dQ = s sum (dw x K w + w x K dw)``."""
    out_th, out_u = np.zeros(2), np.zeros_like(w)
    for g, gb in enumerate(st.system.gears):
        o = st.system.offsets
        sl = slice(o[g], o[g + 1])
        s, r = gb.sense, dyn_np.rot(gb.sense * theta[g])
        w2, kw2 = w[sl].reshape(-1, 2), kw[sl].reshape(-1, 2)
        dw = d_u[sl].reshape(-1, 2) @ r - s * d_th[g] * (w2 + gb.Y.reshape(-1, 2)) @ JZ.T
        kdw = (gb.stiffness @ dw.ravel()).reshape(-1, 2)
        out_u[sl] = (-(s * d_th[g] * kw2 @ JZ.T + kdw) @ r.T).ravel()
        if keep:
            out_th[g] = s * np.sum(dw[:, 0] * kw2[:, 1] - dw[:, 1] * kw2[:, 0]
                                   + w2[:, 0] * kdw[:, 1] - w2[:, 1] * kdw[:, 0])
    return out_th, out_u


def q_bound(st, g, y, w, kw):
    """Round-off bound of gear ``g``'s disk torque ``Q = s sum w x K w`` from the rounding of
    ``w`` (``~EPS |y|``) and of the product. ``K`` is symmetric, so an error ``dw`` moves
    ``Q`` by ``sum dw x K w + (K Jz w) . dw``: both against forces of the size of ``K w``."""
    stiff = st.system.gears[g].stiffness
    w2, y2, kw2 = st.block(g, w), st.block(g, y), st.block(g, kw)
    kjw = stiff @ (w2.reshape(-1, 2) @ JZ.T).ravel()
    return (4 * EPS * (cross_size(y2, kw2) + cross_size(y2, kjw))
            + 8 * EPS * cross_size(w2, abs(stiff) @ np.abs(w2)))


def node_size(v):
    """``|v_x| + |v_y|`` of each node, for both its components: a bound on the size of either
    component of the vector turned by any angle."""
    return np.repeat(np.abs(v).reshape(-1, 2).sum(1), 2)


def cross_size(a, b):
    """``sum_i (|a_i,x| + |a_i,y|)(|b_i,x| + |b_i,y|)``: a bound on ``sum_i |a_i x b_i|``."""
    return float(np.sum(np.abs(a).reshape(-1, 2).sum(1) * np.abs(b).reshape(-1, 2).sum(1)))


def worst(got, want):
    return float(np.max(np.abs(np.asarray(got) - np.asarray(want))))


def rigid_plus_noise(st, theta, size, seed):
    """Displacements of both teeth turned rigidly by ``theta`` plus random ones of ``size``."""
    rng = np.random.default_rng(seed)
    u = np.empty(st.system.n_u)
    for g, gb in enumerate(st.system.gears):
        y = gb.Y.reshape(-1, 2)
        st.block(g, u)[:] = (y @ dyn_np.rot(gb.sense * theta[g]).T - y).ravel()
    return u + size * rng.standard_normal(u.size)


# -- small pieces ----------------------------------------------------------------------------

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


def test_edge_rows_and_surface_points_match_the_flank(loaded):
    """``edge_at``/``contact_rows`` are :meth:`Flank.locate`; ``data_positions`` (positions,
    velocities) is :func:`spurdyn.contact.search_numpy.data_values`; ``material_point``
    (positions, velocities, accelerations) is :func:`~spurdyn.contact.search_numpy.surface_point`,
    each to ``EPS`` times the size of the terms summed."""
    st, P, S = loaded, loaded.P, loaded.S
    rng = np.random.default_rng(2)
    acc = 1e5 * rng.standard_normal(S.u.size)          # nodal accelerations of the size of a run's
    al = np.array([3e4, -2e4])
    vmats = st.ref.velocity_mats(S.theta, S.omega)
    amats = st.ref.acceleration_mats(S.theta, S.omega, al)
    nd = P.fl_nodes.shape[1]
    out = np.empty((nd, 2))
    big = np.zeros(5)
    for g, gb in enumerate(st.system.gears):
        fl = gb.flank
        r = dyn_np.rot(gb.sense * S.theta[g])
        xg = gb.X + st.block(g, S.u).reshape(-1, 2)
        vg, ag = st.block(g, S.v).reshape(-1, 2), st.block(g, acc).reshape(-1, 2)
        tol_x = 4 * EPS * np.abs(xg).max()
        tol_v = 4 * EPS * (np.abs(vg).max() + abs(S.omega[g]) * 1e-6)
        tol_a = 4 * EPS * (np.abs(ag).max() + (abs(al[g]) + S.omega[g] ** 2) * 1e-6)
        search_c.data_positions(P, g, S.theta[g], 0.0, S.u, out, 0)
        big[0] = max(big[0], worst(out, cref.data_values(fl, xg, r)))
        assert worst(out, cref.data_values(fl, xg, r)) <= tol_x
        search_c.data_positions(P, g, S.theta[g], S.omega[g], S.v, out, 1)
        big[1] = max(big[1], worst(out, cref.data_values(fl, vg, vmats[g])))
        assert worst(out, cref.data_values(fl, vg, vmats[g])) <= tol_v
        for t in (fl.t0, 3.0, 4.3, 7.5, 9.99, fl.t1 - 1e-9, fl.t1):
            nodes, w, row = search_c.edge_at(P.fpar[g], P.side[g], t)
            ln, lw, _ = fl.locate(t)
            assert np.array_equal(nodes, ln + g * st.na) and row == min(int(t), fl.ny - 1)
            assert worst(w, lw) <= 4 * EPS
            got = [search_c.material_point(P, g, t, S.theta[g], S.u, 0, 0.0, 0.0),
                   search_c.material_point(P, g, t, S.theta[g], S.v, 1, S.omega[g], 0.0),
                   search_c.material_point(P, g, t, S.theta[g], acc, 2, S.omega[g], al[g])]
            want = [cref.surface_point(fl, t, xg, r), cref.surface_point(fl, t, vg, vmats[g]),
                    cref.surface_point(fl, t, ag, amats[g])]
            for kind, tol in enumerate((tol_x, tol_v, tol_a)):
                big[2 + kind] = max(big[2 + kind], worst(got[kind], want[kind]))
                assert worst(got[kind], want[kind]) <= tol
        # displacements 1e-12 m larger show
        search_c.data_positions(P, g, S.theta[g], 0.0, S.u + 1e-12, out, 0)
        assert worst(out, cref.data_values(fl, xg, r)) > 100 * tol_x
    cn, cw = np.empty(6, np.int64), np.empty(6)
    c = st.contact
    search_c.contact_rows(P, c.alpha, c.beta, cn, cw)
    assert np.array_equal(cn, st.rows(c)[0]) and worst(cw, st.rows(c)[1]) <= 4 * EPS
    print("data/material points (positions m, velocities m/s; points: m, m/s, m/s^2):", big)


# -- equations of motion ---------------------------------------------------------------------

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
    # each Q to its round-off (the torques are the same at both ends and cancel)
    floor_q = max(q_bound(st, g, y, w, kw) for g in range(2))
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


# -- constraint forces and the Gram matrix -----------------------------------------------------

def test_constraint_force_matches_reference(loaded):
    """``constraint_force`` (``G^T x``: ``-lambda`` on the root nodes, their moments on the
    disks, ``p n`` through the contact weights) against
    :func:`spurdyn.solvers.paper.step_numpy.constraint_force`, for the state's ``x`` and random ones."""
    st, P, S = loaded, loaded.P, loaded.S
    c = st.contact
    cn, cw = st.rows(c)
    rng = np.random.default_rng(6)
    pt = np.abs(np.array([dyn_c.root_phi_theta(P, S.theta, k) for k in range(P.rnode.size)]))
    for x in (S.x, np.abs(S.x).max() * rng.standard_normal(S.x.size)):
        fth, fu = np.empty(2), np.empty(S.u.size)
        dyn_c.constraint_force(P, S.theta, cn, cw, c.normal, x, fth, fu)
        rth, ru = dyn_np.constraint_force(st.system, S.theta, c, x)
        lam = np.abs(x[:-1]).reshape(-1, 2)
        tol_th = 4 * EPS * np.array([np.sum((pt * lam)[P.rgear == g]) for g in range(2)])
        tol_u = 4 * EPS * np.abs(x).max()
        assert worst(fu, ru) <= tol_u
        assert np.all(np.abs(fth - rth) <= tol_th)
        print(f"constraint_force: u {worst(fu, ru):.1e} N (tol {tol_u:.1e}), theta {worst(fth, rth):.1e} N m "
              f"(tol {tol_th.max():.1e}, |f_theta| {np.abs(rth).max():.1e})")
    # the contact force on the neighbouring material point is a different force
    fu2 = np.empty(S.u.size)
    dyn_c.constraint_force(P, S.theta, cn, np.roll(cw, 1), c.normal, S.x, np.empty(2), fu2)
    assert worst(fu2, fu) > 100 * tol_u


def _synthetic_contact(st, alpha, beta, angle):
    """A contact pair at ``(alpha, beta)`` with a unit normal at ``angle`` (the Gram matrix
    needs only the rows and the normal)."""
    fa, fb = st.system.gears[0].flank, st.system.gears[1].flank
    na, wa, _ = fa.locate(alpha)
    nb, wb, _ = fb.locate(beta)
    return cref.ContactPair(alpha=alpha, beta=beta, mode=cref.FLANK,
                            normal=np.array([math.cos(angle), math.sin(angle)]), s=0.0,
                            nodes_a=na, weights_a=wa, nodes_b=nb, weights_b=wb,
                            delta_a=np.zeros(2), delta_b=np.zeros(2))


def _gram_ref(st, theta, c):
    """``G M^-1 G^T`` and the size of its terms, ``|G| M^-1 |G|^T`` with the disk entries of
    the root rows (components of ``-s R Jz Y_i``, each rounded to ``EPS |Y_i|``) taken as
    ``|Y_i|``."""
    g = dyn_np.jacobian(st.system, theta, c)
    minv = dyn_np.inverse_mass(st.system)
    size = np.abs(g)
    ynorm = np.abs(st.P.Y[2 * st.P.rnode]) + np.abs(st.P.Y[2 * st.P.rnode + 1])
    size[np.arange(2 * ynorm.size), np.repeat(st.P.rgear, 2)] = np.repeat(ynorm, 2)
    return (g * minv) @ g.T, (size * minv) @ size.T


def test_gram_is_G_Minv_GT(loaded):
    """``gram`` against ``G M^-1 G^T`` from :func:`spurdyn.solvers.paper.step_numpy.jacobian`, entry
    by entry to ``EPS (|G| M^-1 |G|^T)``: at the state, at other rotations, and with the
    contact on the flank's first element row, where A's and B's root end nodes carry it
    (the coupling of root and contact rows, never met in a run)."""
    st, P, S = loaded, loaded.P, loaded.S
    m = S.x.size
    cases = [(S.theta, st.contact), (np.array([0.3, -1.2]), st.contact),
             (S.theta, _synthetic_contact(st, 0.4, 0.7, 0.3))]
    side0 = st.system.gears[0].flank.side_nodes[0]
    assert side0 in st.system.gears[0].root_nodes          # the root end node is a root node
    for theta, c in cases:
        cn, cw = st.rows(c)
        C = np.empty((m, m))
        dyn_c.gram(P, theta, cn, cw, c.normal, C)
        want, size = _gram_ref(st, theta, c)
        assert np.all(np.abs(C - want) <= 4 * EPS * size)
        print(f"gram: {worst(C, want):.1e} (max entry {np.abs(want).max():.1e}, "
              f"worst ratio to EPS |G| M^-1 |G|^T {np.max(np.abs(C - want) / (EPS * size + 1e-300)):.2f})")
    assert np.abs(C[-1, :-1]).max() > 0                    # the last case couples
    # a rotation 1e-9 rad off moves the disk part of the root blocks beyond the tolerance
    C2 = np.empty((m, m))
    dyn_c.gram(P, S.theta + 1e-9, *st.rows(st.contact), st.contact.normal, C2)
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
    dyn_c.gram(P, S.theta, *st.rows(c0), c0.normal, C)
    root = C[:-1, :-1].copy()
    for c in (_synthetic_contact(st, c0.alpha + 1.3, c0.beta - 0.7, 0.9),
              _synthetic_contact(st, 0.4, 0.7, 0.3), c0):
        dyn_c.gram_contact(P, *st.rows(c), c.normal, C)
        want, size = _gram_ref(st, S.theta, c)
        assert np.array_equal(C[:-1, :-1], root)
        assert np.all(np.abs(C - want) <= 4 * EPS * size)
        print(f"gram_contact: {worst(C, want):.1e} (contact entry {want[-1, -1]:.3e})")
    # the weights matter (a refresh that kept the old row would fail here)
    dyn_c.gram_contact(P, *st.rows(_synthetic_contact(st, c0.alpha + 0.25, c0.beta, 0.0)), c0.normal, C)
    assert abs(C[-1, -1] - want[-1, -1]) > 100 * 4 * EPS * size[-1, -1]


# -- the accelerated iteration -----------------------------------------------------------------

@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_accelerated_update_matches_appendix_b_reference(loaded, n):
    """``accelerated_update`` against :func:`spurdyn.solvers.paper.iteration_numpy.accelerated_update` with
    ``C = scale G M^-1 G^T`` for the three stages' scales and error sizes, from ``x = 0``
    (the update alone), from the state's ``x``, with the contact inactive (``e_p = 0``), and
    with the contact row made the smallest eigenvalue (the other branch of the kernel's
    ``eps_1``). The kernel takes ``eps_1`` from the root block's eigenvalue computed once
    (``fast.root_eigenvalue``) where the reference solves for it each time: the same number
    to round-off. The recursions ``apply_a``/``apply_c`` are compared too.

    Tolerance: ``1e-12`` of the update (the conditioning of ``A_n`` in ``eps_1`` and the
    eigen-solve's round-off, observed ~1e-15) plus ``EPS |x|``.
    """
    st, S = loaded, loaded.S
    m = S.x.size
    h = st.case.dt
    eps_root = st.fast.cfg[6]
    C = np.empty((m, m))
    dyn_c.gram(st.P, S.theta, *st.rows(st.contact), st.contact.normal, C)
    rng = np.random.default_rng(10 + n)
    # contact row scaled: still G M^-1 G^T of a (lighter-looking) contact, p's eigenvalue smallest
    Cs = C.copy()
    Cs[-1, :] *= 0.1
    Cs[:, -1] *= 0.1
    assert Cs[-1, -1] < eps_root
    big = np.zeros(2)
    for scale, emag in ((0.5 * h * h, 1e-12), (h, 1e-12 / h), (1.0, 1e-12 / h**2)):
        for x0, cmat, active in ((np.zeros(m), C, True), (S.x, C, True), (S.x, C, False),
                                 (np.zeros(m), Cs, True)):
            e = emag * rng.standard_normal(m)
            if not active:
                e[-1] = 0.0
            want = iteration.accelerated_update(x0, e, scale * cmat, n)
            got = x0.copy()
            it_c.accelerated_update(got, e, cmat, scale, n, eps_root, np.empty((m, m)), np.empty(m), e[-1] != 0.0)
            tol = 1e-12 * np.abs(want - x0).max() + 4 * EPS * np.abs(x0).max()
            assert worst(got, want) <= tol
            k = int(np.abs(x0).max() > 0)     # the update alone, or on top of x
            unit = np.abs(want - x0).max() if k == 0 else EPS * np.abs(x0).max()
            big[k] = max(big[k], worst(got, want) / unit)
            if not active:
                assert got[-1] == x0[-1]
    # a contact row held at its target (zero error, still in C': its C_pp enters eps_1)
    # against the reference given the same mask
    e = 1e-12 * rng.standard_normal(m)
    e[-1] = 0.0
    want = iteration.accelerated_update(S.x, e, 0.5 * h * h * C, n, np.ones(m, dtype=bool))
    got = S.x.copy()
    it_c.accelerated_update(got, e, C, 0.5 * h * h, n, eps_root, np.empty((m, m)), np.empty(m), True)
    assert worst(got, want) <= 1e-12 * np.abs(want - S.x).max() + 4 * EPS * np.abs(S.x).max()
    print(f"accelerated_update n={n}: from x = 0 {big[0]:.1e} of the update; from the state's x "
          f"{big[1]:.2f} EPS |x|")
    # eps_1 matters (b_bar and the b_k depend on it): 1 % off changes the update beyond the tolerance
    e = 1e-12 * rng.standard_normal(m)
    got, got2 = np.zeros(m), np.zeros(m)
    it_c.accelerated_update(got, e, C, 0.5 * h * h, n, eps_root, np.empty((m, m)), np.empty(m), True)
    it_c.accelerated_update(got2, e, C, 0.5 * h * h, n, 1.01 * eps_root, np.empty((m, m)), np.empty(m), True)
    assert worst(got, got2) > 1e3 * 1e-12 * np.abs(got).max()
    # the recursions themselves
    c1 = C / np.abs(C).sum(1).max()
    b, _, _, _ = iteration.coefficients(n, 0.02)
    for k in range(1, n + 1):
        out = np.empty(m)
        it_c.apply_c(c1, b, k, e, out)
        want = iteration.apply_c(c1, b, k, e)
        assert worst(out, want) <= 1e-13 * np.abs(want).max()
    out = np.empty(m)
    it_c.apply_a(c1, b, n, e, out)
    assert worst(out, iteration.apply_a(c1, b, n, e)) <= 1e-13 * np.abs(out).max()


# -- the sliding terms (Appendix A) --------------------------------------------------------------

@pytest.mark.parametrize("mode", [cref.FLANK, cref.CORNER_A, cref.CORNER_B])
def test_sliding_terms_match_appendix_a_reference(loaded, mode):
    """``search_c.sliding`` against :func:`spurdyn.contact.search_numpy.sliding_acceleration` at
    the state's contact pair (the state's positions and velocities; the position splines
    left by ``search``), in each mode's formula for ``alpha_dot``, ``beta_dot``.

    The terms are ``alpha_dot^2 n . P''`` and ``2 alpha_dot n . V'`` of splines through ~5 cm
    positions and ~100 m/s velocities: their round-off is that of the splines' derivatives,
    ``~6 EPS |P| / h^2`` and ``6 EPS |V| / h`` (``h`` the data spacing), times the rates.
    """
    st, P, S = loaded, loaded.P, loaded.S
    c = dataclasses.replace(st.contact, mode=mode)
    nd = P.fl_nodes.shape[1]
    va, vb, Ma, Mb = (np.empty((nd, 2)) for _ in range(4))
    a, b, mode_s, _, _, _ = search_c.search(P, S.theta, S.u, np.array([c.alpha, c.beta]), va, vb, Ma, Mb)
    assert mode_s == cref.FLANK and abs(a - c.alpha) < 1e-9 and abs(b - c.beta) < 1e-9
    got = search_c.sliding(P, S.theta, S.omega, S.u, S.v, c.alpha, c.beta, mode, c.normal[0], c.normal[1],
                            va, vb, Ma, Mb)
    gb = st.system.gears
    pos = [gb[g].X + st.block(g, S.u).reshape(-1, 2) for g in range(2)]
    vel = [st.block(g, S.v).reshape(-1, 2) for g in range(2)]
    rots = [dyn_np.rot(gb[g].sense * S.theta[g]) for g in range(2)]
    want, ad, bd = cref.sliding_acceleration(gb[0].flank, gb[1].flank, *pos, *rots, *vel,
                                             *st.ref.velocity_mats(S.theta, S.omega), c)
    hs = P.fpar[:, F.h].min()
    psize = max(np.abs(va).max(), np.abs(vb).max())
    vsize = np.abs(S.v).max()
    tol = 6 * EPS * ((ad * ad + bd * bd) * psize / hs**2 + 2 * (abs(ad) + abs(bd)) * vsize / hs)
    assert abs(got - want) <= tol
    assert abs(want) > 1e6 * tol
    print(f"sliding mode {mode}: {abs(got - want):.1e} m/s^2 (tol {tol:.1e}, extra {want:.3e})")
    # velocities a part in 1e9 larger change the terms (quadratic in them) beyond that
    got2 = search_c.sliding(P, S.theta, S.omega, S.u, S.v * (1 + 1e-9), c.alpha, c.beta, mode,
                             c.normal[0], c.normal[1], va, vb, Ma, Mb)
    assert abs(got2 - got) > 10 * tol


# -- Z = M^-1 G^T x and the response matrices of the superposed step ---------------------------

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
    c = st.contact
    cn, cw = st.rows(c)
    gmat = dyn_np.jacobian(st.system, S.theta, c)
    minv = dyn_np.inverse_mass(st.system)
    # Z for the state's x
    zth, zu, nz, mark = np.empty(2), np.zeros(n), np.empty(nn, np.int64), np.zeros(nn, np.int64)
    nnz = resp_c._z_of(P, S.theta, cn, cw, c.normal, S.x, zth, zu, nz, mark)
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
    resp_c.response_columns(P, h, pred, S.theta, cn, cw, c.normal, 0, m, Wq, Wv, scratch, mark, touched,
                       nz, zu, acc3, acc4)
    assert not (scratch.any() or mark.any() or zu.any() or acc3.any() or acc4.any())
    rows = np.concatenate([[0, 1], 2 + np.ravel(np.column_stack([2 * rel, 2 * rel + 1]))])
    mass = np.concatenate([[P.J[0], P.J[1]], P.mass])
    big = np.zeros(2)
    for j in range(m):
        z = minv * gmat[j]                       # M^-1 G^T e_j
        zcol_th, zcol_u, nzc = np.empty(2), np.zeros(n), np.empty(nn, np.int64)
        k = resp_c._z_col(P, S.theta, cn, cw, c.normal, j, zcol_th, zcol_u, nzc)
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


def test_band_value_matches_its_reference():
    """``band_value`` (compiled) against its NumPy twin, and the rule itself: a contact error
    inside the band is held, one outside is brought inside by its excess (at least the
    margin, at most to zero), keeping its sign."""
    tol, margin = 1e-12, 1e-4
    cases = [0.0, 0.3e-12, -1e-12, 1.0000001e-12, -1.5e-12, 2.5e-12, -7e-9, 1e-12 + 1e-20]
    want = [iteration.band_value(e, tol, margin) for e in cases]
    got = [it_c.band_value(e, tol, margin) for e in cases]
    assert got == want
    for e, t in zip(cases, want):
        if abs(e) <= tol:
            assert t == e
        else:
            assert abs(t) < tol and t * e >= 0.0
    assert want[4] == pytest.approx(-0.5e-12, rel=1e-12)         # excess 0.5 tol: inset 0.5 tol
    assert want[5] == 0.0 and want[6] == 0.0                        # excess beyond tol: aim at zero
    assert want[7] == pytest.approx(tol * (1 - margin), rel=1e-12)  # tiny excess: the margin
