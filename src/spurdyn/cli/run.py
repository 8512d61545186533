"""``spurdyn run``: run cases and leave their results in folders, losing nothing.

Order of work: every case is read and checked and every output folder is checked
*before* anything is created, so bad input writes nothing. Each run then writes into a
hidden temporary folder beside its output folder, which is moved into place once all
files are written (an existing folder is replaced only with ``--force``). The solver
returns what it computed when it stops early (non-convergence, NaN, Ctrl-C); such a run
is written like a complete one with ``status = "incomplete"`` and its reason.
"""

from __future__ import annotations

import math
import os
import shutil
import signal
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Protocol, Sequence

from spurdyn.casefile import Case
from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.result import Result
from spurdyn.settings import RunCase

#: Exit statuses of ``spurdyn run``.
EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130

Progress = Callable[[int, float, float], None]


class Simulate(Protocol):
    def __call__(self, pair: GearPair, case: RunCase,
                 progress: Progress | None = None) -> Result: ...


def load_simulate() -> Simulate:
    """The solver's entry point ``spurdyn.solvers.loop.simulate``.

    Raises
    ------
    InputError
        If this installation has no solver yet.
    """
    try:
        from spurdyn.solvers.loop import simulate
    except ImportError as err:
        raise InputError("solver", f"spurdyn.solvers.loop.simulate is not available ({err})") from None
    return simulate


#: Models ``spurdyn run --model`` offers.
MODELS = ("fe", "lumped")


def simulate_lumped_run(pair: GearPair, case: RunCase, progress: Progress | None = None) -> Result:
    """The lumped model (:func:`spurdyn.lumped.simulate_lumped`, no damping) with the
    solver's call signature, for ``spurdyn run --model lumped``.

    Module-level so that ``--jobs`` can hand it to worker processes. The progress callback
    is called once, at the end (a lumped run takes a fraction of a second).
    """
    from spurdyn.lumped import simulate_lumped

    result = simulate_lumped(pair, case)
    if progress is not None and len(result.angle):
        progress(result.steps, float(result.angle[-1]), float(result.angle[-1]))
    return result


@dataclass(frozen=True)
class RunPlan:
    """One case and the folder its results go to."""

    case: Case
    out: Path
    force: bool = False
    vtu: bool = False


def _occupied(path: Path) -> bool:
    return path.exists() and (not path.is_dir() or any(path.iterdir()))


def plan_runs(cases: Sequence[Case], out: str | None, force: bool, vtu: bool = False,
              base: Path = Path("out")) -> list[RunPlan]:
    """Where each case's results go, refusing occupied folders (nothing is created).

    One case goes to ``out`` (default ``out/<case name>``); several go to
    ``<out>/<case name>`` (default ``out/<case name>``).

    Raises
    ------
    InputError
        If a folder is a file, or exists and is not empty while ``force`` is off.
    """
    plans = []
    for case in cases:
        if out is None:
            target = base / case.name
        elif len(cases) == 1:
            target = Path(out)
        else:
            target = Path(out) / case.name
        if target.exists() and not target.is_dir():
            raise InputError(str(target), "is a file, not a folder; give another --out")
        if _occupied(target) and not force:
            raise InputError(str(target), "exists and is not empty; use --force to replace it "
                             "or give another --out")
        for parent in target.parents:
            if parent.exists():
                if not parent.is_dir():
                    raise InputError(str(target), f"cannot be made: {parent} is a file")
                if not os.access(parent, os.W_OK | os.X_OK):
                    raise InputError(str(target), f"cannot be made: {parent} is not writable")
                break
        plans.append(RunPlan(case=case, out=target, force=force, vtu=vtu))
    names = [p.out.resolve() for p in plans]
    if len(set(names)) != len(names):
        raise InputError("--out", "two cases would write to the same folder")
    return plans


# -- progress --------------------------------------------------------------------------

class ProgressBar:
    """A tqdm bar of the angle reached, steps per second and time left.

    Shown only when ``enabled`` and the stream is a terminal: silent in pipes.
    """

    def __init__(self, name: str, enabled: bool = True, stream: Any = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.enabled = bool(enabled) and bool(isatty())
        self.name = name
        self.bar: Any = None
        self.start = time.perf_counter()

    def __call__(self, step: int, angle: float, total: float) -> None:
        if not self.enabled:
            return
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=round(math.degrees(total), 3), desc=self.name, unit="deg",
                            file=self.stream, dynamic_ncols=True, leave=True,
                            bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} deg "
                                       "[{elapsed}<{remaining}{postfix}]")
        self.bar.n = min(round(math.degrees(angle), 3), self.bar.total)
        elapsed = time.perf_counter() - self.start
        self.bar.set_postfix_str(f"{step / elapsed:,.0f} steps/s" if elapsed > 0 else "",
                                 refresh=False)
        self.bar.refresh()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


# -- interrupts ------------------------------------------------------------------------

class _Interrupts:
    """Counts Ctrl-C while still raising KeyboardInterrupt (the solver catches it)."""

    count = 0
    deferred = False

    @classmethod
    def handler(cls, signum: int, frame: Any) -> None:
        cls.count += 1
        if not cls.deferred:
            raise KeyboardInterrupt

    @classmethod
    @contextmanager
    def installed(cls) -> Iterator[None]:
        try:
            old = signal.signal(signal.SIGINT, cls.handler)
        except ValueError:  # not the main thread: leave signals alone
            yield
            return
        try:
            yield
        finally:
            signal.signal(signal.SIGINT, old)

    @classmethod
    @contextmanager
    def held(cls) -> Iterator[None]:
        """Hold Ctrl-C back (counted, not raised) while results are written."""
        cls.deferred = True
        try:
            yield
        finally:
            cls.deferred = False


# -- one run ---------------------------------------------------------------------------

def _free_name(target: Path) -> Path:
    """``target`` itself, or ``<target>-2``, ``<target>-3``, ... whichever is free."""
    k = 2
    while True:
        alt = target.with_name(f"{target.name}-{k}")
        if not alt.exists():
            return alt
        k += 1


def _move_into_place(tmp: Path, target: Path, force: bool = True) -> Path:
    """Move the written folder ``tmp`` to ``target``; return where it went.

    ``target`` was checked before the run, but another run may have filled it since:
    without ``force`` that folder is kept and the results go beside it under a free
    name, so neither is lost.
    """
    if target.exists():
        if target.is_dir() and not any(target.iterdir()):
            target.rmdir()
        elif not force:
            target = _free_name(target)
        else:
            old = target.with_name(f".{target.name}.old-{os.getpid()}")
            target.rename(old)
            tmp.rename(target)
            shutil.rmtree(old, ignore_errors=True)
            return target
    tmp.rename(target)
    return target


def execute(plan: RunPlan, simulate: Simulate, progress: bool = True) -> dict[str, Any]:
    """Run one case and write its folder; return the summary (plus ``out``).

    The results go to a temporary folder first and are moved into place when written.
    A ``KeyboardInterrupt`` that escapes the solver (it should not) leaves nothing.
    """
    from spurdyn.results.io import write_run

    target = plan.out
    made = [p for p in [target.parent, *target.parent.parents] if not p.exists()]
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(f".{target.name}.partial-{os.getpid()}")
    if tmp.exists():
        shutil.rmtree(tmp)
    bar = ProgressBar(plan.case.name, enabled=progress)
    try:
        tmp.mkdir()
        t0 = time.perf_counter()
        try:
            result = simulate(plan.case.pair, plan.case.run, bar)
        finally:
            bar.close()
        if not result.wall_s:
            result.wall_s = time.perf_counter() - t0
        with _Interrupts.held():
            summary = write_run(result, plan.case, tmp, vtu=plan.vtu)
            model = result.info.get("model") if isinstance(result.info, dict) else None
            if model and model != "fe":  # say which model made it (the FE solver's is implied)
                from spurdyn.results.io import SUMMARY_FILE, write_summary

                summary["model"] = model
                write_summary(summary, tmp / SUMMARY_FILE)
            final = _move_into_place(tmp, target, plan.force)
            if final != target:
                print(f"spurdyn: {target} was filled by another run meanwhile; "
                      f"{plan.case.name} written to {final} instead", file=sys.stderr)
                target = final
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
        if not target.exists():  # nothing came of it: remove the folders made for it
            for folder in made:
                try:
                    folder.rmdir()
                except OSError:
                    break
    summary["out"] = str(target)
    return summary


def _report(summary: dict[str, Any], quiet: bool) -> None:
    out = summary["out"]
    if summary["status"] == "complete":
        if not quiet:
            dyn = summary.get("dynamic_factor")
            peak = summary.get("peak_force_N")
            peak_s = "no contact" if peak is None else f"peak {peak:,.1f} N" + \
                (f" = {dyn:.3f} x static" if dyn is not None else "")
            print(f"{summary['case']}: complete, {summary['steps']:,} steps in "
                  f"{summary['wall_s']:.1f} s, {peak_s}, {summary['separations']} "
                  f"separation(s) -> {out}", flush=True)
            print(f"  plot: {Path(out) / 'contact_force.png'}", flush=True)
    else:
        print(f"spurdyn: {summary['case']} incomplete: {summary['reason'] or 'stopped'}; "
              f"{summary['steps']:,} steps ({summary['angle_deg']:.3f} deg) kept in {out}",
              file=sys.stderr, flush=True)


# -- several runs ----------------------------------------------------------------------

def _cases_bar(total: int, enabled: bool, stream: Any = None) -> Any:
    """A tqdm bar of the cases finished by ``--jobs`` workers (None in pipes or off)."""
    stream = sys.stderr if stream is None else stream
    if not (enabled and getattr(stream, "isatty", lambda: False)()):
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc="cases finished", unit="case", file=stream,
                dynamic_ncols=True, leave=True)


_WORKER_SIMULATE: Simulate | None = None


def _init_worker(simulate: Simulate | None) -> None:
    global _WORKER_SIMULATE
    _WORKER_SIMULATE = simulate
    signal.signal(signal.SIGINT, _Interrupts.handler)


def _worker(plan: RunPlan) -> dict[str, Any] | None:
    if _Interrupts.count:
        return None  # Ctrl-C was pressed: start nothing new
    simulate = _WORKER_SIMULATE or load_simulate()
    try:
        return execute(plan, simulate, progress=False)
    except KeyboardInterrupt:
        return None


def run_plans(plans: Sequence[RunPlan], simulate: Simulate, *, jobs: int = 1,
              progress: bool = True, quiet: bool = False) -> int:
    """Run every plan (side by side on ``jobs`` processes); return the exit status."""
    statuses: list[str] = []
    with _Interrupts.installed():
        _Interrupts.count = 0
        if jobs <= 1 or len(plans) <= 1:
            for plan in plans:
                if _Interrupts.count:
                    statuses.append("not run")
                    print(f"spurdyn: {plan.case.name} not run (interrupted)", file=sys.stderr)
                    continue
                try:
                    summary = execute(plan, simulate, progress=progress)
                except KeyboardInterrupt:
                    print(f"spurdyn: {plan.case.name} interrupted before any result; "
                          "nothing written", file=sys.stderr)
                    return EXIT_INTERRUPTED
                statuses.append(summary["status"])
                _report(summary, quiet)
        else:
            # The solver goes to the workers as an importable function (by reference).
            # The workers draw no bars of their own (they would overwrite each other):
            # the command shows the cases finished instead.
            cases_bar = _cases_bar(len(plans), progress)
            with ProcessPoolExecutor(max_workers=min(jobs, len(plans)),
                                     initializer=_init_worker, initargs=(simulate,)) as pool:
                futures = {pool.submit(_worker, p): p for p in plans}
                pending = set(futures)
                while pending:
                    try:
                        for fut in as_completed(pending):
                            pending.discard(fut)
                            plan = futures[fut]
                            if cases_bar is not None:
                                cases_bar.update(1)
                            try:
                                summary = fut.result()
                            except Exception as err:  # a worker died: report and go on
                                statuses.append("failed")
                                print(f"spurdyn: {plan.case.name} failed: {err!r}", file=sys.stderr)
                                continue
                            if summary is None:
                                statuses.append("not run")
                                print(f"spurdyn: {plan.case.name} not run (interrupted)",
                                      file=sys.stderr)
                                continue
                            statuses.append(summary["status"])
                            _report(summary, quiet)
                    except KeyboardInterrupt:
                        # Workers got Ctrl-C too: let them write what they have.
                        for fut in list(pending):
                            if fut.cancel():
                                pending.discard(fut)
                                statuses.append("not run")
                                print(f"spurdyn: {futures[fut].case.name} not run (interrupted)",
                                      file=sys.stderr)
            if cases_bar is not None:
                cases_bar.close()
    if statuses and all(s == "complete" for s in statuses):
        return EXIT_OK
    return EXIT_INCOMPLETE
