"""``spurdyn sweep`` on Dask clusters of real processes, and clusters that fail: a local
cluster, an external scheduler and worker on 127.0.0.1 (over TCP and TLS), a scheduler
that never answers, a worker killed in the middle of a point, a scheduler lost in the
middle of a sweep; every finished point kept, the rest computed by the same command, no
process of the command left behind.

The clusters are built by :mod:`cluster_helpers`; the points are the lumped model's
(no compiled kernels), one of them made slow enough to be killed in the middle of.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import xarray as xr

import cluster_helpers as ch
from spurdyn.cli.main import main
from spurdyn.sweep import backends
from spurdyn.sweep import point as point_mod
from spurdyn.sweep.point import run_point
from spurdyn.sweep.store import STATUS_CODES

COMPLETE, NOT_RUN = STATUS_CODES["complete"], STATUS_CODES["not_run"]
RPMS = "8000,10000,12000"      # the longest (slowest) first: 12,000 rpm runs last


def sweep(capsys, *argv):
    code = main(["sweep", *[str(a) for a in argv]])
    out = capsys.readouterr()
    return code, out.out, out.err


def statuses(folder: Path) -> dict[float, int]:
    with xr.open_dataset(folder / "sweep_lumped.nc", engine="netcdf4") as ds:
        return {float(r): int(s) for r, s in zip(ds["rpm"].values, ds["status"].values)}


@pytest.fixture
def cluster(tmp_path):
    """A TCP scheduler on 127.0.0.1 (no worker yet), stopped afterwards."""
    c = ch.LoopbackCluster(tmp_path / "cluster")
    try:
        c.start_scheduler()
        yield c
    finally:
        c.stop()


@pytest.fixture
def slow(monkeypatch):
    """The sweep's points computed by :func:`cluster_helpers.slow_point`."""
    monkeypatch.setattr(point_mod, "run_point", ch.slow_point)


def _kill_when_started(cluster: ch.LoopbackCluster, proc_of, kept: Path | None = None) -> threading.Thread:
    """In the background: once the slow point has started (and, given the sweep's folder
    ``kept``, the two other points are kept in it: a worker's threads may still be finishing
    one when the slow point starts), SIGKILL ``proc_of()``."""
    def kill() -> None:
        ch.wait_for(cluster.marks / f"{ch.SLOW_RPM:.0f}.started")
        deadline = time.monotonic() + 120.0
        while kept is not None and len(list((kept / "points").glob("*.json"))) < 2:
            if time.monotonic() > deadline:
                raise TimeoutError(f"the fast points were not kept in {kept}")
            time.sleep(0.05)
        cluster.kill(proc_of())

    thread = threading.Thread(target=kill, daemon=True)
    thread.start()
    return thread


# -- reaching a scheduler --------------------------------------------------------------

def test_silent_port_refused_in_bounded_time(tmp_path, capsys):
    """A port that accepts connections and never speaks: one line naming --scheduler,
    exit 2, nothing written, within the timeout (it used to wait forever)."""
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen(8)
        address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
        t0 = time.monotonic()
        code, out, err = sweep(capsys, "paper-fig8", "--rpm", "1000", "--model", "lumped",
                               "--out", tmp_path / "sw", "--scheduler", address,
                               "--scheduler-timeout", "1.5")
        took = time.monotonic() - t0
    assert code == 2 and out == "" and not (tmp_path / "sw").exists()
    assert err == (f"spurdyn: error: --scheduler: no Dask scheduler answered at {address} "
                   f"within 1.5 s (--scheduler-timeout S waits longer)\n")
    assert 1.5 <= took < 1.5 + 5.0    # the handshake's bound, and not much more


def test_closed_port_refused(tmp_path):
    from spurdyn.errors import InputError
    from spurdyn.sweep.scheduler import scheduler_backend

    with pytest.raises(InputError, match="no Dask scheduler answered at .* within 1 s"):
        with scheduler_backend(f"tcp://127.0.0.1:{ch.free_port()}", timeout_s=1.0):
            pass


# -- a cluster that works --------------------------------------------------------------

@pytest.mark.slow
def test_local_cluster_of_processes(tmp_path, capsys):
    out = tmp_path / "sw"
    code, stdout, err = sweep(capsys, "paper-fig8", "--rpm", "8000:20000:4000", "--model",
                              "lumped", "--jobs", "2", "--out", out)
    assert code == 0, err
    assert "4 computed on 2 local workers" in stdout
    workers = {json.loads(p.read_text())["worker"] for p in (out / "points").glob("*.json")}
    assert all(w.split(":")[1] != str(os.getpid()) for w in workers)  # other processes
    assert set(statuses(out).values()) == {COMPLETE}


@pytest.mark.slow
def test_external_scheduler_on_loopback(tmp_path, capsys, cluster):
    cluster.start_worker()
    out = tmp_path / "sw"
    code, stdout, err = sweep(capsys, "paper-fig8", "--rpm", "10000:20000:5000", "--model",
                              "lumped", "--scheduler", cluster.address, "--out", out)
    assert code == 0, err
    assert f"3 computed on {cluster.address}" in stdout
    workers = {json.loads(p.read_text())["worker"] for p in (out / "points").glob("*.json")}
    assert len(workers) == 1 and workers.pop().split(":")[1] != str(os.getpid())
    assert set(statuses(out).values()) == {COMPLETE}


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("openssl") is None, reason="needs openssl for certificates")
def test_tls_sweep(tmp_path, capsys):
    """A TLS cluster with certificates of a CA made here: the sweep runs with the CA and a
    certificate it signed, and a client without them is refused in one line."""
    certs = ch.make_certificates(tmp_path / "certs")
    c = ch.LoopbackCluster(tmp_path / "cluster", certificates=certs)
    try:
        c.start_scheduler()
        c.start_worker()
        assert c.address.startswith("tls://")
        out = tmp_path / "sw"
        tls = ["--tls-ca-file", certs["ca"], "--tls-cert", certs["cert"],
               "--tls-key", certs["key"]]
        code, stdout, err = sweep(capsys, "paper-fig8", "--rpm", "10000,15000", "--model",
                                  "lumped", "--scheduler", c.address, "--out", out, *tls)
        assert code == 0, err
        assert f"2 computed on {c.address}" in stdout
        assert set(statuses(out).values()) == {COMPLETE}

        # the same scheduler over plain TCP: refused (it speaks TLS only)
        plain = c.address.replace("tls://", "tcp://")
        code, _, err = sweep(capsys, "paper-fig8", "--rpm", "10000", "--model", "lumped",
                             "--scheduler", plain, "--scheduler-timeout", "2",
                             "--out", tmp_path / "plain")
        assert code == 2 and err.startswith(f"spurdyn: error: --scheduler: no Dask "
                                            f"scheduler answered at {plain}")
        assert err.count("\n") == 1 and not (tmp_path / "plain").exists()

        # a certificate of another authority: refused (the scheduler does not admit it)
        other = ch.make_certificates(tmp_path / "other")
        code, _, err = sweep(capsys, "paper-fig8", "--rpm", "10000", "--model", "lumped",
                             "--scheduler", c.address, "--scheduler-timeout", "2",
                             "--out", tmp_path / "other-sw", "--tls-ca-file", other["ca"],
                             "--tls-cert", other["cert"], "--tls-key", other["key"])
        assert code == 2 and err.startswith(f"spurdyn: error: --scheduler: no Dask "
                                            f"scheduler answered at {c.address}")
        assert err.count("\n") == 1 and not (tmp_path / "other-sw").exists()
    finally:
        c.stop()


# -- a cluster that fails --------------------------------------------------------------

@pytest.mark.slow
def test_worker_killed_mid_point_then_same_command_resumes(tmp_path, capsys, cluster, slow,
                                                           monkeypatch):
    """The only worker (no nanny) is SIGKILLed in the middle of the last point: the two
    finished points are kept, the sweep stops once the cluster has had no worker for the
    grace period, and the same command with a worker again computes only the third."""
    monkeypatch.setattr(backends, "NO_WORKER_GRACE_S", 2.0)
    cluster.start_worker()
    argv = ["paper-fig8", "--rpm", RPMS, "--model", "lumped", "--scheduler",
            cluster.address, "--out", tmp_path / "sw", "--quiet"]
    killer = _kill_when_started(cluster, lambda: cluster.workers[-1], kept=tmp_path / "sw")
    code, _, err = sweep(capsys, *argv)
    killer.join(timeout=5)
    assert code == 1
    lost, stopped = err.splitlines()
    assert lost.startswith("spurdyn: a worker (tcp://127.0.0.1:")
    assert lost.endswith(") was lost while running 12,000 rpm; it runs again on a worker of "
                         "the cluster (up to distributed.scheduler.allowed-failures times)")
    assert stopped == (f"spurdyn: sweep stopped (ClusterLost: no worker in the cluster for "
                       f"2 s): 2 of 3 points kept in {tmp_path / 'sw'}; run the same command "
                       f"to compute the rest")
    assert statuses(tmp_path / "sw") == {8000.0: COMPLETE, 10000.0: COMPLETE,
                                         12000.0: NOT_RUN}

    cluster.start_worker()
    code, out, err = sweep(capsys, *argv[:-1])
    assert code == 0, err
    assert f"1 computed on {cluster.address}, 2 already in" in out
    assert set(statuses(tmp_path / "sw").values()) == {COMPLETE}


@pytest.mark.slow
def test_scheduler_lost_mid_sweep_then_same_command_resumes(tmp_path, capsys, cluster, slow):
    """The scheduler is SIGKILLed in the middle of the last point: the sweep says so at
    once, keeps the finished points, and the same command on a new scheduler at the same
    address computes only the rest."""
    cluster.start_worker()
    argv = ["paper-fig8", "--rpm", RPMS, "--model", "lumped", "--scheduler",
            cluster.address, "--out", tmp_path / "sw"]
    killer = _kill_when_started(cluster, lambda: cluster.scheduler, kept=tmp_path / "sw")
    t0 = time.monotonic()
    code, _, err = sweep(capsys, *argv)
    killer.join(timeout=5)
    assert code == 1
    assert ("spurdyn: sweep stopped (ClusterLost: lost the connection to the scheduler): "
            f"2 of 3 points kept in {tmp_path / 'sw'}") in err
    assert time.monotonic() - t0 < 60.0
    assert statuses(tmp_path / "sw")[12000.0] == NOT_RUN

    for worker in cluster.workers:       # the old worker belonged to the old scheduler
        cluster.kill(worker)
    cluster.start_scheduler()
    cluster.start_worker()
    code, out, err = sweep(capsys, *argv)
    assert code == 0, err
    assert f"1 computed on {cluster.address}, 2 already in" in out
    assert set(statuses(tmp_path / "sw").values()) == {COMPLETE}


def _session(sid: int) -> list[int]:
    """The processes of session ``sid`` still alive."""
    import psutil

    found = []
    for proc in psutil.process_iter():
        try:
            if os.getsid(proc.pid) == sid and proc.status() != psutil.STATUS_ZOMBIE:
                found.append(proc.pid)
        except (ProcessLookupError, psutil.Error):
            pass
    return found


@pytest.mark.slow
def test_local_worker_killed_mid_point_and_no_process_left(tmp_path):
    """``spurdyn sweep --jobs 1`` as a command of its own: its worker process SIGKILLed in
    the middle of a point is restarted, the point runs again (and the command says so),
    every point completes, and no process of the command outlives it."""
    marks = tmp_path / "marks"
    marks.mkdir()
    tests = str(Path(__file__).resolve().parent)
    code = ("import sys; import cluster_helpers as ch; from spurdyn.sweep import point; "
            "point.run_point = ch.slow_point; from spurdyn.cli.command import entry; entry()")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([tests, *sys.path]), ch.MARKS: str(marks)}
    proc = subprocess.Popen([sys.executable, "-c", code, "sweep", "paper-fig8", "--rpm", RPMS,
                             "--model", "lumped", "--jobs", "1", "--out", str(tmp_path / "sw")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True)
    try:
        started = ch.wait_for(marks / f"{ch.SLOW_RPM:.0f}.started")
        worker = int(started.read_text())
        assert worker != proc.pid and os.getsid(worker) == proc.pid
        os.kill(worker, signal.SIGKILL)
        out, err = proc.communicate(timeout=180)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 0, err
    assert "was lost while running 12,000 rpm" in err
    assert "3 computed on 1 local worker" in out
    assert set(statuses(tmp_path / "sw").values()) == {COMPLETE}
    deadline = time.monotonic() + 10
    while _session(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert _session(proc.pid) == []


def _dying_point(task):
    """A point function whose worker process dies at 10,000 rpm (importable by workers)."""
    if task.key.rpm == 10000.0:
        time.sleep(1.0)  # let the client fetch the point finished before on this worker
        os._exit(3)
    return run_point(task)


@pytest.mark.slow
def test_worker_dying_too_often_fails_only_its_point(tmp_path):
    import dask
    import distributed  # noqa: F401 - its defaults must be loaded before config.set

    from spurdyn.case import preset_case
    from spurdyn.sweep.backends import local_backend
    from spurdyn.sweep.runner import run_sweep
    from spurdyn.sweep.spec import SweepPlan

    plan = SweepPlan(case=preset_case("paper-fig8"), model="lumped",
                     rpms=(8000.0, 10000.0, 12000.0), torques=None, out=tmp_path / "sw")
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with local_backend(1) as backend:
            report = run_sweep(plan, backend, progress=False, point_fn=_dying_point)
    status = report.dataset["status"]
    assert int(status.sel(rpm=10000.0)) == STATUS_CODES["failed"]
    assert "KilledWorker" in str(report.dataset["reason"].sel(rpm=10000.0).values)
    assert (status.sel(rpm=[8000.0, 12000.0]).values == COMPLETE).all()
    assert report.computed == 3 and len(list((tmp_path / "sw" / "points").glob("*"))) == 3
