"""The first run's compile: ``python benchmarks/bench_fig8_compile.py``.

Runs Fig. 8 (the paper's RK4, point contact, compiled) through ``simulate`` in a fresh
process on an empty compile cache (a new ``SPURDYN_CACHE_DIR``): first the first 0.5 deg
of the engagement, which compiles what such a run calls, then the same again, warm; the
difference is the compile. The contact is the preset's, the point one, unless ``--contact
hertz`` (``RunSettings``' own default is the strip: before 2026-11-29 this benchmark timed
the strip's kernel by mistake); ``--integrator implicit`` times the implicit step instead; ``--warm N`` adds N warm runs of the whole engagement (the loop's speed).

The compile's CPU time is printed too: on a busy machine the wall time grows with the
load, the CPU time much less (on an idle one the two are the same, one core compiling).
Each time is printed in seconds and as a ratio to a calibration measured in the same run
(a fixed pure-Python workload and a dense product, best of three: Numba's compiling is
mostly Python and LLVM on one core), with the load average, so that runs on a loaded or
another machine compare. It also runs on commits before the restructure (their names).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

CHILD = """
import json, math, sys, time
args = json.loads(sys.argv[1])
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
try:
    from spurdyn.settings import RunSettings as R, RPM
    from spurdyn.solvers.loop import simulate
except ImportError:
    from spurdyn.solver.case import RunCase as R, RPM
    from spurdyn.integrate import simulate
base = dict(speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE, frames_every=0)
extra = {k: v for k, v in (("contact", args["contact"]), ("integrator", args["integrator"]))
         if v is not None}
short = R(**base, **extra, angle=math.radians(0.5))
times, cpu = [], []
for _ in range(2):
    t, c = time.perf_counter(), time.process_time()
    r = simulate(paper_pair(), short)
    times.append(time.perf_counter() - t); cpu.append(time.process_time() - c)
whole = []
for _ in range(args["warm"]):
    t = time.perf_counter(); w = simulate(paper_pair(), R(**base, **extra)); whole.append(time.perf_counter() - t)
print(json.dumps({"first_s": times[0], "again_s": times[1], "first_cpu_s": cpu[0],
                  "again_cpu_s": cpu[1], "steps": int(r.steps), "warm_s": sorted(whole)}))
"""


def calibration() -> float:
    """Seconds of a fixed pure-Python workload and a dense product (best of 3)."""
    import numpy as np

    dense = np.random.default_rng(0).normal(size=(400, 400))
    best = float("inf")
    for _ in range(3):
        t = time.perf_counter()
        table: dict[int, int] = {}
        for i in range(300_000):
            table[i % 1009] = table.get(i % 1009, 0) + i
        sorted(str(i) for i in range(100_000))
        dense @ dense
        best = min(best, time.perf_counter() - t)
    return best


def first_run(args: argparse.Namespace) -> dict:
    """The child's figures, on a compile cache of its own that starts empty."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "SPURDYN_CACHE_DIR": cache}
        env.pop("NUMBA_CACHE_DIR", None)
        child = {"contact": args.contact, "integrator": args.integrator, "warm": args.warm}
        out = subprocess.run([sys.executable, "-c", CHILD, json.dumps(child)], env=env,
                             check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--contact", choices=("point", "hertz"), default="point",
                    help="the contact (default: point, as the preset paper-fig8)")
    ap.add_argument("--integrator", choices=("rk4", "implicit"), help="default: rk4")
    ap.add_argument("--warm", type=int, default=0, metavar="N",
                    help="warm runs of the whole engagement after the compile (default 0)")
    args = ap.parse_args()
    load0, cal = os.getloadavg()[0], calibration()
    got = first_run(args)
    compile_s = got["first_s"] - got["again_s"]
    compile_cpu = got["first_cpu_s"] - got["again_cpu_s"]
    print(f"calibration {cal:.3f} s; load average {load0:.1f} before, "
          f"{os.getloadavg()[0]:.1f} after")
    print(f"first 0.5 deg on an empty cache {got['first_s']:6.1f} s, again {got['again_s']:.2f} s "
          f"({got['steps']} steps) -> compiling {compile_s:6.1f} s = {compile_s / cal:6.0f} x "
          f"calibration; CPU {compile_cpu:.1f} s")
    if got["warm_s"]:
        print("whole engagement, warm: " + ", ".join(f"{t:.2f} s" for t in got["warm_s"]))
    print(json.dumps({**got, "compile_s": compile_s, "compile_cpu_s": compile_cpu,
                      "calibration_s": cal,
                      "ratio": compile_s / cal}))


if __name__ == "__main__":
    main()
