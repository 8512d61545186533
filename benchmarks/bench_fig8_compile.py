"""Fig. 8 through ``simulate``: the first call on an empty compile cache, then three warm calls.

Run with a fresh cache folder to time the compilation::

    SPURDYN_CACHE_DIR=$(mktemp -d) python benchmarks/bench_fig8_compile.py

Prints one JSON line: ``first_s`` (compile + run), the sorted ``warm_s``, the steps and the
mean iterations per stage. It also runs on commits before the restructure (their names),
so the two can be compared on one machine.
"""
import json, sys, time
t0 = time.perf_counter()
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
try:
    from spurdyn.settings import RunSettings as R, RPM
    from spurdyn.solvers.loop import simulate
except ImportError:
    from spurdyn.solver.case import RunCase as R, RPM
    from spurdyn.integrate import simulate
c = R(speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE, frames_every=0)
t1 = time.perf_counter(); r = simulate(paper_pair(), c); t2 = time.perf_counter()
walls = []
for _ in range(3):
    a = time.perf_counter(); r = simulate(paper_pair(), c); walls.append(time.perf_counter() - a)
print(json.dumps({"first_s": t2 - t1, "warm_s": sorted(walls), "steps": r.steps,
                  "it": [float(x) for x in r.iterations.mean(axis=0)]}))
