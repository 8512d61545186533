"""Benchmark of the steady-state sweeps and the sector model's mesh cycle (issues 15, 16):
``python benchmarks/bench_steady.py``.

Prints

1. the sector model's quasi-static mesh cycle of the paper's pair (41 positions, default
   mesh and teeth), best of ``--reps``, in this process (``spurdyn stiffness``'s work);
2. the wall time of ``spurdyn sweep paper-fig8 --model lumped --cycles 20 --damping 0.05
   --rpm 1000:20000/40`` in a fresh process and an empty folder (Python start-up, the local
   Dask cluster and the stiffness included), with the tooth's stiffness and with
   ``--stiffness sector``;
3. the same with the sector stiffness and ``--continuation up`` (one process, in turn).

Options: ``--reps N`` (item 1), ``--jobs N`` (the sweeps' workers).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SWEEP = ["sweep", "paper-fig8", "--model", "lumped", "--cycles", "20", "--damping", "0.05",
         "--rpm", "1000:20000/40", "--quiet"]


def _spurdyn(args: list[str]) -> float:
    exe = Path(sys.executable).with_name("spurdyn")
    t0 = time.perf_counter()
    subprocess.run([str(exe), *args], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--jobs", type=int, default=None)
    args = parser.parse_args()
    from spurdyn.case import preset_case
    from spurdyn.sector.statics import mesh_cycle

    case = preset_case("paper-fig8")
    times = []
    for _ in range(args.reps):
        t0 = time.perf_counter()
        mc = mesh_cycle(case.pair, case.run.torque, 4, 14)
        times.append(time.perf_counter() - t0)
    print(f"mesh cycle, paper's pair, 41 positions, {mc.n_dof:,} DOFs: best {min(times):.2f} s "
          f"of {args.reps}")
    jobs = [] if args.jobs is None else ["--jobs", str(args.jobs)]
    with tempfile.TemporaryDirectory() as tmp:
        for label, extra in (("tooth stiffness", jobs), ("sector stiffness", ["--stiffness", "sector", *jobs]),
                             ("sector stiffness, --continuation up", ["--stiffness", "sector", "--continuation", "up"])):
            out = Path(tmp) / label.replace(" ", "_").replace(",", "")
            wall = _spurdyn(SWEEP + extra + ["--out", str(out)])
            print(f"steady sweep, 40 speeds x 20 cycles, {label}: {wall:.1f} s")
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
