"""``spurdyn report CASE``: a design report an engineer can hand on (issue 36).

Order of work, as ``spurdyn sweep``: the options, the case and the output folder are
checked before anything is written (a refusal is one line naming the key, exit status
2). The speed points then run through the sweep's own machinery (the registry, the
sweep store in ``DIR/sweep`` with each point's run folder, a local Dask cluster or the
one at ``--scheduler``), so a repeated report reuses its finished points and an
interrupted one resumes. The page ``DIR/report.html`` and its numbers ``DIR/report.json``
are written last, also when some points failed (they show as failed, with their reason).
See docs/report.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import Any, Iterator

from spurdyn.errors import InputError

#: Exit statuses (those of ``spurdyn sweep``).
EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT = 0, 1, 2

#: The default speeds: :data:`DEFAULT_SPEEDS` evenly spaced, the lowest one step above zero,
#: up to :data:`RESONANCE_REACH` times the model's main mesh resonance speed, the step
#: rounded to :data:`SPEED_STEP_ROUND` rpm (docs/report.md, "The default speeds").
DEFAULT_SPEEDS, RESONANCE_REACH, SPEED_STEP_ROUND = 20, 1.3, 50.0

#: The model drawn beside the report's (sector) model against speed.
BESIDE = "lumped"

#: The files a report writes in its folder (the sweep's store is ``SWEEP_DIR``).
HTML_FILE, JSON_FILE, SWEEP_DIR = "report.html", "report.json", "sweep"


def check_report_out(out: Path, force: bool) -> None:
    """Refuse a folder that cannot hold a report (nothing is created).

    A folder that exists and is not empty must hold a report (``report.json`` or the
    sweep store) unless ``--force``: a report adds to its own folder, resuming it.
    """
    if out.exists() and not out.is_dir():
        raise InputError("--out", f"{out} is a file, not a folder; give another --out")
    if out.is_dir() and any(out.iterdir()) and not force:
        if not ((out / JSON_FILE).is_file() or (out / SWEEP_DIR).is_dir()):
            raise InputError("--out", f"{out} exists, is not empty and holds no report; give "
                             "another --out (or --force)")


def _sweep_namespace(args: argparse.Namespace, rpm: str, out: Path) -> argparse.Namespace:
    """The options of ``spurdyn sweep`` for the report's points: its parser's defaults,
    the report's case, speeds, torques, mesh and cluster, every point's run folder kept."""
    from spurdyn.cli.sweep import add_sweep_parser

    parser = argparse.ArgumentParser(add_help=False)
    add_sweep_parser(parser.add_subparsers())
    ns = parser.parse_args(["sweep", args.case, "--rpm", rpm])
    ns.torque, ns.mesh, ns.jobs, ns.scheduler = args.torque, args.mesh, args.jobs, args.scheduler
    ns.out, ns.keep_runs, ns.force, ns.quiet = str(out / SWEEP_DIR), True, args.force, args.quiet
    return ns


def default_rpm(resonance_rpm: float) -> str:
    """``--rpm`` when not given: :data:`DEFAULT_SPEEDS` speeds ``n = i s`` (``i = 1 ...
    DEFAULT_SPEEDS``) whose step ``s`` is :data:`RESONANCE_REACH` times the main mesh
    resonance speed ``resonance_rpm`` over :data:`DEFAULT_SPEEDS`, rounded to
    :data:`SPEED_STEP_ROUND` rpm (at least that)."""
    step = RESONANCE_REACH * resonance_rpm / DEFAULT_SPEEDS
    step = max(SPEED_STEP_ROUND, round(step / SPEED_STEP_ROUND) * SPEED_STEP_ROUND)
    return f"{step:g}:{step * DEFAULT_SPEEDS:g}/{DEFAULT_SPEEDS}"


def build_report_plan(args: argparse.Namespace) -> tuple[Any, str, Any]:
    """Check the options, the case and the folder; the sweep plan, the ``--rpm`` used and
    the resonance estimate (:func:`spurdyn.sweep.resonance.resonance_estimate`, from which
    the default speeds come).

    Raises
    ------
    InputError
        Naming the option or case key (nothing is written).
    """
    from spurdyn.cli.sweep import build_plan, sweep_case
    from spurdyn.sweep.resonance import resonance_estimate
    from spurdyn.sweep.spec import parse_torques

    out = Path(args.out)
    check_report_out(out, args.force)
    rpm, resonance = args.rpm, None
    torques = parse_torques(args.torque) if args.torque is not None else None
    case, model, _ = sweep_case(_sweep_namespace(args, "1", out), torques, 1000.0)
    if case.run.faults:
        raise InputError("fault", "not read by `spurdyn report` yet: `spurdyn sweep` makes a faulty pair's "
                         "data set, `spurdyn run --model sector` runs one, `spurdyn stiffness` follows it over "
                         "its revolution")
    if rpm is None:
        resonance = resonance_estimate(case, model)
        rpm = default_rpm(resonance.resonance_rpm)
    plan = build_plan(_sweep_namespace(args, rpm, out))
    if resonance is None:
        resonance = resonance_estimate(plan.case, plan.model)
    return replace(plan, run_pictures=False), rpm, resonance  # the page needs the numbers


def beside_plan(plan: Any) -> tuple[Any, str | None]:
    """The lumped model's sweep beside the sector model's, or ``None`` and why not.

    The same speeds, torques, pair and tooth mesh, in the same sweep store (its points are
    the lumped model's keys, so they resume and are reused as the sector's); its stiffness
    the sector model's quasi-static mesh cycle (``stiffness = "sector"``), its mesh damper
    the sector run's ratio, its cycles and most cycles the sector run's (docs/lumped.md,
    "With the sector model's stiffness"). No run folders: its figures are the points'.
    """
    from spurdyn.errors import InputError
    from spurdyn.sector.rules import mesh_damping
    from spurdyn.simulators import DEFAULTS, MODELS

    own = MODELS[plan.model]
    if plan.model == BESIDE or not own.sector_stiffness(plan.case.run):
        return None, ("the lumped model is drawn beside a model of whole gears whose mesh "
                      f"stiffness is the sector model's mesh cycle, not beside the {own.title}")
    entry = MODELS[BESIDE]
    run = plan.case.run
    reset = {n: DEFAULTS[n] for n in entry.unread}      # the sector model's own settings
    try:
        run = run.with_(**reset).with_(stiffness="sector", damping_ratio=mesh_damping(run)[0])
        entry.refuse(run, None, plan.case.pair)
    except InputError as err:
        return None, f"the lumped model cannot run this case: {err}"
    return replace(plan, model=BESIDE, case=replace(plan.case, run=run), keep_runs=False,
                   continuation=None), None


class _PerPointLines:
    """A backend that passes every point through and, off a terminal, prints a plain line
    per point finished (points done, time spent, time left); on a terminal the sweep's
    tqdm bar shows the same."""

    def __init__(self, backend: Any, total: int, enabled: bool) -> None:
        self.backend, self.total, self.enabled = backend, total, enabled
        self.description = getattr(backend, "description", "")

    def run(self, tasks: Any, fn: Any) -> Iterator[Any]:
        t0, done = time.perf_counter(), 0
        for task, outcome, note in self.backend.run(tasks, fn):
            done += 1
            if self.enabled:
                spent = time.perf_counter() - t0
                left = spent / done * (self.total - done)
                status = outcome.status if outcome is not None else (note or "not run")
                print(f"spurdyn: point {done}/{self.total} ({task.key.rpm:g} rpm, "
                      f"{task.key.torque:g} N m): {status}; {spent:.0f} s spent, about "
                      f"{left:.0f} s left", file=sys.stderr, flush=True)
            yield task, outcome, note

    def cancel(self) -> None:
        self.backend.cancel()


def _backend(args: argparse.Namespace, todo: int) -> tuple[Any, str]:
    """Where the points run (the sweep command's seams, so tests can replace them)."""
    from spurdyn.cli import sweep as cli_sweep
    from spurdyn.sweep import backends

    if todo == 0:
        return cli_sweep._nothing_to_run(), "no worker"
    if args.scheduler is not None:
        return cli_sweep.scheduler_backend(args.scheduler), args.scheduler
    jobs = min(args.jobs or backends.default_jobs(), todo)
    return cli_sweep.local_backend(jobs), f"{jobs} local worker{'s' if jobs > 1 else ''}"


def run_points(plan: Any, beside: Any, resonance: Any, args: argparse.Namespace
               ) -> tuple[Any, Any]:
    """Run the report's missing points through :func:`spurdyn.sweep.runner.run_sweep`: the
    model's, then those of the lumped model beside it (``beside``, or ``None``), on the
    same workers; the two sweeps' reports (the second ``None`` without ``beside``)."""
    from spurdyn.sweep.runner import points_to_compute, run_sweep

    plans = [plan] + ([beside] if beside is not None else [])
    todo = [len(points_to_compute(p)) for p in plans]
    backend_cm, where = _backend(args, sum(todo))
    if not args.quiet:
        counts = " and ".join(f"{len(p.keys())} {p.model} points ({n} to compute)"
                              for p, n in zip(plans, todo))
        print(f"spurdyn: report of {plan.case.name}: {counts} on {where}", file=sys.stderr,
              flush=True)
    plain = not args.quiet and not sys.stderr.isatty()
    sweeps = []
    with backend_cm as backend:
        for p, n in zip(plans, todo):
            sweeps.append(run_sweep(p, _PerPointLines(backend, n, plain), resonance=resonance,
                                    progress=not args.quiet))
            if sweeps[-1].interrupted:
                break
    return sweeps[0], (sweeps[1] if len(sweeps) > 1 else None)


def cmd_report(args: argparse.Namespace) -> int:
    """Run ``spurdyn report``; return the exit status."""
    from spurdyn.cli.design_data import gather
    from spurdyn.cli.design_page import write_report

    if args.out is None:
        args.out = str(Path("out") / f"report-{Path(args.case).stem}")
    plan, rpm, resonance = build_report_plan(args)
    beside, why_not = (None, "left out (--no-lumped)") if args.no_lumped else beside_plan(plan)
    sweep, lumped = run_points(plan, beside, resonance, args)
    data = gather(plan, sweep, resonance, args, rpm, (beside, lumped, why_not))
    html, js = write_report(Path(args.out), data)
    if not args.quiet:
        print(f"-> {html}\n-> {js}")
    return EXIT_OK if sweep.all_complete else EXIT_INCOMPLETE


def add_report_parser(sub: argparse._SubParsersAction) -> None:
    """Add ``spurdyn report`` to the subcommands."""
    p = sub.add_parser(
        "report", help="a design report: one self-contained HTML page and its numbers in JSON",
        description="Write DIR/report.html (one self-contained page: verdict, inputs, "
        "geometry, quasi-static mesh cycle, figures against speed, ISO 6336 rating, model "
        "and limits) and DIR/report.json (every number the page shows). The speed points "
        "run as 'spurdyn sweep' runs them (kept in DIR/sweep: a repeated report reuses "
        "them, an interrupted one resumes). Exit status: 0 every point complete, 1 some "
        "point not complete (shown on the page), 2 bad input (nothing written). See "
        "docs/report.md.")
    p.add_argument("case", metavar="CASE", help="a TOML case file (or a preset name)")
    p.add_argument("--rpm", metavar="A:B/N", help="speeds of gear A (rpm): START:STOP/N, "
                   "START:STOP:STEP or A,B,C (default: 20 speeds up to 1.3 times the main "
                   "mesh resonance speed of the model's mean mesh stiffness)")
    p.add_argument("--torque", metavar="T1,T2,...", help="driver torques (N m; default the "
                   "case's)")
    p.add_argument("--mesh", metavar="NXxNY", help="Q8 elements across x along each tooth")
    p.add_argument("--jobs", type=int, metavar="N",
                   help="worker processes of the local Dask cluster (default: one per core)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="run the points on the existing Dask cluster of this scheduler")
    p.add_argument("--out", metavar="DIR", help="report folder (default out/report-<case>); "
                   "running again into it reuses the finished points")
    p.add_argument("--no-lumped", action="store_true", help="leave out the lumped model "
                   "beside the sector model against speed (its points cost about as much "
                   "as the sector model's)")
    p.add_argument("--force", action="store_true", help="compute every point again")
    p.add_argument("--quiet", action="store_true", help="no progress, no report lines")
    p.set_defaults(func=cmd_report)


__all__ = ["add_report_parser", "beside_plan", "build_report_plan", "check_report_out", "cmd_report",
           "default_rpm"]
