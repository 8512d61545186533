"""``spurdyn run``, ``cases``, ``plot`` and ``animate`` end to end.

Most tests run the command with a synthetic solver (``fake``, see ``cli_helpers.py``)
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
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from spurdyn.case import resolve_cases
from spurdyn.cli import run as runner
from spurdyn.settings import METHODS, RPM
from cli_helpers import (  # noqa: F401 (fake, here: fixtures)
    EXAMPLES, PNG_MAGIC, SHORT, _Terminal, check_run_folder, fake, here, leftovers, run,
)


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
