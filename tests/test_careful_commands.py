"""The last gaps of "every command as careful as run" (docs/cli.md, "Limits"): an error of
the system named for what failed, a sweep's point count bounded by what planning holds a
point, a frozen scheduler given up on, the sector model's whole bodies bounded by their
time, and the FE model at a torque too small to load its teeth."""

from __future__ import annotations

import errno
import os
import signal
from contextlib import contextmanager
from pathlib import Path

import pytest

from cli_helpers import EXAMPLES, fake, here, run  # noqa: F401  (fixtures)
from spurdyn.cli import main as cli_main


# -- what failed: a read is not a write -----------------------------------------------

@pytest.mark.parametrize("code, words", [(errno.ENOENT, "No such file or directory"),
                                         (errno.EACCES, "Permission denied"),
                                         (errno.EISDIR, "Is a directory")])
def test_an_error_reading_an_input_names_it_without_cannot_be_written(here, capsys,
                                                                      monkeypatch, code, words):
    def reads(args):
        raise OSError(code, words, "/data/gears/torque.csv")

    monkeypatch.setattr(cli_main, "cmd_info", reads)
    code_, out, err = run(capsys, "info", "paper")
    assert code_ == 2 and out == "" and err.count("\n") == 1
    assert err == f"spurdyn: error: /data/gears/torque.csv: {words}\n", err


def test_an_error_writing_under_out_still_says_cannot_be_written(here, capsys, monkeypatch):
    def writes(args):
        raise OSError(errno.ENOSPC, "No space left on device", str(here / "res" / "result.nc"))

    monkeypatch.setattr(cli_main, "cmd_run", writes)
    code, out, err = run(capsys, "run", "paper-fig8", "--out", here / "res")
    assert code == 2 and "res/result.nc: cannot be written (No space left on device)" in err


@pytest.mark.parametrize("command", (["info"], ["stiffness"], ["run"]), ids=lambda c: c[0])
def test_a_folder_given_as_case_file_is_said_to_be_a_folder(here, capsys, command):
    (here / "case.toml").mkdir()
    code, out, err = run(capsys, command[0], "case.toml", *command[1:])
    assert code == 2 and err == "spurdyn: error: case.toml: is a folder, not a file\n", err


# -- a sweep's points: counted before they are made, stopped cleanly while planned -----

def test_a_product_of_grids_is_refused_by_its_count_before_any_point(here, capsys,
                                                                     monkeypatch):
    from spurdyn.sweep import spec

    def planned(self):
        raise AssertionError("the sweep made its points before counting them")

    monkeypatch.setattr(spec.SweepPlan, "keys", planned)
    code, out, err = run(capsys, "sweep", "paper-fig8", "--rpm", "1000:20000/10000",
                         "--torque", "0:40/10000", "--out", here / "o")
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("spurdyn: error: --torque: 10,000 speeds x 10,000 torques = "
                          f"100,000,000 points; at most {spec.MAX_POINTS:,}"), err
    assert list(here.iterdir()) == []


def test_the_count_bound_is_the_memory_guard_over_a_points_bytes():
    from spurdyn.solvers.limits import MAX_BYTES
    from spurdyn.sweep import spec

    assert spec.MAX_POINTS * spec.BYTES_PER_POINT <= MAX_BYTES
    assert (spec.MAX_POINTS + 1) * spec.BYTES_PER_POINT > MAX_BYTES
    spec.check_count((1.0,) * spec.MAX_POINTS, None)           # the bound itself runs
    with pytest.raises(spec.InputError, match="--rpm"):
        spec.check_count((1.0,) * (spec.MAX_POINTS + 1), None)


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_sweep_stopped_before_its_first_point_writes_nothing(here, capsys, monkeypatch,
                                                               signum, status):
    from spurdyn.cli import sweep as cli_sweep
    from spurdyn.sweep import point as point_mod
    from spurdyn.sweep.backends import SerialBackend

    @contextmanager
    def local(jobs):
        yield SerialBackend()

    def stopped(task):
        os.kill(os.getpid(), signum)
        raise AssertionError("the signal should have stopped the sweep")

    monkeypatch.setattr(cli_sweep, "local_backend", local)
    monkeypatch.setattr(point_mod, "run_point", stopped)
    code, out, err = run(capsys, "sweep", "paper-fig8", "--model", "lumped", "--rpm",
                         "6000,8000", "--out", here / "o" / "sw")
    name = "SIGTERM" if signum == signal.SIGTERM else "Ctrl-C"
    assert code == status and err == f"spurdyn: interrupted by {name}\n", err
    assert list(here.iterdir()) == []


class _Future:
    def __init__(self, key, task, fn, n):
        self.key, self.task, self.fn, self.n, self.status = key, task, fn, n, "finished"

    def result(self, timeout=None):
        return self.fn(self.task)

    def release(self):
        pass


class _Client:
    """A client of one single-threaded worker whose tasks finish as soon as looked at."""

    status = "running"

    def __init__(self):
        self.submitted = 0

    def submit(self, fn, task, key, pure, retries, priority):
        self.submitted += 1
        return _Future(key, task, fn, self.submitted)

    def scheduler_info(self):
        return {"workers": {"tcp://w": {"nthreads": 1}}}

    def subscribe_topic(self, topic, handler):
        pass

    def cancel(self, futures, force=False):
        pass


def test_a_cluster_is_handed_a_few_points_at_a_time(monkeypatch):
    from spurdyn.case.presets import preset_case
    from spurdyn.sweep import backends
    from spurdyn.sweep.point import PointOutcome, PointTask
    from spurdyn.sweep.spec import SweepPlan, parse_speeds

    plan = SweepPlan(case=preset_case("paper-fig8"), model="lumped",
                     rpms=parse_speeds("1000:20000/60"), torques=None, out=Path("unused"))
    tasks = [PointTask(k, plan.point_case(k), False) for k in plan.keys()]
    most = []

    def wait_some(self):
        most.append(len(self._pending))
        return {min(self._pending, key=lambda f: f.n)}       # in the order submitted

    monkeypatch.setattr(backends.DaskBackend, "_wait_some", wait_some)
    client = _Client()
    backend = backends.DaskBackend(client, "fake")
    got = [t.key.rpm for t, _, _ in backend.run(
        tasks, lambda task: PointOutcome(key=task.key, status="complete", reason="",
                                         finished=0.0))]
    assert sorted(got) == sorted(plan.rpms) and client.submitted == 60
    assert max(most) == max(backends.MIN_AHEAD, backends.AHEAD_PER_THREAD * 1)
    assert got[0] == min(plan.rpms)        # the longest point (the slowest speed) first
