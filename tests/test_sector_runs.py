"""The sector model's runs through the command and the API (docs/sector.md, section 6): the
command's files, the bodies' damping, a case file's model, a continuation, a sweep's
continuation, the compiled loop against the NumPy loop, and a run going on until it settles
(split from test_sector_dynamics.py, which keeps the model's pieces and balances)."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.geometry.presets import paper_pair
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.run import simulate_sector

PAIR = paper_pair()
MESH = dict(nx=2, ny=8)
#: The bodies without their default structural damping (the checks of the undamped
#: equations and of the mesh damper alone).
UNDAMPED = dict(rayleigh_mass=0.0, rayleigh_stiffness=0.0)


@pytest.mark.slow
def test_spurdyn_run_model_sector_writes_the_pairs_and_the_transmission_error(tmp_path, capsys):
    from spurdyn.cli.main import main

    out = tmp_path / "run"
    code = main(["run", "paper-fig8", "--model", "sector", "--cycles", "1", "--mesh", "2x8",
                 "--out", str(out), "--quiet"])
    assert code == 0
    ds = xr.open_dataset(out / "result.nc")
    assert {"pair_force", "mesh_force", "load_share", "pair_roll_deg", "transmission_error"} <= set(ds)
    assert ds["transmission_error"].attrs["units"] == "m"
    share = ds["load_share"].values
    touching = ds["mesh_force"].values > 0
    np.testing.assert_allclose(np.nansum(share[touching], axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(ds["mesh_force"].values, ds["pair_force"].values.sum(axis=1))
    summary = json.loads((out / "summary.json").read_text())
    assert summary["model"] == "sector" and summary["cycles"] == 1
    assert summary["integrator"] == "implicit" and summary["contact"] == "hertz"
    assert summary["dt_s"] == pytest.approx(ds.time.values[1] - ds.time.values[0])
    assert summary["dynamic_factor"] is not None and summary["mesh_stiffness_mean_N_per_m"] > 0
    assert (out / "mesh.png").stat().st_size > 10_000       # the pairs' picture beside the force's
    for name in ("mesh_cycle.png", "transmission_error.png"):     # the last mesh cycle's
        assert (out / name).stat().st_size > 10_000
    # the quasi-static cycle kept beside the run: the run starts in its first position's equilibrium
    static = ds["static_pair_force"].values[0]
    np.testing.assert_allclose(ds["pair_force"].sel(pair=list(range(static.size))).values[0], static,
                               rtol=1e-6)
    assert ds["static_transmission_error"].values[0] == pytest.approx(ds["transmission_error"].values[0],
                                                                      rel=1e-6)
    # no Rayleigh damping given: the bodies' default, and the summary says whose it was
    from spurdyn.solvers.sector.run import BODY_DAMPING_FREQUENCY, BODY_DAMPING_RATIO

    assert summary["body_damping"]["source"] == "model default"
    assert summary["body_damping"]["rayleigh_mass"] == 0.0
    assert summary["body_damping"]["rayleigh_stiffness"] * math.pi * BODY_DAMPING_FREQUENCY == pytest.approx(BODY_DAMPING_RATIO)
    ds.close()


def test_the_bodies_damping_is_the_models_default_unless_given_and_zero_is_none(tmp_path):
    """A run that gives no Rayleigh damping runs the sector bodies with
    ``BODY_DAMPING_RATIO`` at ``BODY_DAMPING_FREQUENCY``; one that gives 0 runs them undamped, and
    a case file keeps the difference through its round trip (0 is written, nothing is not)."""
    from spurdyn.case import case_from_dict, case_to_dict, preset_case
    from spurdyn.solvers.sector.run import BODY_DAMPING_FREQUENCY, BODY_DAMPING_RATIO, body_rayleigh

    s = run_settings(PAIR, 1000 * RPM, 60.0, model="sector", cycles=1)
    a, b = body_rayleigh(s)
    assert a == 0.0 and b * 2 * math.pi * BODY_DAMPING_FREQUENCY / 2 == pytest.approx(BODY_DAMPING_RATIO)
    assert s.rayleigh == (0.0, 0.0) and not s.damped         # the paper model's: none
    assert body_rayleigh(s.with_(**UNDAMPED)) == (0.0, 0.0)
    assert body_rayleigh(s.with_(rayleigh_mass=3.0)) == (3.0, 0.0)
    case = preset_case("paper-fig8")
    assert case.run.rayleigh_mass is None
    # a sector sweep's points say which bodies' damping they ran with; the others' hash is as before
    from spurdyn.sweep.spec import settings_hash

    assert settings_hash(case, None, "sector") != settings_hash(case)
    assert settings_hash(case, None, "lumped") == settings_hash(case)
    # the mesh damper's default is in a sector point's hash: 0 given is another point
    zero = dataclasses.replace(case, run=case.run.with_(damping_ratio=0.0))
    assert settings_hash(zero, None, "sector") != settings_hash(case, None, "sector")
    for run in (case.run, case.run.with_(**UNDAMPED)):
        back = case_from_dict(case_to_dict(dataclasses.replace(case, run=run)))
        assert (back.run.rayleigh_mass, back.run.rayleigh_stiffness) == (run.rayleigh_mass, run.rayleigh_stiffness)


def test_a_case_file_asks_for_its_model_and_the_flag_overrides_it(tmp_path):
    """``[model] kind`` picks the model of a case file (``--model`` wins), survives the round
    trip through the stored case, and a bad kind or key is refused in one line naming it."""
    from spurdyn.case import case_from_dict, case_to_dict, load_case
    from spurdyn.cli.main import main, model_of
    from spurdyn.errors import InputError
    from spurdyn.settings import MODEL_NAMES
    from spurdyn.simulators import MODELS

    assert tuple(MODELS) == MODEL_NAMES
    text = (Path(__file__).resolve().parents[1] / "examples" / "pinion_23_47.toml").read_text()
    path = tmp_path / "mine.toml"
    path.write_text(text + '\n[model]\nkind = "sector"\n')
    case = load_case(path)
    assert case.model == "sector" and model_of([case], None) == "sector"
    assert model_of([case], "lumped") == "lumped"
    assert case_from_dict(case_to_dict(case)).model == "sector"
    assert load_case(path, {"model.kind": "fe"}).model == "fe"
    for extra, field in (('\n[model]\nkind = "rigid"\n', "model.kind"), ('\n[model]\nkinds = "fe"\n', "model")):
        path.write_text(text + extra)
        with pytest.raises(InputError) as err:
            load_case(path)
        assert err.value.field.startswith(field)
    path.write_text(text + '\n[model]\nkind = "rigid"\n')
    assert main(["run", str(path), "--out", str(tmp_path / "no")]) == 2
    assert not (tmp_path / "no").exists()


def test_a_bare_case_runs_the_sector_model_and_the_presets_the_papers():
    """Issue 35: a case file (or a Python run) that names no model gets the sector model with
    its cycles and mesh damper; the paper's presets keep the paper's model; a case's model
    survives its round trip whichever it is; 0 damping given is not the default."""
    from spurdyn.case import case_from_dict, case_to_dict, load_case, preset_case
    from spurdyn.sector.rules import DEFAULT_CYCLES, MESH_DAMPING_RATIO, mesh_damping
    from spurdyn.simulators import MODELS

    root = Path(__file__).resolve().parents[1] / "examples"
    bare, paper = load_case(root / "pinion_23_47.toml"), preset_case("paper-fig8")
    assert (bare.model, paper.model, load_case(root / "paper_fig8.toml").model) == ("sector", "fe", "fe")
    for case in (bare, paper):
        assert case_from_dict(case_to_dict(case)).model == case.model
    assert bare.run.damping_ratio is None and bare.run.cycles is None
    run = MODELS["sector"].with_defaults(bare.run)
    assert run.cycles == DEFAULT_CYCLES and MODELS["fe"].with_defaults(paper.run) == paper.run
    assert mesh_damping(run) == (MESH_DAMPING_RATIO, "model default")
    assert mesh_damping(run.with_(damping_ratio=0.0)) == (0.0, "run")
    assert run.mesh_damping == 0.0 and not run.damped   # the FE and lumped models': none
    assert case_from_dict(case_to_dict(bare)).run.damping_ratio is None
    zero = bare.run.with_(damping_ratio=0.0)
    assert case_from_dict(case_to_dict(dataclasses.replace(bare, run=zero))).run.damping_ratio == 0.0


@pytest.mark.slow
def test_a_run_continued_from_anothers_end_is_the_long_runs_second_half():
    """Three cycles, then three more from their end state (a continuation's next speed, here
    the same one): the pair forces and the transmission error are those of one run of six
    cycles over its last three, the teeth numbered on by three, but for the continuation's
    reset of the pair's common rotation to its speed (the long run's had drifted by 7e-6 of
    it through its corner contacts: 0.094 % of the largest force where a pair enters and 9e-5
    of the transmission error measured, asserted within 0.2 % and 2e-4); and at twice the
    speed the continued run starts with the end state's shape, its rates scaled."""
    from spurdyn.sector.state import unpack_state

    s3 = run_settings(PAIR, 4000 * RPM, 22.25, model="sector", cycles=3, max_cycles=3, damping_ratio=0.05, **MESH)
    first = simulate_sector(PAIR, s3)
    end = first.info["sector_end_state"]
    again = simulate_sector(PAIR, s3.with_(start_state=end))
    whole = simulate_sector(PAIR, s3.with_(cycles=6, max_cycles=6))
    assert again.info["tooth_offset"] == -3
    # the end state is a continuation's, kept in memory: not in result.nc
    from spurdyn.case import Case
    from spurdyn.results.io import result_to_dataset

    ds = result_to_dataset(first, Case(name="c", pair=PAIR, run=s3, model="sector"))
    assert "sector_end_state" not in ds.attrs["info"] and "tooth_offset" in ds.attrs["info"]
    n = again.steps
    half = whole.steps - n
    scale = np.nanmax(whole.pair_force)
    assert 0.0 < abs(again.info["common_rotation_reset"]) < 1e-4
    np.testing.assert_allclose(np.nansum(again.pair_force, axis=1), np.nansum(whole.pair_force[half:], axis=1),
                               rtol=0, atol=2e-3 * scale)
    np.testing.assert_allclose(again.transmission_error, whole.transmission_error[half:], rtol=0,
                               atol=2e-4 * np.abs(whole.transmission_error).max())
    # at another speed the state's shape carries over, the transmission error's rate scales with
    # the speed, and the pair's common rotation is that speed's (docs/sector.md, 6.5)
    fast = simulate_sector(PAIR, s3.with_(speed_a=2 * s3.speed_a, speed_b=2 * s3.speed_b, start_state=end))
    dq = unpack_state(end, fast.info["coordinates"]).dq
    ra, rb, drn = PAIR.gear_a.base_radius, PAIR.gear_b.base_radius, fast.info["modes"][0] + 1
    w = fast.omega[0]
    assert ra * w[0] - rb * w[1] == pytest.approx(2 * s3.speed_a * (ra * dq[0] - rb * dq[drn]), rel=1e-9)
    assert fast.transmission_error[0] == pytest.approx(first.transmission_error[-1], rel=1e-9)
    # an end whose gears turn 2 % too fast together (a chain's points carried such errors on):
    # the run turns at its own speed all the same, its three cycles three pitches to within
    # the transmission error (2 % would be 0.06 pitch), and its end is numbered on by three
    from spurdyn.sector.state import pack_state

    st = unpack_state(end, fast.info["coordinates"])
    dq = st.dq.copy()
    dq[[0, drn]] *= 1.02
    off = simulate_sector(PAIR, s3.with_(start_state=pack_state(st._replace(dq=dq))))
    pitch = 2 * math.pi / PAIR.gear_a.teeth
    assert abs(off.theta[-1, 0] - off.theta[0, 0] - 3 * pitch) < 1e-3 * pitch
    assert unpack_state(off.info["sector_end_state"], fast.info["coordinates"]).offset == -6
    # an end a whole pitch further on: the run's own end is numbered on by the four pitches
    # its driver turned from there, not by its three cycles
    ahead = st.q.copy()
    ahead[0] += pitch
    ahead[drn] += 2 * math.pi / PAIR.gear_b.teeth
    on = simulate_sector(PAIR, s3.with_(start_state=pack_state(st._replace(q=ahead))))
    assert on.status == "complete"
    assert unpack_state(on.info["sector_end_state"], fast.info["coordinates"]).offset == -7
    # a state of other bodies, or on a sector, is refused in one line naming the key
    from spurdyn.errors import InputError

    with pytest.raises(InputError) as err:
        simulate_sector(PAIR, s3.with_(start_state=end[:1] + (3.0,) + end[2:]))
    assert err.value.field == "start_state"
    with pytest.raises(InputError):
        simulate_sector(PAIR, s3.with_(cycles=1, max_cycles=1, start_state=end))


@pytest.mark.slow
def test_a_sector_sweep_carries_each_speeds_end_to_the_next(tmp_path, capsys):
    """``spurdyn sweep --model sector --continuation up``: the chain's first point is the
    point a sweep without continuation computes; the next starts from its end (and so
    differs from a start at the static equilibrium); each gear's largest root stress is the
    one ``spurdyn run`` of the point reports; fewer than three cycles (a sector rather than
    whole gears) are refused in one line."""
    from spurdyn.cli.main import main

    common = ["sweep", "paper-fig8", "--model", "sector", "--cycles", "3", "--max-cycles", "3", "--damping", "0.05",
              "--mesh", "2x8", "--rpm", "4000,5000", "--quiet"]
    assert main(common + ["--continuation", "up", "--out", str(tmp_path / "up")]) == 0
    assert main(common + ["--jobs", "1", "--out", str(tmp_path / "alone")]) == 0
    up = xr.open_dataset(tmp_path / "up" / "sweep.nc").sel(model="sector")
    alone = xr.open_dataset(tmp_path / "alone" / "sweep.nc").sel(model="sector")
    assert float(up.peak_force.sel(rpm=4000)) == pytest.approx(float(alone.peak_force.sel(rpm=4000)), rel=1e-6)
    assert abs(float(up.peak_force.sel(rpm=5000)) / float(alone.peak_force.sel(rpm=5000)) - 1) > 1e-4
    # each gear's largest root stress is the one `spurdyn run` of the same point reports
    assert main(["run", "paper-fig8", "--model", "sector", "--cycles", "3", "--max-cycles", "3", "--damping", "0.05",
                 "--mesh", "2x8", "--speed-a", "4000", "--quiet", "--out", str(tmp_path / "run")]) == 0
    run_max = json.loads((tmp_path / "run" / "summary.json").read_text())["root_stress_max_Pa"]
    swept = [float(alone[f"root_stress_max_{g}"].sel(rpm=4000)) for g in "ab"]
    assert swept == pytest.approx(run_max, rel=1e-12) and min(swept) > 0
    capsys.readouterr()
    assert main(["sweep", "paper-fig8", "--model", "sector", "--cycles", "2", "--mesh", "2x8",
                 "--rpm", "4000,5000", "--continuation", "up", "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("spurdyn: error: --continuation:") and err.count("\n") == 1
    assert not (tmp_path / "bad").exists()


@pytest.mark.slow
def test_the_compiled_loop_is_the_numpy_loops_twin():
    """Modal bodies of whole gears step in the compiled loop (``backend = "numba"``, the
    default; docs/sector.md 6.3): pair forces, transmission error, gaps and hubs against the
    NumPy loop to round-off, through engagements, exits and the mesh damper; and the end
    state a continuation starts from is the same."""
    s = run_settings(PAIR, 4000 * RPM, 22.25, model="sector", cycles=3, max_cycles=3, damping_ratio=0.05, **MESH)
    fast = simulate_sector(PAIR, s)
    ref = simulate_sector(PAIR, s.with_(backend="numpy"))
    assert fast.status == ref.status == "complete"
    fa, fr = np.nan_to_num(fast.pair_force), np.nan_to_num(ref.pair_force)
    assert (fr > 0).sum(axis=1).max() >= 2 and (fr[1:] > 0).sum() < (fr > 0).size   # shared, made and broken
    np.testing.assert_allclose(fa, fr, rtol=0, atol=1e-9 * fr.max())
    np.testing.assert_allclose(fast.transmission_error, ref.transmission_error, rtol=0,
                               atol=1e-9 * np.abs(ref.transmission_error).max())
    np.testing.assert_allclose(fast.gap, ref.gap, rtol=0, atol=1e-15, equal_nan=True)
    np.testing.assert_allclose(fast.omega, ref.omega, rtol=1e-12)
    np.testing.assert_allclose(fast.info["sector_end_state"], ref.info["sector_end_state"], rtol=1e-6, atol=1e-12)


@pytest.mark.slow
def test_a_run_not_settled_goes_on_a_cycle_at_a_time_until_it_settles():
    """``max_cycles``: a run not settled after its cycles goes on, one cycle at a time, and
    stops at the first cycle end where the settled test holds. So it is the run asked for
    exactly those cycles (the same arrays, to the bit), the run of one cycle fewer has not
    settled, and by default it may go on to ``SETTLE_CYCLES_FACTOR`` times its cycles."""
    from spurdyn.settings import SETTLE_CYCLES_FACTOR

    s = run_settings(PAIR, 6000 * RPM, 22.25, cycles=3, model="sector", max_cycles=12, damping_ratio=0.1, **MESH)
    run = simulate_sector(PAIR, s)
    st = run.info["steady"]
    done = st["cycles_done"]
    assert st["settled"] and 3 < done < 12 and st["cycles"] == 3 and st["max_cycles"] == 12
    exact = simulate_sector(PAIR, s.with_(cycles=done, max_cycles=done))
    for name in ("pair_force", "transmission_error", "theta", "omega", "time"):
        np.testing.assert_array_equal(getattr(run, name), getattr(exact, name))
    assert run.info["sector_end_state"] == exact.info["sector_end_state"]
    short = simulate_sector(PAIR, s.with_(cycles=done - 1, max_cycles=done - 1))
    assert not short.info["steady"]["settled"]
    assert simulate_sector(PAIR, s.with_(cycles=done - 1, max_cycles=None)).info["steady"]["max_cycles"] == \
        SETTLE_CYCLES_FACTOR * (done - 1)
