"""The report as a whole: its introduction, the assembly of the sections, the command line."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from typing import Sequence

from .context import Ctx
from .convergence import section_convergence
from .helpers import n0, n2, pct, upct
from .limits import section_limits
from .lumped import section_lumped
from .paper import section_paper
from .physics import section_physics
from .relief import section_relief
from .runs import Run, all_runs, plain
from .settings import DATA, REPORT, RUNNER
from .sweep import section_sweep


def intro(ctx: Ctx, wall: float) -> str:
    """The page's title and summary, from the figures the sections left in ``ctx``."""
    R = ctx.runs
    fe = [r for r in R.values() if r.meta["spec"]["kind"] != "lumped"]
    total = sum(r.meta["wall_s"] for r in R.values())
    gits = sorted({r.meta["git"] for r in R.values()})
    dates = sorted(r.meta["date"] for r in R.values())
    df = ctx.figures["dynamic_factor"]
    c = ctx.figures["mesh_criterion"]
    fr = ctx.figures["frequency"]
    bal = ctx.figures["balances"]
    return f"""# Validation: what the results are worth

*This page is written by `docs/validation/report/`; every number in it is computed by
that script from the runs it makes (re-run it to regenerate the page and the figures in
`docs/figures/validation_*.png`). Runs: {len(R)} ({len(fe)} of the FE solver or its
stepper), {total / 60:.1f} min of computing in all, made {dates[0]} – {dates[-1]} on
{"commit " + gits[0] if len(gits) == 1 else "commits " + ", ".join(gits)}.*

> **The distributed contact** is measured on its own page,
> [`docs/contact_validation.md`](contact_validation.md), written by
> `docs/validation/contact.py`: stiffness against the mesh (even and graded), every
> preset and Figs. 8-10 on finer meshes with both contacts, pairs at design loads, Hertz,
> energy. This page measures the paper's point contact, which its presets use.
>
> **Root and contact stress** are measured on
> [`docs/stress_validation.md`](stress_validation.md), written by
> `docs/validation/stress.py`: the fillet stress against the mesh and ISO 6336-3 for
> three pairs, the strip against Hertz and ISO 6336-2, the dynamic root stress of Figs. 8-10.
>
> **The sector model**, several elastic teeth on elastic rims, is measured on
> [`docs/sector_validation.md`](sector_validation.md) (its quasi-static mesh cycle against
> ISO 6336-1) and [`docs/sector_dynamics_validation.md`](sector_dynamics_validation.md)
> (its dynamic run: load balance, energy, ring and damping, time step, modal against whole
> bodies, dynamic factor against speed), written by `docs/validation/sector.py` and
> `docs/validation/sector_dynamics.py`.

The model is the paper's: one elastic Q8 tooth on a rigid disk per gear, the second
tooth pair replaced by the torque ramps of its Fig. 7, undamped, frictionless, plane
stress (section 6). Within that model:

* **The paper's cases** (section 1): dynamic factor {n2(df['fig8'])} at 4,000 rpm and
  {n2(df['fig9'])} at 20,000 rpm (peaks of the 10-µs-averaged force, the figure
  `spurdyn run` reports; the raw peaks give {n2(R['fig8']['contact_force'].max() / ctx.static)}
  and {n2(R['fig9']['contact_force'].max() / ctx.static)}). The rattling cases depend on which gear
  drives: read literally (A drives, the presets) Fig. 10 rattles with {len(ctx.impacts('fig10'))} impacts
  (factor {n2(df['fig10'])}) and Fig. 11 has no contact at all; with B driving Fig. 10
  rattles (factor {n2(df['fig10_b'])}) and Fig. 11 is one long hard impact (factor
  {n2(df['fig11_b_dt15'])}{", and its preset stops at the paper's Δt" if ctx.figures.get('fig11_b_failed') else ""}).
* **Convergence** (section 2): the peak of the 10-µs-averaged force of the default
  4 × 14 mesh is {pct(c)} from the 6 × 20 mesh's; the time step, the spline points and the
  tolerance change it by at most {upct(ctx.figures['settings_change'], 2)}. The raw force carries a ripple (the teeth' own
  vibration at about {ctx.figures['ripple']['freq'] / 1e3:.0f} kHz, rung by the contact point crossing
  element edges) of about ±{ctx.figures['ripple']['max']:.0f} N. In impacts the raw peaks are not
  converged ({n0(ctx.figures['impact_raw_range'][0])}–{n0(ctx.figures['impact_raw_range'][1])} N in
  Fig. 10 across the settings tried); the 10-µs averaged peaks agree to
  {upct(ctx.figures['impact_avg_spread'], 1)}. Finer meshes than 4 × 14 need more spline data points,
  and with the paper's point contact some runs stop (section 2.1; the distributed contact
  runs most of them to the end, `docs/contact_validation.md`).
* **Physics** (section 3): the quasi-static mean force is within
  {upct(abs(ctx.figures['quasi_static']), 1)} of τ0/r_b; angular momentum balances to
  {upct(bal['momentum'], 2)} of the impulses; energy to a few per cent of the strain
  energy ({upct(bal['energy_fig8'], 1)} in Fig. 8, {upct(bal['energy_fig10'], 1)} in the impacts of
  Fig. 10); the pair is {ctx.figures['iso_ratio']:.1f} times as stiff as ISO 6336's c′, for
  known reasons; the force oscillates at {fr['fe'] / 1e3:.2f} kHz against
  {fr['theory'] / 1e3:.2f} kHz for two disks on the model's own stiffness.
* **The lumped model** (section 4), given the FE model's stiffness, reproduces the FE
  averaged peaks to {upct(ctx.figures['lumped_agreement'], 1)}; it misses the tooth-level detail
  (ripple, chatter, raw impact peaks), and with an assumed spring its answer moves.
* **Tip relief** (section 5) moves the start and end of contact as the paper says of
  the NASA gears, but makes the one-tooth model rattle, because the prescribed torque
  ramps load the pair before the relieved teeth touch. No NASA data were available.
* **Against speed** (section 7): the FE and lumped dynamic-factor curves of the paper's
  pair from 500 to 30,000 rpm, the resonance each shows against the estimate from the
  torsional natural frequency, and where the two models part.
"""


def build_report(runs: dict[str, Run], wall: float) -> str:
    """The whole page from ``runs``; also writes the sections' figures to ``figures.json``."""
    ctx = Ctx(runs)
    parts = [section_paper(ctx), section_convergence(ctx), section_physics(ctx),
             section_lumped(ctx), section_relief(ctx), section_limits(ctx), section_sweep()]
    head = intro(ctx, wall)
    tail = f"""
## How this page is made

`.venv/bin/python docs/validation validation --sweep` regenerates everything: it runs
`docs/validation/sweep.py` (the sweeps of section 7, resumed from `out/sweep-validation`),
then every case it needs (cached in
`docs/validation_data/<run>.npz`, git-ignored; a run is redone when its settings
change, or all with `--rerun`), then writes this page and the figures. Helpers it uses:
`spurdyn.solvers.loop.simulate`, `spurdyn.lumped.simulate_lumped`,
`spurdyn.results.balances.track`, `spurdyn.model.stiffness` and the pure functions of
`docs/validation/report/helpers.py` (moving average, dynamic factor, zone masks, contact
episodes, frequencies), which `tests/test_validation_script.py` checks on synthetic data.
The script's code is the package `docs/validation/report/`, one module per section.
Writing the page from the cache took {wall:.0f} s.
"""
    DATA.mkdir(parents=True, exist_ok=True)
    (DATA / "figures.json").write_text(json.dumps(plain(ctx.figures), indent=2))
    return head + "".join(parts) + tail


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: make the missing runs, then write ``docs/validation.md`` and the figures."""
    parser = argparse.ArgumentParser(prog="docs/validation validation",
                                     description="Regenerate docs/validation.md and its figures.")
    parser.add_argument("--rerun", action="store_true", help="ignore the cached runs")
    parser.add_argument("--runs-only", action="store_true", help="make the runs, write nothing")
    parser.add_argument("--sweep", action="store_true",
                        help="first run the sweeps of section 7 (validation_sweep; resumes them)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    if args.sweep:
        subprocess.run([sys.executable, str(RUNNER), "validation_sweep"], check=True)
    runs = all_runs(args.rerun)
    t1 = time.perf_counter()
    print(f"runs ready in {t1 - t0:.0f} s")
    if args.runs_only:
        return 0
    text = build_report(runs, 0.0)
    wall = time.perf_counter() - t1
    text = text.replace("Writing the page from the cache took 0 s.",
                        f"Writing the page from the cache took {wall:.0f} s.")
    REPORT.write_text(text, encoding="utf-8")
    print(f"wrote {REPORT} in {wall:.0f} s")
    return 0


