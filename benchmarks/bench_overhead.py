"""The command's time outside the time loop: ``python benchmarks/bench_overhead.py``.

Runs ``spurdyn run paper-fig8`` (a warm compile cache; one run first to make sure) ``--reps``
times and splits its wall time into the time loop (``loop_s``, which the solver stores in
``result.nc``) and everything else: Python start-up and imports, building and checking the
case and the system, making the stepper, and writing every output file. Then the import
of the command's module alone, and the set-up parts timed in process (the case file, the
system, the run check, the stepper). Prints a JSON line per figure and a summary table;
``--json FILE`` keeps them.

The target of issue 13: at most 1.5 s outside the loop for ``spurdyn run paper-fig8``.

``--command PATH`` times another ``spurdyn`` (an older checkout's, to compare): with
``PYTHONPATH=<checkout>/src`` the in-process figures are that checkout's too.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SPURDYN = str(Path(sys.executable).parent / "spurdyn")

IN_PROCESS = r"""
import json, time
t0 = time.perf_counter()
from spurdyn.case import resolve_cases
t1 = time.perf_counter()
case = resolve_cases("paper-fig8")[0]            # parse, build the system, run check
t2 = time.perf_counter()
from spurdyn.model.system import build_system
from spurdyn.solvers.check import check_run
from spurdyn.solvers.loop import make_stepper
system = build_system(case.pair, case.run)       # kept from the check: no second build
check_run(case.pair, case.run, system)
t3 = time.perf_counter()
stepper = make_stepper(system, case.run)         # pack, start state (compiled code loads)
t4 = time.perf_counter()
print(json.dumps({"import_cases": t1 - t0, "case_and_check": t2 - t1,
                  "second_build_and_check": t3 - t2, "stepper": t4 - t3}))
"""


def run_once(out: Path, command: str = SPURDYN) -> tuple[float, float]:
    """``(command wall time, loop_s)`` of one ``spurdyn run paper-fig8``."""
    t0 = time.perf_counter()
    subprocess.run([command, "run", "paper-fig8", "--out", str(out), "--force", "--quiet"],
                   check=True)
    wall = time.perf_counter() - t0
    import xarray as xr

    with xr.open_dataset(out / "result.nc") as ds:
        loop = float(json.loads(ds.attrs["info"])["loop_s"])
    return wall, loop


def import_time() -> float:
    """Wall time of ``python -c 'import spurdyn.cli.main'`` minus a bare interpreter's."""
    def timed(code: str) -> float:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        return time.perf_counter() - t0
    bare = min(timed("pass") for _ in range(3))
    return min(timed("import spurdyn.cli.main") for _ in range(3)) - bare


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--command", default=SPURDYN, help="the spurdyn to time")
    args = ap.parse_args()
    load_before = os.getloadavg()[0]      # the figures mean little on a busy machine
    tmp = Path(tempfile.mkdtemp())
    try:
        run_once(tmp / "warm", args.command)       # compile cache and disk cache warm
        runs = [run_once(tmp / f"r{i}", args.command) for i in range(args.reps)]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    walls, loops = zip(*runs)
    outside = [w - lp for w, lp in runs]
    parts = json.loads(subprocess.run([sys.executable, "-c", IN_PROCESS], check=True,
                                      capture_output=True, text=True).stdout.splitlines()[-1])
    figures = {
        "command_wall_s_median": statistics.median(walls),
        "loop_s_median": statistics.median(loops),
        "outside_loop_s_median": statistics.median(outside),
        "outside_loop_s_min": min(outside),
        "outside_loop_s_each": [round(x, 3) for x in outside],
        "loop_s_each": [round(x, 3) for x in loops],
        "import_cli_s": import_time(),
        **{f"in_process_{k}_s": v for k, v in parts.items()},
        "load_before": load_before,
        "load_after": os.getloadavg()[0],
        "reps": args.reps,
        "python": sys.version.split()[0],
    }
    for key, value in figures.items():
        print(f"{key:<40} {value:.3f}" if isinstance(value, float) else f"{key:<40} {value}")
    if args.json:
        args.json.write_text(json.dumps(figures, indent=1))


if __name__ == "__main__":
    main()
