"""The table of the "pinned" method in docs/solver.md, section 6.

    .venv/bin/python docs/make_pinned_table.py      # about 3 minutes

For fine meshes where the paper's method stalls: the paper's method and the "pinned"
one with the same spline points, and, where the paper's method gets past the peak with
241 points, that run as the reference for the averaged peak. Each mesh at 0.9 of its own
stable RK4 step, the whole engagement. "Spikes" counts the samples of the raw force above
three times the quasi-static force tau_0 / r_b: none in a sound run of Fig. 8 or 9 (the
default mesh peaks at 1.2 and 1.8 times), while Fig. 10's impacts themselves reach 3.9
times on the default mesh, so there the count includes the impacts.
"""

from __future__ import annotations

import math
import time

import numpy as np

from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.solvers.loop import simulate
from spurdyn.solvers.check import stable_step
from spurdyn.result import Result
from spurdyn.results.headline import averaged_peak, window_means
from spurdyn.settings import RPM, RunSettings
from spurdyn.model.system import build_system

#: (label, rpm A, rpm B, nx, ny, spline points, compare with the paper's method at 241 points)
CASES = (("Fig. 9, 8 × 28", 20000.0, 20000.0, 8, 28, 61, True),
         ("Fig. 10, 6 × 20", 4000.0, 4040.0, 6, 20, 61, True),
         ("Fig. 8, 12 × 40", 4000.0, 4000.0, 12, 40, 241, False))


def describe(r: Result, wall: float, static: float) -> str:
    if r.status != "complete":
        return f"stops at {math.degrees(r.angle[-1]):.2f}° (step {r.steps + 1:,})"
    its = r.iterations[1:]
    mean = " / ".join(f"{x:.1f}" for x in its.mean(axis=0))
    top = " / ".join(str(int(x)) for x in its.max(axis=0))
    spikes = int((r.contact_force > 3 * static).sum())
    return (f"complete, {r.steps:,} steps, {wall:.1f} s; iterations {mean} a step (at most "
            f"{top}); raw peak {r.contact_force.max():,.0f} N, {spikes} spikes")


def timed(case: RunSettings) -> tuple[Result, float]:
    t0 = time.perf_counter()
    r = simulate(paper_pair(), case)
    return r, time.perf_counter() - t0


def main() -> None:
    static = PAPER_TORQUE / paper_pair().gear_a.base_radius
    print("| run | `\"paper\"` | `\"pinned\"` | 10-µs-averaged peak of the pinned run "
          "(against the paper's method with 241 points) |")
    print("| --- | --- | --- | --- |")
    for label, a, b, nx, ny, ns, compare in CASES:
        base = RunSettings(contact="point", speed_a=a * RPM, speed_b=b * RPM, torque=PAPER_TORQUE, nx=nx, ny=ny,
                       n_spline=ns, frames_every=0)
        base = base.with_(dt=0.9 * stable_step(build_system(paper_pair(), base)))
        paper = describe(*timed(base), static)
        pin, wall = timed(base.with_(method="pinned"))
        p_pin = averaged_peak(pin.time, pin.contact_force)[0]
        cell = f"{p_pin:,.1f} N"
        if compare:
            ref = simulate(paper_pair(), base.with_(n_spline=241))
            ta, fa, _ = window_means(ref.time, ref.contact_force)
            past = ta[-1] - ta[int(np.argmax(fa))]
            note = "" if ref.status == "complete" else \
                f", a run that stops at {math.degrees(ref.angle[-1]):.2f}°, {past * 1e6:.0f} µs after its peak"
            cell += f" (against {fa.max():,.1f} N{note}: {p_pin / fa.max() - 1:+.1%})"
        print(f"| {label}, {ns} points | {paper} | {describe(pin, wall, static)} | {cell} |",
              flush=True)


if __name__ == "__main__":
    main()
