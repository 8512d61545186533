"""The two-disk, one-spring lumped model (spurdyn.lumped)."""

import copy
import math
from dataclasses import replace

import numpy as np
import pytest

from spurdyn.geometry import paper_pair
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, paper_gear
from spurdyn.lumped import (
    MeshStiffnessTable,
    equivalent_mass,
    mesh_stiffness_table,
    simulate_lumped,
    torsional_natural_frequency,
)
from spurdyn.settings import RPM, RunSettings


@pytest.fixture(scope="module")
def pair():
    return paper_pair()


@pytest.fixture(scope="module")
def table(pair):
    return mesh_stiffness_table(pair)


def run(pair, table, rpm_a, rpm_b=None, torque=PAPER_TORQUE, dt=1e-6, **kw):
    rpm_b = rpm_a if rpm_b is None else rpm_b
    case = RunSettings(contact="point", speed_a=rpm_a * RPM, speed_b=rpm_b * RPM, torque=torque, dt=dt,
                   **{k: v for k, v in kw.items() if k in ("angle", "save_every")})
    return simulate_lumped(pair, case, table=table,
                           **{k: v for k, v in kw.items() if k == "damping_ratio"})


def single_zone(pair, res):
    return (res.angle > pair.theta_2) & (res.angle < pair.theta_s - pair.theta_2)


def energy(pair, res, k):
    ja, jb = pair.gear_a.disk_inertia, pair.gear_b.disk_inertia
    delta = np.maximum(-res.gap, 0.0)
    return 0.5 * ja * res.omega[:, 0] ** 2 + 0.5 * jb * res.omega[:, 1] ** 2 + 0.5 * k * delta**2


def momentum(pair, res):
    """``J_A w_A / r_bA + J_B w_B / r_bB``: its rate is ``tau_A / r_bA + tau_B / r_bB``."""
    a, b = pair.gear_a, pair.gear_b
    return a.disk_inertia * res.omega[:, 0] / a.base_radius + b.disk_inertia * res.omega[:, 1] / b.base_radius


# -- stiffness table and natural frequency ------------------------------------------------
def test_table_spans_the_path_and_is_symmetric(pair, table):
    assert table.roll_a[0] == pair.start_roll_a and table.roll_a[-1] == pair.end_roll_a
    assert table.roll_a.size == 41
    assert np.allclose(table.stiffness, table.stiffness[::-1], rtol=1e-9)
    r = np.linspace(pair.start_roll_a, pair.end_roll_a, 333)
    k = table(r)
    assert np.all(k > 0.9 * table.stiffness.min())
    assert k == pytest.approx([table.scalar(float(x)) for x in r], rel=1e-12)
    assert table(table.roll_a) == pytest.approx(table.stiffness, rel=1e-12)
    # Out of mesh beyond the ends of the path.
    assert table(pair.start_roll_a - 1e-3) == 0.0 and table.scalar(pair.end_roll_a + 1e-3) == 0.0


def test_natural_frequency_formula(pair):
    j, rb = pair.gear_a.disk_inertia, pair.gear_a.base_radius
    assert equivalent_mass(pair) == pytest.approx(j / (2 * rb**2), rel=1e-14)
    # Reference figures: 4.9 kHz with ISO's c' b = 8.0e7 N/m.
    assert torsional_natural_frequency(pair, 8.0e7) == pytest.approx(4.9e3, rel=0.01)
    f = torsional_natural_frequency(pair, np.array([1e8, 4e8]))
    assert f[1] == pytest.approx(2 * f[0], rel=1e-14)


# -- runs ---------------------------------------------------------------------------------
def test_result_layout_and_grid(pair, table):
    res = run(pair, table, 4000, dt=3e-8, save_every=10)
    n = res.time.size
    assert res.complete and res.info["model"] == "lumped" and res.info["n_dof"] == 2
    assert np.array_equal(res.time, (np.arange(n) * 10) * 3e-8)
    assert res.time[-1] <= res.info["t_end"] < res.time[-1] + 3e-7
    assert res.info["angle_end"] == pytest.approx(pair.theta_s, rel=1e-9)
    for name, shape in (("angle", (n,)), ("contact_force", (n,)), ("gap", (n,)), ("roll", (n, 2)),
                        ("theta", (n, 2)), ("omega", (n, 2)), ("torque", (n, 2))):
        assert getattr(res, name).shape == shape, name
    assert res.frame_u.shape == (0, 0) and res.frame_theta.shape == (0, 2) and res.frame_time.shape == (0,)
    # no constraint iteration and no contact point: none, not zeros (issue 35)
    assert res.residual is None and res.iterations is None and res.corner is None
    assert np.array_equal(res.angle, res.theta[:, 0])
    assert res.roll[:, 0] == pytest.approx(pair.start_roll_a + res.angle, rel=1e-14)
    assert res.roll[0, 1] == pytest.approx(pair.end_roll_a, rel=1e-12)  # starts at B's tip
    assert res.info["single_zone"] == pytest.approx((pair.theta_2, pair.theta_s - pair.theta_2))
    assert res.info["static_force"] == pytest.approx(PAPER_TORQUE / pair.gear_a.base_radius)
    assert len(res.info["mesh_stiffness_table"]["stiffness"]) == 41
    # Compression where the force acts, F = k(roll) * (-gap).
    on = res.contact_force > 0
    assert np.all(res.gap[on] < 0)
    assert res.contact_force[on] == pytest.approx(table(res.roll[on, 0]) * -res.gap[on], rel=1e-12)


def test_stops_at_the_requested_angle(pair, table):
    res = run(pair, table, 4000, dt=1e-7, angle=0.1)
    assert res.complete and res.info["angle_end"] == pytest.approx(0.1, rel=1e-9)
    assert res.angle[-1] <= 0.1 and res.angle[-1] > 0.1 - 1e-7 * 4000 * RPM * 1.01


def test_quasi_static_limit(pair, table):
    res = run(pair, table, 200)
    f0 = PAPER_TORQUE / pair.gear_a.base_radius
    sz = single_zone(pair, res)
    assert res.contact_force[sz].mean() == pytest.approx(f0, rel=0.01)
    # Everywhere the force follows the torque ramps within a few per cent of f0.
    assert np.abs(res.contact_force - res.torque[:, 0] / pair.gear_a.base_radius).max() < 0.03 * f0
    # Equal pitch-line speeds throughout, the drive never slips ahead.
    assert np.all(res.contact_force[1:] > 0)


def test_ringing_frequency_is_the_torsional_frequency(pair, table):
    res = run(pair, table, 500, dt=1e-7)
    sz = single_zone(pair, res)
    x = res.contact_force[sz] - PAPER_TORQUE / pair.gear_a.base_radius
    t = res.time[sz]
    i = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    assert tc.size >= 8
    f_measured = (tc.size - 1) / (tc[-1] - tc[0])
    k_single = table.mean(*pair.single_contact_roll_a)
    assert f_measured == pytest.approx(torsional_natural_frequency(pair, k_single), rel=0.03)


def test_constant_spring_rings_at_exactly_its_frequency(pair):
    k = 1.9e8
    res = run(pair, MeshStiffnessTable.constant(pair, k), 1000, dt=1e-7)
    sz = single_zone(pair, res)
    x = res.contact_force[sz] - PAPER_TORQUE / pair.gear_a.base_radius
    t = res.time[sz]
    i = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    assert (tc.size - 1) / (tc[-1] - tc[0]) == pytest.approx(torsional_natural_frequency(pair, k), rel=1e-6)


def test_free_impact_conserves_momentum_and_energy(pair):
    """No torque, A 1 % faster: one elastic impact, then the teeth part for good."""
    k = 1.9e8
    res = run(pair, MeshStiffnessTable.constant(pair, k), 1010, 1000, torque=0.0, dt=1e-7)
    assert res.complete
    p = momentum(pair, res)
    assert np.abs(p / p[0] - 1).max() < 1e-10
    e = energy(pair, res, k)
    assert np.abs(e / e[0] - 1).max() < 1e-10
    # Restitution 1: the relative speed along the line of action is reversed.
    rb = pair.gear_a.base_radius
    v = rb * (res.omega[:, 0] - res.omega[:, 1])
    assert v[-1] == pytest.approx(-v[0], rel=1e-8)
    on = res.contact_force > 0
    assert on.any() and not on[-1]
    assert np.count_nonzero(np.diff(on.astype(int)) == 1) == 1


def test_energy_balance_with_torques_and_varying_stiffness(pair, table):
    """dE/dt = tau_A w_A + tau_B w_B + 1/2 (dk/dt) delta^2 (derived in docs/lumped.md)."""
    res = run(pair, table, 3000, 3030, dt=2e-8)
    e = energy(pair, res, table(res.roll[:, 0]))
    delta = np.maximum(-res.gap, 0.0)
    dk_dt = table.slope(res.roll[:, 0]) * res.omega[:, 0]
    power = (res.torque * res.omega).sum(axis=1) + 0.5 * dk_dt * delta**2
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(res.time))])
    assert np.abs(e - e[0] - work).max() < 1e-6 * e[0]
    # Momentum changes only through the external torques.
    a, b = pair.gear_a, pair.gear_b
    rate = res.torque[:, 0] / a.base_radius + res.torque[:, 1] / b.base_radius
    impulse = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(res.time))])
    mom = momentum(pair, res)
    assert np.abs(mom - mom[0] - impulse).max() < 1e-8 * mom[0]


def count_contacts(force):
    on = force > 0
    return np.count_nonzero(np.diff(on.astype(int)) == 1) + int(on[0])


def test_driven_gear_ahead_separates_then_rattles(pair, table):
    """Paper Fig. 10 with A driving: B starts 1 % faster and runs away, then strikes back."""
    res = run(pair, table, 4000, 4040, dt=1e-7)
    f = res.contact_force
    assert np.all(f[1:50] == 0) and np.all(res.gap[1:50] > 0)
    assert count_contacts(f) >= 2
    first_on = np.argmax(f > 0)
    first_off = first_on + np.argmax(f[first_on:] == 0)
    assert first_off > first_on and f[first_off:].max() > 0  # parts, then strikes again


def test_driver_ahead_strikes_at_once(pair, table):
    """With B driving and 1 % faster, contact is immediate and then breaks."""
    res = run(replace(pair, driver="b"), table, 4000, 4040, dt=1e-7)
    f = res.contact_force
    assert np.all(f[1:20] > 0)
    assert (f == 0).any() and count_contacts(f) >= 2
    assert res.roll[0, 0] == pytest.approx(pair.end_roll_a, rel=1e-12)  # starts at A's tip


def test_damping_calms_the_ringing_but_not_the_mean(pair, table):
    f0 = PAPER_TORQUE / pair.gear_a.base_radius
    free = run(pair, table, 1000, dt=1e-7)
    damped = run(pair, table, 1000, dt=1e-7, damping_ratio=0.1)
    sz = single_zone(pair, free)
    assert np.ptp(damped.contact_force[sz]) < 0.5 * np.ptp(free.contact_force[sz])
    assert damped.contact_force[sz].mean() == pytest.approx(f0, rel=0.01)
    assert damped.info["damping_ratio"] == 0.1
    with pytest.raises(ValueError):
        run(pair, table, 1000, damping_ratio=-0.1)


def test_copy_of_gear_a_gives_identical_results(pair):
    case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE, dt=1e-7)
    g = paper_gear()
    same = simulate_lumped(GearPair(gear_a=g, gear_b=g), case)
    twin = simulate_lumped(GearPair(gear_a=g, gear_b=copy.deepcopy(g)), case)
    preset = simulate_lumped(pair, case)
    for res in (twin, preset):
        for name in ("time", "contact_force", "gap", "roll", "theta", "omega", "torque"):
            assert np.array_equal(getattr(res, name), getattr(same, name)), name


@pytest.mark.parametrize("driver", ["a", "b"])
def test_unequal_pair_static_force_follows_the_driver(driver):
    g = paper_gear()
    p = GearPair(gear_a=g, gear_b=replace(g, teeth=40, disk_inertia=8.0e-4), driver=driver)
    res = run(p, mesh_stiffness_table(p), 200, 200 * 28 / 40)
    r_driver = (p.gear_a if driver == "a" else p.gear_b).base_radius
    sz = single_zone(p, res)
    assert res.info["static_force"] == pytest.approx(PAPER_TORQUE / r_driver)
    assert res.contact_force[sz].mean() == pytest.approx(PAPER_TORQUE / r_driver, rel=0.01)
    assert res.theta[-1, 1] == pytest.approx(res.info["theta_s_b"], rel=1e-4)


def test_the_damping_ratio_of_a_case_reaches_the_lumped_model_and_the_fe_rk4_refuses_it(
        tmp_path, capsys, monkeypatch):
    """run.damping_ratio / --damping: the lumped model's mesh damper; never ignored (the FE
    model's RK4 is undamped and says so; its implicit integrator takes it)."""
    from spurdyn.case import case_from_dict, case_to_dict, resolve_cases
    from spurdyn.cli.main import main
    from spurdyn.errors import InputError
    from spurdyn.settings import RunSettings
    from spurdyn.simulators import MODELS

    plain = resolve_cases("paper-fig9")[0]
    damped = resolve_cases("paper-fig9", {"run.damping_ratio": 0.1})[0]
    assert damped.run.damping_ratio == 0.1
    assert case_from_dict(case_to_dict(damped), check_step=False).run.damping_ratio == 0.1
    f0 = MODELS["lumped"](plain.pair, plain.run).contact_force
    f1 = MODELS["lumped"](damped.pair, damped.run).contact_force
    assert np.nanmax(f1) < np.nanmax(f0)         # the damper takes off the overshoot
    with pytest.raises(InputError, match="damping_ratio: needs the implicit integrator"):
        MODELS["fe"](damped.pair, damped.run)      # the FE model's entry refuses it
    for bad in (-0.1, 1.0, float("nan"), True):
        with pytest.raises(InputError, match="damping_ratio"):
            RunSettings(speed_a=1.0, speed_b=1.0, torque=1.0, damping_ratio=bad)
    monkeypatch.chdir(tmp_path)
    for argv in (["run", "paper-fig9", "--damping", "0.05"],
                 ["sweep", "paper-fig9", "--rpm", "4000", "--damping", "0.05"]):
        assert main(argv) == 2
        _, err = capsys.readouterr()
        assert err.startswith("spurdyn: error: --damping: needs the implicit integrator") and \
            err.count("\n") == 1
    assert not any(tmp_path.iterdir())
