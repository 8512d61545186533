"""A Dask cluster of real processes on 127.0.0.1 for the sweep tests, that a test can break.

:class:`LoopbackCluster` starts ``dask scheduler`` and ``dask worker`` processes (over TCP,
or TLS with the certificates of :func:`make_certificates`) and kills them on demand;
:func:`slow_point` is a point function the workers import by name (this folder is on
their ``PYTHONPATH``) that marks when each point starts, so that a test can kill a
process in the middle of a point.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

from spurdyn.sweep.point import run_point

#: Where :func:`slow_point` marks the points it starts (set for the workers).
MARKS = "SPURDYN_TEST_MARKS"

#: The speed (rpm) whose point :func:`slow_point` makes last a few seconds.
SLOW_RPM = 12000.0

#: How long that point takes (s): long enough to be killed in the middle of.
SLOW_S = 4.0


def slow_point(task):
    """:func:`spurdyn.sweep.point.run_point`, the point at :data:`SLOW_RPM` after
    :data:`SLOW_S` s; each point writes ``<rpm>.started`` (holding the worker's process
    id) in ``$SPURDYN_TEST_MARKS`` first."""
    marks = os.environ.get(MARKS)
    if marks:
        (Path(marks) / f"{task.key.rpm:.0f}.started").write_text(str(os.getpid()))
    if task.key.rpm == SLOW_RPM:
        time.sleep(SLOW_S)
    return run_point(task)


def wait_for(path: Path, timeout_s: float = 120.0) -> Path:
    """Wait until ``path`` exists."""
    deadline = time.monotonic() + timeout_s
    while not path.exists():
        if time.monotonic() > deadline:
            raise TimeoutError(f"{path} did not appear within {timeout_s:g} s")
        time.sleep(0.05)
    return path


def free_port() -> int:
    """A port nobody listens on (now)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def dask(*args: str) -> list[str]:
    """The ``dask`` command of this environment."""
    return [str(Path(sys.executable).with_name("dask")), *args]


def make_certificates(folder: Path) -> dict[str, Path]:
    """A certificate authority and one certificate it signed (for 127.0.0.1), with
    ``openssl``: the files ``ca``, ``cert``, ``key``."""
    folder.mkdir(parents=True, exist_ok=True)
    ca, ca_key = folder / "ca.pem", folder / "ca.key"
    cert, key, csr = folder / "node.pem", folder / "node.key", folder / "node.csr"
    steps = (
        ["req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", ca_key, "-out", ca,
         "-days", "2", "-subj", "/CN=spurdyn test CA"],
        ["req", "-newkey", "rsa:2048", "-nodes", "-keyout", key, "-out", csr,
         "-subj", "/CN=127.0.0.1"],
        ["x509", "-req", "-in", csr, "-CA", ca, "-CAkey", ca_key, "-CAcreateserial",
         "-out", cert, "-days", "2"],
    )
    for step in steps:
        subprocess.run(["openssl", *map(str, step)], check=True, capture_output=True)
    return {"ca": ca, "cert": cert, "key": key}


class LoopbackCluster:
    """A scheduler and workers on 127.0.0.1, each a process of its own.

    Parameters
    ----------
    folder
        For the scheduler file and the marks of :func:`slow_point`.
    certificates
        :func:`make_certificates`'s files: a TLS cluster; ``None``: TCP.
    """

    def __init__(self, folder: Path, certificates: dict[str, Path] | None = None) -> None:
        self.folder = folder
        self.marks = folder / "marks"
        self.marks.mkdir(parents=True, exist_ok=True)
        self.tls = certificates
        self.port = free_port()
        self.address = f"{'tls' if certificates else 'tcp'}://127.0.0.1:{self.port}"
        self.env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path),
                    MARKS: str(self.marks)}
        self.scheduler: subprocess.Popen | None = None
        self.workers: list[subprocess.Popen] = []

    def _tls_args(self) -> list[str]:
        if self.tls is None:
            return []
        return ["--tls-ca-file", str(self.tls["ca"]), "--tls-cert", str(self.tls["cert"]),
                "--tls-key", str(self.tls["key"])]

    def _start(self, argv: list[str]) -> subprocess.Popen:
        return subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env=self.env, start_new_session=True)

    def start_scheduler(self) -> None:
        """Start the scheduler (again) on its port; wait until it listens."""
        scheduler_file = self.folder / "scheduler.json"
        scheduler_file.unlink(missing_ok=True)
        self.scheduler = self._start(dask(
            "scheduler", "--host", "127.0.0.1", "--port", str(self.port), "--no-dashboard",
            "--scheduler-file", str(scheduler_file),
            *(["--protocol", "tls"] if self.tls else []), *self._tls_args()))
        wait_for(scheduler_file, 60.0)
        time.sleep(0.2)
        assert json.loads(scheduler_file.read_text())["address"] == self.address

    def start_worker(self, nanny: bool = False) -> None:
        """Start one worker of one thread (without a nanny: nobody restarts it)."""
        self.workers.append(self._start(dask(
            "worker", self.address, "--host", "127.0.0.1", "--nworkers", "1",
            "--nthreads", "1", "--no-dashboard", *([] if nanny else ["--no-nanny"]),
            *self._tls_args())))

    def kill(self, proc: subprocess.Popen | None) -> None:
        """SIGKILL ``proc`` (and what it started) and reap it."""
        if proc is not None and proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        if proc is not None:
            proc.wait(timeout=20)

    def stop(self) -> None:
        """Stop every process of the cluster."""
        for proc in [*self.workers, self.scheduler]:
            if proc is not None and proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
        for proc in [*self.workers, self.scheduler]:
            if proc is None:
                continue
            try:
                proc.wait(timeout=5)       # test processes: no need to wait for a clean exit
            except subprocess.TimeoutExpired:
                self.kill(proc)
