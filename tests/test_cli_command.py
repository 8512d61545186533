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
