"""summary.json says only what is true of its model (issue 35): the list of keys of
spurdyn.results.keys, docs/summary.md generated from it, and each model's summary on a small
case holding exactly the keys the list gives it (and result.nc no zero arrays in place of
what a model does not compute)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.case import case_from_dict, case_to_dict, resolve_cases
from spurdyn.results import keys
from spurdyn.results.io import RESULT_FILE, write_run
from spurdyn.settings import MODEL_NAMES, RunSettings, setting_keys, settings_read_by
from spurdyn.simulators import MODELS

DOCS = Path(__file__).resolve().parents[1] / "docs" / "summary.md"
BEGIN, END = "<!-- generated: spurdyn.results.keys.markdown -->\n", "<!-- end generated -->"
SOLVER_VARIABLES = ("residual_displacement", "residual_velocity", "residual_acceleration",
                    "iterations_displacement", "iterations_velocity", "iterations_acceleration",
                    "corner")


def test_the_docs_table_is_the_list():
    text = DOCS.read_text()
    assert text.count(BEGIN) == 1 and text.count(END) == 1
    assert text.split(BEGIN)[1].split(END)[0] == keys.markdown()


def test_the_list_names_only_models_and_conditions_it_knows():
    names = [k.name for k in keys.KEYS]
    assert len(names) == len(set(names))
    assert set(keys.MODEL_CONDITIONS) == set(MODEL_NAMES)
    for k in keys.KEYS:
        assert k.unit and k.meaning and k.when, k.name
        assert set(k.when) <= set(MODEL_NAMES), k.name
        for conditions in k.when.values():
            assert set(conditions) <= set(keys.CONDITIONS), k.name
    # every model writes the headline; only the FE model its constraint iteration
    for name in ("peak_force_N", "dynamic_factor", "settings"):
        assert all(keys.BY_NAME[name].when[m] == () for m in MODEL_NAMES)
    assert set(keys.BY_NAME["iterations_mean"].when) == {"fe"}


def test_select_keeps_the_runs_keys_and_refuses_unknown_or_missing_ones():
    met = keys.run_conditions("sector", True, False, {})
    figures = {name: 1.0 for name in keys.required("sector", met)}
    assert list(keys.select(figures, "sector", met)) == list(figures)
    # a figure of one engagement is dropped from a steady state's summary
    assert "theta_s_deg" not in keys.select({**figures, "theta_s_deg": 21.0}, "sector", met)
    with pytest.raises(ValueError, match="not declared"):
        keys.select({**figures, "bogus_key": 0.0}, "sector", met)
    with pytest.raises(ValueError, match="misses"):
        keys.select({k: v for k, v in figures.items() if k != "cycles"}, "sector", met)


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_settings_lists_only_what_the_model_reads(model):
    case = resolve_cases("paper-fig8", {"run.damping_ratio": 0.05})[0]
    whole = case_to_dict(case)
    got = keys.settings_of(whole, model)
    reads = settings_read_by(model)
    owner = {key: f.name for f in dataclasses.fields(RunSettings) for key in setting_keys(f.name)}
    for table in ("run", "mesh"):
        for key in whole[table]:
            read = owner[f"{table}.{key}"] in reads
            assert (key in got[table]) == read, (model, table, key)
    assert got["gear_a"] == whole["gear_a"] and got["pair"] == whole["pair"]
    if model == "sector":   # the paper's run settings a sector run does not read
        assert not {"dt", "n_spline", "tol_disp", "max_iter", "accel_levels", "frames_every"} & set(got["run"])


def _with_strengths(case):
    """``case`` with ISO 6336-5's allowable stress numbers on gear A's material."""
    d = case_to_dict(case)
    d["gear_a"]["material"].update(sigma_flim=4.3e8, sigma_hlim=1.5e9)
    return dataclasses.replace(case_from_dict(d, check_step=False), name=case.name, model=case.model)


def _run(case, folder: Path) -> tuple[dict, xr.Dataset, frozenset]:
    """Run ``case`` on its model, write its folder; its summary, dataset and conditions."""
    result = MODELS[case.model](case.pair, case.run)
    folder.mkdir()
    summary = write_run(result, case, folder, png=False)
    with xr.open_dataset(folder / RESULT_FILE) as ds:
        ds = ds.load()
    info = json.loads(ds.attrs["info"])
    met = keys.run_conditions(case.model, "steady" in info, "root_stress" in ds,
                              json.loads(ds.attrs["case"]))
    assert json.loads((folder / "summary.json").read_text()) == summary
    return summary, ds, met


def _check_keys(summary: dict, model: str, met: frozenset) -> None:
    """Every required key present, nothing the list does not give the run."""
    have = set(summary)
    assert set(keys.required(model, met)) <= have, set(keys.required(model, met)) - have
    assert have <= set(keys.allowed(model, met)), have - set(keys.allowed(model, met))


def test_the_fe_models_summary(tmp_path):
    """The paper's FE model (NumPy backend, 0.3 deg of paper-fig9, tooth frames, strengths):
    its constraint iteration's three stages, the root stress of its frames, the safety
    factors; the implicit integrator's one stage (its Newton iteration)."""
    case = _with_strengths(resolve_cases("paper-fig9", {
        "run.angle_deg": 0.3, "run.frames_every": 20, "run.backend": "numpy"})[0])
    summary, ds, met = _run(case, tmp_path / "rk4")
    assert met == {keys.ENGAGEMENT, keys.ROOT_STRESS, keys.STRENGTHS}
    _check_keys(summary, "fe", met)
    assert set(summary) == set(keys.required("fe", met))     # no optional key on the FE model
    assert list(summary["iterations_mean"]) == ["displacement", "velocity", "acceleration"]
    assert summary["iterations_mean"]["velocity"] > 0 and all(v in ds for v in SOLVER_VARIABLES)
    assert summary["safety_root_model"][0] > 0 and summary["contact_pressure_max_Pa"] > 0
    implicit = resolve_cases("paper-fig9", {"run.angle_deg": 0.3, "run.integrator": "implicit",
                                            "run.backend": "numpy", "run.frames_every": 0})[0]
    summary, ds, met = _run(implicit, tmp_path / "implicit")
    _check_keys(summary, "fe", met)
    assert list(summary["iterations_mean"]) == list(summary["residual_max"]) == ["displacement"]
    assert summary["iterations_mean"]["displacement"] >= 1
    assert "residual_velocity" not in ds and "iterations_acceleration" not in ds and "corner" in ds
    assert "root_stress_max_Pa" not in summary and summary["frames"] == 0


def _no_solver_zeros(summary: dict, ds: xr.Dataset, strip: bool = False) -> None:
    """No constraint iteration, no contact point, no frames, no step of its own: absent; the
    strip's pressure and the model's own safety factors only where it has a ``strip``
    (the sector model) and strengths were given (none here)."""
    assert not set(SOLVER_VARIABLES) & set(ds)
    for name in ("iterations_mean", "residual_max", "frames", "safety_root_model", "safety_contact_model",
                 *(() if strip else ("contact_pressure_max_Pa",))):
        assert name not in summary, name


def test_the_lumped_models_summary_of_one_engagement_and_of_a_steady_state(tmp_path):
    base = resolve_cases("paper-fig8", {"run.save_every": 10})[0]
    one = _with_strengths(dataclasses.replace(base, model="lumped"))
    summary, ds, met = _run(one, tmp_path / "one")
    assert met == {keys.ENGAGEMENT, keys.STRENGTHS}
    _check_keys(summary, "lumped", met)
    _no_solver_zeros(summary, ds)
    assert "dt_s" not in summary and summary["safety_root_iso"][0] > 0
    assert summary["angle_target_deg"] == pytest.approx(summary["theta_s_deg"])
    steady = dataclasses.replace(base, model="lumped", run=base.run.with_(cycles=2, max_cycles=2))
    summary, ds, met = _run(steady, tmp_path / "steady")
    assert met == {keys.STEADY}
    _check_keys(summary, "lumped", met)
    _no_solver_zeros(summary, ds)
    for name in ("angle_target_deg", "theta_s_deg", "single_zone_deg", "mean_force_single_zone_N"):
        assert name not in summary and "angle_target_deg" not in ds.attrs
    _peaks_in_the_last_cycles(summary, ds)


def _peaks_in_the_last_cycles(summary: dict, ds: xr.Dataset) -> None:
    """A steady state's peaks are where its last cycles' are, not the whole run's."""
    lo = json.loads(ds.attrs["info"])["steady"]["window_s"][0]
    last = ds["time"].values >= lo - 1e-15
    angle, force = ds["angle_deg"].values, ds["contact_force"].values
    assert angle[last][0] <= summary["peak_angle_deg"] <= angle[-1]
    assert summary["peak_angle_raw_deg"] == angle[last][np.argmax(force[last])]


@pytest.mark.slow
def test_the_sector_models_summary(tmp_path):
    """The sector model on 2 x 8 teeth for one mesh cycle: a steady state, its back flanks
    and bodies' damping, no step of the paper's run settings in its settings."""
    base = resolve_cases("paper-fig8", {"mesh.nx": 2, "mesh.ny": 8})[0]
    case = dataclasses.replace(base, model="sector", run=base.run.with_(cycles=1))
    summary, ds, met = _run(case, tmp_path / "sector")
    assert met == {keys.STEADY}
    _check_keys(summary, "sector", met)
    _no_solver_zeros(summary, ds, strip=True)
    assert summary["contact_pressure_max_Pa"] > 0 and all(s > 0 for s in summary["root_stress_max_Pa"])
    assert summary["dt_s"] == pytest.approx(ds["time"].values[1] - ds["time"].values[0])
    assert "dt" not in summary["settings"]["run"] and summary["model"] == "sector"
    _peaks_in_the_last_cycles(summary, ds)
