"""The console command (spurdyn.cli.command): the command's exit status, and an exit that
skips the interpreter's teardown but still runs the exit handlers, flushes the streams
and waits for a thread still running."""

from __future__ import annotations

import subprocess
import sys


def _command(prelude: str, *args: str) -> subprocess.CompletedProcess[str]:
    """``spurdyn ARGS`` through :func:`spurdyn.cli.command.entry`, after ``prelude``."""
    code = (f"import sys\n{prelude}\nsys.argv = ['spurdyn', *{list(args)!r}]\n"
            "from spurdyn.cli.command import entry\nentry()\n")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)


def test_the_command_exits_with_its_status_and_its_output() -> None:
    done = _command("", "cases")
    assert done.returncode == 0
    assert "paper-fig8" in done.stdout and done.stdout.endswith("\n")
    refused = _command("", "run", "no-such-case.toml")
    assert refused.returncode == 2
    assert refused.stderr.startswith("spurdyn: error:")


def test_exit_handlers_run_and_their_output_is_kept() -> None:
    prelude = "import atexit\natexit.register(lambda: print('handler ran'))"
    done = _command(prelude, "cases")
    assert done.returncode == 0
    assert done.stdout.rstrip().endswith("handler ran")


def test_a_thread_still_running_is_waited_for() -> None:
    prelude = ("import threading, time\n"
               "def late():\n    time.sleep(0.5)\n    print('thread done', flush=True)\n"
               "threading.Thread(target=late).start()")
    done = _command(prelude, "cases")
    assert done.returncode == 0
    assert "thread done" in done.stdout


def test_a_run_keeps_dask_out_and_other_commands_leave_it() -> None:
    """``spurdyn run`` takes Dask for not installed (xarray then imports none of it); the
    other commands, and a process that loaded Dask already, keep it."""
    probe = ("atexit.register(lambda: print('dask blocked', sys.modules.get('dask', 0) is None))")
    assert "dask blocked True" in _command(f"import atexit\n{probe}", "run", "x.toml").stdout
    assert "dask blocked False" in _command(f"import atexit\n{probe}", "cases").stdout
    loaded = _command(f"import atexit, dask\n{probe}", "run", "x.toml").stdout
    assert "dask blocked False" in loaded


def test_a_sector_runs_modules_leave_out_the_libraries_it_never_calls() -> None:
    """What a ``spurdyn run`` of the sector model imports (the command, the registry, the
    model's run and compiled loop, the writers and pictures) brings no SciPy signal
    processing or statistics (~0.5 s to import; the summary's vibration figures import them
    when a diagnostics study asks), no ODE solvers or splines (the lumped and paper models')."""
    code = ("import sys\n"
            "import spurdyn.cli.main, spurdyn.solvers.sector.run, spurdyn.solvers.sector.stepper_compiled\n"
            "import spurdyn.results.io, spurdyn.results.folder, spurdyn.results.mesh_plot, spurdyn.results.prefetch\n"
            "from spurdyn.results.mesh_plot import plot_pair_pictures\n"
            "import spurdyn.results.cycle_plot, spurdyn.results.teeth_stress_plot, spurdyn.results.vibration_plot\n"
            "import spurdyn.lumped.sources, spurdyn.iso6336.rating\n"
            "heavy = ('scipy.signal', 'scipy.stats', 'scipy.integrate', 'scipy.interpolate')\n"
            "print(sorted(m for m in heavy if m in sys.modules))\n"
            "import spurdyn.lumped\n"
            "print(callable(spurdyn.lumped.simulate_lumped), 'scipy.integrate' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:2] == ["[]", "True True"]


def test_a_run_writes_apart_and_other_commands_in_their_own_process() -> None:
    """``spurdyn run`` writes its folders in a process of its own (spurdyn.results.apart);
    the other commands, and a Python session calling main(), write in theirs."""
    probe = ("atexit.register(lambda: print('apart', getattr(sys.modules.get('spurdyn.cli.run'), "
             "'WRITE_APART', False)))")
    assert "apart True" in _command(f"import atexit\n{probe}", "run", "x.toml").stdout
    assert "apart False" in _command(f"import atexit\n{probe}", "cases").stdout
    from spurdyn.cli import run

    assert run.WRITE_APART is False
