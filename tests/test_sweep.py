"""``spurdyn sweep``: grids, sweep.nc, the picture, resuming, interruptions, failures,
refusals (the points on Dask clusters of real processes: tests/test_sweep_cluster.py).

Most tests use the lumped model in this process (``serial``: the local cluster replaced
by :class:`~spurdyn.sweep.backends.SerialBackend`, so that a monkeypatched point function
is the one that runs).
"""

from __future__ import annotations

import json
import math
import os
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.cli import sweep as cli_sweep
from spurdyn.cli.main import main
from spurdyn.sweep import point as point_mod
from spurdyn.sweep.backends import SerialBackend, default_jobs
from spurdyn.sweep.point import run_point
from spurdyn.sweep.spec import parse_speeds, parse_torques
from spurdyn.sweep.store import STATUS_CODES

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
FIGS = ("peak_force", "dynamic_factor", "mean_force_single_zone", "separations", "rms_force",
        "status", "wall_s", "reason", "dynamic_factor_raw", "peak_force_raw")


def sweep(capsys, *argv):
    code = main(["sweep", *[str(a) for a in argv]])
    out = capsys.readouterr()
    return code, out.out, out.err


def load(path: Path) -> xr.Dataset:
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


@pytest.fixture
def serial(monkeypatch):
    """Run the points in this process; count the local clusters asked for."""
    started: list[int] = []

    @contextmanager
    def local(jobs):
        started.append(jobs)
        yield SerialBackend()

    monkeypatch.setattr(cli_sweep, "local_backend", local)
    return started


@pytest.fixture
def calls(monkeypatch):
    """Count the points computed (the real point function still runs)."""
    done: list[float] = []

    def counted(task):
        done.append(task.key.rpm)
        return run_point(task)

    monkeypatch.setattr(point_mod, "run_point", counted)
    return done


# -- grids -----------------------------------------------------------------------------

def test_grids():
    assert parse_speeds("1000:3000:1000") == (1000.0, 2000.0, 3000.0)
    assert parse_speeds("1000:2900:1000") == (1000.0, 2000.0)
    assert parse_speeds("1000:20000/40")[:2] == (1000.0, round(1000 + 19000 / 39, 6))
    assert len(parse_speeds("1000:20000/40")) == 40
    assert parse_speeds("5000, 1000,5000") == (1000.0, 5000.0)
    assert parse_speeds("0.1:0.3:0.1") == (0.1, 0.2, 0.3)
    assert parse_torques("0,10") == (0.0, 10.0)
    assert parse_torques("10:30:10") == (10.0, 20.0, 30.0)


# -- what a sweep leaves ---------------------------------------------------------------

@pytest.mark.slow
def test_lumped_sweep_files_and_agreement_with_run(tmp_path, capsys, serial, calls):
    out = tmp_path / "sw"
    code, stdout, err = sweep(capsys, "paper-fig8", "--rpm", "4000:20000:8000", "--model",
                              "lumped", "--out", out)
    assert code == 0, err
    assert "3 points (3 computed" in stdout and "15,176 rpm" in stdout
    assert sorted(calls) == [4000.0, 12000.0, 20000.0]
    assert (out / "dynamic_factor.png").read_bytes()[:8] == PNG_MAGIC
    assert len(list((out / "points").glob("*.json"))) == 3
    own = load(out / "sweep_lumped.nc")
    assert dict(own.sizes) == {"rpm": 3} and float(own["torque"]) == 22.25
    for name in FIGS:
        assert name in own, name
    assert own["status"].attrs["flag_meanings"].split() == list(STATUS_CODES)
    assert "legend" in own["status"].attrs
    assert (own["status"].values == STATUS_CODES["complete"]).all()
    assert own["mesh_frequency"].values.tolist() == pytest.approx([28 * n / 60 for n in (4e3, 12e3, 2e4)])
    assert own.attrs["resonance_rpm"] == pytest.approx(60 * own.attrs["natural_frequency_hz"] / 28)
    assert 5e3 < own.attrs["natural_frequency_hz"] < 1e4
    combined = load(out / "sweep.nc")
    assert dict(combined.sizes) == {"model": 1, "rpm": 3}
    np.testing.assert_array_equal(combined["dynamic_factor"].sel(model="lumped").values,
                                  own["dynamic_factor"].values)
    # A point is what ``spurdyn run`` of the same case reports.
    assert main(["run", "paper-fig8", "--model", "lumped", "--speed-a", "12000", "--speed-b",
                 "12000", "--out", str(tmp_path / "run"), "--quiet"]) == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    p = own.sel(rpm=12000.0)
    assert float(p["peak_force"]) == pytest.approx(summary["peak_force_N"], rel=1e-12)
    assert float(p["dynamic_factor"]) == pytest.approx(summary["dynamic_factor"], rel=1e-12)
    assert float(p["peak_force_raw"]) == pytest.approx(summary["peak_force_raw_N"], rel=1e-12)
    assert float(p["dynamic_factor_raw"]) == pytest.approx(summary["dynamic_factor_raw"],
                                                           rel=1e-12)
    assert float(p["mean_force_single_zone"]) == pytest.approx(summary["mean_force_single_zone_N"],
                                                               rel=1e-12)
    assert int(p["separations"]) == summary["separations"]
    # the lumped model has no fillets: its root stress is absent, not zero
    assert np.isnan(own["root_stress_max_a"].values).all() and np.isnan(own["root_stress_max_b"].values).all()
    run = load(tmp_path / "run" / "result.nc")
    force = run["contact_force"].values
    assert float(p["rms_force"]) == pytest.approx(np.sqrt(np.mean(force**2)), rel=1e-12)
    # the headline is the averaged force's: at most the raw one (the lumped force is smooth)
    factor, raw = own["dynamic_factor"].values, own["dynamic_factor_raw"].values
    assert (factor <= raw).all() and (factor > 0.9).all() and (factor > 0.99 * raw).all()
    assert own.attrs["averaging_window_s"] == 10e-6 == combined.attrs["averaging_window_s"]
    assert "10 us" in own.attrs["dynamic_factor_note"]


@pytest.mark.slow
def test_torque_dimension_and_fe_overlay(tmp_path, capsys, serial, calls, monkeypatch):
    out = tmp_path / "sw"
    code, _, err = sweep(capsys, "paper-fig8", "--rpm", "6000,12000", "--torque", "11.125,22.25",
                         "--model", "lumped", "--out", out, "--quiet")
    assert code == 0, err
    own = load(out / "sweep_lumped.nc")
    assert dict(own.sizes) == {"rpm": 2, "torque": 2} and own["dynamic_factor"].dims == ("rpm", "torque")
    static = own["static_force"].isel(rpm=0).values
    assert static[1] == pytest.approx(2 * static[0])
    assert len(calls) == 4

    # A second model in the same folder: overlaid in the picture, a model dimension in
    # sweep.nc (outer join: speeds this model's sweep did not ask for are not_requested).
    # (The lumped model stands in for the FE solver here: only the bookkeeping is tested.)
    real = point_mod.simulate_model
    monkeypatch.setattr(point_mod, "simulate_model", lambda model, case: real("lumped", case))
    code, _, err = sweep(capsys, "paper-fig8", "--rpm", "12000,18000", "--torque", "22.25",
                         "--model", "fe", "--out", out, "--quiet")
    assert code == 0, err
    both = load(out / "sweep.nc")
    assert both["model"].values.tolist() == ["fe", "lumped"]
    assert both["rpm"].values.tolist() == [6000.0, 12000.0, 18000.0]
    status = both["status"]
    assert int(status.sel(model="fe", rpm=6000.0, torque=22.25)) == STATUS_CODES["not_requested"]
    assert int(status.sel(model="lumped", rpm=18000.0, torque=22.25)) == STATUS_CODES["not_requested"]
    assert int(status.sel(model="fe", rpm=12000.0, torque=22.25)) == STATUS_CODES["complete"]
    assert (out / "sweep_fe.nc").is_file() and (out / "dynamic_factor.png").is_file()


# -- nothing lost, resumable -----------------------------------------------------------

@pytest.mark.slow
def test_resume_computes_only_missing_points(tmp_path, capsys, serial, calls):
    out = tmp_path / "sw"
    args = ["paper-fig9", "--model", "lumped", "--out", out, "--quiet"]
    assert sweep(capsys, *args, "--rpm", "10000:14000:2000")[0] == 0
    jobs = default_jobs()
    assert len(calls) == 3 and serial == [min(jobs, 3)]  # no more workers than points
    calls.clear()
    assert sweep(capsys, *args, "--rpm", "8000:16000:2000")[0] == 0
    assert sorted(calls) == [8000.0, 16000.0] and serial[-1] == min(jobs, 2)
    calls.clear()
    code, stdout, _ = sweep(capsys, *args[:-1], "--rpm", "8000:16000:2000")
    assert code == 0 and calls == [] and len(serial) == 2  # nothing to do: no cluster
    assert "0 computed" in stdout and "5 already in" in stdout
    ds = load(out / "sweep_lumped.nc")
    assert ds.sizes["rpm"] == 5 and (ds["status"].values == 0).all()
    # Another setting is another point; --force computes everything again.
    assert sweep(capsys, *args, "--rpm", "8000:16000:2000", "--angle", "10")[0] == 0
    assert len(calls) == 5
    calls.clear()
    assert sweep(capsys, *args, "--rpm", "8000:16000:2000", "--force")[0] == 0
    assert len(calls) == 5
    assert len(list((out / "points").glob("*.json"))) == 10


def test_interrupted_sweep_keeps_finished_points(tmp_path, capsys, serial, monkeypatch):
    out = tmp_path / "sw"
    done: list[float] = []

    def interrupted_after_two(task):
        if len(done) == 2:
            raise KeyboardInterrupt
        done.append(task.key.rpm)
        return run_point(task)

    monkeypatch.setattr(point_mod, "run_point", interrupted_after_two)
    args = ["paper-fig8", "--model", "lumped", "--rpm", "6000:14000:2000", "--out", out]
    code, _, err = sweep(capsys, *args)
    assert code == 1 and "interrupted: 2 of 5 points kept" in err
    assert len(list((out / "points").glob("*.json"))) == 2
    ds = load(out / "sweep_lumped.nc")
    status = ds["status"].values
    assert (status == STATUS_CODES["complete"]).sum() == 2
    assert (status == STATUS_CODES["not_run"]).sum() == 3
    assert set(ds["reason"].values[status == STATUS_CODES["not_run"]]) == {"interrupted"}
    # The longest runs go first: the two lowest speeds were computed.
    assert sorted(done) == [6000.0, 8000.0]
    assert np.isfinite(ds["dynamic_factor"].sel(rpm=[6000.0, 8000.0]).values).all()
    # Rerunning computes the three others only.
    done.clear()
    monkeypatch.setattr(point_mod, "run_point", lambda task: (done.append(task.key.rpm),
                                                               run_point(task))[1])
    assert sweep(capsys, *args, "--quiet")[0] == 0
    assert sorted(done) == [10000.0, 12000.0, 14000.0]


def test_failed_and_incomplete_points_recorded_and_sweep_goes_on(tmp_path, capsys, serial,
                                                                 monkeypatch, calls):
    out = tmp_path / "sw"
    real = point_mod.simulate_model
    broken = {"on": True}

    def flaky(model, case):
        rpm = case.run.speed_a * 60 / (2 * math.pi)
        if broken["on"] and abs(rpm - 8000) < 1e-6:
            raise FloatingPointError("the stiffness table went bad")
        result = real(model, case)
        if abs(rpm - 10000) < 1e-6:  # as the solver reports a stage that does not converge
            n = len(result.time) // 2
            result.contact_force[n:] = np.nan
            result.status, result.reason = "incomplete", "displacement stage did not converge"
        return result

    monkeypatch.setattr(point_mod, "simulate_model", flaky)
    args = ["paper-fig8", "--model", "lumped", "--rpm", "6000:12000:2000", "--out", out]
    code, _, err = sweep(capsys, *args)
    assert code == 1
    assert "8,000 rpm, 22.25 N m: failed: FloatingPointError: the stiffness table went bad" in err
    assert "10,000 rpm, 22.25 N m: incomplete: displacement stage did not converge" in err
    assert len(calls) == 4
    ds = load(out / "sweep_lumped.nc")
    assert int(ds["status"].sel(rpm=8000.0)) == STATUS_CODES["failed"]
    assert "FloatingPointError" in str(ds["reason"].sel(rpm=8000.0).values)
    assert np.isnan(float(ds["dynamic_factor"].sel(rpm=8000.0)))
    assert int(ds["status"].sel(rpm=10000.0)) == STATUS_CODES["incomplete"]
    assert str(ds["reason"].sel(rpm=10000.0).values) == "displacement stage did not converge"
    assert np.isfinite(float(ds["peak_force"].sel(rpm=10000.0)))
    # stopped early: no dynamic factor, averaged or raw, in any file of the sweep
    for name in ("dynamic_factor", "dynamic_factor_raw"):
        assert np.isnan(float(ds[name].sel(rpm=10000.0)))
        assert np.isnan(float(load(out / "sweep.nc")[name].sel(model="lumped", rpm=10000.0)))
    record = json.loads(next((out / "points").glob("lumped_rpm10000*.json")).read_text())
    assert record["status"] == "incomplete" and record["dynamic_factor"] is None
    assert (ds["status"].sel(rpm=[6000.0, 12000.0]).values == STATUS_CODES["complete"]).all()
    # A failure is computed again by the next run; an incomplete run is a result and is not.
    broken["on"] = False
    calls.clear()
    assert sweep(capsys, *args, "--quiet")[0] == 1  # still one incomplete point
    assert calls == [8000.0]
    assert int(load(out / "sweep_lumped.nc")["status"].sel(rpm=8000.0)) == STATUS_CODES["complete"]


# -- refusals --------------------------------------------------------------------------

@pytest.mark.parametrize("argv, field", [
    (["--rpm", "1000-2000"], "--rpm"),
    (["--rpm", "1000:2000"], "--rpm"),
    (["--rpm", "a:2000:100"], "--rpm"),
    (["--rpm", "2000:1000:100"], "--rpm"),
    (["--rpm", "1000:2000:0"], "--rpm"),
    (["--rpm", "1000:2000/0"], "--rpm"),
    (["--rpm=-1000:2000:500"], "--rpm"),
    (["--rpm", "-1000:2000:500"], "argument --rpm"),
    (["--rpm", "0,1000"], "--rpm"),
    (["--rpm", "1:1e9:1"], "--rpm"),
    (["--rpm", "1000", "--torque", "-5"], "--torque"),
    (["--rpm", "1000", "--model", "rigid"], "--model"),
    (["--rpm", "1000", "--jobs", "0"], "--jobs"),
    (["--rpm", "1000", "--scheduler", "localhost:8786"], "--scheduler"),
    (["--rpm", "1000", "--scheduler", "tcp://127.0.0.1:8786", "--jobs", "2"], "--jobs"),
    (["--rpm", "1000", "--scheduler-timeout", "5"], "--scheduler-timeout"),
    (["--rpm", "1000", "--scheduler", "tcp://127.0.0.1:1", "--scheduler-timeout", "0"],
     "--scheduler-timeout"),
    (["--rpm", "1000", "--scheduler", "tcp://127.0.0.1:1", "--scheduler-timeout", "nan"],
     "--scheduler-timeout"),
    (["--rpm", "1000", "--tls-ca-file", "ca.pem"], "--tls-ca-file"),
    (["--rpm", "1000", "--scheduler", "tcp://127.0.0.1:1", "--tls-cert", "c.pem"], "--tls-cert"),
    (["--rpm", "1000", "--scheduler", "tls://127.0.0.1:1"], "--tls-ca-file"),
    (["--rpm", "1000", "--scheduler", "tls://127.0.0.1:1", "--tls-ca-file", "no.pem",
      "--tls-cert", "no.pem"], "--tls-ca-file"),
    (["--rpm", "1000", "--dt", "1e-6"], "--dt"),
    (["--rpm", "1000", "--mesh", "4by14"], "--mesh"),
    (["--rpm", "1000:20000:1000", "--angle", "0.001"], "--angle"),
])
def test_bad_input_refused_in_one_line(tmp_path, capsys, serial, argv, field):
    out = tmp_path / "sw"
    model = [] if "--model" in argv else ["--model", "lumped"]
    code, stdout, err = sweep(capsys, "paper-fig8", *model, *argv, "--out", out)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"spurdyn: error: {field}: "), err
    assert not out.exists() and serial == []


def test_bad_case_and_folder_refused(tmp_path, capsys, serial):
    code, _, err = sweep(capsys, "paper-all", "--rpm", "1000", "--model", "lumped",
                         "--out", tmp_path / "a")
    assert code == 2 and err.startswith("spurdyn: error: CASE: ") and "group" in err
    code, _, err = sweep(capsys, "no-such-case", "--rpm", "1000", "--out", tmp_path / "b")
    assert code == 2 and err.startswith("spurdyn: error: CASE: ")
    busy = tmp_path / "busy"
    busy.mkdir()
    (busy / "notes.txt").write_text("mine")
    code, _, err = sweep(capsys, "paper-fig8", "--rpm", "1000", "--model", "lumped",
                         "--out", busy)
    assert code == 2 and "holds no sweep" in err and sorted(os.listdir(busy)) == ["notes.txt"]
    assert serial == []


# -- the FE model, for real ------------------------------------------------------------

def test_tiny_fe_sweep_keeps_runs(tmp_path, capsys, serial):
    out = tmp_path / "fe"
    code, stdout, err = sweep(capsys, "paper-fig9", "--rpm", "18000,20000", "--angle", "1",
                              "--keep-runs", "--out", out)
    assert code == 0, err
    ds = load(out / "sweep_fe.nc")
    assert (ds["status"].values == 0).all() and (ds["peak_force"].values > 0).all()
    assert (ds["steps"].values > 200).all()
    runs = sorted((out / "runs").iterdir())
    assert [r.name.split("_")[1] for r in runs] == ["rpm18000", "rpm20000"]
    for r, rpm in zip(runs, (18000.0, 20000.0)):
        summary = json.loads((r / "summary.json").read_text())
        assert summary["speed_a_rpm"] == rpm and summary["status"] == "complete"
        for name, key in (("peak_force", "peak_force_N"), ("dynamic_factor", "dynamic_factor"),
                          ("dynamic_factor_raw", "dynamic_factor_raw")):
            assert float(ds[name].sel(rpm=rpm)) == pytest.approx(summary[key], rel=1e-12)
        assert (r / "result.nc").is_file() and (r / "contact_force.png").is_file()
    assert not [p for p in (out / "runs").iterdir() if p.name.startswith(".")]


def test_sweep_progress_on_a_terminal_only():
    """Points done and not complete, and the time left (weighted by steps), on a terminal;
    nothing in a pipe or with --quiet."""
    import io

    from spurdyn.sweep.runner import SweepProgress

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    tty = Terminal()
    bar = SweepProgress("fe sweep", total_cost=1000, n_points=3, stream=tty)
    bar.update(600, ok=True)
    bar.update(100, ok=False)
    bar.close()
    text = tty.getvalue()
    assert "fe sweep: 2/3 points, 1 not complete" in text
    assert " 70%|" in text        # 700 of the 1,000 steps: the long point counts for more
    for stream, enabled in ((io.StringIO(), True), (Terminal(), False)):
        quiet = SweepProgress("fe sweep", total_cost=1000, n_points=3, enabled=enabled,
                              stream=stream)
        quiet.update(600, ok=True)
        quiet.close()
        assert stream.getvalue() == ""
