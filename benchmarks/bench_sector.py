"""Benchmark of the sector model in motion (issues 15, 16): ``python benchmarks/bench_sector.py``.

Prints

1. the cost of a step per coordinate of the sector model, whole bodies and modal, on the
   paper's pair at 4,000 rpm over 3 mesh cycles at the default teeth (the loop only, its
   setup apart), beside the paper model's RK4 and implicit steps on Fig. 8 (the issue's
   yardstick: within 1.5 times the paper model's per step per DOF), and the modal loop with
   the back flanks as contacts (the pair 0.1 mm further apart: 69 um of backlash, no back
   contact) beside it without them, 20 cycles, and with the hubs on bearings beside them held;
2. the wall time of ``spurdyn sweep paper-fig8 --model sector --integrator implicit --cycles 20
   --damping 0.05 --rpm 1000:20000/40`` (the issue's command; modal bodies, their default damping) in a fresh process and an empty folder, unless
   ``--no-sweep``; ``--speeds N`` for fewer speeds (the sweep's time scales with them).

Options: ``--jobs N`` (the sweep's workers).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from bench_steady import _spurdyn   # a spurdyn command in a fresh process, timed


def sector_steps() -> None:
    from spurdyn.geometry.presets import paper_pair
    from spurdyn.settings import RPM
    from spurdyn.solvers.check import run_settings
    from spurdyn.solvers.sector.run import simulate_sector

    pair = paper_pair()
    for bodies in ("full", "modal"):
        s = run_settings(pair, 4000 * RPM, 22.25, dt=1e-6, cycles=3, max_cycles=3, bodies=bodies)
        ticks: list[float] = []
        run = simulate_sector(pair, s, lambda k, a, tot: ticks.append(time.perf_counter()))
        steps = run.steps
        # the loop from the first progress call (1 % of the steps) to the last
        loop = (ticks[-1] - ticks[0]) / (steps * (len(ticks) - 1) / len(ticks))
        n = run.info["coordinates"]
        print(f"sector, {bodies} bodies: {n:,} coordinates ({run.info['n_dof']:,} FE DOFs), "
              f"{steps:,} steps, {loop * 1e3:.2f} ms a step, {loop / n * 1e6:.3f} us a step per "
              f"coordinate, {loop / run.info['n_dof'] * 1e6:.3f} us per FE DOF; run {run.wall_s:.1f} s")


def back_flank_steps() -> None:
    """The compiled modal loop with and without the back flanks, 20 cycles at 4,000 rpm."""
    import dataclasses

    from spurdyn.geometry.presets import paper_pair
    from spurdyn.settings import RPM
    from spurdyn.solvers.check import run_settings
    from spurdyn.solvers.sector.run import simulate_sector

    pair = paper_pair()
    loose = dataclasses.replace(pair, centre_distance=pair.centre_distance + 0.1e-3)
    s = run_settings(loose, 4000 * RPM, 22.25, dt=1e-6, cycles=20, max_cycles=20, damping_ratio=0.05)
    simulate_sector(loose, s.with_(back_flanks=True))        # the modes and the compiled loop, once
    for back in (False, True):
        _step_time(loose, s.with_(back_flanks=back), f"back flanks {'on' if back else 'off'}")


def _step_time(pair: object, settings: object, label: str) -> None:
    """Print the compiled modal loop's time a step of one run (from its progress ticks)."""
    from spurdyn.solvers.sector.run import simulate_sector

    ticks: list[float] = []
    run = simulate_sector(pair, settings, lambda k, a, tot: ticks.append(time.perf_counter()))
    loop = (ticks[-1] - ticks[0]) / (run.steps * (len(ticks) - 1) / len(ticks))
    print(f"sector, modal, {label}: {run.steps:,} steps, {loop * 1e6:.1f} us a step; run {run.wall_s:.2f} s")


def bearing_steps() -> None:
    """The compiled modal loop with the hubs on bearings (1e8 N/m, 1e3 N s/m each) beside it
    with their centres held, 20 cycles at 4,000 rpm (docs/sector.md, 6.12)."""
    from spurdyn.geometry.presets import paper_pair
    from spurdyn.settings import RPM, Bearing
    from spurdyn.solvers.check import run_settings
    from spurdyn.solvers.sector.run import simulate_sector

    pair = paper_pair()
    s = run_settings(pair, 4000 * RPM, 22.25, dt=1e-6, cycles=20, max_cycles=20)
    on = (Bearing(1e8, 1e3), Bearing(1e8, 1e3))
    simulate_sector(pair, s.with_(bearings=on))        # the modes and the compiled loop, once
    for bearings in (None, on):
        _step_time(pair, s.with_(bearings=bearings), f"bearings {'on' if bearings else 'off'}")


def paper_steps() -> None:
    from spurdyn.case import preset_case
    from spurdyn.solvers.loop import simulate

    case = preset_case("paper-fig8")
    for integrator in ("rk4", "implicit"):
        run = case.run.with_(integrator=integrator, angle=case.pair.theta_s * 0.3)
        if integrator == "implicit":
            from spurdyn.model.alpha import accuracy_step
            from spurdyn.solvers.check import round_down

            run = run.with_(dt=round_down(accuracy_step(run.speed_a, case.pair.gear_a.teeth), 2))
        simulate(case.pair, run.with_(angle=run.dt * run.speed_a * 50))     # compile, warm
        t0 = time.perf_counter()
        res = simulate(case.pair, run)
        wall = time.perf_counter() - t0
        n = int(res.info.get("n_dof", 0)) or 1
        print(f"paper model, {integrator}: {n:,} DOFs, {res.steps:,} steps, "
              f"{wall / res.steps * 1e6:.1f} us a step, {wall / res.steps / n * 1e6:.3f} us a step per DOF")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=None)
    parser.add_argument("--speeds", type=int, default=40)
    parser.add_argument("--no-sweep", action="store_true")
    args = parser.parse_args()
    paper_steps()
    sector_steps()
    back_flank_steps()
    bearing_steps()
    if args.no_sweep:
        return
    jobs = [] if args.jobs is None else ["--jobs", str(args.jobs)]
    with tempfile.TemporaryDirectory() as tmp:
        wall = _spurdyn(["sweep", "paper-fig8", "--model", "sector", "--integrator", "implicit", "--cycles", "20",
                         "--damping", "0.05", "--rpm", f"1000:20000/{args.speeds}", "--quiet", "--out",
                         str(Path(tmp) / "s"), *jobs])
        print(f"sector sweep, {args.speeds} speeds x 20 cycles, modal bodies: {wall:.1f} s")


if __name__ == "__main__":
    main()
