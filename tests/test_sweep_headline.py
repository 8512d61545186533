"""A sweep's dynamic factor is the 10-us-averaged force's, as ``spurdyn run``'s: points
stopped early have none (NaN, their status, a hollow mark in the picture), and files from
before the change (whose ``dynamic_factor`` was the raw peak's) are not mixed in."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.figure import Figure

from spurdyn.case import preset_case
from spurdyn.sweep.backends import SerialBackend
from spurdyn.sweep.plot import draw_dynamic_factor
from spurdyn.sweep.point import FIGURES, PointOutcome, run_point
from spurdyn.sweep.runner import run_sweep
from spurdyn.sweep.spec import PointKey, SweepPlan
from spurdyn.sweep.store import (STATUS_CODES, combine, model_datasets, point_path,
                                 point_record, read_point, sweep_dataset, sweep_file,
                                 write_dataset)

RPMS = (6000.0, 12000.0, 18000.0)


@pytest.fixture(scope="module")
def case():
    return preset_case("paper-fig8")


def _plan(case, out: Path, model: str = "lumped") -> SweepPlan:
    return SweepPlan(case=case, model=model, rpms=RPMS, torques=None, out=out)


def _figures(factor: float | None, raw: float | None) -> dict:
    return {name: None for name in FIGURES} | {
        "peak_force": 600.0, "dynamic_factor": factor, "peak_force_raw": 700.0,
        "dynamic_factor_raw": raw, "static_force": 532.7, "steps": 10, "separations": 0}


def test_the_picture_shows_a_run_stopped_early_as_missing(case, tmp_path):
    plan = _plan(case, tmp_path)
    keys = plan.keys()
    records = {
        keys[0]: point_record(PointOutcome(keys[0], "complete", "", _figures(1.1, 1.3))),
        # a stale factor on a point stopped early is not drawn either
        keys[1]: point_record(PointOutcome(keys[1], "incomplete", "did not converge",
                                           _figures(1.5, 1.9))),
        keys[2]: point_record(PointOutcome(keys[2], "complete", "", _figures(1.2, 1.4))),
    }
    ds = sweep_dataset(plan, records)
    assert ds["status"].values.tolist() == [0, STATUS_CODES["incomplete"], 0]
    fig = Figure()
    ax = fig.subplots()
    draw_dynamic_factor(ax, {"lumped": ds}, None)
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    curve = np.asarray(lines["lumped (two disks, mesh spring)"].get_ydata(), float)
    assert curve[0] == 1.1 and math.isnan(curve[1]) and curve[2] == 1.2   # a gap
    hollow = lines["lumped: run stopped early (no factor)"]
    assert list(hollow.get_xdata()) == [12000.0] and hollow.get_markerfacecolor() == "white"
    assert list(hollow.get_ydata()) == [0.0]        # along the bottom, not at a factor
    assert "10-µs average" in ax.get_ylabel()


def _old_format(path: Path) -> None:
    """Make a point file look as it did when dynamic_factor was the raw peak's."""
    record = json.loads(path.read_text())
    record["peak_force_smoothed"] = record.pop("peak_force")
    record["dynamic_factor_smoothed"] = record.pop("dynamic_factor")
    record["peak_force"] = record.pop("peak_force_raw")
    record["dynamic_factor"] = record.pop("dynamic_factor_raw")
    path.write_text(json.dumps(record))


def test_points_and_sweeps_from_before_are_not_mixed_in(case, tmp_path):
    out = tmp_path / "sw"
    plan = _plan(case, out)
    done: list[float] = []

    def counted(task):
        done.append(task.key.rpm)
        return run_point(task)

    first = run_sweep(plan, SerialBackend(), progress=False, point_fn=counted)
    assert first.all_complete and sorted(done) == list(RPMS)
    key = plan.keys()[1]
    _old_format(point_path(out, key))
    assert read_point(out, key) is None            # not a result of today's figures
    done.clear()
    again = run_sweep(plan, SerialBackend(), progress=False, point_fn=counted)
    assert done == [12000.0] and again.all_complete
    assert read_point(out, key)["dynamic_factor_raw"] is not None
    np.testing.assert_allclose(again.dataset["dynamic_factor"].values,
                               first.dataset["dynamic_factor"].values, rtol=1e-12)
    # an FE sweep file written before the change is left out of sweep.nc, not combined
    old = first.dataset.drop_vars(["peak_force_raw", "dynamic_factor_raw"])
    old.attrs["model"] = "fe"
    write_dataset(old, out / sweep_file("fe"))
    assert list(model_datasets(out)) == ["lumped"]
    assert combine(model_datasets(out))["model"].values.tolist() == ["lumped"]
    # a failed point's record is read as before (it is computed again anyway)
    failed = PointKey("lumped", 1000.0, 22.25, plan.settings)
    path = point_path(out, failed)
    path.write_text(json.dumps({**failed.as_dict(), "status": "failed", "reason": "x"}))
    assert read_point(out, failed)["status"] == "failed"


def test_sweep_files_say_what_the_factor_is(case, tmp_path):
    ds = sweep_dataset(_plan(case, tmp_path), {})
    assert ds.attrs["averaging_window_s"] == 10e-6
    assert "averaged over a centred 10 us" in ds.attrs["dynamic_factor_note"]
    assert "NaN where the run stopped early" in ds.attrs["dynamic_factor_note"]
    assert "no dynamic factor" in ds["status"].attrs["legend"]
    assert "10 us" in ds["peak_force"].attrs["long_name"]
    write_dataset(ds, tmp_path / "s.nc")
    with xr.open_dataset(tmp_path / "s.nc", engine="netcdf4") as back:
        assert back.attrs["averaging_window_s"] == 10e-6
