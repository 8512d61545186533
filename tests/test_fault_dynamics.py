"""Faults in the sector model's dynamic runs (docs/faults.md, "Faults in motion"): the
faulty gear's flexibility by the pair of teeth, the compiled loop against the NumPy one, a
missing tooth's contacts never made, a pit of no depth the healthy run, the refusals."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.bodies import _pair_flex, _tooth_frames
from spurdyn.sector.fault_bodies import body_tooth
from spurdyn.sector.model import SectorModel
from spurdyn.sector.reduced import reduce_gear
from spurdyn.sector.system import gear_block
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.run import simulate_sector
from spurdyn.solvers.sector.stepper import SectorRecord, make_stepper

PAIR = paper_pair()
#: A pair of few teeth: a faulty run takes two of its revolutions
SMALL = GearPair(gear_a=replace(PAIR.gear_a, teeth=18), gear_b=replace(PAIR.gear_b, teeth=18), driver="a")
MESH = dict(nx=2, ny=4)
#: A crack's mouth splits the fillet's first flank edge; at 2 x 4 on the 18-tooth gear that edge
#: reaches the lowest contacts (refused), at 2 x 6 it does not
CRACK_MESH = dict(nx=2, ny=6)
SPALL = Fault("a", 1, "spall", roll=(math.radians(18.0), math.radians(24.0)), depth=2e-6)


def _run(faults: tuple[Fault, ...], backend: str = "numba") -> object:
    s = run_settings(SMALL, 8000 * RPM, 22.25, model="sector", cycles=1, max_cycles=1, faults=faults,
                     backend=backend, **MESH)
    return simulate_sector(SMALL, s)


def test_the_flexibility_by_pairs_of_teeth_is_the_rings_by_distance_on_a_healthy_gear():
    gear = PAIR.gear_a
    blk = gear_block(gear, 1.0, -(gear.teeth // 2), gear.teeth, 2, 4, 1.0)
    reduced = reduce_gear(blk, 60e3)
    _, ring = _tooth_frames(reduced, 2)
    f = ring.shape[-1]
    turns = [[np.kron(np.eye(f // 2), blk.turn_of(blk.first + t, s)) for s in range(2)] for t in range(blk.count)]
    pairs = _pair_flex(reduced, 2, turns)
    for i in (0, 3, 27):
        for j in (0, 5, 27):
            for s in range(2):
                for t in range(2):
                    want = ring[(i - j) % blk.count, s, t]
                    assert np.abs(pairs[i, s, j, t] - want).max() <= 1e-9 * np.abs(want).max()


@pytest.mark.slow
def test_the_compiled_faulty_steps_are_the_numpy_ones():
    # the first three mesh cycles, which meet the missing tooth and the pit
    s = run_settings(PAIR, 8000 * RPM, 22.25, model="sector", cycles=3, faults=(Fault("a", 2, "missing"), SPALL),
                     **MESH)
    model = SectorModel.build(PAIR, s)
    n = 3 * model.per_cycle
    forces = []
    for backend in ("numba", "numpy"):
        record = SectorRecord(model, model.per_cycle * model.cycles)
        stepper = make_stepper(model, record, "implicit", backend)
        assert stepper.steps(n) == ""
        forces.append(record.force[:n + 1])
    fast, slow = forces
    assert np.nanmax(fast) > 0.0
    assert np.nanmax(np.abs(fast - slow)) <= 1e-9 * np.nanmax(fast)


@pytest.mark.slow
def test_a_missing_teeths_contacts_are_never_made_and_a_pit_of_no_depth_is_healthy():
    gone = _run((Fault("a", 2, "missing"),))
    # the driver's contact -2 meets the missing tooth in cycle 2
    col = int(np.flatnonzero(np.asarray(gone.info["pair_teeth"]) == -2)[0])
    assert np.nanmax(gone.pair_force[:, col]) == 0.0
    assert np.nanmax(gone.pair_force) > 0.0
    # two revolutions of the faulty gear, the second repeating the first to the settled test
    steady = gone.info["steady"]
    assert steady["cycles_done"] == 36 and steady["period_mesh_cycles"] == 18
    flat = _run((Fault("a", 1, "spall", roll=SPALL.roll, depth=0.0),))
    s = run_settings(SMALL, 8000 * RPM, 22.25, model="sector", cycles=36, max_cycles=36, **MESH)
    healthy = simulate_sector(SMALL, s)
    assert np.array_equal(healthy.pair_force, flat.pair_force, equal_nan=True)


def test_a_missing_tooth_at_the_start_carries_nothing_and_has_no_flank():
    # fault tooth 0 is pair 0 at the start: the static start's load goes to the others
    s = run_settings(PAIR, 8000 * RPM, 22.25, model="sector", cycles=3, faults=(Fault("a", 0, "missing"),), **MESH)
    model = SectorModel.build(PAIR, s)
    start = model.start()
    assert start.force[np.searchsorted(model.teeth, 0)] == 0.0
    assert start.force.sum() == pytest.approx(model.load, rel=1e-9)
    with pytest.raises(IndexError):
        model.blocks[0].flank_dofs(0)


def test_a_fault_sits_on_the_body_tooth_that_meets_it():
    # the driver's fault tooth k on its body tooth -k, the driven gear's on +k, round the ring
    assert body_tooth(5, 0, -14, 28) == -5
    assert body_tooth(20, 0, -14, 28) == 8
    assert body_tooth(5, 1, -14, 28) == 5
    assert body_tooth(20, 1, -14, 28) == -8


def test_a_crack_opening_on_a_loaded_flank_edge_is_refused():
    s = run_settings(SMALL, 8000 * RPM, 22.25, model="sector", cycles=1, faults=(Fault("a", 0, "crack", depth=1e-3),),
                     **MESH)
    with pytest.raises(InputError) as err:
        SectorModel.build(SMALL, s)
    assert err.value.field == "fault" and "finer mesh" in err.value.reason


@pytest.mark.parametrize("faults, settings, key", [
    # spalls over part of the face width on both gears would split a pair four ways
    ((Fault("a", 1, "spall", roll=SPALL.roll, depth=1e-6, width_fraction=0.5),
      Fault("b", 1, "spall", roll=SPALL.roll, depth=1e-6, width_fraction=0.5)), {}, "fault"),
    ((Fault("a", 1, "missing"),), {"bodies": "full"}, "fault"),
])
def test_what_a_faulty_dynamic_run_refuses(faults, settings, key):
    kw = {"cycles": 3, **MESH, **settings}
    s = run_settings(PAIR, 8000 * RPM, 22.25, model="sector", faults=faults, **kw)
    with pytest.raises(InputError) as err:
        SectorModel.build(PAIR, s)
    assert err.value.field == key


SMALL_TOML = """[gear_a]
teeth = 18
module = 0.003175
face_width = 0.00635

[mesh]
nx = 2
ny = 4

[run]
torque = 22.25
speed_a_rpm = 8000
"""


@pytest.mark.slow
def test_a_faulty_runs_sensors_indicators_and_picture(tmp_path, capsys):
    from cli_helpers import run

    healthy, faulty = tmp_path / "healthy.toml", tmp_path / "faulty.toml"
    healthy.write_text(SMALL_TOML)
    faulty.write_text(SMALL_TOML + '\n[[fault]]\ngear = "a"\ntooth = 4\nkind = "missing"\n')
    out = {}
    for name, case, more in (("h", healthy, ["--cycles", "36", "--max-cycles", "36"]), ("f", faulty, ["--cycles", "36", "--max-cycles", "36"])):
        code, _, err = run(capsys, "run", case, "--model", "sector", "--out", tmp_path / name, *more)
        assert code in (0, 1), err
        out[name] = json.loads((tmp_path / name / "summary.json").read_text())
    # the stored case carries the fault, and the summary's settings show it
    assert out["f"]["settings"]["fault"] == [{"gear": "a", "tooth": 4, "kind": "missing"}]
    assert (tmp_path / "f" / "vibration.png").exists()
    ds = xr.open_dataset(tmp_path / "f" / "result.nc")
    # the hub's acceleration is its speed's rate; the bearing's force the mesh force's components
    a = ds["hub_acceleration_a"].values
    t, w = ds["time"].values, ds["omega_a"].values
    central = (w[2:] - w[:-2]) / (t[2:] - t[:-2])
    assert np.abs(a[1:-1] - central).max() <= 1e-9 * np.abs(central).max()
    alpha = PAIR.working_pressure_angle
    assert np.allclose(ds["bearing_force_separating"].values, np.nan_to_num(ds["mesh_force"].values) * math.sin(alpha))
    ds.close()
    # a missing tooth's impacts make the mesh force impulsive and modulated by the shaft: its
    # kurtosis, FM0 and sideband energy well above the healthy pair's (whose mesh force repeats
    # every mesh cycle: no shaft orders but the mesh's)
    vf, vh = (out[k]["vibration"]["signals"]["mesh_force"] for k in ("f", "h"))
    assert vf["revolutions"] >= 1 and vh["revolutions"] >= 1
    assert vf["kurtosis"] > 3.0 * vh["kurtosis"] and vf["fm0"] > 3.0 * vh["fm0"]
    assert vh["sideband_energy_ratio"] < 0.01 < 1.0 < vf["sideband_energy_ratio"]


@pytest.mark.slow
def test_a_faulty_runs_balances_are_as_tight_as_a_healthy_ones():
    """rho_inf = 1, no damping, 1,000 rpm, 800 steps a cycle, over the two mesh cycles that
    meet the missing tooth 1 (its neighbours' entries and exits, the gap between them) and a
    cracked tooth 0 (its faces a contact of their own): each hub's momentum changes by its torques' trapezoidal
    impulse to round-off, and the energy stays within the model's left-out terms, 4 % of the
    largest strain energy (the healthy run's bound, test_sector_dynamics)."""
    faults = (Fault("a", 1, "missing"), Fault("a", 0, "crack", depth=1.0e-3))
    s = run_settings(SMALL, 1000 * RPM, 60.0, model="sector", cycles=1, rho_inf=1.0, faults=faults,
                     damping_ratio=0.0, rayleigh_mass=0.0, rayleigh_stiffness=0.0, backend="numpy", **CRACK_MESH)
    model = SectorModel.build(SMALL, s, dt=2 * math.pi / SMALL.gear_a.teeth / s.speed_a / 800)
    record = SectorRecord(model, model.per_cycle * model.cycles, energy=True)
    stepper = make_stepper(model, record, "implicit", "numpy", energy=True)
    n = 2 * model.per_cycle
    assert stepper.steps(n) == ""
    e = record.energy[:n + 1]
    total = e[:, 0] + e[:, 1] + e[:, 2] - e[:, 3]
    assert np.abs(total - total[0]).max() < 0.04 * e[:, 1].max()
    # the crack's faces close and carry a force in these cycles (up to 25 N a node pair), and
    # never pass through each other
    faces = record.faces[:n + 1]
    assert faces[:, 0].max() > 1.0 and faces[:, 1].min() >= -1e-12 * faces[:, 2].max()
    assert np.ptp(e[:, 1]) > 0.1 * e[:, 1].max()
    h = model.h
    torque = e[:, 6:8] + record.torque[:n + 1]
    impulse = np.concatenate([np.zeros((1, 2)), np.cumsum(0.5 * h * (torque[1:] + torque[:-1]), axis=0)])
    p = e[:, 4:6]
    assert (np.abs(impulse).max(axis=0) > 1e-3 * np.abs(p[0])).all()
    np.testing.assert_allclose(p - p[0], impulse, rtol=0, atol=1e-9 * np.abs(p[0]).max())


def test_a_tied_nodes_mass_goes_to_its_edge_kept_whole_and_positive():
    from spurdyn.sector.body import tied_masses

    m = np.array([1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 0.5, 0.5])        # four nodes, node 3 tied
    ties = np.array([[3, 0, 1, 2]])
    w = np.array([[-0.125, 0.375, 0.75]])       # a quadratic edge's weights at a quarter: one negative
    out = tied_masses(m, ties, w)
    assert out.sum() == pytest.approx(m.sum(), rel=1e-15)
    assert (out[:6] >= m[:6]).all() and out[6:].sum() == 0.0
    assert np.allclose(out[:6:2] - m[:6:2], 0.5 * w[0] ** 2 / np.sum(w[0] ** 2))
