"""Pairs other than the paper's, through the real solver.

* The unequal pair of ``examples/pinion_gear.toml`` (20-tooth pinion driving a 40-tooth
  gear, different disk inertias): the quasi-static limit, the driven gear's load torque,
  and each gear's angular momentum balance.
* The same file through ``spurdyn run`` (the console script, in a subprocess).
* A tip relief written in a TOML case: contact starts later, where two free disks under
  the Fig. 7 torque ramp would close the relief gap.

The expected values are recomputed here from the TOML numbers (base radii, path of
contact, torque ramps, relief gap), not taken from the package or pasted from the docs.
The runs use short angles, a coarse mesh at its stable step, or both, to stay within a
few seconds each once the solver is compiled.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

from spurdyn.case import load_case
from spurdyn.solvers.loop import simulate
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper
from spurdyn.solvers.check import stable_step
from spurdyn.results.balances import snapshot, track
from spurdyn.settings import RPM
from spurdyn.model.system import build_system

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PINION_TOML = EXAMPLES / "pinion_gear.toml"
PAPER_TOML = EXAMPLES / "paper_fig8.toml"
PINION = tomllib.loads(PINION_TOML.read_text())

#: The coarse mesh of the quick runs and a step just below its stable RK4 step (checked).
COARSE = {"mesh.nx": 3, "mesh.ny": 10, "run.dt": 4.5e-8}


def base_radius(table: dict) -> float:
    """Base radius (m) of a TOML gear table given by module and pressure angle."""
    return table["module"] * table["teeth"] / 2.0 * math.cos(math.radians(table["pressure_angle_deg"]))


def tip_radius(table: dict) -> float:
    return table["module"] * table["teeth"] / 2.0 + table["addendum"]


def schedule(phi, theta_s: float, theta_2: float):
    """The Fig. 7 trapezoid: linear rise over theta_2, plateau, linear fall to theta_s."""
    phi = np.asarray(phi, dtype=float)
    return np.clip(np.minimum(phi, theta_s - phi) / theta_2, 0.0, 1.0)


RB_A, RB_B = base_radius(PINION["gear_a"]), base_radius(PINION["gear_b"])
TAU0 = PINION["run"]["torque"]
CENTRE = PINION["gear_a"]["module"] * (PINION["gear_a"]["teeth"] + PINION["gear_b"]["teeth"]) / 2.0
PATH = (math.sqrt(tip_radius(PINION["gear_a"]) ** 2 - RB_A**2)
        + math.sqrt(tip_radius(PINION["gear_b"]) ** 2 - RB_B**2)
        - CENTRE * math.sin(math.radians(20.0)))
#: Each gear's angle of action and double-contact angle (its own rotation).
ANGLES = [(PATH / rb, PATH / rb - 2.0 * math.pi / PINION[g]["teeth"])
          for rb, g in ((RB_A, "gear_a"), (RB_B, "gear_b"))]


def pinion_case(**overrides):
    return load_case(PINION_TOML, overrides=overrides)


# -- 1. the unequal pair: quasi-static limit, torques, momentum -----------------------------

def test_unequal_pair_geometry_as_read_from_the_case_file():
    case = pinion_case()
    pair = case.pair
    assert (pair.gear_a.teeth, pair.gear_b.teeth, pair.driver) == (20, 40, "a")
    assert pair.gear_a.base_radius == pytest.approx(RB_A, rel=1e-12)
    assert pair.gear_b.base_radius == pytest.approx(RB_B, rel=1e-12)
    assert pair.centre_distance == pytest.approx(CENTRE, rel=1e-12)
    assert pair.path_of_contact == pytest.approx(PATH, rel=1e-12)
    assert pair.theta_s == pytest.approx(ANGLES[0][0], rel=1e-12)
    assert pair.theta_2 == pytest.approx(ANGLES[0][1], rel=1e-12)
    # gear B starts at the speed that meshes with A
    assert case.run.speed_b == pytest.approx(case.run.speed_a * RB_A / RB_B, rel=1e-12)
    assert case.static_force == pytest.approx(TAU0 / RB_A, rel=1e-12)


@pytest.fixture(scope="module")
def quasi_static():
    """The pinion at 2,000 rpm (mesh frequency 667 Hz against the pair's ~9 kHz) through
    the single-contact zone, on the coarse mesh at its stable step."""
    z1 = math.degrees(ANGLES[0][0] - ANGLES[0][1])          # end of the single-contact zone
    case = pinion_case(**COARSE, **{"run.speed_a_rpm": 2000.0, "run.angle_deg": z1 + 0.1,
                                    "run.save_every": 10, "run.frames_every": 0})
    system = build_system(case.pair, case.run)
    limit = stable_step(system)
    assert case.run.dt <= limit                              # 4.55e-8 s for the 3 x 10 pinion
    return case, simulate(case.pair, case.run)


@pytest.mark.slow
def test_unequal_pair_quasi_static_mean_force_is_driver_torque_over_its_base_radius(quasi_static):
    case, r = quasi_static
    assert r.status == "complete", r.reason
    static = TAU0 / RB_A                                     # 1,773.6 N; tau0 / r_bB would be half
    assert r.info["static_force"] == pytest.approx(static, rel=1e-12)
    z0, z1 = r.info["single_zone"]
    assert z0 == pytest.approx(ANGLES[0][1], rel=1e-9)
    assert z1 == pytest.approx(ANGLES[0][0] - ANGLES[0][1], rel=1e-9)
    sel = (r.angle >= z0) & (r.angle <= z1)
    assert sel.sum() > 500
    assert np.all(r.contact_force[sel] > 0.0)                # one pair in contact throughout
    mean = r.contact_force[sel].mean()
    print(f"\nquasi-static: mean {mean:.1f} N against {static:.1f} N ({100 * (mean / static - 1):+.2f} %)")
    assert mean == pytest.approx(static, rel=0.02)
    # the disks turn at the ratio of the base radii (the teeth deflect by a few micrometres)
    assert r.theta[-1, 1] / r.theta[-1, 0] == pytest.approx(RB_A / RB_B, rel=2e-3)


@pytest.mark.slow
def test_driven_gear_carries_tau0_times_the_ratio_of_base_radii(quasi_static):
    """Each disk's torque follows its own Fig. 7 ramp; the driven gear's full load torque
    is tau0 r_bB / r_bA (100 N m here), so that both pass the same tooth force."""
    _, r = quasi_static
    (ts_a, t2_a), (ts_b, t2_b) = ANGLES
    load = TAU0 * RB_B / RB_A
    assert np.allclose(r.torque[:, 0], TAU0 * schedule(r.theta[:, 0], ts_a, t2_a), rtol=0, atol=1e-9 * TAU0)
    assert np.allclose(r.torque[:, 1], -load * schedule(r.theta[:, 1], ts_b, t2_b), rtol=0, atol=1e-9 * load)
    assert r.torque[:, 1].min() == pytest.approx(-load, rel=1e-12)     # B reached its plateau
    assert r.torque[:, 0].max() == pytest.approx(TAU0, rel=1e-12)


@pytest.mark.slow
def test_unequal_pair_angular_momentum_balance():
    """Each gear's angular momentum changes by the angular impulse of its centre torque and
    of the contact force (to 1 % of the largest impulse), through the ramp at 10,000 rpm."""
    case = pinion_case(**COARSE, **{"run.speed_a_rpm": 10000.0, "run.frames_every": 0})
    stepper = CompiledStepper(build_system(case.pair, case.run), case.run)
    rec = track(stepper, steps=4000)
    assert rec.status == 0
    assert math.degrees(rec.angle[-1]) > 10.0 and rec.contact_force.max() > 1000.0
    impulse = np.abs(rec.angular_impulse).max(axis=0)
    error = np.abs(rec.momentum_error).max(axis=0)
    print(f"\nmomentum: error / largest impulse A {error[0] / impulse[0]:.2e}, B {error[1] / impulse[1]:.2e}")
    assert np.all(impulse > 1e-4)
    assert np.all(error < 0.01 * impulse)
    # The two torques balance through one tooth force tau_A / r_bA, so what is left on each
    # disk is the dynamic part of the contact force times that gear's base radius: the
    # impulses are in the ratio r_bB / r_bA (a load torque of tau0 on B would not balance).
    print(f"impulse ratio B / A {impulse[1] / impulse[0]:.4f} (r_bB / r_bA = {RB_B / RB_A:.4f})")
    assert impulse[1] / impulse[0] == pytest.approx(RB_B / RB_A, rel=0.05)
    # the contact force acts along the line of action: its moment about each centre is the
    # force times that gear's base radius, the same sense on both (A is held back, B driven)
    now = snapshot(stepper)
    assert now.contact_force > 1000.0
    assert now.contact_moment[0] == pytest.approx(now.contact_force * RB_A, rel=0.01)
    assert now.contact_moment[1] == pytest.approx(now.contact_force * RB_B, rel=0.01)


# -- 2. the case file through the command line ------------------------------------------

def spurdyn_command() -> list[str]:
    script = Path(sys.executable).parent / "spurdyn"
    return [str(script)] if script.is_file() else [sys.executable, "-m", "spurdyn.cli.main"]


@pytest.mark.slow
def test_pinion_gear_file_runs_from_the_command_line(tmp_path):
    out = tmp_path / "pg"
    proc = subprocess.run([*spurdyn_command(), "run", str(PINION_TOML), "--angle", "2", "--out", str(out)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "pinion_gear: complete" in proc.stdout
    summary = json.loads((out / "summary.json").read_text())
    with xr.open_dataset(out / "result.nc") as ds:
        ds = ds.load()
    assert summary["status"] == "complete" == ds.attrs["status"]
    assert summary["angle_deg"] >= 2.0
    assert summary["speed_b_rpm"] == pytest.approx(PINION["run"]["speed_a_rpm"] * RB_A / RB_B)
    # the quasi-static force is the driver's torque over the driver's base radius
    assert summary["static_force_N"] == pytest.approx(TAU0 / RB_A, rel=1e-9)
    assert ds.attrs["static_force_N"] == pytest.approx(TAU0 / RB_A, rel=1e-9)
    assert summary["dynamic_factor"] == pytest.approx(summary["peak_force_N"] / (TAU0 / RB_A))

    force, gap, angle = ds["contact_force"].values, ds["gap"].values, ds["angle_deg"].values
    assert np.all(np.isfinite(force)) and np.all(force >= 0.0)
    on = force > 0.0
    # force only where the flanks touch (within the 1e-12 m tolerance), none where apart
    assert np.abs(gap[on]).max() < 1e-11
    assert gap[~on].min() > -1e-11
    # once the torque ramp loads the teeth (from 0.5 deg: 4 % of the ramp) they stay in
    # contact and push; the few touches before are the unloaded start
    loaded = angle >= 0.5
    assert loaded.sum() > 1000 and np.all(on[loaded])
    # still in the ramp: below the full quasi-static force, and the torques in the ratio
    assert 0.0 < summary["peak_force_N"] < TAU0 / RB_A
    ts_b, t2_b = ANGLES[1]
    expected_b = -TAU0 * RB_B / RB_A * schedule(ds["theta_b"].values, ts_b, t2_b)
    assert np.allclose(ds["torque_b"].values, expected_b, rtol=0, atol=1e-9 * TAU0)


# -- 3. tip relief, end to end ------------------------------------------------------------

def paper_case_with_relief(tmp_path: Path, amount: float, start_deg: float, angle_deg: float):
    """examples/paper_fig8.toml with a linear tip relief on gear A (B is a copy of A)."""
    text = PAPER_TOML.read_text()
    anchor = "disk_inertia = 2.965e-4\n"
    assert text.count(anchor) == 1
    if amount > 0.0:
        text = text.replace(anchor, anchor + f"tip_relief = {amount!r}\n"
                            f"tip_relief_start_roll_deg = {start_deg!r}\n"
                            'tip_relief_shape = "linear"\n')
    path = tmp_path / f"relief_{amount * 1e6:g}um.toml"
    path.write_text(text)
    return load_case(path, overrides={"run.angle_deg": angle_deg, "run.frames_every": 0})


def free_disk_contact(case) -> float:
    """Rotation of A (rad) at which two rigid disks, driven apart from conjugate motion by
    the Fig. 7 torque ramps alone (no tooth force), close the relief gap.

    Rigid conjugate motion keeps ``r_bA theta_A - r_bB theta_B = 0``; the torques make it
    grow. The unloaded relieved flanks stand apart by ``depth_A(xi_A) + depth_B(xi_B)`` at
    the rigid contact point (docs/relief.md, first order in the depth).
    """
    pair, run = case.pair, case.run
    ga, gb = pair.gear_a, pair.gear_b
    ra, rb = ga.base_radius, gb.base_radius
    angles = [(pair.path_of_contact / g.base_radius,
               pair.path_of_contact / g.base_radius - 2.0 * math.pi / g.teeth) for g in (ga, gb)]

    def gap(theta_a: float) -> float:
        xi_a = pair.start_roll_a + theta_a
        xi_b = float(pair.roll_b_from_roll_a(xi_a))
        return float(ga.relief_depth(ga.radius_at_roll_angle(xi_a))
                     + gb.relief_depth(gb.radius_at_roll_angle(xi_b)))

    def rhs(t, y):
        tau_a = run.torque * schedule(y[0], *angles[0])
        tau_b = -run.torque * rb / ra * schedule(y[2], *angles[1])
        return [y[1], tau_a / ga.disk_inertia, y[3], tau_b / gb.disk_inertia]

    def closed(t, y):
        return ra * y[0] - rb * y[2] - gap(y[0])

    closed.terminal, closed.direction = True, 1.0
    sol = solve_ivp(rhs, (0.0, pair.theta_s / run.speed_a), [0.0, run.speed_a, 0.0, run.speed_b],
                    events=closed, rtol=1e-10, atol=1e-14, max_step=1e-6)
    assert sol.t_events[0].size == 1
    return float(sol.y_events[0][0][0])


def first_contact_deg(r) -> float:
    on = np.flatnonzero(r.contact_force > 0.0)
    assert on.size, "no contact"
    return float(np.degrees(r.angle[on[0]]))


@pytest.fixture(scope="module")
def hpstc_deg():
    """Roll angle (deg) of the highest point of single-tooth contact on the paper's gear:
    a 'long' relief from there to the tip acts over the whole double-contact zone."""
    pair = load_case(PAPER_TOML).pair
    return math.degrees(pair.single_contact_roll_a[1])


@pytest.fixture(scope="module")
def unrelieved_first_contact(tmp_path_factory):
    case = paper_case_with_relief(tmp_path_factory.mktemp("relief"), 0.0, 0.0, 1.0)
    r = simulate(case.pair, case.run)
    assert r.status == "complete", r.reason
    return first_contact_deg(r)


@pytest.mark.slow
@pytest.mark.parametrize("amount", [5e-6, 20e-6])
def test_tip_relief_delays_first_contact_to_where_the_free_disks_close_the_gap(
        tmp_path, hpstc_deg, unrelieved_first_contact, amount):
    probe = paper_case_with_relief(tmp_path, amount, hpstc_deg, 1.0)
    pair = probe.pair
    assert pair.gear_a.tip_relief == pair.gear_b.tip_relief == amount
    assert math.degrees(pair.gear_b.tip_relief_start_roll) == pytest.approx(hpstc_deg)
    # the relief at B's tip, which meets A at the start of contact, is the whole amount,
    # and the relief ends (at the highest point of single contact) one theta_2 later
    xi_b0 = float(pair.roll_b_from_roll_a(pair.start_roll_a))
    depth_b0 = float(pair.gear_b.relief_depth(pair.gear_b.radius_at_roll_angle(xi_b0)))
    assert depth_b0 == pytest.approx(amount, rel=1e-6)
    assert xi_b0 - pair.gear_b.tip_relief_start_roll == pytest.approx(pair.theta_2, rel=1e-9)

    predicted = math.degrees(free_disk_contact(probe))
    assert 1.0 < predicted < math.degrees(pair.theta_2)
    case = paper_case_with_relief(tmp_path, amount, hpstc_deg, predicted + 0.4)
    r = simulate(case.pair, case.run)
    assert r.status == "complete", r.reason
    first = first_contact_deg(r)
    print(f"\nrelief {amount * 1e6:g} um: first contact {first:.3f} deg (predicted {predicted:.3f}, "
          f"without relief {unrelieved_first_contact:.4f}); gap at start {r.gap[0] * 1e6:.3f} um")
    assert unrelieved_first_contact < 0.01                   # without relief: at once
    assert first > unrelieved_first_contact + 1.0
    assert first == pytest.approx(predicted, abs=0.05)
    # the teeth start apart by the relief and close the gap without touching
    assert r.gap[0] == pytest.approx(amount, rel=0.02)
    before = np.degrees(r.angle) < first
    assert np.all(r.contact_force[before] == 0.0) and np.all(r.gap[before] > 0.0)
    # after the first contact the relief pushes a real load through
    assert r.contact_force.max() > 0.5 * case.static_force
