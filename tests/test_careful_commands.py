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
from types import SimpleNamespace

import pytest

from spurdyn.errors import InputError
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
        self.scheduler = SimpleNamespace(identity=lambda: {"workers": {"tcp://w": {"nthreads": 1}}})

    def sync(self, call, callback_timeout=None):
        return call()

    def submit(self, fn, task, key, pure, retries, priority):
        self.submitted += 1
        return _Future(key, task, fn, self.submitted)

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


# -- a scheduler that freezes in the middle of a sweep ---------------------------------

@pytest.mark.slow
def test_a_frozen_scheduler_is_given_up_keeping_the_finished_points(tmp_path, capsys,
                                                                    monkeypatch):
    """The scheduler is stopped (SIGSTOP: its connections stay open, nothing comes back)
    while the last point runs: the sweep gives it up after the silence allowed, in one
    line, keeping the two finished points (it used to wait for ever: the watchdog below
    wakes the scheduler after 90 s so that such a wait ends in a failure, not a hang)."""
    import threading
    import time

    import cluster_helpers as ch
    from spurdyn.sweep import backends
    from spurdyn.sweep import point as point_mod

    monkeypatch.setattr(backends, "SILENCE_S", 3.0, raising=False)
    monkeypatch.setattr(point_mod, "run_point", ch.slow_point)
    cluster = ch.LoopbackCluster(tmp_path / "cluster")
    done = threading.Event()    # the test over: the scheduler is let go of, not woken
    try:
        cluster.start_scheduler()
        cluster.start_worker()

        def freeze() -> None:
            ch.wait_for(cluster.marks / f"{ch.SLOW_RPM:.0f}.started")
            # and the two others kept (on a loaded machine they may finish after it starts)
            deadline = time.monotonic() + ch.SLOW_S
            while len(list((tmp_path / "sw" / "points").glob("*.json"))) < 2 and \
                    time.monotonic() < deadline:
                time.sleep(0.02)
            if not done.is_set():    # (Popen signals no process it has reaped)
                cluster.scheduler.send_signal(signal.SIGSTOP)
            if not done.wait(90.0):   # else the test has ended and stopped the scheduler
                cluster.scheduler.send_signal(signal.SIGCONT)

        threading.Thread(target=freeze, daemon=True).start()
        t0 = time.monotonic()
        code, out, err = run(capsys, "sweep", "paper-fig8", "--rpm", "8000,10000,12000",
                             "--model", "lumped", "--scheduler", cluster.address,
                             "--scheduler-timeout", "2", "--out", tmp_path / "sw")
        took = time.monotonic() - t0
    finally:
        done.set()
        if cluster.scheduler is not None and cluster.scheduler.poll() is None:
            os.kill(cluster.scheduler.pid, signal.SIGCONT)
        cluster.stop()
    assert code == 1, err
    assert ("spurdyn: sweep stopped (ClusterLost: the scheduler has not answered for 3 s): "
            f"2 of 3 points kept in {tmp_path / 'sw'}") in err, err
    assert took < 60.0, took
    assert len(list((tmp_path / "sw" / "points").glob("*.json"))) == 2


# -- the sector model's whole bodies: bounded by their time, not their step count ------

def test_whole_bodies_that_would_take_hours_are_refused_naming_bodies(fake, here, capsys):
    code, out, err = run(capsys, "run", "paper-fig8", "--model", "sector", "--bodies", "full",
                         "--cycles", "20", "--damping", "0.05")
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("spurdyn: error: --bodies: paper-fig8 would take 64,320 steps"), err
    assert "55,554 coordinates" in err and 'give modal bodies (bodies = "modal"' in err, err
    assert list(here.iterdir()) == []


def test_the_whole_bodies_estimate_counts_the_runs_coordinates_and_their_time():
    """The coordinates are those the run steps (25,474 on 2 x 8 teeth over one cycle, as a
    run's summary says; 55,554 on the whole gears, docs/performance.md), the time a run may
    take is MAX_SECONDS whatever the model, and the modal bodies keep their step count."""
    from dataclasses import replace

    from spurdyn.case.presets import preset_case
    from spurdyn.sector.rules import full_coordinates
    from spurdyn.simulators import FULL_STEP_S_PER_COORDINATE, MODELS
    from spurdyn.solvers.limits import MAX_SECONDS, MAX_STEPS, check_size

    case = preset_case("paper-fig8")
    entry = MODELS["sector"]

    def sized(**kw):
        c = replace(case, run=entry.with_defaults(case.run.with_(damping_ratio=0.05, **kw)))
        return c, entry.size(c)

    small = dict(cycles=1, max_cycles=1, bodies="full", nx=2, ny=8)
    assert full_coordinates(case.pair, case.run.with_(**small)) == 25_474
    assert full_coordinates(case.pair, case.run.with_(cycles=3, bodies="full")) == 55_554
    c, size = sized(**small)                    # results_identical.py's run: still allowed
    assert size.steps_per_s == pytest.approx(1.0 / (FULL_STEP_S_PER_COORDINATE * 25_474))
    assert size.most_steps == int(MAX_SECONDS * size.steps_per_s) < MAX_STEPS
    check_size(c, {}, size)
    c, size = sized(cycles=20, bodies="full")
    assert size.steps / size.steps_per_s > MAX_SECONDS
    with pytest.raises(InputError, match="run.bodies"):
        check_size(c, {}, size)
    c, modal = sized(cycles=20)
    assert modal.most_steps == MAX_STEPS and modal.steps == size.steps
    check_size(c, {}, modal)


# -- the FE model without a load, and with one lost in the rounding --------------------

@pytest.mark.parametrize("torque", ["1e-12", "1e-300"])
def test_an_fe_load_lost_in_the_rounding_is_refused(fake, here, capsys, torque):
    """Such a run used to end `complete` with a dynamic factor of 1.35e18 (1e-20 N m on
    Fig. 8): its peak force the unloaded run's, over a static force of nothing."""
    code, out, err = run(capsys, "run", "paper-fig8", "--torque", torque)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith(f"spurdyn: error: --torque: {float(torque):g} N m deflects the teeth "
                          "by less than the rounding of positions"), err
    assert err.endswith("; or 0 for an unloaded run\n") and list(here.iterdir()) == []


@pytest.mark.slow
def test_an_unloaded_fe_run_is_a_clean_result(here, capsys):
    import json
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, _, err = run(capsys, "run", "paper-fig9", "--angle", "0.3", "--torque", "0",
                           "--backend", "numpy", "--out", here / "o", "--quiet")
    assert code == 0 and err == "", err
    summary = json.loads((here / "o" / "summary.json").read_text())
    assert summary["status"] == "complete" and summary["reason"] == ""
    assert summary["dynamic_factor"] is None and summary["static_force_N"] == 0.0
    assert summary["dynamic_factor_note"] == "none: no quasi-static force (zero torque)"


def test_a_stop_signal_while_the_local_cluster_starts_closes_it(monkeypatch):
    """Cut short inside ``LocalCluster``, the half-made cluster was left to Dask's own close
    at exit, which printed an AssertionError's traceback; the signal is now acted on once
    the cluster can be closed."""
    import distributed

    from spurdyn.signals import Interrupts
    from spurdyn.sweep import backends

    closed = []

    class Cluster:
        def __init__(self, **kw):
            os.kill(os.getpid(), signal.SIGTERM)

        def close(self, timeout=None):
            closed.append("cluster")

    class Client:
        def __init__(self, cluster):
            pass

        def unsubscribe_topic(self, topic):
            pass

        def close(self, timeout=None):
            closed.append("client")

    monkeypatch.setattr(distributed, "LocalCluster", Cluster)
    monkeypatch.setattr(distributed, "Client", Client)
    with Interrupts.installed():
        Interrupts.reset()
        with pytest.raises(KeyboardInterrupt):
            with backends.local_backend(2):
                raise AssertionError("the sweep should not start")
    assert closed == ["client", "cluster"] and Interrupts.name() == "SIGTERM"
