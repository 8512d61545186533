"""``spurdyn run``: run cases and leave their results in folders, losing nothing.

Order of work: every case is read and checked and every output folder is checked
*before* anything is created, so bad input writes nothing. Each run then writes into a
hidden temporary folder beside its output folder, which is moved into place once all
files are written (an existing folder is replaced only with ``--force``; see
:mod:`spurdyn.results.folder`). The solver returns what it computed when it stops early
(non-convergence, NaN, Ctrl-C, SIGTERM); such a run is written like a complete one with
``status = "incomplete"`` and its reason. Stop signals are handled by
:mod:`spurdyn.signals`: one that lands after the solver's loop has ended waits until the
files are written.
"""

from __future__ import annotations

import math
import os
import signal
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from spurdyn.case.file import Case
from spurdyn.errors import InputError
from spurdyn.settings import DEFAULT_MODEL
from spurdyn.signals import Interrupts, install_in_worker
from spurdyn.simulators import MODELS, Simulate

#: Exit statuses of ``spurdyn run`` (a stop signal before any result: 128 + signal).
EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130


def load_simulate(model: str = DEFAULT_MODEL) -> Simulate:
    """The entry of ``model`` (:data:`spurdyn.simulators.MODELS`), called to simulate (a seam
    the tests replace with a fake solver). Every model is part of the package: a solver that
    fails to import is a bug, and its ``ImportError`` is not turned into a refusal."""
    return MODELS[model]


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

    Shown only when ``enabled`` and the stream is a terminal: silent in pipes. The rate
    counts from the first report on, so the compilation of a first run (before the first
    chunk of steps returns) does not enter it.
    """

    def __init__(self, name: str, enabled: bool = True, stream: Any = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.enabled = bool(enabled) and bool(isatty())
        self.name = name
        self.bar: Any = None
        self.first: tuple[int, float] | None = None

    def rate(self, step: int) -> float | None:
        """Steps per second since the first report (``None`` before the second)."""
        now = time.perf_counter()
        if self.first is None:
            self.first = (step, now)
            return None
        step0, t0 = self.first
        return (step - step0) / (now - t0) if now > t0 and step > step0 else None

    def __call__(self, step: int, angle: float, total: float) -> None:
        if not self.enabled:
            return
        if self.bar is None:
            from tqdm import tqdm

            # Without tqdm's monitor thread (it tunes bars advanced by iteration; this one is
            # set by hand), which would outlive the bar: with no other thread left, the
            # picture is drawn in a forked child (spurdyn.results.beside).
            unmonitored = type("UnmonitoredTqdm", (tqdm,), {"monitor_interval": 0})
            self.bar = unmonitored(
                total=round(math.degrees(total), 3), desc=self.name, unit="deg",
                file=self.stream, dynamic_ncols=True, leave=True,
                bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} deg "
                           "[{elapsed}<{remaining}{postfix}]")
        self.bar.n = min(round(math.degrees(angle), 3), self.bar.total)
        rate = self.rate(step)
        self.bar.set_postfix_str("" if rate is None else f"{rate:,.0f} steps/s", refresh=False)
        self.bar.refresh()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


# -- one run ---------------------------------------------------------------------------

def _compiling_note(plan: RunPlan, simulate: Simulate, quiet: bool) -> None:
    """Say so, and for about how long, before a first run compiles the solver (nothing
    to show otherwise while it compiles)."""
    compiles = getattr(simulate, "compiles", None)   # a registry entry's (a stand-in has none)
    if not quiet and compiles is not None and compiles(plan.case.run):
        seconds = simulate.compile_seconds(plan.case.run)
        print(f"spurdyn: compiling the solver (first run only, about {seconds:.0f} s on a "
              "2-core machine)...", file=sys.stderr, flush=True)


#: Whether a run writes its folder in a process of its own (:mod:`spurdyn.results.apart`),
#: which keeps the writers' libraries out of the process that steps: set by the console
#: command for ``spurdyn run`` (:func:`spurdyn.cli.command.entry`). A Python session that
#: calls :func:`spurdyn.cli.main.main` writes in its own process.
WRITE_APART = False


def execute(plan: RunPlan, simulate: Simulate, progress: bool = True,
            quiet: bool = False) -> dict[str, Any]:
    """Run one case and write its folder; return the summary (plus ``out``).

    Stop signals reach the solver only at its progress reports (inside its loop, which
    returns the run so far); one that comes later waits until the folder is written. A
    ``KeyboardInterrupt`` before the solver's loop (or escaping it) leaves nothing.
    """
    from spurdyn.results import apart, prefetch

    target = plan.out
    made = [p for p in [target.parent, *target.parent.parents] if not p.exists()]
    bar = ProgressBar(plan.case.name, enabled=progress)
    helpers: dict[str, Any] = {"writer": None}   # the writer process, or the loading thread

    def report(step: int, angle: float, total: float) -> None:
        # the loop runs: the writers load on the other core, in the writer process or in a
        # thread here (the compiled loop runs without the GIL)
        if helpers["writer"] is not None:
            apart.begin(helpers["writer"])
        elif "thread" not in helpers:
            helpers["thread"] = prefetch.start()
        bar(step, angle, total)
        Interrupts.checkpoint()

    try:
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise InputError(str(target), f"cannot be made ({err.strerror or err}); give "
                             "another --out") from None
        if WRITE_APART:   # started while this process is small, before Numba loads
            helpers["writer"] = apart.start()
        _compiling_note(plan, simulate, quiet or not progress)
        t0 = time.perf_counter()
        with Interrupts.held():  # from the moment the solver's loop has ended
            try:
                with Interrupts.checkpoints():
                    result = simulate(plan.case.pair, plan.case.run, report)
            finally:
                bar.close()
            if not result.wall_s:
                result.wall_s = time.perf_counter() - t0
            if Interrupts.last is not None and \
                    (result.reason or "").startswith("interrupted by the user"):
                result.reason = result.reason.replace("by the user", f"by {Interrupts.name()}", 1)
            prefetch.wait(helpers.get("thread"))
            summary, target = _write(plan, result, helpers["writer"])
    finally:
        apart.stop(helpers["writer"])   # one not given a result (a stop before any)
        if not target.exists():  # nothing came of it: remove the folders made for it
            for folder in made:
                try:
                    folder.rmdir()
                except OSError:
                    break
    summary["out"] = str(target)
    return summary


def _write(plan: RunPlan, result: Any, writer: Any) -> tuple[dict[str, Any], Path]:
    """Write the run's folder (in ``writer``'s process if there is one); the summary and
    the folder written, which is another when another run filled the planned one meanwhile."""
    from spurdyn.results import apart

    try:
        summary, final = apart.write(writer, result, plan.case, plan.out, force=plan.force,
                                     vtu=plan.vtu)
    except OSError as err:
        raise InputError(str(plan.out), f"cannot be written ({err.strerror or err}); "
                         "give another --out") from None
    if final != plan.out:
        print(f"spurdyn: {plan.out} was filled by another run meanwhile; "
              f"{plan.case.name} written to {final} instead", file=sys.stderr)
    return summary, final


def report_line(summary: dict[str, Any]) -> str:
    """The command's one line about a finished run (without the folder).

    A complete run gives the peak of its 10-us-averaged contact force and that peak's
    dynamic factor (the headline, :mod:`spurdyn.results.headline`), with the raw
    step-to-step peak beside it; a run stopped early says so and gives no factor.
    """
    steps = f"{summary['steps']:,} steps"
    if summary["status"] != "complete":
        target = summary.get("angle_target_deg")      # one engagement's (a steady state has none)
        reached = f"{summary['angle_deg']:.3f}" + ("" if target is None else f" of {target:.3f}")
        return (f"{summary['case']} incomplete: {summary['reason'] or 'stopped'}; {steps} "
                f"({reached} deg); stopped early: no dynamic factor")
    peak, dyn = summary.get("peak_force_N"), summary.get("dynamic_factor")
    raw = summary.get("peak_force_raw_N")
    window = f"{summary.get('averaging_window_s', 10e-6) * 1e6:g}-us average"
    if peak is None:
        peak_s = "no contact"
    else:
        peak_s = f"peak {peak:,.1f} N" + (f" = {dyn:.3f} x static" if dyn is not None else "") \
            + f" ({window}; raw {raw:,.1f} N)"
    back = summary.get("back_flanks") or {}
    back_s = (f", back flanks {back['peak_force_N']:,.1f} N at most ({back['steps_in_contact']:,} steps)"
              if back.get("steps_in_contact") else "")
    return (f"{summary['case']}: complete{_settled_words(summary)}, {steps} in {summary['wall_s']:.1f} s, "
            f"{peak_s}, {summary['separations']} separation(s){back_s}{safety_phrase(summary)}")


def safety_phrase(summary: dict[str, Any]) -> str:
    """The part of the command's line naming every safety factor below 1, e.g.
    ``", S_F below 1: gear B 0.83 (ISO)"``, or ``""`` when none is (or none computed)."""
    parts = []
    for name, key in (("S_F", "safety_root"), ("S_H", "safety_contact")):
        low = [f"gear {'AB'[g]} {s:.3g} ({way})"
               for way, suffix in (("ISO", "_iso"), ("model", "_model"))
               for g, s in enumerate(summary.get(key + suffix) or ())
               if s is not None and s < 1.0]
        if low:
            parts.append(f"{name} below 1: " + ", ".join(low))
    return "".join(f", {p}" for p in parts)


def _settled_words(summary: dict[str, Any]) -> str:
    """A steady state's settling in words: its cycles, and NOT SETTLED (its figures are the
    last cycle's, not the steady state's) when it did not; nothing for one engagement."""
    if "settled" not in summary:
        return ""
    done = f"{summary['cycles_done']} mesh cycles"
    if summary["settled"]:
        return f", settled in {done}"
    return f" but NOT SETTLED after {done} (the figures are its last cycle's, not a steady state's)"


def _report(summary: dict[str, Any], quiet: bool) -> None:
    out = summary["out"]
    if summary["status"] == "complete":
        if not quiet:
            print(f"{report_line(summary)} -> {out}", flush=True)
            print(f"  plot: {Path(out) / 'contact_force.png'}", flush=True)
    else:
        print(f"spurdyn: {report_line(summary)}; kept in {out}", file=sys.stderr, flush=True)


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
    install_in_worker()


def _worker(plan: RunPlan) -> dict[str, Any] | None:
    if Interrupts.count:
        return None  # a stop signal came: start nothing new
    simulate = _WORKER_SIMULATE or load_simulate()
    try:
        return execute(plan, simulate, progress=False, quiet=True)
    except KeyboardInterrupt:
        return None


def _not_run(plan: RunPlan, statuses: list[str]) -> None:
    statuses.append("not run")
    print(f"spurdyn: {plan.case.name} not run (interrupted by {Interrupts.name()})",
          file=sys.stderr)


def _run_serial(plans: Sequence[RunPlan], simulate: Simulate, statuses: list[str],
                progress: bool, quiet: bool) -> int | None:
    """Run the plans one after the other; an exit status if a stop left nothing."""
    for plan in plans:
        if Interrupts.count:
            _not_run(plan, statuses)
            continue
        try:
            summary = execute(plan, simulate, progress=progress, quiet=quiet)
        except KeyboardInterrupt:
            print(f"spurdyn: {plan.case.name} interrupted by {Interrupts.name()} before any "
                  "result; nothing written", file=sys.stderr)
            return Interrupts.exit_status()
        statuses.append(summary["status"])
        _report(summary, quiet)
    return None


def _run_pool(plans: Sequence[RunPlan], simulate: Simulate, statuses: list[str], jobs: int,
              progress: bool, quiet: bool) -> None:
    """Run the plans side by side on ``jobs`` worker processes."""
    # The solver goes to the workers as an importable function (by reference). The
    # workers draw no bars of their own (they would overwrite each other): the command
    # shows the cases finished instead.
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
                        _not_run(plan, statuses)
                        continue
                    statuses.append(summary["status"])
                    _report(summary, quiet)
            except KeyboardInterrupt:
                # Ctrl-C reaches the workers too (one process group); SIGTERM is sent to
                # this process only: pass it on. Either way they write what they have.
                for pid in list(getattr(pool, "_processes", {}) or {}):
                    try:
                        os.kill(pid, Interrupts.last or signal.SIGINT)
                    except OSError:
                        pass
                for fut in list(pending):
                    if fut.cancel():
                        pending.discard(fut)
                        _not_run(futures[fut], statuses)
    if cases_bar is not None:
        cases_bar.close()


def run_plans(plans: Sequence[RunPlan], simulate: Simulate, *, jobs: int = 1,
              progress: bool = True, quiet: bool = False) -> int:
    """Run every plan (side by side on ``jobs`` processes); return the exit status.

    0 every run complete, 1 some run incomplete or not run (what was computed is kept),
    128 + signal (130 Ctrl-C, 143 SIGTERM) when a stop signal came before any result.
    """
    statuses: list[str] = []
    with Interrupts.installed():
        Interrupts.reset()
        if jobs <= 1 or len(plans) <= 1:
            stopped = _run_serial(plans, simulate, statuses, progress, quiet)
            if stopped is not None:
                return stopped
        else:
            _run_pool(plans, simulate, statuses, jobs, progress, quiet)
    if statuses and all(s == "complete" for s in statuses):
        return EXIT_OK
    return EXIT_INCOMPLETE
