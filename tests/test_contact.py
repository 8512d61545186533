"""Contact between the flanks: conjugate action, finite-difference checks of the contact
Jacobian and of the Appendix A sliding terms, and the compiled kernels against SciPy."""

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from spurdyn.contact.search_numpy import FLANK, find_contact, flank_spline, sliding_acceleration
from spurdyn.geometry.presets import paper_pair
from spurdyn.contact import search_compiled as search_c
from spurdyn.solvers.loop import _roll
from spurdyn.settings import RunSettings
from spurdyn.solvers.paper.step_numpy import PaperMethod
from spurdyn.solvers.paper.dynamics_numpy import blocks, jacobian, rot, root_phi, root_phi_theta
from spurdyn.model.system import build_system

JZ = np.array([[0.0, -1.0], [1.0, 0.0]])


@pytest.fixture(scope="module")
def system():
    pair = paper_pair()
    case = RunSettings(contact="point", speed_a=400.0, speed_b=400.0, torque=22.25)
    s = build_system(pair, case)
    return s, PaperMethod(s, case)


def rigid(system, theta, omega=(0.0, 0.0), alpha=(0.0, 0.0)):
    """Absolute displacements, velocities and accelerations of both teeth turning rigidly."""
    n = system.n_u
    u, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    for g, (gb, ub, vb, ab) in enumerate(zip(system.gears, blocks(system, u), blocks(system, v),
                                             blocks(system, a))):
        y = gb.Y.reshape(-1, 2)
        r = rot(gb.sense * theta[g])
        ry = y @ r.T
        ub[:] = (ry - y).ravel()
        vb[:] = (gb.sense * omega[g] * ry @ JZ.T).ravel()
        ab[:] = (gb.sense * alpha[g] * ry @ JZ.T - omega[g] ** 2 * ry).ravel()
    return u, v, a


def _rigid_roll_errors(s, ref):
    pair = s.pair
    guess = (s.gears[0].flank.t0 + 0.5, s.gears[1].flank.t1)
    worst_s, worst_roll = 0.0, 0.0
    for d in np.linspace(0.0, pair.theta_s * 0.98, 15):
        u, _, _ = rigid(s, (d, d))
        c = ref.contact_at(np.array([d, d]), u, guess)
        guess = (c.alpha, c.beta)
        roll_a = _roll(s, 0, np.array([c.alpha]))[0]
        roll_b = _roll(s, 1, np.array([c.beta]))[0]
        worst_s = max(worst_s, abs(c.s))
        worst_roll = max(worst_roll, abs(roll_a - (pair.start_roll_a + d)),
                         abs(roll_b - float(pair.roll_b_from_roll_a(pair.start_roll_a + d))))
    return worst_s, worst_roll


def test_rigid_teeth_stay_in_contact_on_the_line_of_action(system):
    """Conjugate rotation of the undeformed teeth: zero gap, contact point on the line of
    action; the point's position converges with the number of spline points."""
    s, ref = system
    worst_s, worst_roll = _rigid_roll_errors(s, ref)
    assert worst_s < 1e-14
    # 61 points: the contact point sits within ~1e-7 rad of roll (a few nm on the flank).
    assert worst_roll < 1e-6
    fine = build_system(s.pair, ref.case.with_(n_spline=241))
    fine_s, fine_roll = _rigid_roll_errors(fine, PaperMethod(fine, ref.case.with_(n_spline=241)))
    assert fine_s < 1e-14
    assert fine_roll < worst_roll / 8.0


def bent(system, theta):
    """Rigid displacements at ``theta`` plus a smooth bend of every node, and the nodes'
    reference positions ``(n, 2)``: the envelope property holds for a smooth surface,
    where random nodal noise would kink the element edges against the spline."""
    u0, _, _ = rigid(system, theta)
    y = np.concatenate([g.Y for g in system.gears]).reshape(-1, 2)
    return u0 + 1e-4 * np.column_stack([y[:, 1] ** 2, y[:, 0] * y[:, 1]]).ravel(), y


def smooth_field(y, rng):
    """A smooth random nodal field: quadratic polynomials of the node positions ``y``."""
    cx, cy = rng.standard_normal(6), rng.standard_normal(6)
    z = y / 0.05
    basis = np.column_stack([np.ones(len(y)), z[:, 0], z[:, 1], z[:, 0] ** 2, z[:, 0] * z[:, 1],
                             z[:, 1] ** 2])
    return np.column_stack([basis @ cx, basis @ cy]).ravel()


def test_contact_jacobian_by_finite_differences(system):
    """ds/du along random flank displacements equals the contact row of G (envelope property)."""
    s, ref = system
    rng = np.random.default_rng(1)
    theta = np.array([0.1, 0.1])
    u0, y = bent(s, theta)
    c = ref.contact_at(theta, u0, (5.0, 11.0))
    g = jacobian(s, theta, c)[-1, 2:]
    for _ in range(3):
        du = smooth_field(y, rng)
        eps = 1e-9
        sp = ref.contact_at(theta, u0 + eps * du, (c.alpha, c.beta)).s
        sm = ref.contact_at(theta, u0 - eps * du, (c.alpha, c.beta)).s
        assert (sp - sm) / (2 * eps) == pytest.approx(g @ du, rel=2e-5, abs=1e-9)


def test_root_constraint_jacobian_by_finite_differences(system):
    s, _ = system
    gb = s.gears[1]
    u = np.zeros(gb.n_u)
    for th in (0.0, 0.2, -0.3):
        eps = 1e-6
        fd = (root_phi(gb, th + eps, u) - root_phi(gb, th - eps, u)) / (2 * eps)
        assert np.allclose(fd, root_phi_theta(gb, th), rtol=1e-8, atol=1e-14)


@pytest.mark.parametrize("speeds,accels", [((300.0, 300.0), (2e4, -3e4)),
                                           ((2000.0, 2000.0), (0.0, 5e4))])
def test_appendix_a_terms_against_the_contact_trajectory(system, speeds, accels):
    """The relative normal acceleration of the contact points (Appendix A) equals the second
    time derivative of the gap between the rigidly moving, accelerating teeth."""
    s, ref = system
    th0 = np.array([0.12, 0.12])
    om, al = np.array(speeds), np.array(accels)
    guess = (5.0, 10.0)

    def gap(t):
        th = th0 + om * t + 0.5 * al * t * t
        u, _, _ = rigid(s, th)
        return ref.contact_at(th, u, guess)

    c0 = gap(0.0)
    assert abs(c0.s) < 1e-13 and c0.mode == FLANK
    # small enough that the O(dt^2 omega^2) truncation of the difference is ~1e-6
    dt = 2e-7
    fd = (gap(dt).s - 2 * c0.s + gap(-dt).s) / dt**2
    u, v, a = rigid(s, th0, om, al)
    ua, ub = blocks(s, u)
    va, vb = blocks(s, v)
    ra, rb = (rot(g.sense * t) for g, t in zip(s.gears, th0))
    ma, mb = ref.velocity_mats(th0, om)
    extra, ad, bd = sliding_acceleration(s.gears[0].flank, s.gears[1].flank,
                                         s.gears[0].X + ua.reshape(-1, 2), s.gears[1].X + ub.reshape(-1, 2),
                                         ra, rb, va.reshape(-1, 2), vb.reshape(-1, 2), ma, mb, c0)
    s_tilde = ref.normal_of(c0, a, ref.acceleration_mats(th0, om, al)) + extra
    # The sliding terms are large (they are most of the contact points' centripetal
    # motion) and cancel against the material accelerations; the check is against their
    # size, to the accuracy of the 61-point spline's second derivatives.
    assert abs(extra) > abs(s_tilde)
    assert abs(s_tilde - fd) < 2e-5 * abs(extra)
    # and the contact parameters move as the kinematics says
    c1 = gap(dt)
    assert (c1.alpha - c0.alpha) / dt == pytest.approx(ad, rel=1e-3)
    assert (c1.beta - c0.beta) / dt == pytest.approx(bd, rel=1e-3)


def test_appendix_a_terms_converge_with_spline_points(system):
    """At 2,000 rad/s the 61-point error (~1e-5 of the sliding terms) falls with more points."""
    s61, ref61 = system
    errors = []
    for ref in (ref61, PaperMethod(build_system(s61.pair, ref61.case.with_(n_spline=241)),
                                        ref61.case.with_(n_spline=241))):
        s = ref.system
        th0, om, al = np.array([0.12, 0.12]), np.array([2000.0, 2000.0]), np.array([0.0, 5e4])

        def gap(t):
            th = th0 + om * t + 0.5 * al * t * t
            return ref.contact_at(th, rigid(s, th)[0], (5.0, 10.0))

        c0, dt = gap(0.0), 2e-7
        fd = (gap(dt).s - 2 * c0.s + gap(-dt).s) / dt**2
        u, v, a = rigid(s, th0, om, al)
        ua, ub = blocks(s, u)
        va, vb = blocks(s, v)
        ra, rb = (rot(g.sense * t) for g, t in zip(s.gears, th0))
        extra, _, _ = sliding_acceleration(s.gears[0].flank, s.gears[1].flank,
                                           s.gears[0].X + ua.reshape(-1, 2), s.gears[1].X + ub.reshape(-1, 2),
                                           ra, rb, va.reshape(-1, 2), vb.reshape(-1, 2),
                                           *ref.velocity_mats(th0, om), c0)
        errors.append(abs(ref.normal_of(c0, a, ref.acceleration_mats(th0, om, al)) + extra - fd) / abs(extra))
    assert errors[0] < 2e-5
    assert errors[1] < errors[0] / 4


def test_compiled_spline_matches_scipy_not_a_knot():
    rng = np.random.default_rng(3)
    t0, h, n = 2.5, 0.19, 61
    t = t0 + h * np.arange(n)
    vals = np.column_stack([np.sin(t) + 0.01 * rng.standard_normal(n), np.cos(2 * t)])
    m = np.empty_like(vals)
    search_c.spline_second(vals, h, m)
    ref = CubicSpline(t, vals, bc_type="not-a-knot")
    out = np.empty(6)
    for x in np.concatenate([rng.uniform(t[0], t[-1], 50), [t[0], t[-1], t[-1] + 0.05, t[0] - 0.05]]):
        search_c.spline_eval(vals, m, t0, h, x, out)
        assert np.allclose(out[0:2], ref(x), atol=1e-12)
        assert np.allclose(out[2:4], ref(x, 1), atol=1e-10)
        assert np.allclose(out[4:6], ref(x, 2), atol=1e-8)


def test_compiled_contact_search_matches_reference(system):
    s, ref = system
    from spurdyn.solvers.paper.stepper_compiled import pack
    from spurdyn.solvers.paper.step_compiled import search

    p = pack(s, ref.case)
    rng = np.random.default_rng(5)
    for d in (0.0, 0.05, 0.2, pair_end := s.pair.theta_s * 0.999):
        th = np.array([d, d * 1.0001])
        u, _, _ = rigid(s, th)
        u = u + 2e-7 * rng.standard_normal(u.size)
        c = ref.contact_at(th, u, (5.0, 12.0))
        nd = p.fl_nodes.shape[1]
        va, vb, ma, mb = (np.empty((nd, 2)) for _ in range(4))
        a, b, mode, nx, ny, sc = search(p, th, u, np.array([5.0, 12.0]), va, vb, ma, mb)
        assert (a, b, mode) == pytest.approx((c.alpha, c.beta, c.mode), abs=1e-9)
        assert sc == pytest.approx(c.s, abs=1e-15)
        assert np.allclose([nx, ny], c.normal, atol=1e-12)
    assert pair_end > 0


@pytest.mark.parametrize("relief", [False, True])
def test_flank_surface_passes_through_the_outline_nodes(relief):
    """The exact (relieved) flank of the contact model runs through the mesh's outline
    nodes, where the offset ``delta`` from the element edges vanishes; Python and
    compiled versions agree."""
    from spurdyn.geometry.pair import GearPair
    from spurdyn.geometry.presets import nasa_like_relief
    from spurdyn.solvers.paper.stepper_compiled import pack

    pair = paper_pair()
    if relief:
        g = nasa_like_relief(pair.gear_a, pair.gear_b)
        pair = GearPair(gear_a=g, gear_b=g)
        assert g.tip_relief > 0
    case = RunSettings(contact="point", speed_a=400.0, speed_b=400.0, torque=1.0)
    s = build_system(pair, case)
    p = pack(s, case)
    for g, gb in enumerate(s.gears):
        f = gb.flank
        for k in range(int(np.ceil(2 * f.t0)), 2 * f.ny + 1):
            t = k / 2.0
            assert np.hypot(*f.delta(t)) < 1e-12
            assert np.allclose(search_c.delta_at(p.fpar[g], p.sideY[g], t), f.delta(t), atol=1e-15)
        # between the nodes the quadratic edges miss the involute by nanometres
        mid = [np.hypot(*f.delta(t + 0.25)) for t in range(int(np.ceil(f.t0)), f.ny)]
        assert 0 < max(mid) < 1e-6


def _wavy_flanks(system):
    """Flank splines of paper-fig11-bdrive at step 819, iterate 6 (the mirrored pair: B
    drives, B's hard impact at 20,200 rpm): after the impact the flanks are wavy and
    locally nearly conforming, and Newton's iteration for the pair cycles."""
    from pathlib import Path

    from spurdyn.contact import search_numpy as cref

    s, ref = system
    data = np.load(Path(__file__).parent / "data" / "wavy_flanks_fig11_bdrive.npz")
    th, u, guess = data["theta"], data["u"], tuple(data["guess"])
    ua, ub = blocks(s, u)
    fa, fb = s.gears[0].flank, s.gears[1].flank
    pa = cref.flank_spline(fa, s.gears[0].X + ua.reshape(-1, 2), rot(s.gears[0].sense * th[0]))
    pb = cref.flank_spline(fb, s.gears[1].X + ub.reshape(-1, 2), rot(s.gears[1].sense * th[1]))
    return th, u, guess, pa, pb, fa, fb


def test_contact_search_finds_the_deepest_point_where_newton_cycles(system):
    from spurdyn.contact import search_numpy as cref

    s, ref = system
    th, u, guess, pa, pb, fa, fb = _wavy_flanks(system)
    # The case this guards: Newton fails from the guess and from the scan's start.
    assert not cref._newton_pair(pa, pb, *guess)[2]
    assert not cref._newton_pair(pa, pb, *cref._scan(pa, pb, fa, fb, guess[1]))[2]
    c = ref.contact_at(th, u, guess)
    assert c.mode == FLANK
    # Brute force: the normal gap along A, densely, near the pair found.
    a_grid = np.linspace(c.alpha - 0.3, c.alpha + 0.3, 601)
    b = c.beta
    gaps = []
    for a in a_grid:
        g, b = cref._gap(pa, pb, fb, a, b)
        gaps.append(g)
    gaps = np.array(gaps)
    best = int(np.argmin(gaps))
    assert abs(a_grid[best] - c.alpha) <= 1.5e-3          # the grid's spacing is 1e-3
    g_pair, _ = cref._gap(pa, pb, fb, c.alpha, c.beta)
    assert g_pair <= gaps.min() + 1e-15


def test_compiled_search_matches_reference_where_newton_cycles(system):
    from spurdyn.solvers.paper.stepper_compiled import pack
    from spurdyn.solvers.paper.step_compiled import search

    s, ref = system
    th, u, guess, *_ = _wavy_flanks(system)
    c = ref.contact_at(th, u, guess)
    p = pack(s, ref.case)
    nd = p.fl_nodes.shape[1]
    va, vb, ma, mb = (np.empty((nd, 2)) for _ in range(4))
    a, b, mode, nx, ny, sc = search(p, th, u, np.array(guess), va, vb, ma, mb)
    assert (a, b, mode) == pytest.approx((c.alpha, c.beta, c.mode), abs=1e-8)
    assert sc == pytest.approx(c.s, abs=1e-14)


def test_compiled_search_constants_are_the_reference_ones():
    from spurdyn.contact import search_numpy as cref

    assert ((search_c.GOLDEN, search_c.GOLDEN_TOL, search_c.EDGE, search_c.POLISH)
            == (cref.GOLDEN, cref.GOLDEN_TOL, cref.EDGE, cref.POLISH))
