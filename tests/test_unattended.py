"""Issue 19: nothing lost, nothing hangs, nothing misleads.

Stop signals (SIGTERM as Ctrl-C, the window after the solver returns), folders left by
killed runs, settings bounded where their meaning ends (each refusal naming the key the
user wrote), the step/size limits, and outputs that say what is true.
"""

from __future__ import annotations

import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from spurdyn.cli import run as runner
from spurdyn.signals import Interrupts
from spurdyn.settings import MAX_ACCEL_LEVELS
from spurdyn.solvers.paper.iteration_numpy import coefficients
from cli_helpers import check_run_folder, fake, here, leftovers, run  # noqa: F401 (fixtures)
from run_helpers import fake_simulate

SHORT = ["--angle", "0.3"]


# -- signals -----------------------------------------------------------------------------

def test_sigterm_keeps_the_run_so_far(fake, here, capsys, monkeypatch):
    calls = []

    def sigterm(self, step, angle, total):
        calls.append(step)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(runner.ProgressBar, "__call__", sigterm)
    code, out, err = run(capsys, "run", "paper-all", *SHORT, "--out", "all")
    assert code == 1 and out == ""
    ds, summary = check_run_folder(here / "all" / "paper-fig8")
    assert summary["status"] == "incomplete" and summary["steps"] == 40
    assert summary["reason"] == "interrupted by SIGTERM at step 40"
    assert "paper-fig9 not run (interrupted by SIGTERM)" in err
    assert leftovers(here / "all") == []


def test_signal_after_the_solver_returned_loses_nothing(fake, here, capsys, monkeypatch):
    """A Ctrl-C that lands after the solver's loop has ended (before the files are
    written) waits: the complete result is written and reported."""
    def simulate(pair, case, progress=None):
        result = fake_simulate(pair, case, progress)
        os.kill(os.getpid(), signal.SIGINT)  # the loop is over, the result not yet kept
        return result

    monkeypatch.setattr(runner, "load_simulate", lambda model="fe": simulate)
    code, out, err = run(capsys, "run", "paper-fig9", *SHORT)
    assert code == 0, err
    _, summary = check_run_folder(here / "out" / "paper-fig9")
    assert summary["status"] == "complete" and "complete" in out


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_stop_before_the_solver_loop_leaves_nothing(here, capsys, monkeypatch, signum, status):
    def compiling(pair, case, progress=None):
        os.kill(os.getpid(), signum)  # before any progress report: raises at once
        raise AssertionError("the signal should have stopped the run")

    monkeypatch.setattr(runner, "load_simulate", lambda model="fe": compiling)
    code, _, err = run(capsys, "run", "paper-fig9", *SHORT)
    name = "SIGTERM" if signum == signal.SIGTERM else "Ctrl-C"
    assert code == status and f"interrupted by {name} before any result; nothing written" in err
    assert list(here.iterdir()) == []


@pytest.mark.slow
def test_console_script_keeps_results_on_sigterm(tmp_path):
    """The command, stopped by SIGTERM in its time loop, keeps its steps.

    Its stderr is a terminal, so the progress bar shows when the loop has reported once.
    """
    import pty
    import select

    out = tmp_path / "run"
    import fcntl
    import struct
    import termios

    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))  # 100 columns
    # the console command's entry: its run writes the folder in a process of its own
    entry = "from spurdyn.cli.command import entry; entry()"
    proc = subprocess.Popen([sys.executable, "-c", entry, "run", "paper-fig8", "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=slave)
    os.close(slave)
    def read(timeout: float) -> bytes:
        if not select.select([master], [], [], timeout)[0]:
            return b""
        try:
            return os.read(master, 4096)
        except OSError:  # the command has ended and closed the terminal
            return b""

    seen = b""
    deadline = time.monotonic() + 180  # a first run compiles for up to a minute
    while b" deg [" not in seen and time.monotonic() < deadline and proc.poll() is None:
        seen += read(0.5)
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=120)
    while chunk := read(0.2):
        seen += chunk
    os.close(master)
    err = seen.decode(errors="replace")
    assert proc.returncode == 1, err
    assert "Traceback" not in err and "incomplete: interrupted by SIGTERM" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "incomplete" and summary["steps"] >= 500  # a chunk or more
    assert [p.name for p in tmp_path.iterdir()] == ["run"]


def test_interrupts_count_and_checkpoint():
    Interrupts.reset()
    with Interrupts.installed():
        with Interrupts.held():
            os.kill(os.getpid(), signal.SIGTERM)  # counted, not raised
        assert Interrupts.count == 1 and Interrupts.exit_status() == 143
        Interrupts.reset()
        with Interrupts.checkpoints():
            with pytest.raises(KeyboardInterrupt):  # before the first report: at once
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(1.0)
        Interrupts.reset()
        with Interrupts.checkpoints():
            Interrupts.checkpoint()  # the first report ...
            os.kill(os.getpid(), signal.SIGINT)  # ... after which a signal waits
            assert Interrupts.count == 1
            with pytest.raises(KeyboardInterrupt):
                Interrupts.checkpoint()
    Interrupts.reset()


# -- folders left by killed runs ---------------------------------------------------------

def test_folders_of_killed_runs_are_cleaned_or_reported(fake, here, capsys):
    from spurdyn.results.folder import _host

    (here / "out").mkdir()
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = here / "out" / f".paper-fig9.partial-{_host()}-{dead.pid}"
    (stale / "result.nc").parent.mkdir()
    (stale / "result.nc").write_bytes(b"half")
    alive = here / "out" / f".paper-fig9.partial-{_host()}-{os.getppid()}"  # still running
    alive.mkdir()
    other = here / "out" / ".paper-fig9.partial-elsewhere-12"
    other.mkdir()
    code, _, err = run(capsys, "run", "paper-fig9", *SHORT, "--quiet")
    assert code == 0, err
    assert not stale.exists() and alive.exists() and other.exists()
    assert "removed 1 folder(s) left by a killed run" in err
    assert f"{other.name} was left by process 12 on elsewhere" in err
    check_run_folder(here / "out" / "paper-fig9")


# -- bounds and limits -------------------------------------------------------------------

def test_accel_levels_bound_is_where_the_coefficients_underflow():
    """The largest n with a finite b_bar for the smallest eps_1 the iteration admits."""
    assert math.isfinite(coefficients(MAX_ACCEL_LEVELS, 1e-12)[3])
    with np.errstate(divide="ignore"):
        assert not math.isfinite(coefficients(MAX_ACCEL_LEVELS + 1, 1e-12)[3])


REFUSED = [
    (["--speed-a", "1e300"], "--speed-a: 1e+300 rpm"),
    (["--speed-a", "2e6"], "--speed-a:"),                 # fewer than 100 steps
    (["--speed-b", "1e300"], "--speed-b: 1e+300 rpm is above the bursting speed"),
    (["--torque", "1e300"], "--torque: 1e+300 N m strains"),
    (["--save-every", "10000000"], "--save-every: 10,000,000 keeps fewer than 3 samples"),
    (["--dt", "1e-300"], "--dt: paper-fig8 would take"),   # the time step is to blame
    (["--speed-a", "10"], "--speed-a: paper-fig8 would take 11,7"),
    (["--frames-every", "1", "--speed-a", "500"],           # 234,000 frames of 820 numbers
     "--frames-every: paper-fig8 would keep about 1.5 GiB"),
]


@pytest.mark.parametrize("argv, message", REFUSED)
def test_absurd_options_are_refused_by_name(fake, here, capsys, argv, message):
    code, out, err = run(capsys, "run", "paper-fig8", *argv)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith(f"spurdyn: error: {message}"), err
    assert list(here.iterdir()) == []


RUN_KEYS_REFUSED = [
    ("n_spline", 10**9, "run.n_spline: must be at most 8,193"),
    ("accel_levels", 30, f"run.accel_levels: must be at most {MAX_ACCEL_LEVELS}"),
    ("accel_levels", 1000, "run.accel_levels: must be at most"),
    ("max_iter", 2**63 - 1, "run.max_iter: must be at most 100,000"),
    ("tol_disp", 1e300, "run.tol_disp: must lie between"),
    ("tol_disp", 1e-30, "run.tol_disp: must lie between"),
    ("save_every", 10**12, "run.save_every:"),
    ("torque", 1e300, "run.torque:"),
    ("speed_a_rpm", 1e300, "run.speed_a_rpm:"),
    ("dt", 1e-20, "run.dt: paper_fig8 would take"),
]


@pytest.mark.parametrize("key, value, message", RUN_KEYS_REFUSED)
def test_absurd_run_keys_are_refused_by_name(fake, here, capsys, key, value, message):
    from test_properties import case_file

    path = case_file(here, {key: value})
    code, out, err = run(capsys, "run", path, "--out", here / "o")
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith(f"spurdyn: error: {message}"), err
    assert not (here / "o").exists()


def test_allow_large_runs_what_the_limit_refuses(fake, here, capsys):
    fake.update(chunk=10**8)
    argv = ["paper-fig8", "--speed-a", "30", "--save-every", "100000", "--frames-every", "0"]
    assert run(capsys, "run", *argv)[0] == 2
    code, _, err = run(capsys, "run", *argv, "--allow-large", "--quiet")
    assert code == 0, err
    _, summary = check_run_folder(here / "out" / "paper-fig8")
    assert summary["steps"] > 2_000_000


# -- true outputs ------------------------------------------------------------------------

def test_vtu_refused_when_gear_b_drives(fake, here, capsys):
    code, _, err = run(capsys, "run", "paper-fig10-bdrive", *SHORT, "--vtu")
    assert code == 2 and "--vtu: needs tooth frames, but paper-fig10-bdrive is driven by " \
        "gear B" in err
    assert list(here.iterdir()) == []


def test_no_contact_says_no_contact(fake, here, capsys):
    fake.update(separations=((-1.0, 100.0),))
    code, out, _ = run(capsys, "run", "paper-fig9", *SHORT)
    assert code == 0 and "no contact" in out and "-0.0" not in out
    _, summary = check_run_folder(here / "out" / "paper-fig9")
    assert summary["peak_force_N"] is None and summary["dynamic_factor"] is None


def test_numeric_attributes_stay_numbers(fake, here, capsys):
    """``steps``, ``wall_s``, ``dt_s``, ... are NetCDF numbers, not strings."""
    import netCDF4

    assert run(capsys, "run", "paper-fig9", *SHORT, "--quiet")[0] == 0
    with netCDF4.Dataset(here / "out" / "paper-fig9" / "result.nc") as nc:
        for name in ("steps", "n_dof"):
            assert isinstance(nc.getncattr(name), np.integer), name
        for name in ("wall_s", "dt_s", "angle_target_deg", "theta_s_deg", "static_force_N"):
            assert isinstance(nc.getncattr(name), np.floating), name


def test_long_reason_is_wrapped_in_the_plot_title():
    from spurdyn.results.plots import TITLE_WIDTH, wrap_title

    reason = "step 812: the velocity stage did not converge in 500 iterations " * 3
    lines = wrap_title(f"paper-fig10: contact force (incomplete: {reason})").splitlines()
    assert len(lines) > 1 and max(len(x) for x in lines) <= TITLE_WIDTH
    assert "incomplete" in lines[0]


def test_out_that_cannot_be_made_is_one_line(fake, here, capsys):
    target = "/proc/spurdyn-cannot-exist/run"
    code, out, err = run(capsys, "run", "paper-fig9", *SHORT, "--out", target)
    assert code == 2 and err.count("\n") == 1 and target in err and "Traceback" not in err


def test_picture_that_cannot_be_written_is_one_line(here, capsys):
    code, out, err = run(capsys, "mesh", "paper", "--png", "/proc/spurdyn.png")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("spurdyn: error: /proc/spurdyn.png: cannot be written")


def test_closed_pipe_is_quiet(tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "spurdyn.cli.main", "info", "paper", "--json"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # `spurdyn info paper | head -0`
    err = proc.stderr.read().decode()
    proc.wait(timeout=60)
    assert proc.returncode == 141 and err == ""


# -- first run ---------------------------------------------------------------------------

def test_rate_counts_from_the_first_report(monkeypatch):
    clock = iter([100.0, 160.0, 161.0])  # 60 s of compiling before the first report
    monkeypatch.setattr(runner.time, "perf_counter", lambda: next(clock))
    bar = runner.ProgressBar("x", enabled=False)
    assert bar.rate(500) is None
    assert bar.rate(1500) == pytest.approx(1000.0 / 60.0)
    assert bar.rate(2500) == pytest.approx(2000.0 / 61.0)


def test_compiling_is_announced(tmp_path, capsys, monkeypatch):
    import spurdyn.solvers.warmup as warmup
    from spurdyn.case import resolve_cases
    from spurdyn.simulators import MODELS

    plan = runner.plan_runs(resolve_cases("paper-fig9", {}, {}), str(tmp_path / "o"), False)[0]
    monkeypatch.setattr(warmup, "needs_compiling", lambda settings=None: True)
    runner._compiling_note(plan, MODELS["fe"], quiet=False)
    assert "compiling the solver (first run only" in capsys.readouterr().err
    runner._compiling_note(plan, MODELS["lumped"], quiet=False)
    runner._compiling_note(plan, MODELS["fe"], quiet=True)
    assert capsys.readouterr().err == ""
    empty = subprocess.run([sys.executable, "-c", "from spurdyn.solvers.warmup import "
                            "needs_compiling; print(needs_compiling())"],
                           env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "nb")},
                           capture_output=True, text=True, timeout=120)
    assert empty.stdout.strip() == "True", empty.stderr


def test_animate_reports_progress(fake, here, capsys):
    assert run(capsys, "run", "paper-fig9", *SHORT, "--frames-every", "10", "--quiet")[0] == 0
    code, out, err = run(capsys, "animate", "out/paper-fig9", "--gif", "a.gif", "--max-frames", "3")
    assert code == 0 and "animating a.gif (3 frames)" in err
    assert sorted(p.name for p in here.iterdir()) == ["a.gif", "out"]  # no half GIF left


def test_local_cluster_says_nothing_of_a_taken_dashboard_port():
    import warnings

    from spurdyn.sweep.backends import local_backend

    with socket.socket() as sock:
        try:
            sock.bind(("127.0.0.1", 8787))
            sock.listen()
        except OSError:
            pass  # taken already: the case to test
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with local_backend(1):
                pass
    assert not [w for w in caught if "8787" in str(w.message)]
