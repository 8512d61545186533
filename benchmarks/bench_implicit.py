"""The implicit integrator against RK4, steps and wall time: ``python benchmarks/bench_implicit.py``.

For each of the paper's four cases (point contact, the presets; ``--contact hertz`` for
the distributed one), RK4 at the paper's step (compiled) and the implicit integrator at
its default step (docs/implicit.md), each in a fresh process after a short warm-up run,
``--reps`` times alternately; prints the median time of the time loop, the steps, and the
time per step. ``--json FILE`` keeps the figures.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys

CASES = ("paper-fig8", "paper-fig9", "paper-fig10", "paper-fig11")

CHILD = r"""
import json, sys
from spurdyn.case import preset_case
from spurdyn.model.alpha import accuracy_step
from spurdyn.solvers.check import round_down
from spurdyn.solvers.loop import simulate
name, integrator, contact = sys.argv[1], sys.argv[2], sys.argv[3]
case = preset_case(name)
run = case.run.with_(frames_every=0, contact=contact, integrator=integrator)
if integrator == "implicit":
    run = run.with_(dt=round_down(accuracy_step(run.speed_a, case.pair.gear_a.teeth), 2))
simulate(case.pair, run.with_(angle=20 * run.dt * run.speed_a))     # load what it needs
r = simulate(case.pair, run)
print(json.dumps({"loop_s": r.info["loop_s"], "steps": r.steps, "status": r.status}))
"""


def once(name: str, integrator: str, contact: str) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, name, integrator, contact],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--contact", default="point")
    p.add_argument("--json", metavar="FILE")
    args = p.parse_args()
    table = {}
    for name in CASES:
        runs: dict[str, list[dict]] = {"rk4": [], "implicit": []}
        for _ in range(args.reps):
            for integrator in runs:
                runs[integrator].append(once(name, integrator, args.contact))
        row = {}
        for integrator, rs in runs.items():
            loop = statistics.median(r["loop_s"] for r in rs)
            row[integrator] = {"loop_s": loop, "steps": rs[0]["steps"], "status": rs[0]["status"],
                               "us_per_step": 1e6 * loop / rs[0]["steps"]}
        table[name] = row
        rk, im = row["rk4"], row["implicit"]
        print(f"{name}: RK4 {rk['steps']:,} steps {rk['loop_s']:.2f} s ({rk['us_per_step']:.0f} us/step); "
              f"implicit {im['steps']:,} steps {im['loop_s']:.2f} s ({im['us_per_step']:.0f} us/step, "
              f"{im['status']}); steps x{rk['steps'] / im['steps']:.1f}, time x{rk['loop_s'] / im['loop_s']:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(table, fh, indent=1)


if __name__ == "__main__":
    main()
