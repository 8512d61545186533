"""What a run leaves on disk (result.nc, CSV, summary) and reading it back, and the case
files, on synthetic results shaped like the solver's (``run_helpers.fake_simulate``); the
pictures, tooth frames and ParaView files: test_results_pictures.py."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.case import case_from_dict, case_to_dict, load_case, preset_case, resolve_cases
from spurdyn.errors import InputError
from spurdyn.results.io import (CSV_FILE, PNG_FILE, RESULT_FILE, SUMMARY_FILE, case_from_run,
                                load_run, result_to_dataset, summarize, write_run)
from spurdyn.result import STAGES
from spurdyn.results.headline import moving_average
from run_helpers import (  # noqa: F401 (short_case, run_dir: fixtures)
    PNG_MAGIC, fake_simulate, run_dir, short_case,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


# -- result.nc -------------------------------------------------------------------------

def test_run_folder_files(run_dir):
    d, _, _ = run_dir
    for name in (RESULT_FILE, CSV_FILE, PNG_FILE, SUMMARY_FILE, "result.pvd"):
        assert (d / name).is_file(), name
    assert (d / PNG_FILE).read_bytes()[:8] == PNG_MAGIC


def test_netcdf_layout_units_and_case(run_dir, short_case):
    d, result, _ = run_dir
    with xr.open_dataset(d / RESULT_FILE, engine="netcdf4") as ds:
        assert ds.sizes["time"] == len(result.time)
        assert ds["time"].attrs["units"] == "s"
        assert np.issubdtype(ds["time"].dtype, np.floating)  # not decoded as timedelta
        expected = {"angle_deg": "degree", "contact_force": "N", "gap": "m",
                    "omega_a": "rad s-1", "omega_b": "rad s-1", "torque_a": "N m",
                    "torque_b": "N m", "theta_a": "rad", "theta_b": "rad",
                    "roll_a_deg": "degree", "roll_b_deg": "degree",
                    "residual_displacement": "m", "residual_velocity": "m s-1",
                    "residual_acceleration": "m s-2"}
        for name, units in expected.items():
            assert ds[name].dims == ("time",)
            assert ds[name].attrs["units"] == units and ds[name].attrs["long_name"]
        for stage in STAGES:
            assert ds[f"iterations_{stage}"].dims == ("time",)
        np.testing.assert_allclose(ds["contact_force"].values, result.contact_force)
        np.testing.assert_allclose(ds["angle_deg"].values, np.degrees(result.angle))
        np.testing.assert_allclose(ds["omega_b"].values, result.omega[:, 1])
        assert ds["frame_u"].dims == ("frame", "dof")
        assert ds.sizes["frame"] == len(result.frame_time)
        np.testing.assert_allclose(ds["frame_theta_b"].values, result.frame_theta[:, 1])
        assert ds.attrs["status"] == "complete" and ds.attrs["reason"] == ""
        assert ds.attrs["case_name"] == "paper-fig9"
        case = json.loads(ds.attrs["case"])
        assert case["run"]["speed_a_rpm"] == pytest.approx(20000.0)
        assert case["run"]["angle_deg"] == pytest.approx(0.3)
        assert json.loads(ds.attrs["info"])["note"] == 1.0


def test_load_run_and_case_round_trip(run_dir, short_case):
    d, result, _ = run_dir
    ds = load_run(d)
    assert float(ds["contact_force"].max()) == pytest.approx(result.contact_force.max())
    case = case_from_run(ds)
    assert case.pair == short_case.pair
    assert case.run == short_case.run
    assert load_run(d / RESULT_FILE).sizes == ds.sizes
    with pytest.raises(InputError, match="not a run folder"):
        load_run(d / "vtu")
    import spurdyn.results

    assert spurdyn.results.load_run is load_run


# -- summary and CSV -------------------------------------------------------------------

def test_summary_figures(run_dir, short_case):
    d, result, summary = run_dir
    assert json.loads((d / SUMMARY_FILE).read_text()) == summary
    static = 22.25 / short_case.pair.gear_a.base_radius
    assert summary["case"] == "paper-fig9" and summary["status"] == "complete"
    assert summary["steps"] == result.steps and summary["dt_s"] == 3e-8
    assert summary["wall_s"] == 0.25 and summary["n_dof"] == result.info["n_dof"]
    assert summary["static_force_N"] == pytest.approx(static)
    raw = result.contact_force.max()
    averaged = np.max(moving_average(result.time, result.contact_force))
    assert summary["peak_force_raw_N"] == pytest.approx(raw)
    assert summary["dynamic_factor_raw"] == pytest.approx(raw / static)
    assert summary["peak_force_N"] == pytest.approx(averaged, rel=1e-12) and averaged < raw
    assert summary["dynamic_factor"] == pytest.approx(averaged / static)
    assert summary["averaging_window_s"] == 10e-6
    assert summary["separations"] == 1
    lost = summary["separation_times_s"][0]
    assert 0.1 < math.degrees(lost * short_case.run.speed_a) < 0.101
    assert summary["mean_force_single_zone_N"] is None  # 0.3 deg never gets there
    assert summary["iterations_mean"] == {"displacement": 6.0, "velocity": 4.0,
                                          "acceleration": 3.0}
    n = len(result.time)
    assert summary["residual_max"]["velocity"] == pytest.approx(1e-6 * n)
    assert summary["frames"] == len(result.frame_time)


def test_summary_single_zone_mean_and_nan(short_case):
    case = preset_case("paper-fig9", {"run.save_every": 20, "run.frames_every": 0},
                       check_step=False)
    result = fake_simulate(case.pair, case.run)
    result.contact_force[-1] = np.nan
    s = summarize(result_to_dataset(result, case))
    deg = np.degrees(result.angle)
    zone = (deg >= math.degrees(case.pair.theta_2)) & \
        (deg <= math.degrees(case.pair.theta_s - case.pair.theta_2))
    assert s["mean_force_single_zone_N"] == pytest.approx(result.contact_force[zone].mean())
    assert s["peak_force_raw_N"] == pytest.approx(np.nanmax(result.contact_force))
    # the NaN sample is left out of the average, not counted as a force
    keep = np.isfinite(result.contact_force)
    averaged = np.max(moving_average(result.time[keep], result.contact_force[keep]))
    assert s["peak_force_N"] == pytest.approx(averaged, rel=1e-12)
    assert s["separations"] == 0 and s["frames"] == 0
    json.dumps(s, allow_nan=False)


def test_csv(run_dir):
    d, result, _ = run_dir
    lines = (d / CSV_FILE).read_text().splitlines()
    assert lines[0] == "angle_deg,time_s,contact_force_N"
    assert len(lines) == len(result.time) + 1
    rows = np.loadtxt(d / CSV_FILE, delimiter=",", skiprows=1)
    np.testing.assert_allclose(rows[:, 2], result.contact_force, rtol=1e-8)
    np.testing.assert_allclose(rows[:, 1], result.time, rtol=1e-8)


def test_incomplete_result_reads_back(tmp_path, short_case):
    calls = []

    def interrupt(step, angle, total):
        calls.append(step)
        if len(calls) == 2:
            raise KeyboardInterrupt

    result = fake_simulate(short_case.pair, short_case.run, interrupt)
    assert result.status == "incomplete" and result.steps == 40
    summary = write_run(result, short_case, tmp_path)
    ds = load_run(tmp_path)
    assert ds.attrs["status"] == "incomplete" == summary["status"]
    assert "interrupted" in ds.attrs["reason"] and summary["reason"] == ds.attrs["reason"]
    assert ds.sizes["time"] == 41 and summary["steps"] == 40


# -- case files ------------------------------------------------------------------------

def test_case_dict_round_trip_and_examples():
    for spec in ("paper-fig11", str(EXAMPLES / "pinion_gear.toml")):
        case = resolve_cases(spec)[0]
        back = case_from_dict(json.loads(json.dumps(case_to_dict(case))), case.name)
        assert back.pair == case.pair and back.run == case.run
    fig8 = load_case(EXAMPLES / "paper_fig8.toml")
    preset = preset_case("paper-fig8")
    assert fig8.pair == preset.pair
    assert fig8.run == preset.run.with_(name="paper_fig8")
    assert fig8.angle == pytest.approx(preset.pair.theta_s)


def test_speed_b_defaults_to_the_meshing_speed():
    pinion = load_case(EXAMPLES / "pinion_gear.toml")
    assert pinion.run.speed_b == pytest.approx(pinion.run.speed_a * 20 / 40)


@pytest.mark.parametrize("run_table, field", [
    ({"speed_a_rpm": 4000, "torque": 1, "colour": "red"}, "run.colour"),
    ({"speed_a_rpm": "fast", "torque": 1}, "run.speed_a_rpm"),
    ({"speed_a_rpm": 4000}, "run.torque"),
    ({"speed_a_rpm": 4000, "torque": -1}, "run.torque"),
    ({"speed_a_rpm": 0, "torque": 1}, "run.speed_a_rpm"),
    ({"speed_a_rpm": 4000, "torque": 1, "dt": -1e-8}, "run.dt"),
    ({"speed_a_rpm": 4000, "torque": 1, "save_every": 1.5}, "run.save_every"),
    ({"speed_a_rpm": 4000, "torque": 1, "keep_theta_term": 1}, "run.keep_theta_term"),
    ({"speed_a_rpm": 4000, "torque": 1, "method": "magic"}, "run.method"),
    ({"speed_a_rpm": 4000, "torque": 1, "angle_deg": 30.0}, "run.angle_deg"),
    ({"speed_a_rpm": 4000, "torque": 1, "dt": 5e-8}, "run.dt"),
])
def test_run_table_refusals(run_table, field):
    data = {"gear_a": case_to_dict(preset_case("paper-fig8"))["gear_a"], "run": run_table}
    with pytest.raises(InputError) as err:
        case_from_dict(data, "bad")
    assert err.value.field == field


def test_separations_count_losses_not_the_end_of_engagement(short_case):
    case = preset_case("paper-fig9", {"run.save_every": 10, "run.frames_every": 0},
                       check_step=False)
    result = fake_simulate(case.pair, case.run, separations=((3.0, 3.5), (9.0, 9.2)))
    assert result.contact_force[0] == 0 and result.contact_force[-1] == 0  # start and end
    s = summarize(result_to_dataset(result, case))
    assert s["separations"] == 2
    assert [math.degrees(t * case.run.speed_a) for t in s["separation_times_s"]] == \
        [pytest.approx(3.0, abs=0.04), pytest.approx(9.0, abs=0.04)]  # 0.036 deg sampling
    # Contact lost for good before the end is a separation.
    result.contact_force[np.degrees(result.angle) > 15.0] = 0.0
    assert summarize(result_to_dataset(result, case))["separations"] == 3


def test_a_loss_of_contact_that_opens_no_gap_is_not_a_separation(short_case):
    """Contact lost while the surfaces stay within SEPARATION_GAP (1 nm) of each other
    (numerical flicker of an unloaded contact) is not counted; the same loss with the gap
    opening to 2 nm is."""
    from spurdyn.results.io import SEPARATION_GAP

    case = preset_case("paper-fig9", {"run.save_every": 10, "run.frames_every": 0},
                       check_step=False)
    result = fake_simulate(case.pair, case.run, separations=((3.0, 3.5), (9.0, 9.2)))
    early = (np.degrees(result.angle) >= 3.0) & (np.degrees(result.angle) < 3.5)
    assert not np.any(result.contact_force[early] > 0)
    result.gap[early] = 0.5 * SEPARATION_GAP
    s = summarize(result_to_dataset(result, case))
    assert s["separations"] == 1
    assert math.degrees(s["separation_times_s"][0] * case.run.speed_a) == pytest.approx(9.0, abs=0.04)
    result.gap[early] = 2.0 * SEPARATION_GAP
    assert summarize(result_to_dataset(result, case))["separations"] == 2


def test_csv_as_a_csv_writer_writes_it(tmp_path):
    """The CSV, built at once, holds what csv.writer wrote row by row, to the byte."""
    import csv

    from spurdyn.results.io import write_csv

    values = np.array([0.0, -0.0, 1e-300, 123456789.123, np.nan, np.inf, -np.inf, 2.5e-8])
    ds = xr.Dataset({"angle_deg": ("time", values[::-1]), "contact_force": ("time", values)},
                    coords={"time": values * 3.0})
    write_csv(ds, tmp_path / "fast.csv")
    with open(tmp_path / "rows.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["angle_deg", "time_s", "contact_force_N"])
        for a, t, f in zip(ds["angle_deg"].values, ds["time"].values, ds["contact_force"].values):
            w.writerow([f"{a:.9g}", f"{t:.9g}", f"{f:.9g}"])
    assert (tmp_path / "fast.csv").read_bytes() == (tmp_path / "rows.csv").read_bytes()
