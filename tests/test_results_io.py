"""What a run leaves on disk (result.nc, CSV, summary, pictures, ParaView) and reading it
back, on synthetic results shaped like the solver's (``fake_simulate``, also used by
``test_cli_run.py``)."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest
import xarray as xr

from spurdyn.case import case_from_dict, case_to_dict, load_case, preset_case, resolve_cases
from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.placement import mesh_angles, to_world_a, to_world_b
from spurdyn.mesh.tooth import tooth_mesh
from spurdyn.results.io import (CSV_FILE, PNG_FILE, RESULT_FILE, SUMMARY_FILE, case_from_run,
                                load_run, result_to_dataset, summarize, tooth_frames, write_run)
from spurdyn.result import STAGES, Result
from spurdyn.results.headline import moving_average
from spurdyn.settings import RunSettings

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


# -- a synthetic solver ----------------------------------------------------------------

def _rot(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def fake_simulate(pair: GearPair, case: RunSettings, progress=None, *, status: str = "complete",
                  reason: str = "", separations: tuple[tuple[float, float], ...] = (),
                  elastic: float = 2e-7, chunk: int = 20) -> Result:
    """A stand-in for ``spurdyn.solvers.loop.simulate`` with the same contract.

    Gear A turns at its initial speed; the force follows the torque schedule with a
    ripple and drops to zero in the windows ``separations`` (deg). Frames hold the rigid
    rotation of each tooth plus an elastic shear of amplitude ``elastic`` (m) at the tip.
    Ctrl-C in ``progress`` ends the run early with ``status = "incomplete"``.
    """
    total = pair.theta_s if case.angle is None else case.angle
    n = max(1, math.ceil(total / (case.speed_a * case.dt)))
    done = n
    try:
        for step in range(chunk, n + chunk, chunk):
            if progress is not None:
                progress(min(step, n), min(step, n) * case.speed_a * case.dt, total)
    except KeyboardInterrupt:
        done = min(step, n)
        status, reason = "incomplete", f"interrupted by the user at step {done}"
    steps = np.unique(np.append(np.arange(0, done + 1, case.save_every), done))
    t = steps * case.dt
    angle = case.speed_a * t
    deg = np.degrees(angle)
    static = case.torque / pair.gear_a.base_radius
    ramp = np.clip(np.minimum(angle, pair.theta_s - angle) / pair.theta_2, 0.0, 1.0)
    force = static * ramp * (1.0 + 0.1 * np.sin(40.0 * angle))
    for lo, hi in separations:
        force[(deg > lo) & (deg < hi)] = 0.0
    ratio = pair.gear_a.teeth / pair.gear_b.teeth
    theta = np.column_stack([angle, angle * ratio])
    it = np.tile([6, 4, 3], (len(t), 1)).astype(np.int64)
    it[0] = 0
    res = np.tile([1e-13, 1e-6, 1.0], (len(t), 1)) * (1.0 + np.arange(len(t)))[:, None]

    mesh_a = tooth_mesh(pair.gear_a, case.nx, case.ny)
    mesh_b = tooth_mesh(pair.gear_b, case.nx, case.ny)
    ta0, tb0 = mesh_angles(pair, pair.start_roll_a)
    c = (np.zeros(2), np.array([0.0, pair.centre_distance]))
    x0 = (to_world_a(mesh_a.nodes, ta0), to_world_b(mesh_b.nodes, tb0, pair.centre_distance))
    frame_steps = np.arange(0, done + 1, case.frames_every) if case.frames_every else np.zeros(0, int)
    frame_u = np.zeros((len(frame_steps), 2 * (mesh_a.n_nodes + mesh_b.n_nodes)))
    for k, s in enumerate(frame_steps):
        blocks = []
        for g, sign in ((0, -1.0), (1, 1.0)):
            a = s * case.dt * case.speed_a * (1.0 if g == 0 else ratio)
            rel = x0[g] - c[g]
            height = np.hypot(*rel.T) - np.hypot(*rel.T).min()
            shear = elastic * k / max(len(frame_steps) - 1, 1) * height / height.max()
            d = np.column_stack([shear, np.zeros_like(shear)])
            blocks.append((c[g] + (rel + d) @ _rot(sign * a).T - x0[g]).ravel())
        frame_u[k] = np.concatenate(blocks)
    return Result(
        time=t, angle=angle, contact_force=force, gap=np.where(force > 0, -force / 2e8, 1e-7),
        roll=np.column_stack([pair.start_roll_a + angle,
                              pair.roll_b_from_roll_a(pair.start_roll_a + angle)]),
        theta=theta, omega=np.column_stack([np.full_like(t, case.speed_a),
                                            np.full_like(t, case.speed_b)]),
        torque=np.column_stack([case.torque * ramp, case.torque * ramp / ratio]),
        residual=res, iterations=it, corner=np.zeros(len(t), np.int8),
        frame_time=frame_steps * case.dt, frame_theta=np.column_stack(
            [frame_steps * case.dt * case.speed_a, frame_steps * case.dt * case.speed_a * ratio])
        if len(frame_steps) else np.zeros((0, 2)),
        frame_u=frame_u, status=status, reason=reason, steps=int(done), wall_s=0.25,
        info={"n_dof": 2 * (mesh_a.n_nodes + mesh_b.n_nodes) + 2, "theta_s": pair.theta_s,
              "theta_2": pair.theta_2, "static_force": static,
              "single_zone": (pair.theta_2, pair.theta_s - pair.theta_2), "note": np.float64(1)},
    )


@pytest.fixture(scope="module")
def short_case():
    """paper-fig9 over 0.3 deg, every step kept, a frame every 10 steps."""
    return preset_case("paper-fig9", {"run.angle_deg": 0.3, "run.frames_every": 10},
                       check_step=False)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory, short_case):
    d = tmp_path_factory.mktemp("run")
    result = fake_simulate(short_case.pair, short_case.run, separations=((0.1, 0.12),))
    summary = write_run(result, short_case, d, vtu=True)
    return d, result, summary


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


# -- tooth frames, ParaView, GIF -------------------------------------------------------

def test_tooth_frames_recover_the_elastic_part(run_dir):
    d, _, _ = run_dir
    frames = tooth_frames(load_run(d))
    assert frames.n_frames >= 3
    # The first frame is the undeformed start: no elastic displacement, no stress.
    for g in (0, 1):
        assert np.abs(frames.elastic(g, 0)).max() < 1e-15
        assert frames.von_mises(g, 0).max() < 1e-3
    last = frames.n_frames - 1
    for g in (0, 1):
        e = frames.elastic(g, last)
        assert np.abs(e[:, 0]).max() == pytest.approx(2e-7, rel=1e-6)
        assert np.abs(e[:, 1]).max() < 1e-15
        assert frames.von_mises(g, last).max() > 1e3
        # Positions: the rigid rotation of the start, plus the elastic part.
        np.testing.assert_allclose(frames.positions(g, last, 1.0),
                                   frames.X0[g] + frames.u[g][last], atol=1e-15)


def test_vtu_series(run_dir):
    d, result, _ = run_dir
    root = ET.parse(d / "result.pvd").getroot()
    sets = root.findall("./Collection/DataSet")
    assert len(sets) == len(result.frame_time)
    assert float(sets[-1].get("timestep")) == pytest.approx(result.frame_time[-1])
    m = meshio.read(d / sets[-1].get("file"))
    assert m.cells[0].type == "quad8"
    assert {"displacement", "elastic_displacement"} <= set(m.point_data)
    assert {"von_mises", "gear"} <= set(m.cell_data)
    assert m.points.shape[1] == 3


@pytest.mark.slow
def test_animation_gif(tmp_path, run_dir):
    from spurdyn.results.animate import animate_run

    d, _, _ = run_dir
    gif = animate_run(load_run(d), tmp_path / "mesh.gif", max_frames=3, fps=5)
    assert gif.read_bytes()[:6] == b"GIF89a"


@pytest.fixture(scope="module")
def loaded_run(tmp_path_factory):
    """Fig. 8 through its first 9 degrees (the load is on), with a frame every 100 steps."""
    from spurdyn.case import resolve_cases
    from spurdyn.simulators import MODELS

    case = resolve_cases("paper-fig8", {"run.angle_deg": 9.0})[0]
    d = tmp_path_factory.mktemp("loaded")
    write_run(MODELS["fe"](case.pair, case.run), case, d)
    return load_run(d)


@pytest.mark.slow
def test_animation_scale_shows_the_fillet_and_the_view_follows_the_teeth(loaded_run):
    """The colour scale is set by the fillets (the contact's peak above it saturates), so
    the fillet elements spread over the scale instead of sitting in one flat colour; each
    frame's view is the box of that frame's teeth."""
    from spurdyn.results.animate import (FILLET_SCALE, _OUTLINE, fillet_elements, frame_view,
                                         stress_scale)
    from spurdyn.results.frames import tooth_frames

    frames = tooth_frames(loaded_run)
    meshes, pair = frames.meshes, frames.case.pair
    fillets = [fillet_elements(m.nodes, m.elements, np.concatenate([m.right_side, m.left_side]),
                               g.form_radius) for m, g in zip(meshes, (pair.gear_a, pair.gear_b))]
    for m, f in zip(meshes, fillets):     # both fillets, at the bottom of the tooth only
        assert 2 <= f.size < m.n_elements / 2
        assert np.hypot(*m.nodes[m.elements[f]].reshape(-1, 2).T).min() < pair.gear_a.form_radius
    stress = [[frames.von_mises(g, k) for g in (0, 1)] for k in range(frames.n_frames)]
    vmax = stress_scale(stress, fillets)
    peak_fillet = max(float(s[g][fillets[g]].max()) for s in stress for g in (0, 1))
    assert vmax == pytest.approx(FILLET_SCALE * peak_fillet)
    assert vmax < max(float(np.nanmax(s[g])) for s in stress for g in (0, 1))  # contact saturates
    k = int(np.argmax([max(s[0][fillets[0]].max(), s[1][fillets[1]].max()) for s in stress]))
    # the view of a frame holds its teeth and little more
    polys = [frames.positions(g, k)[meshes[g].elements[:, _OUTLINE]] for g in (0, 1)]
    (x0, x1), (y0, y1) = frame_view(polys)
    pts = np.concatenate([p.reshape(-1, 2) for p in polys])
    assert x0 < pts[:, 0].min() and pts[:, 0].max() < x1 and y0 < pts[:, 1].min() and pts[:, 1].max() < y1
    size = max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1]))
    assert max(x1 - x0, y1 - y0) < 1.1 * size


@pytest.mark.slow
def test_a_run_keeps_its_root_stress_and_iso_beside_it(loaded_run):
    from spurdyn.iso6336.rating import iso_pair, rate
    from spurdyn.results.frames import case_from_run

    ds = loaded_run
    assert ds["root_stress"].dims == ("frame", "gear") and ds["root_stress"].attrs["units"] == "Pa"
    hi = ds["root_stress"].values
    # the loaded fillet's stress follows the contact force of the frame (quasi-static run)
    force = np.interp(ds["frame_time"].values, ds["time"].values, ds["contact_force"].values)
    assert np.corrcoef(force, hi[:, 0])[0, 1] > 0.95
    assert np.all(ds["root_stress_compressive"].values <= hi)
    s = summarize(ds)
    assert s["root_stress_max_Pa"][0] == pytest.approx(float(np.nanmax(hi[:, 0])))
    case = case_from_run(ds)
    iso = rate(iso_pair(case.pair), case.run.torque)
    assert s["iso6336_sigma_F0_Pa"] == pytest.approx(list(iso.sigma_f0))
    assert s["iso6336_sigma_H0_Pa"] == pytest.approx(iso.sigma_h0)
    pos = s["root_stress_max_position_m"][0]
    assert case.pair.gear_a.root_radius < pos < case.pair.gear_a.form_radius


def test_stress_scale_without_fillet_stress_falls_back_to_the_largest():
    from spurdyn.results.animate import stress_scale

    zero = [np.zeros(4), np.zeros(4)]
    hot = [np.array([0.0, 0.0, 0.0, 7.0]), np.array([np.nan, 0.0, 2.0, 0.0])]
    fillets = [np.array([0, 1]), np.array([0, 1])]
    assert stress_scale([zero, hot], fillets) == 7.0
    assert stress_scale([zero], fillets) == 1.0


def test_overlay_picture(tmp_path, run_dir):
    from spurdyn.results.plots import plot_contact_force

    d, _, _ = run_dir
    png = plot_contact_force([load_run(d), load_run(d)], tmp_path / "two.png")
    assert png.read_bytes()[:8] == PNG_MAGIC


def test_picture_as_drawn_the_plain_way(tmp_path, run_dir):
    """The quicker layout (no layout engine left for savefig to run again; one run's
    legend, inside the axes, left out of it) gives the same picture, to the byte, as
    ``Figure.tight_layout`` with everything in the layout."""
    from matplotlib.figure import Figure

    from spurdyn.results import plots

    d, _, _ = run_dir
    runs = [load_run(d)]
    quick = plots.plot_contact_force(runs, tmp_path / "quick.png", title="t").read_bytes()
    fig = Figure(figsize=(8, 4.8), dpi=120)
    ax = fig.subplots()
    plots.draw_contact_force(ax, runs)
    ax.set_title("t", fontsize=10)
    fig.tight_layout()
    fig.savefig(tmp_path / "plain.png")
    assert (tmp_path / "plain.png").read_bytes() == quick


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


def test_prefetch_draws_a_picture_of_the_run_kind_and_leaves_nothing(tmp_path, monkeypatch):
    """The writers' warm-up (spurdyn.results.prefetch, a thread during the run) writes a
    NetCDF file and a picture like the run's, in a folder of its own that it removes."""
    import tempfile

    from spurdyn.results import prefetch

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    prefetch._load()
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_the_elastic_part_of_all_frames_at_once_is_each_frames(loaded_run):
    from spurdyn.results.frames import tooth_frames

    frames = tooth_frames(loaded_run)
    for g in (0, 1):
        every = frames.elastic_all(g)
        for k in (0, frames.n_frames // 2, frames.n_frames - 1):
            # a difference of positions ~0.05 m: round-off of a few 1e-17 m either way
            np.testing.assert_allclose(every[k], frames.elastic(g, k), rtol=0, atol=1e-16)
