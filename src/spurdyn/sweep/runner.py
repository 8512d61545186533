"""Run a sweep: compute the points that are missing, write each the moment it finishes,
then assemble ``sweep_<model>.nc``, ``sweep.nc`` and ``dynamic_factor.png``.

A point already in the folder with a final status (complete or incomplete) is not
computed again (``force`` recomputes it); failed and missing points are. Ctrl-C, a lost
scheduler or a cluster without workers stop the sweep: the points finished so far are
kept, the rest are marked ``not_run`` with the reason, and the same command finishes
the job later.
"""

from __future__ import annotations

import asyncio
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Iterator, TextIO

import xarray as xr

from spurdyn.case.file import Case
from spurdyn.result import Result
from spurdyn.signals import Interrupts
from spurdyn.sweep import point as _point
from spurdyn.sweep.backends import Backend, PointFn
from spurdyn.sweep.point import COMPLETE, FAILED, INCOMPLETE, PointOutcome, PointTask
from spurdyn.sweep.resonance import ResonanceEstimate
from spurdyn.sweep.spec import PointKey, SweepPlan, expected_steps, settings_dict
from spurdyn.sweep.store import (FINAL, NOT_RUN, PNG_FILE, point_record, run_path,
                                 statuses, stored_points, sweep_dataset, write_point,
                                 write_sweep_files)


@dataclass(frozen=True)
class SweepReport:
    """What a sweep did.

    Attributes
    ----------
    plan
        The sweep.
    dataset
        This model's sweep (what ``sweep_<model>.nc`` holds).
    computed
        Points computed by this command (whatever their outcome).
    reused
        Points found in the folder and not computed again.
    counts
        Points per status (:data:`spurdyn.sweep.store.STATUS_CODES`).
    interrupted
        Ctrl-C stopped the sweep.
    stopped
        Why the sweep stopped early other than Ctrl-C ("" if it did not).
    files
        The files written (``sweep_<model>.nc``, ``sweep.nc``, the picture).
    wall_s
        Wall-clock time of the sweep (s).
    """

    plan: SweepPlan
    dataset: xr.Dataset
    computed: int
    reused: int
    counts: dict[str, int]
    interrupted: bool = False
    stopped: str = ""
    files: tuple[Path, ...] = ()
    wall_s: float = 0.0

    @property
    def all_complete(self) -> bool:
        return self.counts.get(COMPLETE, 0) == sum(self.counts.values())


# -- progress --------------------------------------------------------------------------

class SweepProgress:
    """A tqdm bar: points done and failed, time left (weighted by each point's steps).

    Shown only when ``enabled`` and the stream is a terminal: silent in pipes.
    """

    def __init__(self, label: str, total_cost: int, n_points: int, enabled: bool = True,
                 stream: TextIO | None = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.enabled = bool(enabled) and bool(isatty()) and n_points > 0
        self.label, self.n_points, self.done, self.failed = label, n_points, 0, 0
        self.bar: Any = None
        if self.enabled:
            from tqdm import tqdm

            self.bar = tqdm(total=max(total_cost, 1), desc=label, file=self.stream,
                            dynamic_ncols=True, leave=True, unit="step", unit_scale=True,
                            bar_format="{desc} {percentage:3.0f}%|{bar}| "
                                       "[{elapsed}<{remaining}]")
            self._postfix()

    def _postfix(self) -> None:
        if self.bar is not None:
            self.bar.set_description_str(f"{self.label}: {self.done}/{self.n_points} points, "
                                         f"{self.failed} not complete,", refresh=True)

    def update(self, cost: int, ok: bool) -> None:
        self.done += 1
        self.failed += 0 if ok else 1
        if self.bar is not None:
            self.bar.update(cost)
            self._postfix()

    def write(self, line: str) -> None:
        """Print a line on stderr without breaking the bar."""
        if self.bar is not None:
            self.bar.write(line, file=self.stream)
        else:
            print(line, file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


# -- writing ---------------------------------------------------------------------------

def write_run_folder(out: Path, key: PointKey, case: Case, result: Result,
                     png: bool = True) -> Path:
    """Write a point's whole run folder (``spurdyn run``'s layout) to ``out/runs/``
    (:func:`spurdyn.results.folder.write_run_folder`)."""
    from spurdyn.results.folder import write_run_folder as write_folder

    target = run_path(out, key)
    target.parent.mkdir(parents=True, exist_ok=True)
    return write_folder(result, case, target, force=True, png=png)[1]


def short_error(err: BaseException, limit: int = 240) -> str:
    """``Type: first line of the message``, at most ``limit`` characters."""
    lines = str(err).strip().splitlines()
    text = f"{type(err).__name__}: {lines[0]}" if lines else type(err).__name__
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _describe(key: PointKey) -> str:
    size = "" if key.size is None else f", fault size {key.size:g} m"
    return f"{key.model} {key.rpm:,.6g} rpm, {key.torque:g} N m{size}"


def _stored_and_todo(plan: SweepPlan) -> tuple[dict[PointKey, dict[str, Any]], list[PointKey]]:
    keys = plan.keys()
    stored = {} if plan.force else stored_points(plan.out, keys)
    final = {k for k, r in stored.items() if r["status"] in FINAL}
    if plan.keep_runs:  # a final point without its run folder is computed again
        final = {k for k in final if run_path(plan.out, k).is_dir()}
    return stored, [k for k in keys if k not in final]


def _task(plan: SweepPlan, key: PointKey) -> PointTask:
    """A point's task; a fault sweep's follows the faulty gear's signals."""
    if plan.faults is None:
        return PointTask(key, plan.point_case(key), plan.keep_runs)
    return PointTask(key, plan.point_case(key), plan.keep_runs, follow=plan.faults.fault.gear,
                     samples=plan.faults.samples)


def points_to_compute(plan: SweepPlan) -> list[PointKey]:
    """The points of ``plan`` that :func:`run_sweep` would compute.

    Every point unless ``plan.force`` is off and its folder holds it with a final status
    (complete or incomplete; with ``keep_runs``, also its run folder).
    """
    return _stored_and_todo(plan)[1]


def _point_stream(plan: SweepPlan, backend: Backend, tasks: list[PointTask],
                  records: dict[PointKey, dict[str, Any]], fn: PointFn
                  ) -> Iterator[tuple[PointTask | None, PointOutcome | None, str]]:
    """The points' outcomes as they finish: a continuation's chains in this process
    (:func:`_chain`), the others on ``backend`` (nothing when there are no tasks)."""
    if plan.continuation is not None:
        return _chain(plan, tasks, records, fn)
    return backend.run(tasks, fn) if tasks else iter(())


def _take_points(stream_: Iterator[tuple[PointTask | None, PointOutcome | None, str]],
                 backend: Backend,
                 out: Path, settings: dict[PointKey, dict[str, Any]], cost: dict[PointKey, int], bar: SweepProgress,
                 signals_before: int, records: dict[PointKey, dict[str, Any]],
                 png: bool = True) -> tuple[set[PointKey], dict[PointKey, str], bool, str]:
    """Write each point the moment it finishes, until the stream ends or the sweep stops.

    Parameters
    ----------
    stream_
        The points' outcomes (:func:`_point_stream`); closed at the end.
    backend
        Cancelled if the sweep stops early.
    out
        The sweep's folder.
    settings
        Each point's case's settings, stored with it (a fault sweep's points differ in
        their fault's size).
    cost
        Each point's expected steps (the bar's weights).
    bar
        The progress bar, closed at the end.
    signals_before
        :attr:`Interrupts.count` before the points started.
    records
        The points' records, by key: each point written is added.
    png
        Draw the pictures of the run folders kept.

    Returns
    -------
    finished
        The points written.
    missing
        The points that did not run, with why (as the stream said).
    interrupted
        Ctrl-C (or a stop signal) stopped the sweep.
    stopped
        Why the sweep stopped otherwise ("" if it did not).
    """
    finished: set[PointKey] = set()
    missing: dict[PointKey, str] = {}
    interrupted, stopped = False, ""
    try:
        for task, outcome, note in stream_:
            if task is None:       # a note on the cluster: a worker lost, its points rerun
                bar.write(f"spurdyn: {note}")
                continue
            if outcome is None:
                missing[task.key] = note or "not run"
                continue
            with Interrupts.held():
                write_point(out, outcome, settings[outcome.key])
                if outcome.result is not None:
                    write_run_folder(out, task.key, task.case, outcome.result, png)
                records[task.key] = point_record(_without_result(outcome))
                finished.add(task.key)
            bar.update(cost[task.key], outcome.status == COMPLETE)
            if outcome.status != COMPLETE:
                bar.write(f"spurdyn: {_describe(task.key)}: {outcome.status}: {outcome.reason}")
            if Interrupts.count != signals_before:  # a stop signal came while writing
                raise KeyboardInterrupt
    except KeyboardInterrupt:
        interrupted = True
        backend.cancel()
    except (Exception, asyncio.CancelledError) as err:  # noqa: BLE001 - the cluster failed
        stopped = short_error(err)
        backend.cancel()
    finally:
        bar.close()
        close = getattr(stream_, "close", None)
        if close is not None:
            close()
    return finished, missing, interrupted, stopped


def _mark_missing(tasks: list[PointTask], finished: set[PointKey], missing: dict[PointKey, str],
                  records: dict[PointKey, dict[str, Any]], interrupted: bool, stopped: str) -> None:
    """Mark each task neither finished nor missing yet as missing, with why the sweep
    stopped, and drop the old unfinished records of the missing points (they give way to
    ``not_run``); ``missing`` and ``records`` are changed in place."""
    for task in tasks:
        if task.key not in finished and task.key not in missing:
            missing[task.key] = (Interrupts.stopped() if interrupted else
                                 f"sweep stopped: {stopped}" if stopped else "not run")
    for key in missing:  # an old failed record gives way to "not run"
        if key in records and records[key]["status"] not in FINAL:
            del records[key]


def _write_results(plan: SweepPlan, records: dict[PointKey, dict[str, Any]],
                   missing: dict[PointKey, str], resonance: ResonanceEstimate
                   ) -> tuple[xr.Dataset, tuple[Path, ...]]:
    """Assemble and write ``sweep_<model>.nc``, ``sweep.nc`` and the picture (a fault
    sweep: ``fault_sweep.nc``), held against Ctrl-C; the dataset and the files."""
    out = plan.out
    if plan.faults is not None:
        from spurdyn.sweep.fault_store import write_fault_sweep

        with Interrupts.held():
            out.mkdir(parents=True, exist_ok=True)
            return write_fault_sweep(plan, records, missing, resonance.attrs())
    with Interrupts.held():
        out.mkdir(parents=True, exist_ok=True)
        ds = sweep_dataset(plan, records, missing, extra_attrs=resonance.attrs())
        own, combined = write_sweep_files(out, ds)
        png = out / PNG_FILE
        from spurdyn.sweep.plot import plot_sweep_folder

        plot_sweep_folder(out, png, resonance)
    return ds, (own, combined, png)


def run_sweep(plan: SweepPlan, backend: Backend, *, resonance: ResonanceEstimate | None = None,
              progress: bool = True, point_fn: PointFn | None = None,
              stream: TextIO | None = None) -> SweepReport:
    """Run the points of ``plan`` that are missing from its folder on ``backend``.

    Parameters
    ----------
    plan
        The sweep (see :class:`~spurdyn.sweep.spec.SweepPlan`); its folder is created.
    backend
        Where the points run (:mod:`spurdyn.sweep.backends`).
    resonance
        The natural-frequency estimate stored with the results and marked on the picture;
        ``None`` computes it from the case.
    progress
        Draw a progress bar on ``stream`` (default stderr) when it is a terminal.
    point_fn
        The function computing one point (default :func:`spurdyn.sweep.point.run_point`).

    Returns
    -------
    SweepReport
        Also written: ``sweep_<model>.nc``, ``sweep.nc``, ``dynamic_factor.png``.

    Raises
    ------
    KeyboardInterrupt
        A stop signal came before any point finished: nothing was written.
    """
    t0 = time.perf_counter()
    if resonance is None:
        from spurdyn.sweep.resonance import resonance_estimate

        resonance = resonance_estimate(plan.case, plan.model)
    fn = point_fn if point_fn is not None else _point.run_point
    out = plan.out
    keys = plan.keys()
    stored, todo = _stored_and_todo(plan)
    records: dict[PointKey, dict[str, Any]] = dict(stored)
    tasks = [_task(plan, k) for k in todo]
    cost = {t.key: expected_steps(t.case) for t in tasks}
    settings = {t.key: settings_dict(t.case) for t in tasks}

    bar = SweepProgress(f"{plan.model} sweep", sum(cost.values()), len(tasks),
                        enabled=progress, stream=stream)
    signals_before = Interrupts.count
    stream_ = _point_stream(plan, backend, tasks, records, fn)
    finished, missing, interrupted, stopped = _take_points(
        stream_, backend, out, settings, cost, bar, signals_before, records, plan.run_pictures)
    if interrupted and not finished:
        # As a run stopped before any result: nothing written (the folder is made by the
        # first point written), the folder as it was; main says which signal it was.
        raise KeyboardInterrupt
    _mark_missing(tasks, finished, missing, records, interrupted, stopped)
    ds, files = _write_results(plan, records, missing, resonance)
    return SweepReport(plan=plan, dataset=ds, computed=len(finished),
                       reused=len(keys) - len(tasks), counts=statuses(ds),
                       interrupted=interrupted, stopped=stopped, files=files,
                       wall_s=time.perf_counter() - t0)


def _chain(plan: SweepPlan, tasks: list[PointTask], records: dict[PointKey, dict[str, Any]],
           fn: PointFn) -> Iterator[tuple[PointTask, PointOutcome | None, str]]:
    """A continuation's points, one after the other in this process: per torque, the
    speeds up or down, each point starting from the previous speed's end state (a stored
    point's, or the one just computed); a point after one that failed or stopped early
    starts on its own again."""
    todo = {t.key: t for t in tasks}
    for torque in plan.torque_values:
        chain = [k for k in plan.keys() if k.torque == torque]
        if plan.continuation == "down":
            chain.reverse()
        state: tuple[float, ...] | None = None
        for key in chain:
            task = todo.get(key)
            if task is not None:
                if state is not None:
                    run = task.case.run.with_(start_state=state)
                    task = PointTask(key, replace(task.case, run=run), task.keep_result)
                with Interrupts.installed():
                    before = Interrupts.count
                    outcome = fn(task)
                    if Interrupts.count != before:
                        raise KeyboardInterrupt
                yield task, outcome, ""
                figures, status = outcome.figures, outcome.status
            else:
                record = records.get(key, {})
                figures, status = record, record.get("status")
            end = (figures.get("end_transmission_error"), figures.get("end_transmission_error_slope"))
            if figures.get("end_state") is not None:       # the sector model's whole state
                state = tuple(figures["end_state"]) if status == COMPLETE else None
            else:
                state = (float(end[0]), float(end[1])) if status == COMPLETE and None not in end else None


def _without_result(outcome: PointOutcome) -> PointOutcome:
    from dataclasses import replace

    return replace(outcome, result=None) if outcome.result is not None else outcome


__all__ = ["SweepProgress", "SweepReport", "points_to_compute", "run_sweep", "write_run_folder",
           "COMPLETE", "INCOMPLETE", "FAILED", "NOT_RUN"]
