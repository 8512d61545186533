"""Fault sweeps (docs/sweep.md, "Fault datasets"): the size axis and its refusals, the
points' keys and resuming, the data set's coordinates and CF attributes, the averages'
resampling, and (slow) a real sweep whose size 0 is the healthy run to round-off.

The fast tests run the points in this process with a stand-in point function (the model's
runs are the slow test's), and a stand-in resonance estimate.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from spurdyn.case.presets import resolve_cases
from spurdyn.cli import sweep as cli_sweep
from spurdyn.cli.main import main
from spurdyn.sweep import point as point_mod
from spurdyn.sweep import resonance as resonance_mod
from spurdyn.sweep.backends import SerialBackend
from spurdyn.errors import InputError
from spurdyn.results.vibration import Followed
from spurdyn.sweep.faults import (INDICATORS, SIGNALS, FaultAxis, fault_axis, fault_case, last_revolution,
                                  orders_resampled)
from spurdyn.sweep.point import FIGURES, PointOutcome, PointTask, run_point
from spurdyn.sweep.spec import parse_grid, settings_hash

PAIR = """[gear_a]
teeth = 18
module = 0.003175
face_width = 0.00635

[gear_b]
teeth = 18
module = 0.003175
face_width = 0.00635

[run]
torque = 22.25
speed_a_rpm = 8000

[mesh]
nx = 2
ny = 6

[model]
kind = "sector"
"""
CRACK = '\n[[fault]]\ngear = "a"\ntooth = 1\nkind = "crack"\ndepth = {depth}\n'
MISSING = '\n[[fault]]\ngear = "b"\ntooth = 3\nkind = "missing"\n'


def case_file(tmp_path: Path, name: str, *faults: str) -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(PAIR + "".join(faults))
    return path


def sweep(capsys, *argv) -> tuple[int, str, str]:
    code = main(["sweep", *[str(a) for a in argv]])
    out = capsys.readouterr()
    return code, out.out, out.err


def load(path: Path) -> xr.Dataset:
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


@pytest.fixture
def serial(monkeypatch):
    """The points in this process (the local cluster replaced); the resonance estimate a
    stand-in (a fault sweep's is the healthy pair's, which other tests check)."""
    started: list[int] = []

    @contextmanager
    def local(jobs):
        started.append(jobs)
        yield SerialBackend()

    monkeypatch.setattr(cli_sweep, "local_backend", local)
    monkeypatch.setattr(resonance_mod, "resonance_estimate", lambda case, model=None: resonance_mod.ResonanceEstimate(
        mesh_stiffness_mean=1e8, equivalent_mass=0.035, natural_frequency_hz=8000.0, teeth_a=18))
    return started


def fake_point(task: PointTask) -> PointOutcome:
    """A point from its key alone: figures that follow the speed and the size."""
    size = task.key.size or 0.0
    faults = task.case.run.faults
    assert (size > 0) == bool(faults) and all(f.depth == size for f in faults)
    figures = {name: None for name in FIGURES}
    figures.update(peak_force=1000.0 + 1e5 * size, dynamic_factor=1.1 + size, steps=1234, separations=0,
                   wall_s=1.0, settled=float(size < 1.5e-3), cycles_done=task.case.run.cycles or 36)
    angle = 2 * np.pi * np.arange(task.samples) / task.samples
    signals = {"window_s": [0.0, 1.0], "shaft_frequency_Hz": task.key.rpm / 60, "revolutions": 2,
               "build_s": 0.5}
    for k, name in enumerate(SIGNALS):
        tsa = np.cos(18 * angle) + 1e3 * size * np.cos(angle) + k
        signals[name] = {**{ind: 1.0 + size + k for ind in INDICATORS}, "tsa": tsa.tolist()}
    figures["signals"] = signals
    return PointOutcome(key=task.key, status="complete", figures=figures, worker="test:1", finished=1.0)


@pytest.fixture
def calls(monkeypatch):
    """The points computed, by their size (the stand-in runs)."""
    done: list[float] = []

    def counted(task):
        done.append(task.key.size)
        return fake_point(task)

    monkeypatch.setattr(point_mod, "run_point", counted)
    return done


# -- the averages' samples --------------------------------------------------------------

def test_an_average_keeps_its_orders_below_half_the_samples():
    n = 1024
    for m in (3000, 512):        # down and up
        theta = 2 * np.pi * np.arange(m) / m
        tsa = 1.0 + np.cos(3 * theta) + 0.5 * np.sin(100 * theta + 0.3) + (0.2 * np.cos(700 * theta) if m > 1400 else 0)
        phi = 2 * np.pi * np.arange(n) / n
        want = 1.0 + np.cos(3 * phi) + 0.5 * np.sin(100 * phi + 0.3)
        assert np.abs(orders_resampled(tsa, n) - want).max() < 1e-12


@pytest.mark.parametrize("start", [0.0, 0.3217, 2 * np.pi - 1e-3])
def test_an_average_from_any_start_lands_on_the_gear_s_angles(start):
    """An average whose point 0 is at the gear's angle ``start`` (not on the grid) is put on
    the gear's own angles exactly: its orders turned, not rolled to the nearest point."""
    m, n = 5628, 8192
    theta = start + 2 * np.pi * np.arange(m) / m
    tsa = np.cos(3 * theta) + 0.5 * np.sin(448 * theta + 0.3) + 0.3 * np.cos(500 * theta)
    phi = 2 * np.pi * np.arange(n) / n
    want = np.cos(3 * phi) + 0.5 * np.sin(448 * phi + 0.3) + 0.3 * np.cos(500 * phi)
    assert np.abs(orders_resampled(tsa, n, start) - want).max() < 1e-10


def test_a_point_reads_its_last_revolution():
    angle = np.linspace(0.0, 3.4 * 2 * np.pi, 3401)
    time = angle / 100.0
    f = Followed("a", 28, np.ones(angle.size, bool), angle, time, 100.0 / (2 * np.pi))
    last = last_revolution(f)
    span = last.angle[-1] - last.angle[0]
    assert 2 * np.pi <= span < 2 * np.pi + (angle[1] - angle[0]) + 1e-12
    assert last.sel.sum() == last.angle.size and last.sel[-1] and not last.sel[0]
    assert last.f_shaft == pytest.approx(100.0 / (2 * np.pi), rel=1e-12)


def test_a_size_that_rounds_to_zero_is_refused():
    with pytest.raises(InputError) as err:
        parse_grid("4e-10,1e-3", "--fault-size", positive=False, decimals=9)
    assert err.value.field == "--fault-size"


# -- the axis, the points' cases and keys ----------------------------------------------

def _case(tmp_path, *faults):
    return resolve_cases(str(case_file(tmp_path, "c", *faults)), {}, {})[0]


def test_size_zero_is_the_healthy_pair_over_the_faulty_runs_revolutions(tmp_path):
    case = _case(tmp_path, CRACK.format(depth=1e-3))
    axis = fault_axis(case, (0.0, 5e-4))
    healthy = fault_case(case, axis, 0.0)
    assert healthy.run.faults == ()
    # the faulty run's whole periods: at least two revolutions of the 18-tooth gear, room for two more
    assert (healthy.run.cycles, healthy.run.max_cycles) == (36, 72)
    cracked = fault_case(case, axis, 5e-4)
    assert [f.depth for f in cracked.run.faults] == [5e-4]
    # the cracked point's case says the cycles its model takes: the same whole revolutions
    assert (cracked.run.cycles, cracked.run.max_cycles) == (36, 72)
    given = fault_case(replace(case, run=case.run.with_(cycles=40, max_cycles=50)), axis, 0.0).run
    assert (given.cycles, given.max_cycles) == (54, 54)     # whole revolutions, the most given kept


def test_the_settings_hash_holds_the_fault_but_its_size(tmp_path):
    one, two = _case(tmp_path, CRACK.format(depth=1e-3)), _case(tmp_path, CRACK.format(depth=2e-3))
    h1 = settings_hash(one, model="sector", faults=fault_axis(one, (0.0,)))
    assert h1 == settings_hash(two, model="sector", faults=fault_axis(two, (0.0,)))
    other = _case(tmp_path, CRACK.format(depth=1e-3).replace("tooth = 1", "tooth = 2"))
    assert h1 != settings_hash(other, model="sector", faults=fault_axis(other, (0.0,)))
    assert h1 != settings_hash(one, model="sector")
    axis = fault_axis(one, (0.0,))
    fewer = FaultAxis(axis.fault, axis.sizes, axis.teeth, axis.samples // 2)
    assert h1 != settings_hash(one, model="sector", faults=fewer)


# -- refusals ---------------------------------------------------------------------------

@pytest.mark.parametrize("faults, argv, field", [
    ((CRACK.format(depth=1e-3),), ["--fault-size=-1e-3"], "--fault-size"),
    ((CRACK.format(depth=1e-3),), ["--fault-size", "0:1e-3:0"], "--fault-size"),
    ((), ["--fault-size", "0,1e-3"], "--fault-size"),
    ((MISSING,), ["--fault-size", "0,1e-3"], "--fault-size"),
    ((CRACK.format(depth=1e-3), MISSING), ["--fault-size", "0,1e-3"], "--fault-size"),
    ((CRACK.format(depth=1e-3), MISSING), [], "fault"),
    ((CRACK.format(depth=1e-3),), ["--fault-size", "0,0.05"], "--fault-size"),
    ((CRACK.format(depth=1e-3).replace('"crack"', '"spall"').replace("depth", 'roll_deg = [20, 24]\ndepth'),),
     ["--fault-size", "0,2e-3"], "--fault-size"),
    ((CRACK.format(depth=1e-3),), ["--fault-size", "0,1e-3", "--model", "lumped"], "fault"),   # the model refuses it
    ((CRACK.format(depth=1e-3),), ["--cycles", "36", "--continuation", "up"], "--continuation"),
])
def test_bad_fault_sweeps_refused_in_one_line(tmp_path, capsys, serial, faults, argv, field):
    out = tmp_path / "sw"
    code, _, err = sweep(capsys, case_file(tmp_path, "c", *faults), "--rpm", "8000", *argv, "--out", out)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"spurdyn: error: {field}: "), err
    assert not out.exists() and serial == []


# -- the data set and resuming ----------------------------------------------------------

def test_the_dataset_its_coordinates_and_cf_attributes(tmp_path, capsys, serial, calls):
    out = tmp_path / "sw"
    code, stdout, _ = sweep(capsys, case_file(tmp_path, "c", CRACK.format(depth=1e-3)), "--rpm", "6000,8000",
                            "--torque", "10,20", "--fault-size", "0:2e-3/3", "--out", out)
    assert code == 0 and "fault_sweep.nc" in stdout
    ds = load(out / "fault_sweep.nc")
    assert dict(ds.sizes) == {"rpm": 2, "torque": 2, "fault_size": 3, "angle": 1024}
    assert ds["fault_size"].values.tolist() == [0.0, 1e-3, 2e-3] and ds["fault_size"].attrs["units"] == "m"
    assert ds["faulty"].values.tolist() == [0, 1, 1]
    assert (str(ds["fault_kind"].values), str(ds["fault_gear"].values), int(ds["fault_tooth"])) == ("crack", "a", 1)
    assert ds.attrs["Conventions"].startswith("CF-") and ds.attrs["angle_samples"] == 1024
    assert np.allclose(ds["angle"].values[:2], [0.0, 2 * np.pi / 1024]) and ds["angle"].attrs["units"] == "rad"
    for name in SIGNALS:
        assert ds[f"{name}_tsa"].dims == ("rpm", "torque", "fault_size", "angle")
        for ind in INDICATORS:
            assert ds[f"{name}_{ind}"].attrs["units"] and ds[f"{name}_{ind}"].attrs["long_name"]
    # each point's figures where its key puts them
    assert ds["peak_force"].sel(fault_size=2e-3).values == pytest.approx(1200.0)
    tsa = ds["mesh_force_tsa"].sel(rpm=6000.0, torque=20.0, fault_size=1e-3).values
    assert np.allclose(tsa, np.cos(18 * ds["angle"].values) + np.cos(ds["angle"].values))
    assert (ds["status"].values == 0).all() and ds["status"].attrs["flag_meanings"].startswith("complete")
    assert ds["settled"].sel(fault_size=2e-3).values.tolist() == [[0.0, 0.0], [0.0, 0.0]]
    # the fault's parameters are coordinates of every variable in the file (CF's coordinates attribute)
    with netCDF4.Dataset(out / "fault_sweep.nc") as raw:
        named = raw["mesh_force_rms"].getncattr("coordinates").split()
        assert {"fault_kind", "fault_gear", "fault_tooth", "faulty", "mesh_frequency"} <= set(named)
        for var in raw.variables.values():
            assert "long_name" in var.ncattrs(), var.name


def test_a_fault_sweep_resumes_and_computes_only_new_sizes(tmp_path, capsys, serial, calls, monkeypatch):
    out = tmp_path / "sw"
    case = case_file(tmp_path, "c", CRACK.format(depth=1e-3))
    args = [case, "--rpm", "8000", "--fault-size", "0,1e-3,2e-3", "--out", out, "--quiet"]
    real = point_mod.run_point

    def interrupted_after_one(task):
        if len(calls) == 1:
            raise KeyboardInterrupt
        return real(task)

    monkeypatch.setattr(point_mod, "run_point", interrupted_after_one)
    code, _, err = sweep(capsys, *args)
    assert code == 1 and "1 of 3 points kept" in err
    assert sorted(load(out / "fault_sweep.nc")["status"].values.ravel().tolist()) == [0, 3, 3]
    monkeypatch.setattr(point_mod, "run_point", real)
    assert sweep(capsys, *args)[0] == 0 and sorted(calls) == [0.0, 1e-3, 2e-3] and len(calls) == 3
    calls.clear()
    assert sweep(capsys, *args)[0] == 0 and calls == []
    # the size given by --fault instead of the case's table: the same fault, the same points
    plain = case_file(tmp_path, "plain")
    spec = "gear=a,tooth=1,kind=crack,depth=5e-4"
    assert sweep(capsys, plain, "--fault", spec, *args[1:3], "--fault-size", "0:2e-3/5", *args[5:])[0] == 0
    assert sorted(calls) == [5e-4, 1.5e-3]
    ds = load(out / "fault_sweep.nc")
    assert ds["fault_size"].values.tolist() == [0.0, 5e-4, 1e-3, 1.5e-3, 2e-3]
    assert (ds["status"].values == 0).all()


def test_a_missing_tooth_swept_over_speed_has_no_size(tmp_path, capsys, serial, monkeypatch):
    def missing_point(task: PointTask) -> PointOutcome:
        assert task.key.size is None and task.case.run.faults[0].kind == "missing" and task.follow == "b"
        # the stand-in's figures of a pair it takes as healthy
        return fake_point(replace(task, case=replace(task.case, run=task.case.run.with_(faults=()))))

    monkeypatch.setattr(point_mod, "run_point", missing_point)
    out = tmp_path / "sw"
    assert sweep(capsys, case_file(tmp_path, "c", MISSING), "--rpm", "6000,8000", "--out", out, "--quiet")[0] == 0
    ds = load(out / "fault_sweep.nc")
    assert "fault_size" not in ds.coords and dict(ds.sizes) == {"rpm": 2, "angle": 1024}
    assert (str(ds["fault_kind"].values), str(ds["fault_gear"].values)) == ("missing", "b")


# -- a real sweep -----------------------------------------------------------------------

@pytest.mark.slow
def test_size_zero_is_the_healthy_run_to_round_off(tmp_path, capsys, serial):
    out = tmp_path / "sw"
    code, _, _ = sweep(capsys, case_file(tmp_path, "c", CRACK.format(depth=1e-3)), "--rpm", "8000",
                       "--fault-size", "0,1e-3", "--out", out, "--quiet")
    assert code == 0
    ds = load(out / "fault_sweep.nc")
    # the healthy pair's own run, from a case file without the fault, as `spurdyn run --cycles 36
    # --max-cycles 72` runs it, followed by its driver
    healthy = resolve_cases(str(case_file(tmp_path, "healthy")), {"run.cycles": 36, "run.max_cycles": 72}, {})[0]
    key = point_mod.PointKey("sector", 8000.0, 22.25, "", 0.0)
    alone = run_point(PointTask(key, healthy, follow="a", samples=int(ds.attrs["angle_samples"])))
    assert alone.status == "complete"
    zero = ds.sel(fault_size=0.0).isel(rpm=0)
    for name in ("peak_force", "rms_force", "transmission_error_rms", "cycles_done"):
        assert float(zero[name]) == pytest.approx(alone.figures[name], rel=1e-12, abs=0.0)
    for name in SIGNALS:
        got = alone.figures["signals"][name]
        for ind in INDICATORS:
            assert float(zero[f"{name}_{ind}"]) == pytest.approx(got[ind], rel=1e-12, abs=0.0), (name, ind)
        want = np.asarray(got["tsa"])
        assert np.abs(zero[f"{name}_tsa"].values - want).max() <= 1e-12 * np.abs(want).max()
    # the crack is seen: the mesh force's shaft-order sidebands grow, the peak of the average moves
    cracked = ds.sel(fault_size=1e-3).isel(rpm=0)
    assert float(cracked["mesh_force_sideband_energy_ratio"]) > 10 * float(zero["mesh_force_sideband_energy_ratio"])
    assert int(cracked["revolutions"]) == int(zero["revolutions"]) == 1     # each its last
    assert math.isfinite(float(cracked["build_s"])) and float(cracked["build_s"]) < float(cracked["wall_s"])
