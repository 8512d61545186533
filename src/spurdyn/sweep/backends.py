"""Where the points of a sweep run: in this process, or on a Dask cluster.

A backend turns a list of :class:`~spurdyn.sweep.point.PointTask` into a stream of
``(task, outcome, note)`` in the order the points finish: ``outcome`` is the
:class:`~spurdyn.sweep.point.PointOutcome`, or ``None`` when the point was not computed
(``note`` says why); ``task`` is ``None`` for a note on the cluster alone (a worker lost
and its points run again). The runner writes each outcome the moment it arrives.

:class:`DaskBackend` runs on a ``distributed`` client: a local cluster made by
:func:`local_backend` (one single-threaded worker process per job, on 127.0.0.1) or an
existing cluster reached by :func:`spurdyn.sweep.scheduler.scheduler_backend`.
:class:`SerialBackend` runs the points one after the other in this process (the Python
API, tests and debugging).
"""

from __future__ import annotations

import logging
import os
import signal
import time
import uuid
from collections import deque
from contextlib import contextmanager
from typing import Any, Callable, Iterator, Protocol, Sequence

from spurdyn.signals import Interrupts, ignored
from spurdyn.sweep.point import FAILED, PointOutcome, PointTask
from spurdyn.sweep.spec import expected_steps

PointFn = Callable[[PointTask], PointOutcome]
Stream = Iterator[tuple["PointTask | None", "PointOutcome | None", str]]

#: Seconds a cluster may have no worker before the sweep gives up on the rest.
NO_WORKER_GRACE_S = 120.0

#: Seconds the scheduler may leave a look at the cluster (once a second) unanswered
#: before the sweep counts it lost, keeping its finished points: a scheduler busy with
#: another user's large graph answers within seconds; a frozen one (its connection open,
#: nothing coming back) would hold the sweep for ever.
SILENCE_S = 60.0

#: Points submitted ahead of the workers, per worker thread (at least :data:`MIN_AHEAD`):
#: the scheduler keeps each worker fed, the longest points first, while the rest wait in
#: this process's queue. Submitted at once, a 10,000-point sweep took ~20 s to submit and
#: ~25 kB a point in this process, and a stop signal waited for ~25 s of cancelling
#: (docs/performance_sweep.md, "Many points").
AHEAD_PER_THREAD = 2
MIN_AHEAD = 4

#: Seconds to fetch a finished point's result before looking again (a result held by a
#: worker that has just died is lost and computed again).
RESULT_TIMEOUT_S = 30.0


class Backend(Protocol):
    """What the sweep runner needs of a place to run points."""

    description: str

    def run(self, tasks: Sequence[PointTask], fn: PointFn) -> Stream: ...

    def cancel(self) -> None: ...


def by_cost(tasks: Sequence[PointTask]) -> list[PointTask]:
    """The longest runs first (fewest idle workers at the end of a sweep)."""
    return sorted(tasks, key=lambda t: (-expected_steps(t.case), t.key))


# -- in this process -------------------------------------------------------------------

class SerialBackend:
    """Run the points one after the other in this process.

    The FE solver catches Ctrl-C and returns the run so far as ``incomplete``: such a
    point is not a result of the sweep, so the backend drops it and raises
    ``KeyboardInterrupt`` instead.
    """

    description = "this process"

    def run(self, tasks: Sequence[PointTask], fn: PointFn) -> Stream:
        for task in by_cost(tasks):
            with Interrupts.installed():
                before = Interrupts.count
                outcome = fn(task)
                if Interrupts.count != before:
                    raise KeyboardInterrupt
            yield task, outcome, ""

    def cancel(self) -> None:
        return None


# -- on a Dask cluster -----------------------------------------------------------------

class ClusterLost(RuntimeError):
    """The cluster went away in the middle of a sweep (its scheduler, or every worker)."""


def _failed(task: PointTask, reason: str) -> PointOutcome:
    return PointOutcome(key=task.key, status=FAILED, reason=reason, finished=time.time())


class DaskBackend:
    """Run the points on a ``distributed`` client, one task per point.

    The points are submitted the longest first (scheduler ``priority``), a few per worker
    thread ahead of the workers (:data:`AHEAD_PER_THREAD`), the rest waiting in this
    process; results are taken as they finish. A task whose worker died more often than the scheduler
    allows (``KilledWorker``) is a failed point; tasks cancelled or lost with the scheduler
    are not run. A worker lost while running points is noted (a stream item without a
    task). A lost connection to the scheduler, a scheduler silent for ``silence_s``
    (default :data:`SILENCE_S`), or a cluster without a worker for ``no_worker_grace_s``,
    raises :class:`ClusterLost`: the points not finished are given up
    (the runner marks them not run).
    """

    def __init__(self, client: Any, description: str,
                 no_worker_grace_s: float = NO_WORKER_GRACE_S,
                 silence_s: float | None = None) -> None:
        self.client = client
        self.description = description
        self.no_worker_grace_s = no_worker_grace_s
        self.silence_s = SILENCE_S if silence_s is None else silence_s
        self._lost = False
        self._pending: set[Any] = set()
        self._queue: deque[PointTask] = deque()
        self._tasks: dict[Any, PointTask] = {}
        self._token = ""
        self._events: list[dict[str, Any]] = []

    def _look(self) -> tuple[int, int]:
        """The cluster's workers and worker threads, asked of the scheduler within
        ``silence_s`` (a scheduler that cannot be reached reads as no workers).

        Raises
        ------
        ClusterLost
            The scheduler has not answered within ``silence_s``: it is frozen (its
            connection open, nothing coming back), and every wait on it would last forever.
        """
        try:
            found = self.client.sync(self.client.scheduler.identity,
                                     callback_timeout=self.silence_s)
        except TimeoutError:
            self._lost = True
            raise ClusterLost(f"the scheduler has not answered for {self.silence_s:g} s") from None
        except Exception:  # noqa: BLE001 - a lost scheduler reads as no workers
            return 0, 0
        workers = found.get("workers", {})
        return len(workers), sum(int(w.get("nthreads", 1)) for w in workers.values())

    def _submit_more(self, fn: PointFn, threads: int) -> None:
        """Submit queued points, the longest first, until :data:`AHEAD_PER_THREAD` points
        per worker thread (at least :data:`MIN_AHEAD`) are pending."""
        room = max(MIN_AHEAD, AHEAD_PER_THREAD * threads) - len(self._pending)
        while self._queue and room > 0:
            task = self._queue.popleft()
            fut = self.client.submit(fn, task, key=f"spurdyn-{task.key.stem}-{self._token}",
                                     pure=False, retries=0, priority=expected_steps(task.case))
            self._tasks[fut.key] = task
            self._pending.add(fut)
            room -= 1

    def _watch_losses(self) -> None:
        try:   # the scheduler's "all" topic says which tasks each lost worker was running
            self.client.subscribe_topic("all", lambda event: self._events.append(event[1]))
        except Exception:  # noqa: BLE001 - the sweep runs on without the notes
            pass

    def _wait_some(self) -> set[Any]:
        """The tasks finished within a second (none if none), or :class:`ClusterLost`."""
        from distributed import wait

        try:
            with self.client.as_current():
                return set(wait(list(self._pending), timeout=1.0,
                                return_when="FIRST_COMPLETED").done)
        except TimeoutError:
            return set()
        except Exception as err:  # noqa: BLE001 - the client cancels all on a lost link
            if self.client.status != "running":
                raise ClusterLost("lost the connection to the scheduler") from err
            raise

    def _losses(self) -> Iterator[str]:
        """A note per worker lost while running points of this sweep."""
        events, self._events = self._events, []
        for event in events:
            if event.get("action") != "remove-worker" or event.get("expected"):
                continue
            lost = sorted(self._tasks[k].key for k in event.get("processing-tasks", ())
                          if k in self._tasks)
            if lost:
                points = ", ".join(f"{k.rpm:,.6g} rpm" for k in lost)
                yield (f"a worker ({event.get('worker', '?')}) was lost while running "
                       f"{points}; {'it runs' if len(lost) == 1 else 'they run'} again on "
                       f"a worker of the cluster (up to distributed.scheduler."
                       f"allowed-failures times)")

    def run(self, tasks: Sequence[PointTask], fn: PointFn) -> Stream:
        self._queue = deque(by_cost(tasks))
        self._token = uuid.uuid4().hex[:8]
        self._watch_losses()
        no_worker_since: float | None = None
        while self._pending or self._queue:
            workers, threads = self._look()   # every second: a frozen scheduler is lost
            self._submit_more(fn, threads)
            done = self._wait_some()
            for note in self._losses():
                yield None, None, note
            if not done:
                if workers == 0:
                    no_worker_since = no_worker_since or time.monotonic()
                    if time.monotonic() - no_worker_since > self.no_worker_grace_s:
                        raise ClusterLost(f"no worker in the cluster for "
                                          f"{self.no_worker_grace_s:.0f} s")
                else:
                    no_worker_since = None
                continue
            for fut in sorted(done, key=lambda f: self._tasks[f.key].key):
                self._pending.discard(fut)
                yield from self._outcome(fut, self._tasks[fut.key])

    def _outcome(self, fut: Any, task: PointTask) -> Stream:
        """The finished task's point (nothing if its result died with its worker: the
        task is pending again)."""
        if fut.status == "finished":
            try:
                outcome = fut.result(timeout=RESULT_TIMEOUT_S)
            except TimeoutError:
                # The result died with its worker before it was fetched: the scheduler
                # computes it again (or the no-worker watch gives up).
                self._pending.add(fut)
                return
            except Exception as err:  # noqa: BLE001 - e.g. it cannot be unpickled
                if isinstance(err, OSError) or self.client.status != "running":
                    # the scheduler went between the task's end and its result's fetch
                    # (distributed's CommClosedError): the point is not failed, only not kept
                    raise ClusterLost("lost the connection to the scheduler") from err
                outcome = _failed(task, f"{type(err).__name__}: {err}")
            fut.release()
            yield task, outcome, ""
        elif fut.status == "error":
            err = fut.exception()
            yield task, _failed(task, f"{type(err).__name__}: {err}"), ""
        else:  # cancelled or lost
            yield task, None, f"task {fut.status} (lost its scheduler or cancelled)"

    def cancel(self) -> None:
        self._queue.clear()
        pending, self._pending = list(self._pending), set()
        if pending and not self._lost:    # a frozen scheduler would hold the call for ever
            try:
                self.client.cancel(pending, force=True)
            except Exception:  # noqa: BLE001 - the cluster may be gone already
                pass


def _quiet_distributed() -> None:
    """No log lines from ``distributed`` in this process (the sweep reports what happened)."""
    import distributed  # noqa: F401 - importing it sets its loggers' levels: quiet them after

    for name in ("distributed", "distributed.client", "distributed.scheduler",
                 "distributed.worker", "distributed.nanny", "distributed.core",
                 "distributed.deploy", "distributed.comm", "distributed.utils"):
        logging.getLogger(name).setLevel(logging.CRITICAL)


def default_jobs() -> int:
    """One worker per core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


@contextmanager
def local_backend(jobs: int) -> Iterator[DaskBackend]:
    """A local Dask cluster: ``jobs`` worker processes of one thread each, on 127.0.0.1.

    The scheduler hands a worker one point at a time (``worker-saturation`` 1.0), so the
    longest points start first and a worker that dies loses only the point it was running
    (the scheduler runs it again elsewhere, up to ``distributed.scheduler.allowed-failures``
    times, then the point is failed: ``KilledWorker``).

    The cluster (scheduler and workers) is closed when the block ends, also on Ctrl-C.
    """
    import dask
    from distributed import Client, LocalCluster

    _quiet_distributed()
    # One task at a time per worker: the scheduler keeps the queue (longest points first)
    # and a worker that dies takes only the point it was running with it.
    # Workers ignore Ctrl-C (the client stops the sweep and closes the cluster): SIG_IGN is
    # inherited by the processes spawned now, and the preload sets it in restarted ones.
    # A stop signal while the cluster starts is acted on once it can be closed: cut short,
    # the half-made cluster's own close at exit printed a traceback (AssertionError).
    before = Interrupts.count
    with Interrupts.held():
        with dask.config.set({"distributed.scheduler.worker-saturation": 1.0}), ignored():
            cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address=":0",
                                   # No dashboard; the scheduler's HTTP server (always on)
                                   # takes a free port instead of warning that 8787 is taken.
                                   scheduler_kwargs={"dashboard": False},
                                   silence_logs=logging.CRITICAL,
                                   preload=["spurdyn.sweep.worker_setup"])
        client = Client(cluster)
    try:
        if Interrupts.count != before:
            raise KeyboardInterrupt
        yield DaskBackend(client, f"a local Dask cluster of {jobs} worker process"
                          f"{'es' if jobs > 1 else ''}")
    finally:
        _close(client, cluster)


def _close(client: Any, cluster: Any = None) -> None:
    # A second Ctrl-C or SIGTERM must not leave workers behind.
    with ignored((signal.SIGINT, signal.SIGTERM)):
        try:   # else the scheduler sends this client's own removal to it as it closes
            client.unsubscribe_topic("all")
        except Exception:  # noqa: BLE001
            pass
        try:
            client.close(timeout=10)
        except Exception:  # noqa: BLE001
            pass
        if cluster is not None:
            try:
                cluster.close(timeout=10)
            except Exception:  # noqa: BLE001
                pass
