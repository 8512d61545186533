"""Torques that vary (docs/sector.md, 6.8): a torque history read from a file or a table, a
start from rest with a ramp, and the teeth per gear of a sector run (``--teeth K``).

The history is linear between its samples and repeats if periodic; a constant one is the
constant torque bit for bit; under a varying one both loops are twins and each hub's momentum
is its torques' impulse; an idling driver's fluctuating torque rattles a pair with tens of
micrometres of backlash; a run from rest ramps its load up and settles on the static one;
and every bad input is refused in one line naming its key.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import xarray as xr

from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair
from spurdyn.lumped.steady import simulate_steady
from spurdyn.model.loading import history_at, hub_torques, torque_amplitudes
from spurdyn.sector.system import teeth_for
from spurdyn.settings import RPM, TorqueHistory
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.run import simulate_sector
from spurdyn.case import history_from_table, history_to_table, read_history_csv

PAIR = paper_pair()
MESH = dict(nx=2, ny=8)
#: Steps of the quasi-static runs at 10 rpm (214 a mesh cycle, not the model's 107,000) and
#: of the idling runs at 1,000 rpm (214, not 1,071): what the tests check needs no more.
SLOW_DT, IDLE_DT = 1e-3, 1e-5
#: 0.1 mm beyond the tight centre distance: 69 um of normal backlash.
LOOSE = dataclasses.replace(PAIR, centre_distance=PAIR.centre_distance + 1e-4)
#: An idling driver: 1 N m of mean torque and 4 N m at 200 Hz (examples/idle_rattle_torque.csv).
IDLE_T = np.linspace(0.0, 5e-3, 101)
IDLE = TorqueHistory(time=tuple(IDLE_T.tolist()), driver=tuple((1.0 + 4.0 * np.sin(2 * np.pi * 200 * IDLE_T)).tolist()),
                     periodic=True, source="idle")


# -- the history and the hubs' torques -------------------------------------------------------

def test_a_history_is_linear_between_samples_and_repeats_if_periodic():
    h = TorqueHistory(time=(1.0, 1.5, 3.0), driver=(2.0, 4.0, 1.0), load=(1.0, 1.0, 3.0))
    drv, load = history_at(h, [0.0, 0.25, 0.5, 1.25, 2.0, 9.0])
    np.testing.assert_allclose(drv, [2.0, 3.0, 4.0, 2.5, 1.0, 1.0])   # held past the end
    np.testing.assert_allclose(load, [1.0, 1.0, 1.0, 2.0, 3.0, 3.0])
    p = dataclasses.replace(h, periodic=True)
    assert p.duration == 2.0
    np.testing.assert_allclose(history_at(p, [0.25, 2.25, 4.25, 6.5])[0], [3.0, 3.0, 3.0, 4.0])
    assert history_at(dataclasses.replace(h, load=None), [0.1])[1] is None


@pytest.mark.parametrize("driver", ["a", "b"])
def test_the_hubs_torques_are_the_constant_ones_the_history_and_the_ramp(driver):
    pair = dataclasses.replace(PAIR, driver=driver)
    s = run_settings(pair, 4000 * RPM, 22.25, dt=1e-6, cycles=2, **MESH)
    t = np.linspace(0.0, 1e-3, 7)
    np.testing.assert_array_equal(hub_torques(pair, s, t), np.tile(torque_amplitudes(pair, 22.25), (7, 1)))
    hist = TorqueHistory(time=(0.0, 1e-3), driver=(10.0, 30.0), load=(5.0, 5.0))
    tq = hub_torques(pair, s.with_(torque_history=hist), t)
    drv, drn = (0, 1) if driver == "a" else (1, 0)
    np.testing.assert_allclose(tq[:, drv], 10.0 + 20.0 * t / 1e-3)
    np.testing.assert_allclose(tq[:, drn], -5.0)
    # from rest: linear from 0 over ramp_cycles mesh cycles of the driver at its speed
    rest = s.with_(start="rest", ramp_cycles=2.0)
    t_ramp = 2.0 * 2 * math.pi / (28 * 4000 * RPM)
    np.testing.assert_allclose(hub_torques(pair, rest, [0.0, 0.5 * t_ramp, t_ramp, 2 * t_ramp]),
                               np.outer([0.0, 0.5, 1.0, 1.0], torque_amplitudes(pair, 22.25)))
    # a continuation's point starts from a loaded end: no ramp again
    np.testing.assert_array_equal(hub_torques(pair, rest.with_(start_state=(0.0, 0.0)), t),
                                  np.tile(torque_amplitudes(pair, 22.25), (7, 1)))


def test_a_csv_history_is_read_and_refused_by_key_file_and_line(tmp_path):
    f = tmp_path / "h.csv"
    f.write_text("# a comment\n\ntime_s, driver_Nm, load_Nm\n0, 1.5, 2\n0.001, 2.5, 2\n")
    h = read_history_csv(f, "run.torque_history", periodic=True)
    assert h == TorqueHistory(time=(0.0, 0.001), driver=(1.5, 2.5), load=(2.0, 2.0), periodic=True, source="h.csv")
    assert history_from_table(history_to_table(h), "t", True) == dataclasses.replace(h, source="")
    bad = {
        "time_s,driver_Nm\n0,1\n0.001,x\n": "h.csv line 3: 'x' is not a number (driver_Nm)",
        "time_s,torque\n0,1\n": "the header must name",
        "time_s,driver_Nm\n0,1\n0.001\n": "h.csv line 3: 1 values for the 2 columns",
        "time_s,driver_Nm\n0,1\n0,2\n": "times must increase",
        "time_s,driver_Nm\n0,1\n": "at least two samples",
        "time_s,driver_Nm\n0,1\n1,inf\n": "not a finite number",
        "# nothing\n": "no header",
    }
    for text, why in bad.items():
        f.write_text(text)
        with pytest.raises(InputError) as err:
            read_history_csv(f, "run.torque_history")
        assert err.value.field == "run.torque_history" and why in err.value.reason, (text, err.value.reason)
    with pytest.raises(InputError) as err:
        read_history_csv(tmp_path / "none.csv", "--torque-history")
    assert err.value.field == "--torque-history" and "no such file" in err.value.reason
    with pytest.raises(InputError) as err:
        history_from_table({"time_s": [0, 1], "driver_Nm": [1, "a"]}, "run.torque_history")
    assert err.value.field == "run.torque_history.driver_Nm"


def test_the_settings_refuse_what_a_history_or_a_start_cannot_do():
    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=2, **MESH)
    hist = TorqueHistory(time=(0.0, 1.0), driver=(1.0, 1.0))
    for changes, key in (({"cycles": None, "torque_history": hist}, "torque_history"),
                         ({"cycles": None, "start": "rest"}, "start"),
                         ({"start": "moving"}, "start"),
                         ({"ramp_cycles": 1.0}, "ramp_cycles"),
                         ({"start": "rest", "ramp_cycles": 0.0}, "ramp_cycles"),
                         ({"torque_history": hist, "max_cycles": 3}, "max_cycles"),
                         ({"teeth": 0}, "teeth")):
        with pytest.raises(InputError) as err:
            s.with_(**changes)
        assert err.value.field == key
    assert s.with_(torque_history=hist, max_cycles=None).cycles_limit == 2


# -- the teeth per gear ----------------------------------------------------------------------

def test_the_teeth_asked_for_are_those_needed_and_more_neighbours_or_the_whole_gear():
    need = teeth_for(PAIR, 2.0)
    assert teeth_for(PAIR, 2.0, teeth=need[0][1]) == need
    (fa, ca), (fb, cb) = teeth_for(PAIR, 2.0, teeth=need[0][1] + 3)
    assert ca == cb == need[0][1] + 3
    # the needed ones kept, the new neighbours split with one more behind each mesh
    assert fa == need[0][0] - 2 and fb == need[1][0] - 1
    assert teeth_for(PAIR, 2.0, teeth=28) == ((-14, 28), (-14, 28))
    assert teeth_for(PAIR, 5.0, teeth=9)[0][1] == 9     # a sector, even for a long run
    with pytest.raises(InputError) as err:
        teeth_for(PAIR, 2.0, teeth=need[0][1] - 1)
    assert err.value.field == "teeth" and f"at least {need[0][1]}" in err.value.reason


@pytest.mark.slow
def test_a_run_of_the_default_teeth_asked_for_is_the_default_run():
    """Asking for the default count is the default run, bit for bit; two more neighbours move
    the cut ends away and change the quasi-static transmission error (the pair's compliance)
    by less than 1 %."""
    s = run_settings(PAIR, 10 * RPM, 22.25, dt=1e-6, cycles=1, **MESH)
    k = teeth_for(PAIR, 1.0)[0][1]
    a, b = (simulate_sector(PAIR, x, dt=SLOW_DT) for x in (s, s.with_(teeth=k)))
    np.testing.assert_array_equal(a.pair_force, b.pair_force)
    c = simulate_sector(PAIR, s.with_(teeth=k + 2), dt=SLOW_DT)
    assert c.info["teeth_per_gear"] == [k + 2, k + 2]
    change = np.abs(c.transmission_error - a.transmission_error).max() / np.abs(a.transmission_error).max()
    assert 0.0 < change < 0.01


# -- the sector run under a history, from rest -----------------------------------------------

@pytest.mark.slow
def test_a_constant_history_is_the_constant_torque_bit_for_bit():
    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=3, max_cycles=3, **MESH)
    rb_ra = PAIR.gear_b.base_radius / PAIR.gear_a.base_radius
    hist = TorqueHistory(time=(0.0, 1.0), driver=(22.25, 22.25), load=(22.25 * rb_ra,) * 2)
    a, b = simulate_sector(PAIR, s), simulate_sector(PAIR, s.with_(torque_history=hist, max_cycles=None))
    assert a.status == b.status == "complete" and b.info["torque_history"] == "table"
    np.testing.assert_array_equal(a.pair_force, b.pair_force)
    np.testing.assert_array_equal(a.theta, b.theta)


@pytest.fixture(scope="module")
def idle():
    """The idling driver on 69 um of backlash at 1,000 rpm, three cycles on whole gears,
    undamped with rho_inf = 1, 10 us steps (214 a cycle): both loops, the NumPy one keeping
    its momenta."""
    s = run_settings(LOOSE, 1000 * RPM, 1.0, dt=1e-6, cycles=3, rho_inf=1.0, **MESH, torque_history=IDLE,
                     rayleigh_mass=0.0, rayleigh_stiffness=0.0)
    return (simulate_sector(LOOSE, s, dt=IDLE_DT),
            simulate_sector(LOOSE, s.with_(backend="numpy"), energy=True, dt=IDLE_DT))


@pytest.mark.slow
def test_an_idling_drivers_torque_rattles_across_tens_of_micrometres(idle):
    """When the driver's torque swings below minus the drag's share of its inertia the drive
    flanks part, the driver falls back across the 69 um of backlash (the transmission error
    to ``-j_n``) and its back flanks strike, harder than the static load; both loops alike."""
    fast, ref = idle
    assert fast.status == ref.status == "complete"
    assert ref.info["backlash_normal_m"] > 60e-6
    back, drive = ref.back_force.sum(axis=1), np.nansum(ref.pair_force, axis=1)
    hit = int(np.flatnonzero(back > 0)[0])
    assert (drive[hit - 10:hit] == 0).all()
    assert ref.transmission_error[hit] < -0.95 * ref.info["backlash_normal_m"]
    assert back.max() > 5.0 * ref.info["static_force"]
    # the torque the run carried is the history's
    np.testing.assert_allclose(ref.torque[:, 0], history_at(IDLE, ref.time)[0])
    np.testing.assert_allclose(fast.back_force, ref.back_force, rtol=0, atol=1e-8 * back.max())
    np.testing.assert_allclose(np.nan_to_num(fast.pair_force), np.nan_to_num(ref.pair_force), rtol=0,
                               atol=1e-8 * drive.max())


@pytest.mark.slow
def test_each_hubs_momentum_is_its_varying_torques_impulse(idle):
    """With rho_inf = 1 a hub's momentum changes by the trapezoidal impulse of its torque (the
    history's, at the end of each step) and of the contacts, to round-off through the rattle."""
    _, run = idle
    p = np.array(run.info["momentum"]["hub_momentum"])
    q = np.array(run.info["momentum"]["contact_torque"]) + run.torque
    impulse = np.concatenate([np.zeros((1, 2)), np.cumsum(0.5 * np.diff(run.time)[:, None] * (q[1:] + q[:-1]), axis=0)])
    np.testing.assert_allclose(p - p[0], impulse, rtol=0, atol=1e-9 * np.abs(p[0]).max())


@pytest.mark.slow
def test_a_run_from_rest_ramps_its_load_up_and_carries_it():
    """At 10 rpm (quasi-static), from rest over a ramp of one cycle: no force at the start,
    the pair forces following the torques' ramp and, after it, summing to ``T / r_b`` within
    0.5 %. On whole gears (``teeth`` 28), the bodies the file's other runs use, not a
    two-cycle sector of its own (the same margins: 0.47 % at half the ramp, 0.16 % after it),
    stepped by the NumPy loop as the sector was."""
    s = run_settings(PAIR, 10 * RPM, 22.25, dt=1e-6, cycles=2, max_cycles=2, **MESH, start="rest",
                     teeth=PAIR.gear_a.teeth, backend="numpy")
    run = simulate_sector(PAIR, s, dt=SLOW_DT)
    assert run.status == "complete" and run.info["start"] == "rest" and run.info["ramp_cycles"] == 1.0
    mesh = np.nansum(run.pair_force, axis=1)
    per = run.info["steps_per_cycle"]
    assert mesh[0] == 0.0 and run.torque[0, 0] == 0.0 and run.torque[per, 0] == pytest.approx(22.25)
    assert mesh[per // 2] == pytest.approx(0.5 * run.info["static_force"], rel=0.02)
    np.testing.assert_allclose(mesh[per + 1:], run.info["static_force"], rtol=5e-3)


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_a_run_whose_gears_run_away_stops_and_says_so(backend):
    """A driver's torque far above the load speeds the gears beyond the teeth the run carries:
    the run stops there, incomplete, and says why (both loops)."""
    hist = TorqueHistory(time=(0.0, 1.0), driver=(5000.0, 5000.0))
    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=3, **MESH, torque_history=hist, backend=backend)
    run = simulate_sector(PAIR, s)
    assert run.status == "incomplete" and "beyond the" in run.reason and "teeth cover" in run.reason
    assert np.isfinite(run.pair_force[-1]).any()


@pytest.mark.slow
def test_the_lumped_model_takes_the_history_and_the_start():
    from spurdyn.lumped.model import mesh_stiffness_table

    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=3, max_cycles=3, **MESH)
    table = mesh_stiffness_table(PAIR, 4, 14)
    rb_ra = PAIR.gear_b.base_radius / PAIR.gear_a.base_radius
    flat = TorqueHistory(time=(0.0, 1.0), driver=(22.25, 22.25), load=(22.25 * rb_ra,) * 2)
    a = simulate_steady(PAIR, s, table, 0.05, 3)
    b = simulate_steady(PAIR, s.with_(torque_history=flat, max_cycles=None), table, 0.05, 3)
    np.testing.assert_allclose(b.contact_force, a.contact_force, rtol=0, atol=1e-9 * a.contact_force.max())
    rest = simulate_steady(PAIR, s.with_(start="rest"), table, 0.05, 3)
    assert rest.contact_force[0] == 0.0 and rest.torque[0, 0] == 0.0
    varying = simulate_steady(PAIR, s.with_(torque_history=IDLE, max_cycles=None), table, 0.05, 3)
    np.testing.assert_allclose(varying.torque[:, 0], history_at(IDLE, varying.time)[0])


# -- the command line ------------------------------------------------------------------------

CASE = ("[gear_a]\nteeth = 28\npitch_radius = 0.04445\ntip_radius = 0.047625\nroot_radius = 0.04048\n"
        "pressure_angle_deg = 20.0\nface_width = 0.00635\ndisk_inertia = 2.965e-4\n"
        "[gear_a.material]\nyoung = 210e9\npoisson = 0.3\ndensity = 7800.0\n"
        "[pair]\ncentre_distance = 0.089\n[mesh]\nnx = 2\nny = 8\n"
        "[run]\nspeed_a_rpm = 1000\ntorque = 1.0\ncycles = 3\n"
        "torque_history = \"idle.csv\"\ntorque_history_periodic = true\n[model]\nkind = \"sector\"\n")


@pytest.mark.slow
def test_spurdyn_run_reads_the_history_beside_the_case_and_refuses_in_one_line(tmp_path, capsys, monkeypatch):
    from spurdyn.cli.main import main

    folder = tmp_path / "cases"
    folder.mkdir()
    (folder / "idle.csv").write_text("time_s,driver_Nm\n" + "".join(
        f"{t!r},{d!r}\n" for t, d in zip(IDLE.time, IDLE.driver)))
    case = folder / "idle.toml"
    case.write_text(CASE)
    monkeypatch.chdir(tmp_path)           # the file is found beside the case, not here
    assert main(["run", str(case), "--out", "on"]) == 0
    assert "back flanks" in capsys.readouterr().out
    ds = xr.open_dataset(tmp_path / "on" / "result.nc")
    np.testing.assert_allclose(ds["torque_a"], history_at(IDLE, ds["time"].values)[0], rtol=1e-12)
    summary = json.loads((tmp_path / "on" / "summary.json").read_text())
    assert summary["torque_history"] == "idle.csv" and summary["start"] == "static"
    assert summary["settings"]["run"]["torque_history"]["time_s"] == list(IDLE.time)
    for args, text, key in (
            ([], CASE.replace("torque_history_periodic = true\n", ""), "run.torque_history"),  # too short
            (["--torque-history", "none.csv"], CASE, "--torque-history"),
            (["--teeth", "3"], CASE, "--teeth"),
            (["--teeth", "9"], CASE, "--teeth"),      # enough for 3 cycles, not for the history's 5
            (["--start", "moving"], CASE, "--start"),
            (["--ramp-cycles", "2"], CASE, "--ramp-cycles")):
        case.write_text(text)
        capsys.readouterr()
        assert main(["run", str(case), "--out", "bad", *args]) == 2, args
        err = capsys.readouterr().err
        assert key in err and err.count("\n") == 1 and not (tmp_path / "bad").exists(), err
    case.write_text(CASE)
    assert main(["run", str(case), "--out", "bad", "--model", "fe"]) == 2
    assert "cycles" in capsys.readouterr().err


def test_spurdyn_sweep_refuses_what_its_points_could_not_run(tmp_path, capsys):
    """A sweep of a case under a history that does not cover its slowest point, or a sector
    continuation on fewer teeth than whole gears, is refused in one line before any point."""
    from spurdyn.cli.main import main

    (tmp_path / "idle.csv").write_text("time_s,driver_Nm\n" + "".join(
        f"{t!r},{d!r}\n" for t, d in zip(IDLE.time, IDLE.driver)))
    case = tmp_path / "idle.toml"
    case.write_text(CASE.replace("torque_history_periodic = true\n", "").replace("cycles = 3", "cycles = 2"))
    # 2 cycles last 4.3 ms at 1,000 rpm: the 5-ms history covers them, not at 800 rpm (5.4 ms)
    assert main(["sweep", str(case), "--rpm", "800,1000", "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err
    assert "run.torque_history" in err and "800" in err and err.count("\n") == 1
    case.write_text(CASE)
    assert main(["sweep", str(case), "--rpm", "1000,1100", "--continuation", "up", "--teeth", "20",
                 "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err
    assert "--continuation" in err and "--teeth" in err and err.count("\n") == 1
    assert not (tmp_path / "bad").exists()
