"""Benchmark of the paper's four cases: one command, ``python benchmarks/bench_paper.py``.

For each case (each in a fresh process, so its peak memory is its own): wall time of
``simulate``, steps per second, mean iterations per stage, peak resident memory; then the
NumPy reference on a shortened run of the same case, scaled by steps, for the speed-up;
``paper-all --jobs 2`` through the command line; and where the time of a compiled step
goes (each part timed in a compiled loop on a loaded state).

Then the two figures a user meets first: ``spurdyn run paper-fig8`` from the command line
(Python start-up, set-up, the run and writing every output file), and the first run on
a machine with an empty compile cache (a fresh ``SPURDYN_CACHE_DIR``), which compiles the
kernels before it runs.

The Fig. 8 loop against the bare-RK4 floor (issue 34): in one process, ``simulate`` of
Fig. 8 and a bare compiled RK4 of the same two teeth over as many steps (four force
evaluations a step, the same compiled ``accelerations`` the step calls, no constraint),
taken in turns ``--floor-reps`` times; the best of each and their ratio.

Options: ``--ref-steps N`` (reference steps per case, default 40), ``--quick`` (only
fig9, fewer repetitions), ``--no-cli``, ``--no-compile``, ``--floor-reps N`` (default 3;
0 skips it), ``--floor-only``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

CASES = {"paper-fig8": (4000.0, 4000.0), "paper-fig9": (20000.0, 20000.0),
         "paper-fig10": (4000.0, 4040.0), "paper-fig11": (20000.0, 20200.0)}

CHILD = r"""
import json, math, resource, sys, time
import numpy as np
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
from spurdyn.solvers.loop import simulate
from spurdyn.settings import RunSettings, RPM
a, b, backend, steps = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3], int(sys.argv[4])
pair = paper_pair()
case = RunSettings(contact="point", speed_a=a * RPM, speed_b=b * RPM, torque=PAPER_TORQUE, backend=backend)
if steps:
    case = case.with_(angle=steps * case.dt * case.speed_a)
simulate(pair, case.with_(angle=20 * case.dt * case.speed_a))   # load the compiled code
t = time.perf_counter()
r = simulate(pair, case)
wall = time.perf_counter() - t
print(json.dumps({"status": r.status, "steps": r.steps, "wall": wall,
                  "iterations": r.iterations[1:].mean(axis=0).tolist(),
                  "peak_force": float(r.contact_force.max()),
                  "maxrss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


COLD = r"""
import json, time
t0 = time.perf_counter()
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
from spurdyn.solvers.loop import simulate
from spurdyn.settings import RunSettings, RPM
case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE)
t1 = time.perf_counter()
r = simulate(paper_pair(), case)
t2 = time.perf_counter()
r = simulate(paper_pair(), case)
t3 = time.perf_counter()
print(json.dumps({"import": t1 - t0, "first": t2 - t1, "second": t3 - t2, "status": r.status}))
"""


FLOOR = r"""
import json, sys, time
import numpy as np
from numba import njit
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
from spurdyn.model.system import build_system
from spurdyn.settings import RunSettings, RPM
from spurdyn.solvers.loop import simulate
from spurdyn.solvers.paper.dynamics_compiled import accelerations
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper


@njit
def axpy(out_t, out_u, t, u, c, dt, du):
    for i in range(2):
        out_t[i] = t[i] + c * dt[i]
    for i in range(u.size):
        out_u[i] = u[i] + c * du[i]


@njit
def bare_rk4(P, th, om, u, v, h, steps):
    n = u.size
    w, kw, el, q, f_u, f_t = np.empty(n), np.empty(n), np.empty(n), np.empty(2), np.zeros(n), np.zeros(2)
    at, au = np.empty((4, 2)), np.empty((4, n))      # the stages' accelerations
    vt, vu = np.empty((4, 2)), np.empty((4, n))      # and velocities
    qt, qu = np.empty(2), np.empty(n)
    c = (0.5 * h, 0.5 * h, h)
    for _ in range(steps):
        vt[0], vu[0] = om, v
        accelerations(th, u, f_t, f_u, P, w, kw, el, q, at[0], au[0])
        for k in range(3):
            axpy(qt, qu, th, u, c[k], vt[k], vu[k])
            axpy(vt[k + 1], vu[k + 1], om, v, c[k], at[k], au[k])
            accelerations(qt, qu, f_t, f_u, P, w, kw, el, q, at[k + 1], au[k + 1])
        for i in range(2):
            th[i] += h / 6.0 * (vt[0, i] + 2.0 * vt[1, i] + 2.0 * vt[2, i] + vt[3, i])
            om[i] += h / 6.0 * (at[0, i] + 2.0 * at[1, i] + 2.0 * at[2, i] + at[3, i])
        for i in range(n):
            u[i] += h / 6.0 * (vu[0, i] + 2.0 * vu[1, i] + 2.0 * vu[2, i] + vu[3, i])
            v[i] += h / 6.0 * (au[0, i] + 2.0 * au[1, i] + 2.0 * au[2, i] + au[3, i])


pair = paper_pair()
case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE)
simulate(pair, case.with_(angle=20 * case.dt * case.speed_a))   # load the compiled code
S0 = CompiledStepper(build_system(pair, case), case).S
P = CompiledStepper(build_system(pair, case), case).P


def floor(steps):
    th, om, u, v = S0.theta.copy(), S0.omega.copy(), S0.u.copy(), S0.v.copy()
    t = time.perf_counter()
    bare_rk4(P, th, om, u, v, case.dt, steps)
    return time.perf_counter() - t


floor(10)
loops, floors, steps = [], [], 0
for _ in range(int(sys.argv[1])):
    t = time.perf_counter()
    steps = simulate(pair, case).steps
    loops.append(time.perf_counter() - t)
    floors.append(floor(steps))
print(json.dumps({"steps": steps, "loops": loops, "floors": floors}))
"""


def loop_and_floor(reps: int) -> dict:
    """The Fig. 8 loop and the bare-RK4 floor over as many steps, ``reps`` times each in
    turn in one fresh process."""
    out = subprocess.run([sys.executable, "-c", FLOOR, str(reps)], capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def print_floor(reps: int) -> None:
    """Print the Fig. 8 loop against the bare-RK4 floor (best of ``reps`` each)."""
    f = loop_and_floor(reps)
    loop, bare = min(f["loops"]), min(f["floors"])
    print(f"paper-fig8 loop against the bare-RK4 floor ({f['steps']} steps, best of {reps}, "
          f"load {os.getloadavg()[0]:.2f}): loop {loop:.2f} s ({loop / f['steps'] * 1e6:.1f} us/step), "
          f"floor {bare:.2f} s ({bare / f['steps'] * 1e6:.1f} us/step) -> {loop / bare:.2f} x")


def child(a: float, b: float, backend: str, steps: int) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, str(a), str(b), backend, str(steps)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def cold_start() -> dict:
    """paper-fig8 twice in one process whose compile cache starts empty."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, SPURDYN_CACHE_DIR=cache)
        env.pop("NUMBA_CACHE_DIR", None)
        out = subprocess.run([sys.executable, "-c", COLD], capture_output=True, text=True,
                             check=True, env=env)
    return json.loads(out.stdout.strip().splitlines()[-1])


def breakdown(reps: int) -> dict[str, float]:
    """Microseconds per call of each part of a compiled step, timed inside Numba."""
    import math

    import numpy as np
    from numba import njit

    from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
    from spurdyn.contact import search_compiled as sc_
    from spurdyn.solvers.paper import dynamics_compiled as k
    from spurdyn.solvers.paper import response_compiled as rc
    from spurdyn.solvers.layout import SparseWork
    from spurdyn.solvers.paper import step_compiled as fs
    from spurdyn.solvers.paper.stepper_compiled import CompiledStepper
    from spurdyn.settings import RPM, RunSettings
    from spurdyn.model.system import build_system

    case = RunSettings(contact="point", speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE)
    f = CompiledStepper(build_system(paper_pair(), case), case)
    for _ in range(3000):
        f.step()
    P, S, h = f.P, f.S, case.dt
    n, m = S.u.size, S.x.size
    nd = P.fl_nodes.shape[1]

    @njit
    def t_step(N, P, S, cfg):
        for _ in range(N):
            fs.step(P, S, cfg, None)

    @njit
    def t_predict(N, P, S, h):
        for _ in range(N):
            rc.predict(P, S, h)

    @njit
    def t_columns(N, P, S, h):
        pred = rc.predict(P, S, h)
        R = 2 + 2 * P.rel_nodes.size
        m = S.x.size
        n = S.u.size
        Wq, Wv = np.zeros((R, m)), np.zeros((R, m))
        sc, mk = np.zeros(n), np.zeros(n // 2, dtype=np.int64)
        tch, nz = np.empty(n // 2, dtype=np.int64), np.empty(n // 2, dtype=np.int64)
        zu, a3, a4 = np.zeros(n), np.zeros(n), np.zeros(n)
        for _ in range(N):
            rc.response_columns(P, h, pred, S.theta, S.cn, S.cw, S.normal, S.gth, 0, m, Wq, Wv,
                                SparseWork(sc, mk, tch, nz, zu, a3, a4))

    @njit
    def t_superpose(N, P, S, h):
        pred = rc.predict(P, S, h)
        for _ in range(N):
            rc.superpose(P, S, h, pred, S.x, S.cn, S.cw, S.normal, S.gth, True)

    @njit
    def t_search(N, P, S, nd):
        va, vb, ma, mb = np.empty((nd, 2)), np.empty((nd, 2)), np.empty((nd, 2)), np.empty((nd, 2))
        g = np.array([S.cpar[0], S.cpar[1]])
        for _ in range(N):
            sc_.search(P, S.theta, S.u, g, va, vb, ma, mb)

    @njit
    def t_matvec(N, P, v):
        out = np.empty_like(v)
        for _ in range(N):
            k.bsr_matvec(P.indptr, P.indices, P.data, v, out)

    def clock(fn, *args):
        fn(1, *args)
        t = time.perf_counter()
        fn(reps, *args)
        return (time.perf_counter() - t) / reps * 1e6

    parts = {"whole step": clock(t_step, P, S, f.cfg),
             "RK4 prediction (3 force evaluations)": clock(t_predict, P, S, h),
             f"response columns ({m} of them)": clock(t_columns, P, S, h),
             "superposition of a full state (x2 a step)": clock(t_superpose, P, S, h),
             "spline + contact search (per iteration)": clock(t_search, P, S, nd),
             "stiffness product K v (both teeth)": clock(t_matvec, P, S.u.copy())}
    parts["iterations a step (disp/vel/acc)"] = list(map(int, S.its))
    return parts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ref-steps", type=int, default=40)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-cli", action="store_true")
    ap.add_argument("--no-compile", action="store_true")
    ap.add_argument("--floor-reps", type=int, default=3)
    ap.add_argument("--floor-only", action="store_true")
    args = ap.parse_args()
    if args.floor_only:
        print_floor(max(args.floor_reps, 1))
        return
    cases = {"paper-fig9": CASES["paper-fig9"]} if args.quick else CASES
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, load {os.getloadavg()[0]:.2f}")
    total = 0.0
    rows = []
    for name, (a, b) in cases.items():
        fast = child(a, b, "numba", 0)
        ref = child(a, b, "numpy", args.ref_steps)
        ref_per_step = ref["wall"] / max(ref["steps"], 1)
        total += fast["wall"]
        rows.append((name, fast, ref_per_step))
        its = "/".join(f"{x:.2f}" for x in fast["iterations"])
        print(f"{name:<12} {fast['status']:<10} {fast['steps']:>6} steps {fast['wall']:6.2f} s "
              f"{fast['steps'] / fast['wall']:8.0f} steps/s  iterations {its}  "
              f"peak memory {fast['maxrss_mb']:6.0f} MB  reference {ref_per_step * 1e3:7.1f} ms/step "
              f"-> speed-up {ref_per_step * fast['steps'] / fast['wall']:5.0f}x")
    print(f"all {len(rows)} cases: {total:.1f} s of simulation")
    if args.floor_reps > 0 and not args.quick:
        print_floor(args.floor_reps)
    if not args.no_cli and not args.quick:
        with tempfile.TemporaryDirectory() as tmp:
            t = time.perf_counter()
            subprocess.run([sys.executable, "-m", "spurdyn.cli.main", "run", "paper-all", "--jobs", "2",
                            "--quiet", "--out", os.path.join(tmp, "all")], check=True)
            print(f"spurdyn run paper-all --jobs 2: {time.perf_counter() - t:.1f} s wall "
                  f"(CPU time of the children {resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime:.1f} s)")
    if not args.no_cli:
        with tempfile.TemporaryDirectory() as tmp:
            t = time.perf_counter()
            subprocess.run([sys.executable, "-m", "spurdyn.cli.main", "run", "paper-fig8",
                            "--quiet", "--out", os.path.join(tmp, "fig8")], check=True)
            print(f"spurdyn run paper-fig8 (command, every output file written): "
                  f"{time.perf_counter() - t:.1f} s wall")
    if not args.no_compile and not args.quick:
        c = cold_start()
        print(f"first run with an empty compile cache: paper-fig8 {c['first']:.1f} s "
              f"(compiling included; import {c['import']:.1f} s), the same run again "
              f"{c['second']:.1f} s -> compiling ~{c['first'] - c['second']:.0f} s")
    print("where the time of a compiled step goes (us per call, 4,000 rpm, loaded):")
    for part, us in breakdown(300 if args.quick else 2000).items():
        print(f"  {part:<45} {us if isinstance(us, list) else f'{us:8.1f}'}")


if __name__ == "__main__":
    main()
