"""A run folder written by a process of its own (spurdyn.results.apart).

The folder is the one this process would write, byte for byte; a writer that dies or fails
loses nothing (this process writes instead); one given nothing ends; and the console
command's ``run`` steps without ever loading the writers' libraries, keeping what it
computed when stopped.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from spurdyn.results import apart, beside
from spurdyn.results.folder import write_run_folder
from cli_helpers import FILES, check_run_folder, leftovers
from run_helpers import fake_simulate, short_case  # noqa: F401 (fixture)

TESTS = Path(__file__).resolve().parent
FORKS = hasattr(os, "fork") and sys.platform.startswith("linux")


@pytest.fixture(params=["fork", "fresh"])
def way(request, monkeypatch):
    """A writer forked from this process (which has loaded Numba: allowed here), or a
    freshly started interpreter."""
    if request.param == "fork":
        if not FORKS:
            pytest.skip("a writer is forked only on Linux")
        monkeypatch.setattr(beside, "can_fork", lambda: True)
        monkeypatch.setattr(apart, "_LARGE", ())
    else:
        monkeypatch.setattr(beside, "can_fork", lambda: False)
    return request.param


def test_the_writer_writes_the_folder_this_process_would(tmp_path, short_case, way):
    result = fake_simulate(short_case.pair, short_case.run, separations=((0.1, 0.12),))
    writer = apart.start()
    assert writer is not None and (writer.popen is None) == (way == "fork")
    summary, final = apart.write(writer, result, short_case, tmp_path / "apart")
    assert writer.ended and final == tmp_path / "apart"
    here, _ = write_run_folder(result, short_case, tmp_path / "here")
    assert summary == here
    for name in FILES:
        assert (final / name).read_bytes() == (tmp_path / "here" / name).read_bytes(), name
    assert leftovers(tmp_path) == []


def test_a_writer_that_dies_loses_nothing(tmp_path, short_case, capsys, way):
    result = fake_simulate(short_case.pair, short_case.run)
    writer = apart.start()
    assert writer is not None
    os.kill(writer.pid, signal.SIGKILL)
    summary, final = apart.write(writer, result, short_case, tmp_path / "run")
    ds, written = check_run_folder(final)
    assert written == summary and summary["status"] == "complete"
    assert "the writer process failed" in capsys.readouterr().err
    assert writer.ended and leftovers(tmp_path) == []


def test_a_writer_given_nothing_ends_and_writes_nothing(tmp_path, way):
    writer = apart.start()
    assert writer is not None
    apart.stop(writer)
    assert writer.ended
    apart.stop(writer)   # twice: nothing more to do
    apart.stop(None)
    assert list(tmp_path.iterdir()) == []


def test_a_large_process_starts_a_fresh_writer(monkeypatch):
    """Once Numba is loaded (LLVM's ~75 MB resident), a fork would count it: a fresh one."""
    import numba  # noqa: F401 - loaded, as in a run's process after its first run

    monkeypatch.setattr(beside, "can_fork", lambda: True)
    writer = apart.start()
    assert writer is not None and writer.popen is not None
    apart.stop(writer)


#: The console command with the synthetic solver, stopped by SIGTERM at its second progress
#: report; at its exit, which of the writers' libraries its own process holds.
_STOPPED_RUN = """
import atexit, os, signal, sys
sys.path.insert(0, {tests!r})
from run_helpers import fake_simulate
from spurdyn.cli import run as runner
calls = []
def report(self, step, angle, total):
    calls.append(step)
    if len(calls) == 2:
        os.kill(os.getpid(), signal.SIGTERM)
runner.ProgressBar.__call__ = report
runner.load_simulate = lambda model="fe": fake_simulate
writers = ("xarray", "pandas", "matplotlib", "netCDF4")
atexit.register(lambda: print("loaded:", [m for m in writers if m in sys.modules]))
sys.argv = ["spurdyn", "run", "paper-fig9", "--angle", "0.3", "--frames-every", "10",
            "--out", {out!r}]
from spurdyn.cli.command import entry
entry()
"""


def test_the_command_steps_without_the_writers_and_keeps_what_it_computed(tmp_path):
    out = tmp_path / "run"
    code = _STOPPED_RUN.format(tests=str(TESTS), out=str(out))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 1, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "loaded: []", done.stdout
    assert "incomplete: interrupted by SIGTERM at step 40" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr
    _, summary = check_run_folder(out)
    assert summary["status"] == "incomplete" and summary["steps"] == 40
    assert [p.name for p in tmp_path.iterdir()] == ["run"]


_FAILED_RUN = """
import os, sys
sys.path.insert(0, {tests!r})
from spurdyn.cli import run as runner
def failing(pair, case, progress=None):
    progress(20, 0.001, 0.01)   # the loop has begun: the writer loads the writers
    raise RuntimeError("the solver failed")
runner.load_simulate = lambda model="fe": failing
runner.WRITE_APART = True
from spurdyn.cli.main import main
try:
    main(["run", "paper-fig9", "--angle", "0.3", "--quiet", "--out", {out!r}])
except RuntimeError:
    pass
try:
    os.waitpid(-1, os.WNOHANG)
    print("a child left")
except ChildProcessError:
    print("no child left")
"""


def test_a_run_that_fails_leaves_no_writer_and_no_folder(tmp_path):
    out = tmp_path / "run"
    code = _FAILED_RUN.format(tests=str(TESTS), out=str(out))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.stdout.strip().splitlines()[-1] == "no child left", (done.stdout, done.stderr)
    assert list(tmp_path.iterdir()) == []
