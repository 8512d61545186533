"""``spurdyn run``, ``cases``, ``plot`` and ``animate`` end to end.

Most tests run the command with a synthetic solver (``fake``, see ``test_results_io.py``)
so that they test the run layer quickly. ``test_real_solver_short_run`` runs the real
``spurdyn.solvers.loop.simulate`` on a short case; it skips itself while the solver (or one
of its backends) is not importable.
"""

from __future__ import annotations

import io
import json
import math
import multiprocessing
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.case import resolve_cases
from spurdyn.cli import run as runner
from spurdyn.cli.main import main
from spurdyn.results.headline import AVERAGING_WINDOW_S, moving_average
from spurdyn.settings import METHODS, RPM
from test_results_io import PNG_MAGIC, fake_simulate

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
    for stage in ("displacement", "velocity", "acceleration"):
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


# -- end to end --------------------------------------------------------------------------

def test_run_preset_end_to_end(fake, here, capsys):
    code, out, err = run(capsys, "run", "paper-fig9", *SHORT)
    assert code == 0 and err == ""  # no progress bar in a pipe
    d = here / "out" / "paper-fig9"
    assert f"-> {Path('out') / 'paper-fig9'}" in out and out.count("\n") == 2
    assert f"plot: {Path('out') / 'paper-fig9' / 'contact_force.png'}" in out
    ds, summary = check_run_folder(d)
    assert summary["status"] == "complete" and ds.attrs["status"] == "complete"
    # the line's headline is the averaged peak and its factor, the raw peak beside it
    assert (f"peak {summary['peak_force_N']:,.1f} N = {summary['dynamic_factor']:.3f} x static "
            f"(10-us average; raw {summary['peak_force_raw_N']:,.1f} N)") in out
    assert summary["peak_force_N"] < summary["peak_force_raw_N"]   # the ripple is gone
    assert summary["speed_a_rpm"] == pytest.approx(20000.0)
    assert summary["steps"] == math.ceil(math.radians(0.3) / (20000 * 2 * math.pi / 60 * 3e-8))
    assert ds["time"].attrs["units"] == "s" and ds["contact_force"].attrs["units"] == "N"
    assert leftovers(d.parent) == []


def test_run_options_override_the_case(fake, here, capsys):
    code, out, err = run(capsys, "run", "paper-fig8", "--angle", "0.05", "--speed-a", "5000",
                       "--speed-b", "5050", "--torque", "10", "--dt", "2e-8", "--mesh", "3x10",
                       "--save-every", "3", "--frames-every", "7", "--method", METHODS[-1],
                       "--backend", "numpy", "--out", "custom", "--quiet")
    assert code == 0 and out == "", err
    ds = xr.load_dataset(here / "custom" / "result.nc", engine="netcdf4")
    case = json.loads(ds.attrs["case"])
    expected = {"speed_a_rpm": 5000.0, "speed_b_rpm": 5050.0, "torque": 10.0, "dt": 2e-8,
                "angle_deg": 0.05, "save_every": 3, "frames_every": 7, "method": METHODS[-1],
                "backend": "numpy"}
    for key, value in expected.items():
        assert case["run"][key] == pytest.approx(value) if isinstance(value, float) else \
            case["run"][key] == value, key
    assert case["mesh"] == {"nx": 3, "ny": 10, "grading": 1.0}
    assert ds.attrs["static_force_N"] == pytest.approx(10.0 / 0.0417692, rel=1e-4)


@pytest.mark.parametrize(("spec", "extra", "speed_b"), [
    ("paper-fig8", {}, 18000.0),                       # the preset's equal speeds
    ("paper-fig10", {}, 18180.0),                      # B 1 % fast, as in the preset
    ("paper-fig10", {"run.speed_b_rpm": 17000.0}, 17000.0),  # B's own speed wins
    (str(EXAMPLES / "pinion_23_47.toml"), {}, 18000.0 * 23 / 47),  # B meshes by default
])
def test_speed_a_alone_keeps_the_cases_ratio_of_speeds(spec, extra, speed_b):
    """``--speed-a`` alone scales the case's B as a sweep does (a steady run of a preset
    at 18,000 rpm with B left at 4,000 would start the gears 14,000 rpm apart)."""
    case = resolve_cases(spec, {"run.speed_a_rpm": 18000.0, **extra})[0]
    assert case.run.speed_a == pytest.approx(18000.0 * RPM)
    assert case.run.speed_b == pytest.approx(speed_b * RPM, rel=1e-12)


@pytest.mark.parametrize("example", ["paper_fig8.toml", "pinion_gear.toml"])
def test_run_example_files(fake, here, capsys, example):
    code, _, err = run(capsys, "run", EXAMPLES / example, "--angle", "0.05", "--quiet")
    assert code == 0, err
    ds, _ = check_run_folder(here / "out" / Path(example).stem)
    assert ds.attrs["case_name"] == Path(example).stem


def test_vtu_option(fake, here, capsys):
    code, _, _ = run(capsys, "run", "paper-fig9", *SHORT, "--frames-every", "40", "--vtu", "--quiet")
    d = here / "out" / "paper-fig9"
    assert code == 0 and (d / "result.pvd").is_file()
    assert len(list((d / "vtu").glob("frame_*.vtu"))) == 3  # steps 0, 40, 80 (+ the last)


@pytest.mark.slow
def test_plot_and_animate_commands(fake, here, capsys):
    run(capsys, "run", "paper-fig9", *SHORT, "--quiet")
    run(capsys, "run", "paper-fig11", *SHORT, "--quiet", "--frames-every", "0")
    code, out, _ = run(capsys, "plot", "out/paper-fig9", "out/paper-fig11", "--png", "both.png")
    assert code == 0 and (here / "both.png").read_bytes()[:8] == PNG_MAGIC and "both.png" in out
    code, _, _ = run(capsys, "animate", "out/paper-fig9", "--gif", "a.gif", "--max-frames", "3")
    assert code == 0 and (here / "a.gif").read_bytes()[:6] == b"GIF89a"
    for argv, field in ((["animate", "out/paper-fig11", "--gif", "b.gif"], "no tooth frames"),
                        (["animate", "out", "--gif", "b.gif"], "not a run folder"),
                        (["animate", "out/paper-fig9", "--gif", "b.png"], "--gif"),
                        (["plot", "out/nothing"], "not a run folder"),
                        (["plot", "out/paper-fig9", "--png", "x.jpg"], "--png"),
                        (["plot", "out/paper-fig11", "--stress"], "holds no root stress"),
                        (["plot", "out/paper-fig9", "out/paper-fig9", "--stress"], "--stress")):
        code, _, err = run(capsys, *argv)
        assert code == 2 and field in err and err.count("\n") == 1, argv
    assert not (here / "b.gif").exists() and not (here / "stress_history.png").exists()
    code, out, _ = run(capsys, "plot", "out/paper-fig9", "--stress")
    assert code == 0 and (here / "stress_history.png").read_bytes()[:8] == PNG_MAGIC


def test_cases_lists_presets(capsys):
    code, out, _ = run(capsys, "cases")
    lines = out.splitlines()
    assert code == 0 and len(lines) == 7
    for name, speeds in (("paper-fig8", "4,000/4,000"), ("paper-fig9", "20,000/20,000"),
                         ("paper-fig10", "4,000/4,040"), ("paper-fig11", "20,000/20,200"),
                         ("paper-fig10-bdrive", "4,000/4,040"), ("paper-fig11-bdrive", "20,000/20,200")):
        line = next(x for x in lines if x.startswith(name + " "))
        assert speeds in line and "22.25 N m" in line and "3e-08" in line
    assert lines[-1].startswith("paper-all")
    assert "B driving" in next(x for x in lines if x.startswith("paper-fig10-bdrive"))


def test_bdrive_preset_drives_with_b():
    from spurdyn.case import preset_case

    assert preset_case("paper-fig10-bdrive").pair.driver == "b"
    assert preset_case("paper-fig10").pair.driver == "a"


@pytest.mark.slow
def test_paper_all_sequential(fake, here, capsys):
    code, out, _ = run(capsys, "run", "paper-all", "--angle", "0.05", "--out", "all")
    assert code == 0 and out.count("complete") == 4
    for name in ("paper-fig8", "paper-fig9", "paper-fig10", "paper-fig11"):
        _, summary = check_run_folder(here / "all" / name)
        assert summary["case"] == name


@pytest.mark.slow
@pytest.mark.skipif(multiprocessing.get_start_method(allow_none=False) != "fork",
                    reason="the synthetic solver reaches the workers only when they fork")
def test_paper_all_jobs(fake, here, capsys):
    code, out, _ = run(capsys, "run", "paper-all", "--angle", "0.05", "--jobs", "2")
    assert code == 0 and out.count("complete") == 4
    speeds = {}
    for name in ("paper-fig8", "paper-fig9", "paper-fig10", "paper-fig11"):
        _, summary = check_run_folder(here / "out" / name)
        speeds[name] = summary["speed_b_rpm"]
    assert speeds == {"paper-fig8": 4000, "paper-fig9": 20000, "paper-fig10": 4040,
                      "paper-fig11": 20200}
    assert leftovers(here / "out") == []


# -- progress ----------------------------------------------------------------------------

class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_bar_on_a_terminal_only():
    tty = _Terminal()
    bar = runner.ProgressBar("paper-fig8", stream=tty)
    for step in (500, 1000):
        bar(step, math.radians(5.0 * step / 500), math.radians(21.06))
    bar.close()
    text = tty.getvalue()
    assert "paper-fig8" in text and "/21.06 deg" in text and "steps/s" in text
    pipe = io.StringIO()
    bar = runner.ProgressBar("paper-fig8", stream=pipe)
    bar(500, 0.1, 0.3)
    bar.close()
    assert pipe.getvalue() == ""
    quiet = _Terminal()
    bar = runner.ProgressBar("paper-fig8", enabled=False, stream=quiet)
    bar(500, 0.1, 0.3)
    assert quiet.getvalue() == ""


def test_progress_bar_starts_no_thread():
    """A thread left running would keep the picture from being drawn in a forked child
    (spurdyn.results.beside)."""
    import threading

    before = set(threading.enumerate())
    bar = runner.ProgressBar("paper-fig8", stream=_Terminal())
    bar(500, 0.1, 0.3)
    assert set(threading.enumerate()) <= before
    bar.close()


# -- nothing lost ------------------------------------------------------------------------

def test_overwrite_guard_and_force(fake, here, capsys):
    d = here / "out" / "paper-fig9"
    d.mkdir(parents=True)
    (d / "keep.txt").write_text("precious")
    code, out, err = run(capsys, "run", "paper-fig9", *SHORT)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("spurdyn: error: ") and "--force" in err
    assert sorted(p.name for p in d.iterdir()) == ["keep.txt"]
    code, _, _ = run(capsys, "run", "paper-fig9", *SHORT, "--force", "--quiet")
    assert code == 0 and not (d / "keep.txt").exists()
    check_run_folder(d)
    assert leftovers(d.parent) == []
    # An empty folder may be used without --force; a file may not.
    empty = here / "empty"
    empty.mkdir()
    assert run(capsys, "run", "paper-fig9", *SHORT, "--out", empty, "--quiet")[0] == 0
    (here / "file").write_text("x")
    code, _, err = run(capsys, "run", "paper-fig9", *SHORT, "--out", here / "file", "--force")
    assert code == 2 and "is a file" in err


def test_a_folder_filled_during_the_run_is_kept(fake, here, capsys, monkeypatch):
    """The folder was free when the run started but another run filled it meanwhile:
    without --force neither result is lost (the new one goes beside it, and says so);
    with --force it is replaced."""
    d = here / "out" / "paper-fig9"
    execute = runner.execute

    def fill_then_execute(plan, simulate, progress=True, quiet=False):
        def simulate_while_another_writes(pair, case, bar=None):
            d.mkdir(parents=True, exist_ok=True)
            (d / "other.txt").write_text("another run's result")
            return simulate(pair, case, bar)
        return execute(plan, simulate_while_another_writes, progress, quiet)

    monkeypatch.setattr(runner, "execute", fill_then_execute)
    code, out, err = run(capsys, "run", "paper-fig9", *SHORT)
    assert code == 0, err
    assert sorted(p.name for p in d.iterdir()) == ["other.txt"]
    moved = Path("out") / "paper-fig9-2"
    assert f"written to {moved} instead" in err and f"-> {moved}" in out
    check_run_folder(moved)
    code, _, err = run(capsys, "run", "paper-fig9", *SHORT, "--force", "--out", d)
    assert code == 0, err
    assert not (d / "other.txt").exists()
    check_run_folder(d)
    assert leftovers(here / "out") == []


def test_jobs_show_the_cases_finished_on_a_terminal_only():
    tty = _Terminal()
    bar = runner._cases_bar(4, True, tty)
    bar.update(1)
    bar.close()
    assert "cases finished" in tty.getvalue() and "1/4" in tty.getvalue()
    assert runner._cases_bar(4, True, io.StringIO()) is None   # a pipe
    assert runner._cases_bar(4, False, _Terminal()) is None    # --quiet


def test_interrupted_run_keeps_what_was_computed(fake, here, capsys, monkeypatch):
    calls = []

    def ctrl_c(self, step, angle, total):
        calls.append(step)
        if len(calls) == 2:  # Ctrl-C during the run: the solver returns what it has
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(runner.ProgressBar, "__call__", ctrl_c)
    code, out, err = run(capsys, "run", "paper-all", *SHORT, "--out", "all")
    assert code == 1 and out == ""
    d = here / "all" / "paper-fig8"
    ds, summary = check_run_folder(d)
    assert summary["status"] == "incomplete" == ds.attrs["status"]
    assert "interrupted" in summary["reason"] and summary["steps"] == 40
    assert ds.sizes["time"] == 41
    assert "paper-fig8 incomplete" in err and "kept in" in err
    # The other cases are not started after Ctrl-C.
    assert "paper-fig9 not run" in err and not (here / "all" / "paper-fig9").exists()
    assert leftovers(here / "all") == []


def test_non_convergence_is_incomplete(fake, here, capsys):
    fake.update(status="incomplete", reason="velocity stage did not converge in 500 iterations")
    code, out, err = run(capsys, "run", "paper-fig10", "--angle", "0.05")
    assert code == 1 and "did not converge" in err
    _, summary = check_run_folder(here / "out" / "paper-fig10")
    assert summary["status"] == "incomplete" and "converge" in summary["reason"]
    # stopped early: the line says so and gives no factor, final or not
    assert "stopped early: no dynamic factor" in err and "x static" not in out + err
    assert summary["peak_force_N"] is not None and summary["dynamic_factor"] is None
    assert "stopped early (velocity stage did not" in summary["dynamic_factor_note"]


def test_interrupt_escaping_the_solver_leaves_nothing(here, capsys, monkeypatch):
    def broken(pair, case, progress=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(runner, "load_simulate", lambda model="fe": broken)
    code, _, err = run(capsys, "run", "paper-fig9", *SHORT)
    assert code == 130 and "nothing written" in err
    assert list(here.iterdir()) == []


# -- bad input ---------------------------------------------------------------------------

BAD_ARGS = [
    (["paper-fig12"], "CASE: unknown case"),
    (["paper-fig8", "--dt", "4e-8"], "--dt: dt 4e-08 s is above the stable RK4 step"),
    (["paper-fig8", "--mesh", "8x28"], "--mesh: dt 3e-08 s is above the stable RK4 step"),
    (["paper-fig8", "--mesh", "8x28", "--dt", "5e-8"], "--dt:"),
    (["paper-fig8", "--angle", "25"], "--angle: 25 deg goes beyond the angle of action"),
    (["paper-fig8", "--angle", "-1"], "--angle: must be positive"),
    (["paper-fig8", "--angle", "1e-9"], "--angle: 1e-09 deg is shorter than one time step"),
    (["paper-fig8", "--speed-a", "-4000"], "--speed-a: must be positive"),
    (["paper-fig8", "--speed-b", "0"], "--speed-b: must be positive"),
    (["paper-fig8", "--torque", "-1"], "--torque: must not be negative"),
    (["paper-fig8", "--dt", "0"], "--dt: must be positive"),
    (["paper-fig8", "--dt", "nan"], "--dt: must be a finite number"),
    (["paper-fig8", "--dt", "fast"], "argument --dt"),
    (["paper-fig8", "--save-every", "0"], "--save-every: must be a whole number >= 1"),
    (["paper-fig8", "--mesh", "4by14"], "--mesh: must look like NXxNY"),
    (["paper-fig8", "--mesh", "0x14"], "--mesh: must be a whole number"),
    (["paper-fig8", "--mesh", "100x14"], "--mesh: nx must be a whole number from 1 to 64"),
    (["paper-fig8", "--method", "magic"], "--method: must be one of paper"),
    (["paper-fig8", "--backend", "cuda"], "--backend: must be one of numba, numpy"),
    (["paper-all", "--jobs", "0"], "--jobs: must be a whole number >= 1"),
    (["paper-fig9", "--vtu", "--frames-every", "0"], "--vtu: needs tooth frames"),
    (["paper-fig9", "--vtu", "--model", "lumped"], "--vtu: draws the FE teeth"),
    (["missing.toml"], "missing.toml: no such file"),
    ([str(EXAMPLES / "paper_pair.toml")], "run.speed_a_rpm: is missing"),
]


@pytest.mark.parametrize("argv, message", BAD_ARGS)
def test_bad_arguments_one_line_exit_2_nothing_written(fake, here, capsys, argv, message):
    code, out, err = run(capsys, "run", *argv)
    assert code == 2 and out == ""
    assert err.startswith("spurdyn: error: ") and err.count("\n") == 1
    assert message in err, err
    assert list(here.iterdir()) == []


BAD_TOML = [
    ("speed_a_rpm = 4000.0", "speed_a_rpm = \"fast\"", "run.speed_a_rpm: must be a number"),
    ("speed_a_rpm = 4000.0", "speed_a_rpm = -4000.0", "run.speed_a_rpm: must be positive"),
    ("torque = 22.25", "torque = -22.25", "run.torque: must not be negative"),
    ("dt = 3e-8  ", "dt = 4e-8  ", "run.dt: dt 4e-08 s is above the stable RK4 step"),
    ("# angle_deg = 21.06", "angle_deg = 40.0", "run.angle_deg: 40 deg goes beyond"),
    ("save_every = 1", "save_every = 0", "run.save_every"),
    ("method = \"paper\"", "method = \"fastest\"", "run.method: must be one of"),
    ("keep_theta_term = true", "keep_theta_term = \"yes\"", "run.keep_theta_term"),
    ("n_spline = 61", "n_spline = 61\nspline_points = 61", "run.spline_points: unknown key"),
    ("[run]", "[runs]", "runs: unknown key"),
    ("teeth = 28", "teeth = 4", "gear_a.teeth"),
    ("nx = 4", "nx = 0", "mesh.nx"),
    ("speed_a_rpm = 4000.0", "speed_a_rpm = [4000.0", "is not valid TOML"),
]


@pytest.mark.parametrize("old, new, message", BAD_TOML)
def test_bad_case_file_one_line_exit_2_nothing_written(fake, here, capsys, old, new, message):
    assert old in PAPER_TOML
    bad = here / "bad.toml"
    bad.write_text(PAPER_TOML.replace(old, new, 1))
    code, out, err = run(capsys, "run", bad)
    assert code == 2 and out == ""
    assert err.startswith("spurdyn: error: ") and err.count("\n") == 1
    assert message in err, err
    assert [p.name for p in here.iterdir()] == ["bad.toml"]


def test_console_script_refuses_without_traceback(tmp_path):
    for argv in (["run", "paper-fig12"], ["run", "paper-fig8", "--dt", "1e-7"], ["run"]):
        proc = subprocess.run([sys.executable, "-m", "spurdyn.cli.main", *argv], cwd=tmp_path,
                              capture_output=True, text=True)
        assert proc.returncode == 2, argv
        assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1
        assert proc.stderr.startswith("spurdyn: error: ")
    assert list(tmp_path.iterdir()) == []


# -- the real solver ---------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("backend, angle", [("numpy", "0.1"), ("numba", "0.3")])
def test_real_solver_short_run(here, capsys, backend, angle):
    code, out, err = run(capsys, "run", "paper-fig9", "--angle", angle, "--backend", backend,
                         "--frames-every", "20")
    assert code == 0, err
    ds, summary = check_run_folder(here / "out" / "paper-fig9")
    assert summary["status"] == "complete"
    assert summary["angle_deg"] >= float(angle)
    assert 0 < summary["peak_force_N"] < summary["static_force_N"]  # still in the ramp
    assert ds.sizes["frame"] >= 2
    code, _, _ = run(capsys, "animate", "out/paper-fig9", "--gif", "a.gif", "--max-frames", "3")
    assert code == 0


def test_real_solver_interrupted(here, capsys, monkeypatch):
    def ctrl_c(self, step, angle, total):
        os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(runner.ProgressBar, "__call__", ctrl_c)
    code, _, err = run(capsys, "run", "paper-fig9", "--angle", "0.1", "--backend", "numpy")
    assert code == 1 and "incomplete" in err
    ds, summary = check_run_folder(here / "out" / "paper-fig9")
    assert summary["status"] == "incomplete" and summary["reason"]


# -- the lumped model --------------------------------------------------------------------

def test_model_lumped_writes_a_run_folder(here, capsys):
    """``--model lumped`` runs the two-disk, one-spring model through the same run layer."""
    from spurdyn.case import preset_case
    from spurdyn.lumped import simulate_lumped
    from spurdyn.results.io import load_run

    code, out, err = run(capsys, "run", "paper-fig9", "--angle", "3", "--model", "lumped",
                         "--save-every", "10", "--out", "lumped")
    assert code == 0, err
    assert "lumped: complete" not in out and "paper-fig9: complete" in out
    ds, summary = check_run_folder(here / "lumped")
    assert summary["model"] == "lumped" and summary["status"] == "complete"
    assert summary["n_dof"] == 2 and summary["angle_deg"] > 2.95  # sampled on the saved grid
    assert json.loads(ds.attrs["info"])["model"] == "lumped"
    ds2 = load_run(here / "lumped")                 # readable the documented way
    direct = simulate_lumped(*(lambda c: (c.pair, c.run))(
        preset_case("paper-fig9", {"run.angle_deg": 3.0, "run.save_every": 10})))
    assert np.allclose(ds2["contact_force"].values, direct.contact_force)
    assert 0 < summary["peak_force_N"] < summary["static_force_N"]  # still in the ramp
    code, _, err = run(capsys, "run", "paper-fig9", "--model", "spring", "--out", "x")
    assert code == 2 and err.startswith("spurdyn: error: ") and not (here / "x").exists()
