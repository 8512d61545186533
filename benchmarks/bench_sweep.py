"""Benchmark of speed sweeps: one command, ``python benchmarks/bench_sweep.py``.

Prints the wall time (cluster start-up included, every point computed afresh in an
empty folder) of

1. the FE sweep of the paper's pair over 40 speeds, 1,000-20,000 rpm (``1000:20000/40``),
   the paper's dt (3e-8 s) and default 4 x 14 mesh, whole engagement, on the local Dask
   cluster (``--jobs``, default one worker per core);
2. the lumped sweep of the same 40 speeds, through the command line (``spurdyn sweep``
   in a fresh process: Python start-up included) and through the Python API;
3. a smaller FE sweep, 6 speeds 10,000-20,000 rpm, on 1 and on 2 local workers.

The solver's compiled code is loaded (or compiled) once before timing. The machine's
load average is printed too: the workers share the cores with whatever else runs.

Options: ``--skip-fe40`` (leave out item 1), ``--jobs N`` (workers for items 1-2),
``--keep DIR`` (leave the sweep folders in DIR instead of a temporary folder).
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from spurdyn.case import preset_case
from spurdyn.sweep.backends import default_jobs, local_backend
from spurdyn.sweep.runner import SweepReport, run_sweep
from spurdyn.sweep.spec import SweepPlan, parse_speeds

SPEEDS_40 = "1000:20000/40"
SPEEDS_6 = "10000:20000/6"


def timed_sweep(model: str, speeds: str, out: Path, jobs: int) -> tuple[float, SweepReport]:
    """Wall time of a whole sweep on a fresh local cluster of ``jobs`` workers."""
    plan = SweepPlan(case=preset_case("paper-fig8"), model=model, rpms=parse_speeds(speeds),
                     torques=None, out=out)
    t0 = time.perf_counter()
    with local_backend(jobs) as backend:
        report = run_sweep(plan, backend, progress=False)
    return time.perf_counter() - t0, report


def describe(label: str, wall: float, report: SweepReport, jobs: int) -> str:
    ds = report.dataset
    point_s = np.asarray(ds["wall_s"].values, float)
    steps = np.asarray(ds["steps"].values, float)
    n = int(ds.sizes["rpm"])
    done = report.counts["complete"]
    busy = float(np.nansum(point_s))
    line = (f"| {label} | {n} | {jobs} | {wall:.1f} | {busy:.1f} | "
            f"{busy / (jobs * wall):.0%} | {done}/{n} |")
    if str(ds.attrs["model"]) == "fe":
        line += f" {1e3 * busy / np.nansum(steps):.3f} |"
    else:
        line += " - |"
    return line


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-fe40", action="store_true", help="leave out the 40-speed FE sweep")
    parser.add_argument("--jobs", type=int, default=default_jobs(), help="local workers")
    parser.add_argument("--keep", metavar="DIR", help="keep the sweep folders in DIR")
    args = parser.parse_args()
    root = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="bench_sweep-"))
    root.mkdir(parents=True, exist_ok=True)

    print(f"# spurdyn sweep benchmark: {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    t0 = time.perf_counter()
    from spurdyn.solvers.loop import simulate
    from spurdyn.settings import RPM

    case = preset_case("paper-fig9")
    simulate(case.pair, case.run.with_(angle=30 * case.run.dt * 20000 * RPM, frames_every=0))
    print(f"compiled code loaded (or compiled) in {time.perf_counter() - t0:.1f} s\n")

    print("| sweep | speeds | workers | wall (s) | sum of point times (s) | workers busy "
          "| complete | FE ms/step |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    rows: list[str] = []
    if not args.skip_fe40:
        wall, report = timed_sweep("fe", SPEEDS_40, root / "fe40", args.jobs)
        rows.append(describe(f"FE, {SPEEDS_40} rpm", wall, report, args.jobs))
        print(rows[-1], flush=True)

    cli_out = root / "lumped40-cli"
    t = time.perf_counter()
    subprocess.run([str(Path(sys.executable).with_name("spurdyn")), "sweep", "paper-fig8",
                    "--rpm", SPEEDS_40, "--model", "lumped", "--jobs", str(args.jobs),
                    "--out", str(cli_out), "--quiet", "--force"], check=True)
    cli_wall = time.perf_counter() - t
    wall, report = timed_sweep("lumped", SPEEDS_40, root / "lumped40", args.jobs)
    rows.append(describe(f"lumped, {SPEEDS_40} rpm (Python API)", wall, report, args.jobs))
    print(rows[-1])
    print(f"| lumped, {SPEEDS_40} rpm (`spurdyn sweep` command, Python start-up included) "
          f"| 40 | {args.jobs} | {cli_wall:.1f} | | | | - |", flush=True)

    for jobs in (1, 2):
        wall, report = timed_sweep("fe", SPEEDS_6, root / f"fe6-{jobs}", jobs)
        rows.append(describe(f"FE, {SPEEDS_6} rpm", wall, report, jobs))
        print(rows[-1], flush=True)

    print(f"\nload average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(f"sweep folders: {root}")


if __name__ == "__main__":
    main()
