"""Cost of the distributed contact against the point contact: ``python benchmarks/bench_contact.py``.

For each of the paper's four cases, the same run (default mesh, the paper's step, the
compiled backend) with ``contact="point"`` and ``contact="hertz"``, each in a fresh
process after a short warm-up run, ``--reps`` times alternately; prints the median time
of the time loop per step, the mean iterations per stage, and the ratio. Issue 14 allows
the distributed contact at most 25 % more per step. ``--json FILE`` keeps the figures.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys

CASES = {"paper-fig8": (4000.0, 4000.0), "paper-fig9": (20000.0, 20000.0),
         "paper-fig10": (4000.0, 4040.0), "paper-fig11": (20000.0, 20200.0)}

CHILD = r"""
import json, sys, time
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
from spurdyn.solvers.loop import simulate
from spurdyn.settings import RunSettings, RPM
a, b, contact = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
pair = paper_pair()
case = RunSettings(speed_a=a * RPM, speed_b=b * RPM, torque=PAPER_TORQUE, contact=contact)
simulate(pair, case.with_(angle=20 * case.dt * case.speed_a))   # load the compiled code
r = simulate(pair, case)
print(json.dumps({"status": r.status, "steps": r.steps, "loop_s": r.info["loop_s"],
                  "iterations": r.iterations[1:].mean(axis=0).tolist()}))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--json", metavar="FILE")
    args = parser.parse_args()
    out = {}
    for name, (a, b) in CASES.items():
        runs: dict[str, list[dict]] = {"point": [], "hertz": []}
        for _ in range(args.reps):
            for contact in runs:
                res = subprocess.run([sys.executable, "-c", CHILD, str(a), str(b), contact],
                                     capture_output=True, text=True, check=True)
                runs[contact].append(json.loads(res.stdout.strip().splitlines()[-1]))
        row = {}
        for contact, rs in runs.items():
            per = statistics.median(r["loop_s"] / max(r["steps"], 1) for r in rs)
            row[contact] = {"us_per_step": per * 1e6, "steps": rs[0]["steps"],
                            "status": rs[0]["status"], "iterations": rs[0]["iterations"]}
        row["ratio"] = row["hertz"]["us_per_step"] / row["point"]["us_per_step"]
        out[name] = row
        it = lambda c: "/".join(f"{x:.2f}" for x in row[c]["iterations"])  # noqa: E731
        print(f"{name}: point {row['point']['us_per_step']:.1f} us/step ({row['point']['steps']:,} steps, "
              f"iterations {it('point')}), hertz {row['hertz']['us_per_step']:.1f} us/step "
              f"({row['hertz']['steps']:,} steps, iterations {it('hertz')}): x{row['ratio']:.3f}",
              flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
