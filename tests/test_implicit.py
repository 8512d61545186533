"""The implicit integrator (generalized-alpha with the constraints at the end of each step):
its coefficients, its damping forces, its solves, its energy on a free pair, and the
paper's Fig. 9 against RK4 at a step 22 times larger (docs/implicit.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.case import preset_case
from spurdyn.geometry import paper_pair
from spurdyn.model.alpha import GeneralizedAlpha, accuracy_step
from spurdyn.model.system import build_system
from spurdyn.results.headline import averaged_peak, moving_average
from spurdyn.settings import RPM, RunSettings
from spurdyn.solvers.implicit.damping import rayleigh_forces, rayleigh_from_ratio
from spurdyn.solvers.implicit.step_numpy import ImplicitMethod
from spurdyn.solvers.implicit.stepper import ImplicitStepper
from spurdyn.solvers.loop import simulate
from spurdyn.solvers.paper.dynamics_numpy import blocks, jacobian, rot

PAIR = paper_pair()


def _sdof(rho: float, wh: float, steps: int) -> np.ndarray:
    """Positions of ``qddot + w^2 q = 0`` (w = 1) stepped by the scheme's recursions from
    ``q = 1, qdot = 0`` (equilibrium at n+1, the acceleration-like ``a`` as in the step)."""
    c = GeneralizedAlpha(rho)
    h = wh
    q, v, qdd = 1.0, 0.0, -1.0
    a = qdd
    out = [q]
    am, af, b, g = c.alpha_m, c.alpha_f, c.beta, c.gamma
    for _ in range(steps):
        # qdd1 = -q1, q1 = q + h v + h^2 ((1/2 - b) a + b a1), a1 = ((1-af) qdd1 + af qdd - am a)/(1-am)
        k = h * h * b * (1.0 - af) / (1.0 - am)
        rest = q + h * v + h * h * ((0.5 - b) * a + b * (af * qdd - am * a) / (1.0 - am))
        q1 = rest / (1.0 + k)
        qdd1 = -q1
        a1 = ((1.0 - af) * qdd1 + af * qdd - am * a) / (1.0 - am)
        v = v + h * ((1.0 - g) * a + g * a1)
        q, qdd, a = q1, qdd1, a1
        out.append(q)
    return np.array(out)


def test_the_coefficients_give_the_asked_high_frequency_dissipation_and_second_order():
    c = GeneralizedAlpha(1.0)
    assert (c.alpha_m, c.alpha_f, c.gamma, c.beta) == (0.5, 0.5, 0.5, 0.25)
    for rho in (0.2, 0.5, 0.8):
        # A mode far above the step's resolution decays as n^2 rho^n (the scheme's triple
        # root at -rho_inf): from step 100 to 150 by rho^50 times 1.5^2.
        q = _sdof(rho, 1e6, 150)
        rate = (abs(q[-1]) + abs(q[-2])) / (abs(q[-51]) + abs(q[-52]))
        assert rate ** (1 / 50) == pytest.approx(rho * 1.5 ** (2 / 50), rel=1e-3)
    q = _sdof(1.0, 1e6, 150)                    # rho_inf = 1: no dissipation
    assert abs(q[-1]) == pytest.approx(1.0, abs=1e-6)
    # the resolved mode: the error a quarter period on (cos = 0 there, so the phase error
    # shows at first order) falls 4 times when the step halves
    errs = [abs(_sdof(0.8, 2 * math.pi / n, n // 4)[-1]) for n in (40, 80)]
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.1)
    # and its amplitude decays by much less than the high modes': a few 1e-5 a period at 40 steps
    assert abs(_sdof(0.8, 2 * math.pi / 40, 40)[-1]) > 0.999


def test_the_default_step_is_one_of_accuracy():
    assert accuracy_step(4000 * RPM, 28) == pytest.approx(1 / 1.5e6)       # 150 kHz / 10
    assert accuracy_step(30000 * RPM, 28) == pytest.approx(60 / 30000 / 28 / 175)
    # Fig. 9 (20,000 rpm): 6.1e-7 s once rounded down, at least 20 times RK4's 3e-8 s
    assert accuracy_step(20000 * RPM, 28) >= 6.1e-7 > 20 * 3e-8
    assert rayleigh_from_ratio(0.05, 1e3, 1e5)[0] / (2 * 1e3 * 2 * math.pi) \
        + rayleigh_from_ratio(0.05, 1e3, 1e5)[1] * 2 * math.pi * 1e3 / 2 == pytest.approx(0.05)


def _state(seed: int = 1):
    case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4000 * RPM, torque=10.0)
    system = build_system(PAIR, case)
    rng = np.random.default_rng(seed)
    gb = system.gears[1]
    theta = 0.3
    y = gb.Y.reshape(-1, 2)
    u = (y @ rot(gb.sense * theta).T - y).ravel() + 1e-6 * rng.standard_normal(gb.n_u)
    v = 10.0 * rng.standard_normal(gb.n_u)
    return gb, theta, u, v


def test_rayleigh_forces_are_minus_the_velocity_gradient_of_the_dissipation_function():
    """``f = -dD/dqdot`` with ``D = 1/2 w_dot^T (a M + b K) w_dot``, by central differences."""
    gb, theta, u, v = _state()
    a, b, omega = 300.0, 2e-7, 420.0

    def dissipation(om: float, vel: np.ndarray) -> float:
        q, f = rayleigh_forces(gb, theta, om, u, vel, a, b)
        # D is quadratic in the velocities and f = -dD/dqdot, so D = -1/2 qdot . f
        return -0.5 * (om * q + vel @ f)

    q, f = rayleigh_forces(gb, theta, omega, u, v, a, b)
    h = 10.0          # D is quadratic: central differences are exact at any step, and a
    #                   large one keeps them above the rounding of D
    idx = np.random.default_rng(3).choice(gb.n_u, 12, replace=False)
    for i in idx:
        e = np.zeros(gb.n_u)
        e[i] = h
        fd = (dissipation(omega, v + e) - dissipation(omega, v - e)) / (2 * h)
        assert -fd == pytest.approx(f[i], rel=1e-6, abs=1e-9 * np.abs(f).max())
    fd = (dissipation(omega + h, v) - dissipation(omega - h, v)) / (2 * h)
    assert -fd == pytest.approx(q, rel=1e-6)
    assert -(omega * q + v @ f) > 0.0               # it only ever takes energy


def test_rayleigh_damping_leaves_a_rigid_rotation_alone():
    gb, theta, _, _ = _state()
    y = gb.Y.reshape(-1, 2)
    r = rot(gb.sense * theta)
    u = (y @ r.T - y).ravel()
    omega = 500.0
    v = (gb.sense * omega * (y @ r.T) @ np.array([[0.0, 1.0], [-1.0, 0.0]])).ravel()
    q, f = rayleigh_forces(gb, theta, omega, u, v, 300.0, 2e-7)
    assert abs(q) < 1e-12 and np.abs(f).max() < 1e-9


def test_the_root_columns_of_the_iteration_matrix_match_its_solves():
    case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4000 * RPM, torque=10.0,
                       integrator="implicit", dt=6.6e-7, damping_ratio=0.05)
    system = build_system(PAIR, case)
    method = ImplicitMethod(system, case)
    stepper = ImplicitStepper(system, case)
    theta = np.array([0.1, -0.07])
    g = jacobian(system, theta, stepper.state.contact)
    n_root = sum(system.n_lambda)
    for touching in (False, True):
        cols = method.root_columns(theta, g, touching)
        each = np.column_stack([method.solve(theta, g[k], touching) for k in range(n_root)])
        assert np.abs(cols - each).max() <= 1e-12 * np.abs(each).max()


def _energy(stepper: ImplicitStepper) -> float:
    system, st = stepper.system, stepper.state
    e = 0.0
    for g, (gb, ub, vb) in enumerate(zip(system.gears, blocks(system, st.u), blocks(system, st.v))):
        w = ((gb.Y + ub).reshape(-1, 2) @ rot(gb.sense * st.theta[g])).ravel() - gb.Y
        e += 0.5 * gb.inertia * st.omega[g] ** 2 + 0.5 * np.sum(gb.mass * vb * vb) \
            + 0.5 * w @ (gb.stiffness @ w)
    return e


@pytest.mark.slow
@pytest.mark.parametrize("rho", [1.0, 0.8])
def test_a_free_spinning_pair_keeps_its_energy_up_to_the_dissipation_asked_for(rho):
    """No torque and the teeth apart: without numerical dissipation (rho_inf = 1) the
    energy stays to 1e-9; with rho_inf = 0.8 it never grows and loses less than 1e-6 in
    300 steps (the teeth's start-up vibration is what the scheme damps)."""
    case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4400 * RPM, torque=0.0,
                       integrator="implicit", dt=6.6e-7, rho_inf=rho)
    stepper = ImplicitStepper(build_system(PAIR, case), case)
    e0 = _energy(stepper)
    energies = []
    for _ in range(30):
        assert stepper.advance(10, 10.0, 10**9, np.empty((1, 19)), 0, [])[2] == ""
        assert stepper.state.x[-1] == 0.0
        energies.append(_energy(stepper))
    assert stepper.state.contact.s < -1e-8           # really apart
    change = (np.array(energies) - e0) / e0
    if rho == 1.0:
        assert np.abs(change).max() < 1e-9
    else:
        assert change.max() < 1e-12 and change.min() > -1e-6


@pytest.mark.slow
def test_the_implicit_step_follows_rk4_through_fig9_at_a_step_22_times_larger():
    """Fig. 9 (20,000 rpm, point contact): the 10-us-averaged force within 2 % RMS of its
    peak and the averaged peak within 1 %, at 6.6e-7 s against RK4's 3e-8 s."""
    case = preset_case("paper-fig9")
    ref = simulate(case.pair, case.run.with_(frames_every=0))
    imp = simulate(case.pair, case.run.with_(frames_every=0, integrator="implicit", dt=6.6e-7))
    assert imp.status == "complete" and imp.steps * 20 < ref.steps
    a = moving_average(ref.time, ref.contact_force)
    b = moving_average(imp.time, imp.contact_force)
    on = np.interp(imp.time, ref.time, a)
    ok = np.isfinite(on) & np.isfinite(b)
    peak = averaged_peak(ref.time, ref.contact_force)[0]
    assert np.sqrt(np.mean((on[ok] - b[ok]) ** 2)) < 0.02 * peak
    assert averaged_peak(imp.time, imp.contact_force)[0] == pytest.approx(peak, rel=0.01)


@pytest.mark.slow
def test_a_case_asks_for_the_implicit_integrator_its_step_and_its_damping(tmp_path, monkeypatch):
    """run.integrator / --integrator: a preset without --dt takes the step of accuracy;
    Rayleigh damping from a ratio at two frequencies; the case survives its TOML round
    trip; the run folder says which integrator made it."""
    import json

    from spurdyn.case import case_from_dict, case_to_dict, resolve_cases
    from spurdyn.cli.main import main

    case = resolve_cases("paper-fig8", {"run.integrator": "implicit", "run.rayleigh_ratio": 0.02,
                                        "run.rayleigh_hz": [5e3, 2e5], "run.damping_ratio": 0.05})[0]
    assert case.run.integrator == "implicit" and case.run.dt == 6.6e-7
    assert (case.run.rayleigh_mass, case.run.rayleigh_stiffness) == rayleigh_from_ratio(0.02, 5e3, 2e5)
    again = case_from_dict(case_to_dict(case), check_step=False).run
    assert again == case.run.with_(name=again.name)
    assert resolve_cases("paper-fig8", {"run.integrator": "implicit", "run.dt": 1e-7})[0].run.dt == 1e-7
    monkeypatch.chdir(tmp_path)
    assert main(["run", "paper-fig8", "--integrator", "implicit", "--damping", "0.05",
                 "--angle", "1", "--quiet", "--out", "r"]) == 0
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert summary["integrator"] == "implicit" and summary["settings"]["run"]["damping_ratio"] == 0.05


@pytest.mark.slow
@pytest.mark.parametrize("contact", ["point", "hertz"])
def test_the_compiled_implicit_step_follows_its_numpy_twin(contact):
    """The compiled implicit step (backend numba) against NumPy's, its twin: 150 steps of
    Fig. 9 under load agree to 1e-8 of the force. The Newton
    iterations stop at tol_disp = 1e-12 m, which at the pair's ~2e8 N/m leaves the force
    defined to ~2e-4 N (3e-7 of it); the two agree 30 times closer."""
    case = preset_case("paper-fig9")
    run = case.run.with_(frames_every=0, integrator="implicit", dt=5.3e-7, contact=contact,
                         angle=150 * 5.3e-7 * case.run.speed_a)
    a = simulate(case.pair, run.with_(backend="numba"))
    b = simulate(case.pair, run.with_(backend="numpy"))
    assert a.steps == b.steps == 150 and a.contact_force.max() > 500.0
    assert np.abs(a.contact_force - b.contact_force).max() <= 1e-8 * a.contact_force.max()


@pytest.mark.parametrize("contact", ["point", "hertz"])
def test_the_compiled_implicit_stepper_starts_from_the_free_start_without_a_numpy_step(
        contact, monkeypatch):
    """The compiled implicit stepper takes its start state and its pack from the free
    functions both steppers call (``implicit_scheme``, ``initial_implicit_state``): it
    builds no NumPy step (no ``ImplicitMethod``, whose per-gear factorisations it does not
    need), and it starts from the very state the NumPy stepper starts from."""
    from spurdyn.solvers.implicit import step_numpy
    from spurdyn.solvers.implicit.stepper import CompiledImplicitStepper

    case = RunSettings(contact=contact, speed_a=4000 * RPM, speed_b=4000 * RPM, torque=10.0,
                       integrator="implicit", dt=6.6e-7, damping_ratio=0.05,
                       rayleigh_mass=300.0, rayleigh_stiffness=2e-8)
    system = build_system(PAIR, case)
    ref = ImplicitStepper(system, case)

    def refuse(*args, **kwargs):
        raise AssertionError("the compiled stepper built a NumPy step")

    monkeypatch.setattr(step_numpy.ImplicitMethod, "__init__", refuse)
    fast = CompiledImplicitStepper(system, case.with_(backend="numba"))
    assert not isinstance(fast, ImplicitStepper)
    for name in ("theta", "omega", "u", "v", "x", "qdd", "acc"):
        assert np.array_equal(getattr(fast.state, name), getattr(ref.state, name)), name
    assert fast.t == ref.t and np.array_equal(fast.row(), ref.row())
    assert fast.I.c_mesh == ref.method.c_mesh > 0.0 and np.array_equal(fast.I.mq, ref.method.mq)
