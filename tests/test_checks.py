"""Independent checks of the solver's constraints and of the contact search.

* the constraint errors of a real run, recomputed from the compiled stepper's state with
  the NumPy reference code (root constraints, their velocity and acceleration forms, and
  the contact gap from the reference contact search), against the stage tolerances;
* ``de/dx`` of the velocity stage against ``C = dt G M^-1 G^T`` (docs/solver.md section 7),
  and that the reference stepper iterates the velocity stage with exactly that ``C``;
* the centripetal term ``(Phi_q q_dot)_q q_dot`` of the root constraints against finite
  differences of ``Phi_q q_dot`` along a known motion (docs/solver.md section 3);
* the tip-corner contact rule (docs/solver.md section 4): a tip corner touches the other
  flank, and the normal is that flank's.
"""

import math

import numpy as np
import pytest

import spurdyn.solvers.paper.step_numpy as reference
from spurdyn.contact.search_numpy import (
    CORNER_A, CORNER_B, FLANK, ContactPair, find_contact, flank_spline, outward_normal,
    sliding_acceleration,
)
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper, pack
from spurdyn.solvers.paper.step_compiled import search
from spurdyn.solvers.check import stable_step
from spurdyn.settings import RPM, RunSettings
from spurdyn.solvers.paper.step_numpy import PaperMethod, State, initial_contact_guess
from spurdyn.solvers.paper.dynamics_numpy import blocks, constraint_force, jacobian, rot, root_phi
from spurdyn.model.system import build_system

PAIR = paper_pair()
JZ = np.array([[0.0, -1.0], [1.0, 0.0]])


@pytest.fixture(scope="module")
def paper20k():
    """The paper pair at 20,000 rpm under the paper's torque (default mesh and dt)."""
    case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE)
    system = build_system(PAIR, case)
    return system, case, PaperMethod(system, case)


def rigid(system, theta):
    """Absolute displacements of both teeth turned rigidly by ``theta``."""
    u = np.zeros(system.n_u)
    for g, (gb, ub) in enumerate(zip(system.gears, blocks(system, u))):
        y = gb.Y.reshape(-1, 2)
        ub[:] = (y @ rot(gb.sense * theta[g]).T - y).ravel()
    return u


def reference_state(system, fast):
    """The compiled stepper's state as a reference :class:`State` (contact where the force acts)."""
    S = fast.S
    na = system.gears[0].mesh.n_nodes
    fa, fb = (g.flank for g in system.gears)
    c = ContactPair(alpha=S.cpar[0], beta=S.cpar[1], mode=int(S.cpar[2]), normal=S.normal.copy(),
                    s=S.cpar[3], nodes_a=S.cn[:3].copy(), weights_a=S.cw[:3].copy(),
                    nodes_b=S.cn[3:] - na, weights_b=S.cw[3:].copy(),
                    delta_a=fa.delta(S.cpar[0]), delta_b=fb.delta(S.cpar[1]))
    return State(t=S.t[0], theta=S.theta.copy(), omega=S.omega.copy(), u=S.u.copy(),
                 v=S.v.copy(), x=S.x.copy(), contact=c)


# -- 1. the constraints of a real run, recomputed -------------------------------------------

@pytest.mark.slow
def test_constraints_of_a_real_run_recomputed_with_the_reference_code(paper20k):
    """Through a compiled run of the whole engagement, the reference code's root
    constraints ``Phi``, ``Phi_q q_dot`` and ``Phi_q q_ddot + R Y theta_dot^2``, and the
    contact pair found afresh by the reference search (its gap ``s``, relative normal
    velocity and acceleration), meet the stage tolerances ``1e-12 m``, ``1e-12/dt``,
    ``1e-12/dt^2``: no penetration beyond ``1e-12 m`` ever, and a closed gap wherever the
    force is compressive.

    The stored residuals are what the stepper itself stops on; these are recomputed
    from the state (positions, velocities, accelerations and force) it leaves.
    """
    system, case, ref = paper20k
    tol = np.array([case.tol_disp, case.tol_vel, case.tol_acc])
    # The stepper stops each stage just below its tolerance (the largest recomputed |Phi|
    # is ~0.996e-12 m); the superposed positions carry ~1e-16 m of round-off
    # (tests/test_paper_step_twins.py), so allow that much, 1e-4 of the tolerance, and no more.
    tol = tol * (1.0 + 1e-4)
    fast = CompiledStepper(system, case)
    fa, fb = (g.flank for g in system.gears)
    guess = initial_contact_guess(system)    # the reference search follows its own pair
    # The whole engagement (5,851 steps, until A has turned theta_s): every step of the
    # first 300 (the force builds up from zero), then every 10th, and the last.
    n_checked = 0
    modes = set()
    worst_root = np.zeros(3)
    worst_contact = np.zeros(3)        # |s|, |s_hat|, |s_tilde| while in contact
    worst_pen = -np.inf                # largest s (penetration) at any step
    widest_gap = 0.0                   # most negative s while the force is zero
    worst_pair = 0.0
    p_prev = 0.0
    n_contact = 0
    peak = 0.0
    step = 0
    while fast.S.theta[0] < PAIR.theta_s:
        assert fast.step() == 0
        step += 1
        S = fast.S
        if not (step <= 300 or step % 10 == 0 or S.theta[0] >= PAIR.theta_s):
            p_prev = S.x[-1]
            continue
        n_checked += 1
        th, om, u, v = S.theta, S.omega, S.u, S.v
        # root constraints of both gears
        phi = np.concatenate([root_phi(gb, th[g], ub).ravel()
                              for g, (gb, ub) in enumerate(zip(system.gears, blocks(system, u)))])
        phi_dot = -ref.root_velocity_errors(th, om, v)
        phi_ddot = -ref.root_acceleration_errors(th, om, S.alpha_n, S.a_n)
        worst_root = np.maximum(worst_root, [np.abs(phi).max(), np.abs(phi_dot).max(),
                                             np.abs(phi_ddot).max()])
        # the contact pair from the reference search, from its own last pair
        c = ref.contact_at(th, u, guess)
        guess = (c.alpha, c.beta)
        worst_pair = max(worst_pair, abs(c.alpha - S.cpar[0]) + abs(c.beta - S.cpar[1]))
        assert c.mode == int(S.cpar[2])
        modes.add(c.mode)
        s_hat = ref.normal_of(c, v, ref.velocity_mats(th, om))
        ua, ub = blocks(system, u)
        va, vb = blocks(system, v)
        ra, rb = (rot(g.sense * t) for g, t in zip(system.gears, th))
        ma, mb = ref.velocity_mats(th, om)
        extra, _, _ = sliding_acceleration(
            fa, fb, system.gears[0].X + ua.reshape(-1, 2), system.gears[1].X + ub.reshape(-1, 2),
            ra, rb, va.reshape(-1, 2), vb.reshape(-1, 2), ma, mb, c)
        s_tilde = ref.normal_of(c, S.a_n, ref.acceleration_mats(th, om, S.alpha_n)) + extra
        p = S.x[-1]
        peak = min(peak, p)
        # never a penetration beyond the tolerance; a gap only where the force is zero
        worst_pen = max(worst_pen, c.s)
        assert c.s <= tol[0], (step, c.s)
        if p == 0.0:
            widest_gap = min(widest_gap, c.s)
        if p < 0.0:
            # In contact (the acceleration stage's p < 0 implies the displacement stage's
            # p_bar < 0, which makes pi = s): the gap is closed, and closing no faster
            # than the tolerances.
            assert abs(c.s) <= tol[0], (step, c.s)
            assert s_hat <= tol[1], (step, s_hat)
            assert abs(s_tilde) <= tol[2], (step, s_tilde)
            if p_prev < 0.0:            # in contact over the whole step
                assert abs(s_hat) <= tol[1], (step, s_hat)
                n_contact += 1
                worst_contact = np.maximum(worst_contact, [abs(c.s), abs(s_hat), abs(s_tilde)])
        p_prev = p
    print("largest |Phi|, |Phi_q q_dot|, |Phi_q q_ddot + R Y w^2|:", worst_root,
          "of tolerances", tol)
    print("largest |s|, |s_hat|, |s_tilde| in contact:", worst_contact, "largest s:", worst_pen,
          "widest gap while apart:", widest_gap, "steps in contact:", n_contact)
    print("largest pair difference (flank coordinate):", worst_pair, "steps", step,
          "checked", n_checked, "largest force (N):", -peak, "contact modes seen:", modes)
    assert np.all(worst_root <= tol)
    # the checks saw a real contact under load (the teeth bounce apart for a while near
    # steps 100-450 at this speed, where only s <= tol is required)
    assert n_contact > 500 and -peak > 500.0
    # both searches find the same pair (Newton's stopping step is 1e-11)
    assert worst_pair < 1e-8


# -- 2. de/dx of the velocity stage ----------------------------------------------------------

@pytest.fixture(scope="module")
def loaded20k(paper20k):
    """A reference state in contact under a real force, 1,500 compiled steps into the run."""
    system, case, ref = paper20k
    fast = CompiledStepper(system, case)
    for _ in range(1500):
        assert fast.step() == 0
    st = reference_state(system, fast)
    assert st.x[-1] < -100.0
    return system, case, ref, st


def test_de_dx_against_C_for_the_velocity_stage(loaded20k, monkeypatch):
    """Finite differences of the stage-2 errors ``[-Phi_q q_dot; s_hat]`` against
    ``C = dt G M^-1 G^T``.

    RK4's velocity response to a constant force is ``(dt I + dt^3/12 (A3 + A4)) M^-1``
    (docs/solver.md section 7): ``C`` is its leading term and the stiffness only lowers it,
    by at most ``(w_max dt)^2 / 6`` for a mode. So ``C^-1 de/dx`` has real eigenvalues in
    ``[1 - (w_max dt)^2/6, 1]``. The reference stepper iterates the stage with this ``C``.
    """
    system, case, ref, st = loaded20k
    h = case.dt
    g = jacobian(system, st.theta, st.contact)
    c = h * (g * ref.minv) @ g.T
    # stage 2 keeps the positions of stage 1 and the contact pair found there
    th1, _, u1, _ = ref.rk4(st, *constraint_force(system, st.theta, st.contact, st.x))
    c1 = ref.contact_at(th1, u1, (st.contact.alpha, st.contact.beta))

    def errors(x):
        _, om2, _, v2 = ref.rk4(st, *constraint_force(system, st.theta, st.contact, x))
        sh = ref.normal_of(c1, v2, ref.velocity_mats(th1, om2))
        return np.append(ref.root_velocity_errors(th1, om2, v2), sh)

    m = st.x.size
    fd = np.empty((m, m))
    for j in range(m):
        # the errors are affine in x: a large step keeps the round-off of the velocities
        # (~1e-9 m/s, tests/test_paper_step_twins.py) small against the change
        dx = np.zeros(m)
        dx[j] = max(10.0, abs(st.x[j]))
        fd[:, j] = (errors(st.x + dx) - errors(st.x - dx)) / (2 * dx[j])
    ev = np.linalg.eigvals(np.linalg.solve(c, fd))
    wdt = 2.0 * math.sqrt(2.0) * h / stable_step(system)       # w_max dt
    lower = 1.0 - wdt**2 / 6.0
    print("eigenvalues of C^-1 de/dx:", ev.real.min(), ev.real.max(), "bound", lower,
          "max |imag|", np.abs(ev.imag).max(), "contact diagonal ratio", fd[-1, -1] / c[-1, -1])
    assert np.all(np.abs(ev.imag) < 1e-6 * np.abs(ev.real).max())
    assert ev.real.min() >= lower - 1e-6 and ev.real.max() <= 1.0 + 1e-6
    assert lower - 1e-6 <= fd[-1, -1] / c[-1, -1] <= 1.0 + 1e-6
    # not c = dt^2/2 or c = 1: those are off by orders of magnitude
    assert np.allclose(fd, c, rtol=0.0, atol=0.5 * np.abs(c).max())

    # The reference stepper's velocity stage iterates with exactly this C.
    calls = []
    real = reference.accelerated_update

    def recording(x, e, cmat, n, *active):
        calls.append(cmat.copy())
        return real(x, e, cmat, n, *active)

    monkeypatch.setattr(reference, "accelerated_update", recording)
    _, rep = ref.step(st, 1501)
    i1, i2 = int(rep.iterations[0]), int(rep.iterations[1])
    assert i2 >= 1 and len(calls) == i1 + i2 + int(rep.iterations[2])
    for cmat in calls[i1:i1 + i2]:
        assert np.allclose(cmat, c, rtol=1e-12, atol=1e-12 * np.abs(c).max())


# -- 3. the centripetal term of the root constraints -------------------------------------------

def test_centripetal_term_of_the_root_constraints_by_finite_differences(paper20k):
    """Along a known motion (rigid rotation with angular acceleration, plus a small
    elastic motion of the teeth), ``d/dt (Phi_q q_dot) = Phi_q q_ddot + (Phi_q q_dot)_q q_dot``.

    ``Phi_q q_dot`` is the code's velocity form; its time derivative is taken by finite
    differences, ``Phi_q q_ddot`` by finite differences of ``Phi`` along ``q_ddot``; the
    difference is compared with the code's term ``R Y theta_dot^2``. The whole acceleration
    form is also compared with the second time derivative of ``Phi`` itself.
    """
    system, case, ref = paper20k
    rng = np.random.default_rng(11)
    th0, om, al = np.array([0.3, -0.2]), np.array([2100.0, 1900.0]), np.array([3e4, -5e4])
    # elastic displacements in the disk frame: w(t) = w0 + w1 t + w2 t^2 / 2
    w0, w1, w2 = (k * rng.standard_normal(system.n_u) for k in (1e-6, 1e-2, 1e4))

    def motion(t):
        """q, q_dot and q_ddot at time t: (theta, omega, alpha, u, v, a)."""
        th, thd, thdd = th0 + om * t + 0.5 * al * t * t, om + al * t, al
        w, wd, wdd = w0 + w1 * t + 0.5 * w2 * t * t, w1 + w2 * t, w2
        u, v, a = (np.empty(system.n_u) for _ in range(3))
        for g, gb in enumerate(system.gears):
            sl = slice(system.offsets[g], system.offsets[g + 1])
            s = gb.sense
            r = rot(s * th[g])
            y = gb.Y.reshape(-1, 2)
            p, pd, pdd = (z[sl].reshape(-1, 2) for z in (w, wd, wdd))
            # u = (R - I) Y + R w, differentiated twice (R' = s thd R Jz)
            rj = r @ JZ
            u[sl] = ((y + p) @ r.T - y).ravel()
            v[sl] = (s * thd[g] * (y + p) @ rj.T + pd @ r.T).ravel()
            a[sl] = (s * thdd[g] * (y + p) @ rj.T - thd[g] ** 2 * (y + p) @ r.T
                     + 2 * s * thd[g] * pd @ rj.T + pdd @ r.T).ravel()
        return th, thd, thdd, u, v, a

    def phi(th, u):
        return np.concatenate([root_phi(gb, th[g], ub).ravel()
                               for g, (gb, ub) in enumerate(zip(system.gears, blocks(system, u)))])

    def velocity_form(t):
        th, thd, _, _, v, _ = motion(t)
        return -ref.root_velocity_errors(th, thd, v)          # Phi_q q_dot

    dt = 5e-7                                                 # omega dt ~ 1e-3
    th, thd, thdd, u, v, a = motion(0.0)
    vf = [velocity_form(k * dt) for k in (-2, -1, 1, 2)]
    d_vf = (vf[0] - 8 * vf[1] + 8 * vf[2] - vf[3]) / (12 * dt)  # d/dt (Phi_q q_dot)
    eps = 1e-9                                               # Phi_q q_ddot along q_ddot
    phi_q_qdd = (phi(th + eps * thdd, u + eps * a) - phi(th - eps * thdd, u - eps * a)) / (2 * eps)
    fd_term = d_vf - phi_q_qdd
    code_term = -ref.root_acceleration_errors(th, thd, np.zeros(2), np.zeros(system.n_u))
    scale = np.abs(code_term).max()                          # omega^2 |Y| ~ 2e5 m/s^2
    err = np.abs(fd_term - code_term).max() / scale
    # the term is as large as Phi_q q_ddot here, so a wrong term cannot hide
    assert np.abs(phi_q_qdd).max() > 0.1 * scale
    # the velocity form is the time derivative of Phi
    ph = []
    for k in (-2, -1, 1, 2):
        th_k, _, _, u_k, _, _ = motion(k * dt)
        ph.append(phi(th_k, u_k))
    d_phi = (ph[0] - 8 * ph[1] + 8 * ph[2] - ph[3]) / (12 * dt)
    vf_now = velocity_form(0.0)
    err_v = np.abs(d_phi - vf_now).max() / np.abs(vf_now).max()
    # and the whole acceleration form is the second time derivative of Phi
    ph0 = phi(th, u)
    d2_phi = (-ph[0] + 16 * ph[1] - 30 * ph0 + 16 * ph[2] - ph[3]) / (12 * dt * dt)
    code_acc = -ref.root_acceleration_errors(th, thd, thdd, a)
    err_a = np.abs(d2_phi - code_acc).max() / np.abs(code_acc).max()
    print("relative errors: centripetal term", err, "velocity form", err_v, "acceleration form", err_a)
    assert err < 1e-8
    assert err_v < 1e-8
    assert err_a < 1e-5          # a second difference of ~5 cm positions: round-off ~1e-7


# -- 4. tip-corner contact ---------------------------------------------------------------------

THETA_S = PAIR.theta_s
#: Rigid configurations (theta_A, theta_B) around the start and end of contact (the paper
#: pair's gears are identical, so equal rotations are conjugate).
#: Each: the rotations, the expected mode, the sign of s, and a start (alpha, beta) for
#: the search (None: the start of contact, B's tip on A's flank).
CORNER_CASES = {
    # before the first touch, turned back along the path: B's tip corner stands off A's flank
    "B's tip approaching": ((-1e-3, -1e-3), CORNER_B, -1, None),
    # B turned back alone: its tip corner digs into A's flank
    "B's tip digging in": ((0.0, -1e-4), CORNER_B, +1, None),
    # A turned on past the end of the path: A's tip corner leaves B's flank
    "A's tip leaving": ((THETA_S + 1e-3, THETA_S + 1e-3), CORNER_A, -1, (13.5, 3.5)),
    "mid-engagement": ((0.5 * THETA_S, 0.5 * THETA_S), FLANK, 0, (7.0, 7.0)),
}


def _flanks(system, theta, u):
    ua, ub = blocks(system, u)
    xa = system.gears[0].X + ua.reshape(-1, 2)
    xb = system.gears[1].X + ub.reshape(-1, 2)
    ra, rb = (rot(g.sense * t) for g, t in zip(system.gears, theta))
    fa, fb = (g.flank for g in system.gears)
    return fa, fb, xa, xb, ra, rb, flank_spline(fa, xa, ra), flank_spline(fb, xb, rb)


@pytest.mark.parametrize("name", list(CORNER_CASES))
def test_tip_corner_contact_mode_and_normal(paper20k, name):
    """Where the contact pair would lie beyond a tooth's tip, the search reports that tip
    corner on the other flank (docs/solver.md section 4): ``CORNER_B`` (B's corner on A's
    flank, normal ``n_A``) before and at the start of contact, ``CORNER_A`` (A's corner on
    B's flank, normal ``-n_B``) past its end, ``FLANK`` in between. At a corner the normal
    is the other flank's, not the corner's own tooth's: the two differ there, and the
    corner lies on that normal through the contact point (the foot of the normal)."""
    system, case, ref = paper20k
    theta, mode, sign, guess = CORNER_CASES[name]
    theta = np.array(theta)
    u = rigid(system, theta)
    guess = initial_contact_guess(system) if guess is None else guess
    fa, fb, xa, xb, ra, rb, pa, pb = _flanks(system, theta, u)
    c = find_contact(fa, fb, xa, xb, ra, rb, guess)
    n_a = outward_normal(pa(c.alpha, 1))          # A's flank normal at the pair
    n_b = outward_normal(pb(c.beta, 1))           # B's
    d = pa(c.alpha) - pb(c.beta)                  # from B's point to A's
    assert c.mode == mode
    if mode == CORNER_B:
        assert c.beta == fb.t1 and fa.t0 < c.alpha < fa.t1
        assert np.allclose(c.normal, n_a, rtol=0, atol=1e-14)
        other = -n_b                               # the corner's own tooth's normal
    elif mode == CORNER_A:
        assert c.alpha == fa.t1 and fb.t0 < c.beta < fb.t1
        assert np.allclose(c.normal, -n_b, rtol=0, atol=1e-14)
        other = n_a
    else:
        assert fa.t0 + 1 < c.alpha < fa.t1 - 1 and fb.t0 + 1 < c.beta < fb.t1 - 1
        assert np.allclose(c.normal, n_a, rtol=0, atol=1e-14)
        assert np.allclose(c.normal, -n_b, rtol=0, atol=1e-12)   # tangents parallel
        assert abs(c.s) < 1e-14                                  # conjugate rigid teeth
        other = None
    if other is not None:
        # the rule matters here: the two candidate normals differ by ~1e-4 rad or more
        assert np.hypot(*(other - c.normal)) > 1e-4
        # the corner lies on the flank's normal through the contact point (foot of the
        # normal), and s is the signed distance along it: a gap (< 0) or penetration (> 0)
        assert abs(d[0] * c.normal[1] - d[1] * c.normal[0]) < 1e-9 * np.hypot(*d)
        assert np.sign(c.s) == sign and abs(c.s) > 1e-10
        assert abs(c.s) == pytest.approx(np.hypot(*d), rel=1e-3)
    # the compiled search reports the same
    p = pack(system, case)
    nd = p.fl_nodes.shape[1]
    va, vb, ma, mb = (np.empty((nd, 2)) for _ in range(4))
    a, b, mode_k, nx, ny, sk = search(p, theta, u, np.array(guess), va, vb, ma, mb)
    assert (a, b, mode_k) == pytest.approx((c.alpha, c.beta, c.mode), abs=1e-9)
    assert np.allclose([nx, ny], c.normal, rtol=0, atol=1e-12)
    assert sk == pytest.approx(c.s, rel=1e-6, abs=1e-16)


def test_contact_at_the_very_start_is_at_Bs_tip_corner(paper20k):
    """At the start of contact (the placement, theta = 0) B's tip corner touches A's flank:
    the pair sits at B's tip, the gap is closed, and the flank and corner rules give the
    same normal there (the involutes are tangent on the line of action). The search
    reports ``FLANK`` here (Newton's pair lies ~1e-6 element inside the tip, the spline's
    accuracy) or ``CORNER_B``; turned back by 1e-7 rad it reports ``CORNER_B``."""
    system, case, ref = paper20k
    fb = system.gears[1].flank
    for theta, modes in (((0.0, 0.0), (FLANK, CORNER_B)), ((-1e-7, -1e-7), (CORNER_B,))):
        theta = np.array(theta)
        u = rigid(system, theta)
        fa, fb, xa, xb, ra, rb, pa, pb = _flanks(system, theta, u)
        c = find_contact(fa, fb, xa, xb, ra, rb, initial_contact_guess(system))
        print(theta, "mode", c.mode, "beta", c.beta, "s", c.s)
        assert c.mode in modes
        assert fb.t1 - c.beta < 1e-5
        assert abs(c.s) < 1e-11
        assert np.allclose(c.normal, outward_normal(pa(c.alpha, 1)), rtol=0, atol=1e-14)
        # B's own normal at its tip: the same to the spline's accuracy (and, turned back
        # by 1e-7 rad, to 4e-7: the angle between the two grows as the rotation)
        print("normal against -n_B at the tip:", np.abs(c.normal + outward_normal(pb(fb.t1, 1))).max())
        assert np.allclose(c.normal, -outward_normal(pb(fb.t1, 1)), rtol=0, atol=2e-6)
