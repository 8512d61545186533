"""Shared by the tests of ``spurdyn run`` and its kin (test_cli_run, test_cli_run_guards,
test_unattended): the command run in-process, the synthetic solver put in the real one's
place, an empty working folder, and what a run folder must hold."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.cli import run as runner
from spurdyn.cli.main import main
from spurdyn.results.headline import AVERAGING_WINDOW_S, moving_average
from spurdyn.results.keys import allowed, required, run_conditions
from run_helpers import PNG_MAGIC, fake_simulate

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PAPER_TOML = (EXAMPLES / "paper_fig8.toml").read_text()
FILES = ("result.nc", "contact_force.csv", "contact_force.png", "summary.json")
SHORT = ["--angle", "0.3"]  # paper-fig9 speeds: 84 steps of 3e-8 s


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def fake(monkeypatch):
    """Use the synthetic solver; returns a dict to set its keyword arguments."""
    options: dict = {}

    def simulate(pair, case, progress=None):
        return fake_simulate(pair, case, progress, **options)

    monkeypatch.setattr(runner, "load_simulate", lambda model="fe": simulate)
    return options


@pytest.fixture
def here(tmp_path, monkeypatch):
    """Run in an empty folder (so the default out/<case> lands there)."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if ".partial-" in p.name or ".old-" in p.name)


def check_run_folder(d: Path) -> tuple[xr.Dataset, dict]:
    """Everything a run leaves, and summary.json agreeing with result.nc."""
    for name in FILES:
        assert (d / name).is_file(), name
    assert (d / "contact_force.png").read_bytes()[:8] == PNG_MAGIC
    with xr.open_dataset(d / "result.nc", engine="netcdf4") as ds:
        ds = ds.load()
    summary = json.loads((d / "summary.json").read_text())
    force = ds["contact_force"].values
    assert summary["case"] == ds.attrs["case_name"]
    assert summary["status"] == ds.attrs["status"] and summary["reason"] == ds.attrs["reason"]
    assert summary["steps"] == ds.attrs["steps"] and summary["samples"] == ds.sizes["time"]
    model = summary.get("model", "fe")
    met = _conditions(ds, summary)
    assert set(required(model, met)) <= set(summary) <= set(allowed(model, met))
    if model != "lumped":    # the lumped model's integrator steps adaptively: no dt_s
        assert summary["dt_s"] == ds.attrs["dt_s"] == json.loads(ds.attrs["case"])["run"]["dt"]
    assert summary["n_dof"] == ds.attrs["n_dof"] > 0
    if np.nanmax(force) > 0:  # the headline peak is the averaged force's, the raw one beside
        averaged = np.nanmax(moving_average(ds["time"].values, force))
        assert summary["peak_force_N"] == pytest.approx(averaged, rel=1e-12)
        assert summary["peak_force_raw_N"] == pytest.approx(np.nanmax(force))
        assert summary["peak_force_raw_N"] >= averaged
    else:  # no contact, no peak
        assert summary["peak_force_N"] is None and summary["dynamic_factor"] is None
        assert summary["peak_force_raw_N"] is None and summary["dynamic_factor_raw"] is None
    assert summary["static_force_N"] == pytest.approx(ds.attrs["static_force_N"])
    assert summary["averaging_window_s"] == AVERAGING_WINDOW_S and summary["dynamic_factor_note"]
    if summary["status"] == "complete" and summary["peak_force_N"] is not None:
        assert summary["dynamic_factor"] == pytest.approx(
            summary["peak_force_N"] / summary["static_force_N"])
        assert summary["dynamic_factor_raw"] == pytest.approx(
            summary["peak_force_raw_N"] / summary["static_force_N"])
    else:  # an incomplete run's largest force may be the spike that stopped it
        assert summary["dynamic_factor"] is None and summary["dynamic_factor_raw"] is None
        assert summary["dynamic_factor_note"].startswith("none:")
    assert summary["angle_deg"] == pytest.approx(ds["angle_deg"].values[-1])
    assert summary["time_s"] == pytest.approx(ds["time"].values[-1])
    stages = [s for s in ("displacement", "velocity", "acceleration") if f"residual_{s}" in ds]
    assert list(summary.get("iterations_mean", {})) == list(summary.get("residual_max", {})) == stages
    for stage in stages:
        assert summary["iterations_mean"][stage] == pytest.approx(
            ds[f"iterations_{stage}"].values[1:].mean())
        assert summary["residual_max"][stage] == pytest.approx(
            np.nanmax(ds[f"residual_{stage}"].values))
    contact = force > 0
    first = np.argmax(contact)
    losses = int(np.sum(contact[first:-1] & ~contact[first + 1:]))
    assert summary["separations"] in (losses, losses - 1)  # the tip leaving at the end
    rows = (d / "contact_force.csv").read_text().splitlines()
    assert rows[0] == "angle_deg,time_s,contact_force_N" and len(rows) == ds.sizes["time"] + 1
    return ds, summary


def _conditions(ds: xr.Dataset, summary: dict) -> frozenset[str]:
    """The conditions of :mod:`spurdyn.results.keys` the run in ``ds`` meets."""
    steady = "steady" in json.loads(ds.attrs["info"])
    return run_conditions(summary.get("model", "fe"), steady, "root_stress" in ds, json.loads(ds.attrs["case"]))


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True

