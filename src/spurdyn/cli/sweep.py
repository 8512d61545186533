"""``spurdyn sweep``: one run per speed (and torque), the dynamic factor against speed.

Order of work, as ``spurdyn run``: every option and the case are read and checked, the
output folder is checked and (with ``--scheduler``) the cluster is reached *before*
anything is created, so bad input writes nothing (one line, exit status 2). The points
then run on Dask (a local cluster, or the one at ``--scheduler``); each is written to
``DIR/points/`` as soon as it finishes, and ``sweep.nc`` and ``dynamic_factor.png`` are
assembled at the end, also after Ctrl-C. See docs/sweep.md.
"""

from __future__ import annotations

import argparse
import os
import sys
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Any, Iterator

from spurdyn.cli.options import DYNAMICS_OVERRIDES, add_dynamics_options, parse_mesh
from spurdyn.errors import InputError
from spurdyn.simulators import MODELS as ENTRIES
from spurdyn.sweep import backends as _backends
from spurdyn.sweep import scheduler as _scheduler
from spurdyn.sweep.faults import fault_axis
from spurdyn.sweep.spec import (CONTINUATIONS, MODELS, SweepPlan, check_count, check_plan,
                                parse_grid, parse_speeds, parse_torques)

#: Decimals of ``--fault-size`` (m): a nanometre.
SIZE_DECIMALS = 9

#: Exit statuses of ``spurdyn sweep`` (those of ``spurdyn run``).
EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT = 0, 1, 2

#: ``spurdyn sweep`` options that override the case: (dest, dotted case key, label).
SWEEP_OVERRIDES = (("dt", "run.dt", "--dt"), ("angle", "run.angle_deg", "--angle"),
                   ("grading", "mesh.grading", "--grading"),
                   ("row_grading", "mesh.row_grading", "--row-grading")) + DYNAMICS_OVERRIDES


def local_backend(jobs: int) -> Any:
    """The local Dask cluster (a seam for tests)."""
    return _backends.local_backend(jobs)


def scheduler_backend(address: str, timeout_s: float, tls: _scheduler.TlsFiles) -> Any:
    """An existing Dask cluster (a seam for tests)."""
    return _scheduler.scheduler_backend(address, timeout_s=timeout_s, tls=tls)


def tls_files(args: argparse.Namespace) -> _scheduler.TlsFiles:
    """The ``--tls-*`` files given."""
    return _scheduler.TlsFiles(*(Path(f) if f is not None else None
                                 for f in (args.tls_ca_file, args.tls_cert, args.tls_key)))


def _check_cluster(args: argparse.Namespace) -> None:
    """Refuse --jobs with --scheduler, a malformed --scheduler, a bad --scheduler-timeout
    and --tls-* files without a tls:// scheduler."""
    if args.jobs is not None:
        if args.scheduler is not None:
            raise InputError("--jobs", "has no effect with --scheduler: the cluster's workers "
                             "run the points")
        if args.jobs < 1:
            raise InputError("--jobs", f"must be a whole number >= 1 (got {args.jobs})")
    if args.scheduler is not None:
        _scheduler.check_address(args.scheduler)
    if args.scheduler_timeout is not None:
        if args.scheduler is None:
            raise InputError("--scheduler-timeout", "is for --scheduler (the local cluster "
                             "is started by the command)")
        if not 0.1 <= args.scheduler_timeout <= 3600:    # NaN fails too
            raise InputError("--scheduler-timeout", f"must be seconds between 0.1 and 3600 "
                             f"(got {args.scheduler_timeout:g})")
    _scheduler.check_tls(args.scheduler, tls_files(args))


@contextmanager
def _nothing_to_run() -> Iterator[_backends.SerialBackend]:
    yield _backends.SerialBackend()


def _overrides(args: argparse.Namespace, torques: tuple[float, ...] | None
               ) -> tuple[dict[str, Any], dict[str, str]]:
    overrides: dict[str, Any] = {}
    labels: dict[str, str] = {}
    for dest, key, label in SWEEP_OVERRIDES:
        value = getattr(args, dest)
        if value is not None:
            overrides[key], labels[key] = value, label
    mesh = parse_mesh(args.mesh)
    if mesh is not None:
        overrides["mesh.nx"], overrides["mesh.ny"] = mesh
        labels["mesh.nx"] = labels["mesh.ny"] = "--mesh"
    if torques is not None:
        overrides["run.torque"], labels["run.torque"] = torques[0], "--torque"
    if args.fault:     # beside the case's [[fault]] tables
        overrides["fault"], labels["fault"] = tuple(args.fault), "--fault"
    return overrides, labels


def resolve_sweep_case(spec: str, overrides: dict[str, Any], labels: dict[str, str],
                       first_rpm: float) -> Any:
    """The one case a sweep runs (a preset or a TOML file, not a group).

    A file without ``run.speed_a_rpm`` takes the sweep's first speed there (the sweep
    replaces it at each point anyway; ``run.speed_b_rpm`` defaults to the meshing speed).
    """
    from spurdyn.case.presets import GROUPS, resolve_cases

    if spec in GROUPS:
        raise InputError("CASE", f"{spec!r} is a group of cases; a sweep runs one case "
                         "(e.g. paper-fig8)")
    try:
        cases = resolve_cases(spec, overrides, labels)
    except InputError as err:
        if err.field != "run.speed_a_rpm":
            raise
        more = {**overrides, "run.speed_a_rpm": first_rpm}
        cases = resolve_cases(spec, more, {**labels, "run.speed_a_rpm": "--rpm"})
    return cases[0]


def check_out(out: Path, force: bool) -> None:
    """Refuse an output folder that cannot be a sweep folder (nothing is created).

    A folder that exists and is not empty must hold a sweep (``points/`` or a
    ``sweep*.nc``) unless ``--force``: a sweep adds to its own folder, resuming it.
    """
    if out.exists() and not out.is_dir():
        raise InputError(str(out), "is a file, not a folder; give another --out")
    if out.is_dir() and any(out.iterdir()) and not force:
        is_sweep = (out / "points").is_dir() or any(out.glob("sweep*.nc"))
        if not is_sweep:
            raise InputError(str(out), "exists, is not empty and holds no sweep; give "
                             "another --out (or --force to add a sweep to it)")
    for parent in [out, *out.parents]:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(str(out), f"cannot be made: {parent} is a file")
            if not os.access(parent, os.W_OK | os.X_OK):
                raise InputError(str(out), f"cannot be made: {parent} is not writable")
            break


def sweep_case(args: argparse.Namespace, torques: tuple[float, ...] | None, first_rpm: float
               ) -> tuple[Any, str, dict[str, str]]:
    """The case a sweep runs with its options applied and its model's defaults, the model
    (``--model``, else the case file's) and how to name the options given; refused (one
    line naming the key) where the model cannot run it."""
    overrides, labels = _overrides(args, torques)
    case = resolve_sweep_case(args.case, overrides, labels, first_rpm)
    model = args.model or case.model          # --model, else the case file's [model] kind
    entry = ENTRIES[model]
    entry.refuse(case.run, case.labels(labels), case.pair)   # not ignored in silence
    return replace(case, run=entry.with_defaults(case.run)), model, labels


def build_plan(args: argparse.Namespace) -> SweepPlan:
    """Check every option and the case; the sweep to run (nothing is created)."""
    if args.model is not None and args.model not in MODELS:
        raise InputError("--model", f"must be one of {', '.join(MODELS)} (got {args.model!r})")
    _check_cluster(args)
    rpms = parse_speeds(args.rpm)
    torques = parse_torques(args.torque) if args.torque is not None else None
    check_count(rpms, torques)      # before any point is made
    sizes = parse_grid(args.fault_size, "--fault-size", positive=False, decimals=SIZE_DECIMALS) \
        if args.fault_size is not None else None
    case, model, labels = sweep_case(args, torques, rpms[0])
    faults = fault_axis(case, sizes)
    entry = ENTRIES[model]
    if args.continuation is not None:
        if args.continuation not in CONTINUATIONS:
            raise InputError("--continuation", f"must be one of {', '.join(CONTINUATIONS)} "
                             f"(got {args.continuation!r})")
        if case.run.cycles is None:
            raise InputError("--continuation", "starts each speed from the previous one's "
                             "settled state: it needs a steady-state sweep (--cycles N)")
        entry.refuse_continuation(case)
        if faults is not None:
            raise InputError("--continuation", "starts each speed from the previous one's end: a fault "
                             "sweep's points each start on their own (leave it out)")
        if args.jobs is not None or args.scheduler is not None:
            raise InputError("--continuation", "runs its speeds in turn in this process: "
                             "leave out --jobs and --scheduler")
    if case.run.torque_history is not None:
        # the slowest point lasts longest: its history must cover it too
        from spurdyn.model.loading import check_history
        from spurdyn.settings import RPM

        slow = min(rpms) * RPM / case.run.speed_a      # the rpm are gear A's
        try:
            check_history(case.pair, case.run.with_(speed_a=case.run.speed_a * slow,
                                                    speed_b=case.run.speed_b * slow))
        except InputError as err:
            raise InputError(labels.get("run.torque_history", "run.torque_history"), err.reason) from None
    out = Path(args.out) if args.out else Path("out") / f"sweep-{case.name}"
    check_out(out, args.force)
    plan = SweepPlan(case=case, model=model, rpms=rpms, torques=torques, out=out,
                     keep_runs=args.keep_runs, force=args.force, continuation=args.continuation,
                     faults=faults)
    check_plan(plan)
    _check_points(plan, labels, args.allow_large)
    return plan


def _check_points(plan: SweepPlan, labels: dict[str, str], allow_large: bool) -> None:
    """Refuse points beyond the meaning of their settings, or too large unasked."""
    from spurdyn.solvers.limits import check_run_bounds, check_sampling, check_size

    names = {"speed_a_rpm": "--rpm", "torque": "--torque" if plan.torques is not None
             else "run.torque"}

    def field(key: str) -> str:
        return names.get(key) or labels.get(f"run.{key}", f"run.{key}")

    entry = ENTRIES[plan.model]
    for torque in plan.torque_values[1:]:   # the first is the case's, checked with the case
        entry.check(plan.case.run.with_(torque=torque), {**labels, "run.torque": field("torque")},
                    plan.case.pair)
    points = [plan.point_case(k) for k in plan.keys()]
    for point in points:
        check_run_bounds(point.pair, point.run, field)
        check_sampling(point.pair, point.run, field)
    if not allow_large:     # the largest run at the slowest speed (a fault's sizes differ)
        low = min(p.run.speed_a for p in points)
        sizes = [(entry.size(p), p) for p in points if p.run.speed_a == low]
        size, largest = max(sizes, key=lambda sp: (sp[0].bytes, sp[0].steps))
        check_size(largest, labels, size, speed_field="--rpm")


def _report(report: Any, resonance: Any, where: str, quiet: bool) -> None:
    import numpy as np

    plan, counts = report.plan, report.counts
    n = sum(counts.values())
    parts = [f"{counts['complete']} complete"]
    for name in ("incomplete", "failed", "not_run"):
        if counts.get(name):
            parts.append(f"{counts[name]} {name.replace('_', ' ')}")
    line = (f"{plan.model} sweep of {plan.case.name}: {n} point{'s' if n != 1 else ''} "
            f"({report.computed} computed on {where}, {report.reused} already in "
            f"{plan.out}): {', '.join(parts)}; {report.wall_s:.1f} s")
    if report.interrupted or report.stopped:
        from spurdyn.signals import Interrupts

        why = Interrupts.stopped() if report.interrupted else f"stopped ({report.stopped})"
        print(f"spurdyn: sweep {why}: {counts['complete'] + counts['incomplete']} of {n} "
              f"points kept in {plan.out}; run the same command to compute the rest",
              file=sys.stderr, flush=True)
    if quiet:
        return
    print(line)
    ds = report.dataset
    factor = np.asarray(ds["dynamic_factor"].values, float)
    ok = np.isfinite(factor)
    extra = ""
    if ok.any():
        idx = np.unravel_index(np.nanargmax(np.where(ok, factor, -np.inf)), factor.shape)
        rpm = float(np.atleast_1d(ds["rpm"].values)[idx[0]])
        extra = (f"; largest dynamic factor {factor[idx]:.3f} (of the "
                 f"{ds.attrs.get('averaging_window_s', 10e-6) * 1e6:g}-us average) at "
                 f"{rpm:,.0f} rpm")
    print(f"f_n = {resonance.natural_frequency_hz / 1e3:.3f} kHz (mean mesh stiffness "
          f"{resonance.mesh_stiffness_mean:.3g} N/m): mesh resonance expected at "
          f"{resonance.resonance_rpm:,.0f} rpm{extra}")
    print("-> " + ", ".join(str(p) for p in report.files), flush=True)


def cmd_sweep(args: argparse.Namespace) -> int:
    """Run ``spurdyn sweep``; return the exit status."""
    from spurdyn.sweep.resonance import resonance_estimate
    from spurdyn.sweep.runner import points_to_compute, run_sweep

    plan = build_plan(args)
    entry = ENTRIES[plan.model]
    healthy = replace(plan.case, run=plan.case.run.with_(faults=()))   # a fault sweep's: the healthy pair's
    resonance = resonance_estimate(healthy, plan.model)
    todo = len(points_to_compute(plan))
    if todo == 0:
        backend_cm, where = _nothing_to_run(), "no worker"
    elif plan.continuation is not None:   # one chain in this process: no cluster
        backend_cm, where = _nothing_to_run(), f"this process, speeds {plan.continuation}"
    elif args.scheduler is not None:
        timeout = args.scheduler_timeout or _scheduler.CONNECT_TIMEOUT_S
        backend_cm = scheduler_backend(args.scheduler, timeout, tls_files(args))
        where = args.scheduler
    else:
        jobs = min(args.jobs or _backends.default_jobs(), todo)
        backend_cm = local_backend(jobs)
        where = f"{jobs} local worker{'s' if jobs > 1 else ''}"
    if todo and not args.quiet and entry.compiles(plan.case.run):
        seconds = entry.compile_seconds(plan.case.run)
        print(f"spurdyn: the workers compile the solver first (first run only, about "
              f"{seconds:.0f} s on a 2-core machine)...", file=sys.stderr, flush=True)
    with backend_cm as backend:
        report = run_sweep(plan, backend, resonance=resonance, progress=not args.quiet)
    _report(report, resonance, where, args.quiet)
    return EXIT_OK if report.all_complete else EXIT_INCOMPLETE


def add_sweep_parser(sub: argparse._SubParsersAction) -> None:
    """Add ``spurdyn sweep`` to the subcommands."""
    p = sub.add_parser(
        "sweep", help="one run per speed (and torque): the dynamic factor against speed",
        description="Run CASE once per speed of --rpm (and torque of --torque), the whole "
        "engagement each, gear B at the case's speed ratio (the meshing speed for the "
        "presets but paper-fig10/11). Results: DIR/sweep.nc and DIR/dynamic_factor.png; "
        "each finished point is kept in DIR/points/, and running the same command again "
        "computes only what is missing. The points run on a local Dask cluster (--jobs) "
        "or on the cluster at --scheduler. Exit status: 0 every point complete, 1 some "
        "point incomplete, failed or not run (Ctrl-C and SIGTERM stop the sweep and keep "
        "the finished points), 2 bad input (nothing written). "
        "See docs/sweep.md.")
    p.add_argument("case", metavar="CASE", help="preset name (see 'spurdyn cases') or TOML file")
    p.add_argument("--rpm", required=True, metavar="START:STOP:STEP",
                   help="speeds of gear A (rpm): START:STOP:STEP (STOP included), "
                   "START:STOP/N (N speeds, ends included) or a list A,B,C")
    p.add_argument("--torque", metavar="LIST",
                   help="torques on the driver (N m): a list A,B,C or START:STOP:STEP; "
                   "adds a torque dimension (default: the case's torque)")
    p.add_argument("--fault", action="append", metavar="SPEC",
                   help="a fault beside the case's [[fault]] tables, the keys of one, e.g. "
                   "gear=a,tooth=5,kind=crack,depth=1e-3; kinds missing, spall, crack, chip (the sector "
                   "model; docs/faults.md): a "
                   "faulty sweep writes DIR/fault_sweep.nc, the sensors' signals and indicators")
    p.add_argument("--fault-size", metavar="START:STOP/N",
                   help="sizes (m) of the case's one fault, a crack's length, a spall's depth or a chip's "
                   "height: "
                   "START:STOP/N, START:STOP:STEP or a list A,B,C; 0 is the healthy pair (run by the "
                   "healthy model over the faulty gear's revolutions); adds a fault_size dimension "
                   "(default: the fault's own size)")
    p.add_argument("--model", metavar="|".join(MODELS),
                   help="fe: the paper's FE contact model (the default, or the case file's "
                        "[model] kind); sector: elastic teeth on "
                        "elastic rims (with --cycles; docs/sector.md); lumped: two disks and "
                   "a mesh spring")
    p.add_argument("--out", metavar="DIR", help="sweep folder (default out/sweep-<case name>); "
                   "rerunning into it resumes the sweep")
    p.add_argument("--dt", type=float, metavar="S", help="time step (s)")
    p.add_argument("--mesh", metavar="NXxNY", help="Q8 elements across x along each tooth")
    add_dynamics_options(p)
    p.add_argument("--grading", type=float, metavar="G",
                   help="how much thinner the outline columns of each tooth mesh are than the "
                        "middle ones (default 1: even)")
    p.add_argument("--row-grading", type=float, metavar="G",
                   help="how much taller the fillet rows of each tooth mesh are than its flank "
                        "rows (default 1: even; FE and lumped models)")
    p.add_argument("--angle", type=float, metavar="DEG",
                   help="rotation of A per run (deg; default the whole angle of action)")
    p.add_argument("--jobs", type=int, metavar="N",
                   help="worker processes of the local Dask cluster (default: one per core)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="run on the existing Dask cluster of this scheduler instead "
                   "(tcp:// on a trusted network only; tls:// with --tls-*)")
    p.add_argument("--scheduler-timeout", type=float, metavar="S",
                   help=f"seconds the scheduler has to answer (default "
                   f"{_scheduler.CONNECT_TIMEOUT_S:g}); during the sweep, silent for "
                   f"this or {_backends.SILENCE_S:g} s, the longer, it counts as lost "
                   "(the finished points kept)")
    p.add_argument("--tls-ca-file", metavar="PEM",
                   help="tls:// scheduler: the certificate authority of the cluster")
    p.add_argument("--tls-cert", metavar="PEM",
                   help="tls:// scheduler: this client's certificate, signed by that authority")
    p.add_argument("--tls-key", metavar="PEM",
                   help="tls:// scheduler: the private key of --tls-cert (if not in it)")
    p.add_argument("--keep-runs", action="store_true",
                   help="also keep each point's whole run folder in DIR/runs/")
    p.add_argument("--force", action="store_true",
                   help="compute every point again (and allow a non-sweep DIR)")
    p.add_argument("--continuation", metavar="|".join(CONTINUATIONS),
                   help="steady state (--cycles): run the speeds up or down in turn, each "
                        "starting from the previous speed's end state, so that the jumps of "
                        "the nonlinear response show (one process; default: each on its own)")
    p.add_argument("--allow-large", action="store_true",
                   help="run points even beyond 2,000,000 steps or 1 GiB of results each")
    p.add_argument("--quiet", action="store_true", help="no progress bar, no report lines")
    p.set_defaults(func=cmd_sweep)


__all__ = ["add_sweep_parser", "build_plan", "check_out", "cmd_sweep", "resolve_sweep_case", "sweep_case"]
