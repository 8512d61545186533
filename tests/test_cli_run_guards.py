"""``spurdyn run`` loses nothing and refuses bad input: the overwrite guard, interrupted and
incomplete runs keep what was computed, and a bad argument or case file is one line, exit
status 2 and nothing written (split from test_cli_run.py; the synthetic solver ``fake``,
see ``cli_helpers.py``)."""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from spurdyn.cli import run as runner
from cli_helpers import (  # noqa: F401 (fake, here: fixtures)
    EXAMPLES, PAPER_TOML, SHORT, _Terminal, check_run_folder, fake, here, leftovers, run,
)


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
