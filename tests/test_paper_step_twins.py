"""The compiled stepper against the NumPy reference, and the superposition against
re-integration.

Both compute the same step; they differ in the order of floating-point operations. The
elastic forces come from ``w = R^T (Y + u) - Y``, a difference of ~5 cm positions that
leaves micrometres, so an ulp of position (~1e-17 m) becomes ``K/m`` times that in
acceleration: about ``eps |Y| w_max^2 ~ 1e-16 * 0.045 * (8e7)^2 ~ 0.03 m/s^2`` against
nodal accelerations of ~1e6 m/s^2. That is the round-off floor the tolerances below
are set from: accelerations to ~1e-7 relative, velocities to ``dt`` times that.
"""

import math

import numpy as np
import pytest

from spurdyn.contact.search_numpy import ContactPair
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.solvers.loop import simulate
from spurdyn.solvers.paper import response_compiled as resp_c
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper
from spurdyn.settings import RPM, RunSettings
from spurdyn.solvers.paper.step_numpy import PaperMethod, State, initial_state
from spurdyn.solvers.paper.dynamics_numpy import constraint_force
from spurdyn.model.system import build_system

PAIR = paper_pair()


@pytest.fixture(scope="module")
def pair_of_steppers():
    case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE)
    system = build_system(PAIR, case)
    return system, case, CompiledStepper(system, case), PaperMethod(system, case)


@pytest.mark.slow
def test_compiled_and_reference_steps_agree_over_300_steps():
    """On 2 x 8 teeth meshes (the reference's steps cost as the DOFs: 4 s, not 30 s, on the
    default 4 x 14; the differences are as small a part of the tolerances on either)."""
    case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE, nx=2, ny=8)
    system = build_system(PAIR, case)
    fast, ref = CompiledStepper(system, case), PaperMethod(system, case)
    st = initial_state(ref.system, ref.case)
    worst = np.zeros(4)
    peak = 0.0
    for i in range(300):
        assert fast.step() == 0
        st, rep = ref.step(st, i + 1)
        S = fast.S
        peak = max(peak, -st.x[-1])
        worst = np.maximum(worst, [
            np.abs(S.u - st.u).max(),
            np.abs(S.v - st.v).max(),
            np.abs(S.theta - st.theta).max(),
            abs(S.x[-1] - st.x[-1]),
        ])
    assert peak > 20.0                           # in contact, with a real force
    print("worst differences (m, m/s, rad, N):", worst)
    # The two runs part only by round-off; each step's iterations stop anywhere below the
    # tolerances, so differences may grow to a small part of them, never beyond.
    assert worst[0] < 1e-2 * case.tol_disp       # displacements (m)
    assert worst[1] < 1e-2 * case.tol_vel        # velocities (m/s)
    assert worst[2] < 1e-2 * case.tol_disp / 0.04  # disk rotations (rad)
    assert worst[3] < 1e-3                       # contact force (N), of ~30 N


def test_superposition_equals_reintegration(pair_of_steppers):
    """The predicted step plus the linear response to a force change equals RK4 re-run
    with the changed force, to the round-off floor."""
    system, case, _, ref = pair_of_steppers
    fast = CompiledStepper(system, case)
    for _ in range(80):
        fast.step()
    S, P = fast.S, fast.P
    na = system.gears[0].mesh.n_nodes
    # disk entries in the contact row, as a strip's pair rolling with the disks has
    # (docs/solver.md 11.3; ~1e-7 m/rad): their torques go through the superposition too
    S.gth[:] = (1.3e-7, -2.1e-7)
    c = ContactPair(alpha=S.cpar[0], beta=S.cpar[1], mode=int(S.cpar[2]), normal=S.normal.copy(),
                    s=S.cpar[3], nodes_a=S.cn[:3].copy(), weights_a=S.cw[:3].copy(),
                    nodes_b=S.cn[3:] - na, weights_b=S.cw[3:].copy(),
                    delta_a=np.zeros(2), delta_b=np.zeros(2), theta_row=tuple(S.gth))
    st = State(t=S.t[0], theta=S.theta.copy(), omega=S.omega.copy(), u=S.u.copy(), v=S.v.copy(),
               x=S.x.copy(), contact=c)
    # RK4's first slope: give both the same (the reference recomputes it, the fast stepper
    # carries it over from the last acceleration stage)
    S.alpha_n[:], S.a_n[:] = ref.accelerations(st.theta, st.u, *constraint_force(system, st.theta, c, st.x))
    pred = resp_c.predict(P, S, case.dt)
    rng = np.random.default_rng(0)
    scale = np.abs(S.x).max()
    # the round-off floor of accelerations (module docstring), from this model
    from spurdyn.solvers.check import stable_step
    omega_max = 2.0 * math.sqrt(2.0) / stable_step(system)
    floor_a = np.finfo(float).eps * np.abs(P.Y).max() * omega_max**2
    for trial in range(3):
        x = S.x + 0.3 * scale * rng.standard_normal(S.x.size)
        th1, u1, om1, v1 = resp_c.superpose(P, S, case.dt, pred, x, S.cn, S.cw, S.normal, S.gth, True)
        rth, rom, ru, rv = ref.rk4(st, *constraint_force(system, st.theta, c, x))
        assert np.abs(u1 - ru).max() < 1e-16          # m; displacements ~1e-2 m
        assert np.abs(th1 - rth).max() < 1e-16        # rad
        assert np.abs(v1 - rv).max() < 4 * case.dt * floor_a     # m/s; velocities ~1e2 m/s
        assert np.abs(om1 - rom).max() < 1e-9                    # rad/s; speeds ~2e3 rad/s
        # and the response is far from negligible: a wrong superposition would show
        assert np.abs(u1 - resp_c.superpose(P, S, case.dt, pred, S.x, S.cn, S.cw, S.normal,
                                               S.gth, True)[1]).max() > 1e-12


def test_gear_b_driving_is_the_mirror_image():
    """An identical pair driven by B at equal speeds is the mirror image of the same pair
    driven by A: the same contact force history."""
    case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE,
                   angle=math.radians(2.0), frames_every=0)
    ra = simulate(PAIR, case)
    rb = simulate(GearPair(gear_a=PAIR.gear_a, gear_b=PAIR.gear_b, driver="b"), case)
    assert ra.status == rb.status == "complete"
    n = min(ra.time.size, rb.time.size)
    assert np.allclose(ra.contact_force[:n], rb.contact_force[:n], rtol=1e-6, atol=1e-6)
    # the roles swap: A driven by B turns as B did when driven by A
    assert np.allclose(ra.theta[:n, ::-1], rb.theta[:n], rtol=0, atol=1e-12)
    assert np.allclose(ra.omega[:n, ::-1], rb.omega[:n], rtol=1e-12)
    assert rb.torque[-1, 1] > 0 > rb.torque[-1, 0]        # B's torque drives now


def test_a_stage_that_does_not_converge_stops_both_backends_and_keeps_the_steps_before():
    # With 8 iterations allowed, the velocity stage of step 3 at 20,000 rpm needs more.
    case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE, max_iter=8,
                   angle=0.004, frames_every=0)
    runs = {b: simulate(PAIR, case.with_(backend=b), chunk=50) for b in ("numba", "numpy")}
    for r in runs.values():
        assert r.status == "incomplete"
        assert r.reason.startswith("step 3: the velocity stage did not converge in 8 iterations")
        assert r.steps == 2 and r.time.size == 3      # t = 0 and the two steps made
    assert np.allclose(runs["numba"].omega, runs["numpy"].omega, rtol=1e-9)
    assert np.allclose(runs["numba"].contact_force, runs["numpy"].contact_force, rtol=1e-6, atol=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_a_nan_stops_the_run_and_keeps_the_steps_before(backend, monkeypatch):
    """A NaN in the state (here put into one nodal velocity after the first chunk of 20
    steps) stops the run with status ``incomplete``, a reason naming the NaN and the
    step, and the 20 steps made before it; no row of the history holds a NaN."""
    from spurdyn.solvers import loop as run_module

    make = run_module.make_stepper

    def poisoned(system, case):
        stepper = make(system, case)
        advance = stepper.advance
        calls = []

        def advance_then_poison(*args):
            if calls:  # the second chunk starts from a state with a NaN in it
                stepper.state.v[7] = np.nan
            calls.append(1)
            return advance(*args)

        stepper.advance = advance_then_poison
        return stepper

    monkeypatch.setattr(run_module, "make_stepper", poisoned)
    case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE, backend=backend,
                   angle=0.004, frames_every=0)
    r = simulate(PAIR, case, chunk=20)
    assert r.status == "incomplete"
    assert "NaN" in r.reason and "step 21" in r.reason, r.reason
    assert r.steps == 20 and r.time.size == 21
    assert np.all(np.isfinite(r.contact_force)) and np.all(np.isfinite(r.omega))
