"""The sector model's implicit loop against an RK4 reference: writes
docs/sector_rk4_validation.md (and its numbers, docs/sector_rk4_validation.json).

    .venv/bin/python docs/validation sector_rk4_validation       # ~10 min on one core

The paper's pair (the ``paper-fig8`` case, 4 x 14 teeth, 22.25 N m) on the sector model's
modal bodies, mesh damper zeta = 0.05, the bodies' default damping, at three speeds below,
near and above the sector sweep's main resonance (~11,200 rpm). At each: the implicit loop at
its default step for 20 cycles (going on, as it does, until settled), then RK4
(spurdyn.solvers.sector.rk4) at the paper's step or just below it, a whole number of RK4
steps in each implicit step so that the implicit samples are RK4 samples, for as many cycles
as the implicit run did. Compared over the last cycles (the settled figures' window): the
10-us-averaged mesh force and contact force (the most loaded pair's), their RMS difference
against RK4's averaged peak there, the settled dynamic factors, the contacts made and broken
by each pair and any separation of the mesh (times within 2 us), the steps and wall times.
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Sequence

import numpy as np

from spurdyn.case import preset_case
from spurdyn.results.headline import averaged_peak, moving_average
from spurdyn.results.pairs import steady_figures
from spurdyn.settings import RPM
from spurdyn.solvers.sector.rk4 import PAPER_STEP, highest_frequency, simulate_sector_rk4
from spurdyn.solvers.sector.run import simulate_sector
from validation.common import DOCS, match_impacts, save_figures, timed, touches, write_page

PAGE = DOCS / "sector_rk4_validation.md"
DATA = DOCS / "sector_rk4_validation.json"
SPEEDS_RPM = (4000, 11000, 16000)
CYCLES = 20
ZETA = 0.05
#: A pair's change in RK4 and the implicit run's nearest count as the same event within this (s).
NEAR = 5e-6


def settings(rpm: float, cycles: int = CYCLES, **kw):
    case = preset_case("paper-fig8")
    w = rpm * RPM
    za, zb = case.pair.gear_a.teeth, case.pair.gear_b.teeth
    return case.pair, case.run.with_(speed_a=w, speed_b=w * za / zb, cycles=cycles, damping_ratio=ZETA,
                                     frames_every=0, **kw)


def changes(t: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The samples' times at which a pair's force became positive (made) and zero (broken)."""
    on = np.nan_to_num(f) > 0.0
    made = t[1:][on[1:] & ~on[:-1]]
    broken = t[1:][~on[1:] & on[:-1]]
    return made, broken


def nearest_shifts(ref: np.ndarray, other: np.ndarray) -> list[float]:
    """For each of ``ref``'s times, ``other``'s nearest minus it (NaN if ``other`` has none)."""
    return [float(other[np.argmin(np.abs(other - x))] - x) if other.size else math.nan for x in ref]


def compare(rpm: float) -> dict:
    pair, run = settings(rpm)
    imp, imp_wall = timed(simulate_sector, pair, run)
    done = imp.info["steady"]["cycles_done"]
    h_imp = imp.info["dt_s"]
    k = math.ceil(h_imp / PAPER_STEP - 1e-9)            # RK4 steps an implicit step
    _, rk_run = settings(rpm, done, max_cycles=done)
    rk = simulate_sector_rk4(pair, rk_run, dt=h_imp / k)
    assert rk.steps == k * imp.steps, (rk.steps, k, imp.steps)
    t = imp.time
    assert rk.info["pair_teeth"] == imp.info["pair_teeth"]
    np.testing.assert_allclose(rk.time[::k], t, rtol=1e-9, atol=1e-15)
    lo = imp.info["steady"]["window_s"][0]
    sel = t >= lo - 1e-15
    out = dict(rpm=rpm, cycles=done, dt=(rk.info["dt_s"], h_imp), steps=(rk.steps, imp.steps),
               wall=(rk.info["loop_s"], rk.wall_s, imp_wall),
               settled=(bool(rk.info["steady"]["settled"]), bool(imp.info["steady"]["settled"])),
               window=[lo, float(t[-1])])
    for name, fr, fi in (("mesh", np.nansum(rk.pair_force, axis=1), np.nansum(imp.pair_force, axis=1)),
                         ("contact", rk.contact_force, imp.contact_force)):
        a = moving_average(rk.time, fr)[::k]
        b = moving_average(t, fi)
        peak = averaged_peak(rk.time[rk.time >= lo - 1e-15], fr[rk.time >= lo - 1e-15])[0]
        out[name] = dict(rms=float(np.sqrt(np.mean((a[sel] - b[sel]) ** 2))) / peak,
                         max=float(np.abs(a[sel] - b[sel]).max()) / peak, peak=peak,
                         peak_implicit=averaged_peak(t[sel], fi[sel])[0],
                         raw=(float(np.nanmax(fr[rk.time >= lo - 1e-15])), float(np.nanmax(fi[sel]))))
    # the settled dynamic factors, as the summary computes them
    kv = [steady_figures(r.time, r.contact_force, r.info["steady"], r.complete)["dynamic_factor"] for r in (rk, imp)]
    out["dynamic_factor"] = kv
    # the transmission error over the window
    te_r, te_i = rk.transmission_error[::k][sel], imp.transmission_error[sel]
    out["te"] = dict(rms_diff=float(np.sqrt(np.mean((te_r - te_i) ** 2))), pp=float(te_r.max() - te_r.min()))
    # contacts made and broken, pair by pair, over the whole run; separations of the mesh
    made, broken, counts, lone, unmatched = [], [], [0, 0], [], 0
    for j in range(rk.pair_force.shape[1]):
        fr, fi = np.nan_to_num(rk.pair_force[:, j]), np.nan_to_num(imp.pair_force[:, j])
        (rm, rb), (im, ib) = changes(rk.time, fr), changes(t, fi)
        counts[0] += rm.size + rb.size
        counts[1] += im.size + ib.size
        # RK4's force touching zero for less than one implicit step while the implicit run's
        # pair stays in contact at every sample from a step before to a step after: listed
        # with the implicit run's least force there, RK4's largest around it and how long
        # the pair had touched, and left out of the shifts
        brief = set()
        for x in rm:
            before = rb[rb < x]
            if not before.size or x - before[-1] >= h_imp:
                continue
            w = (t >= before[-1] - h_imp) & (t <= x + h_imp)
            if np.all(fi[w] > 0.0):
                around = (rk.time >= x - 3e-6) & (rk.time <= x + 3e-6)
                entered = rm[rm < before[-1]]
                lone.append((float(x), float(x - before[-1]), float(fi[w].min()), float(fr[around].max()),
                             float(before[-1] - entered[-1]) if entered.size else math.nan))
                brief |= {float(x), float(before[-1])}
        for ref, other, into in ((rm, im, made), (rb, ib, broken)):
            for x, d in zip(ref, nearest_shifts(ref, other)):
                if float(x) in brief:
                    continue
                if abs(d) <= NEAR:
                    into.append(d)
                else:
                    unmatched += 1
            # and the other way: an implicit change with no RK4 change near is unmatched too
            unmatched += sum(1 for d in nearest_shifts(other, ref) if not abs(d) <= NEAR)
    out["pair_changes"] = dict(counts=counts, made_max=float(max(map(abs, made), default=0.0)),
                               broken_max=float(max(map(abs, broken), default=0.0)),
                               unmatched=unmatched, lone=lone)
    mesh_r, mesh_i = np.nansum(rk.pair_force, axis=1), np.nansum(imp.pair_force, axis=1)
    ia, ib = touches(rk.time, mesh_r), touches(t, mesh_i)
    sh, extra = match_impacts(ia, ib)
    out["impacts"] = dict(rk4=len(ia), implicit=len(ib), shifts=sh, extra=extra)
    return out


def verdict(r: dict) -> str:
    fails = []
    if r["steps"][1] * 20 > r["steps"][0]:
        fails.append("steps")
    if r["contact"]["rms"] > 0.02 or r["mesh"]["rms"] > 0.02:
        fails.append("RMS")
    if abs(r["dynamic_factor"][1] / r["dynamic_factor"][0] - 1) > 0.01:
        fails.append("dynamic factor")
    if any(not abs(s) <= 2e-6 for s in r["impacts"]["shifts"]) or not r["pair_changes"]["made_max"] <= 2e-6 \
            or r["pair_changes"]["unmatched"]:
        fails.append("impacts")
    return "all four" if not fails else "fails " + ", ".join(fails)


def row(r: dict) -> str:
    imp = r["impacts"]
    sep = (f"{imp['rk4']} / {imp['implicit']}"
           + (": " + ", ".join(f"{s * 1e6:+.2f}" for s in imp["shifts"]) + " us" if imp["shifts"] else ""))
    pc = r["pair_changes"]
    return (f"| {r['rpm']:,} | {r['cycles']} | {r['dt'][0]:.3g} / {r['dt'][1]:.3g} | "
            f"{r['steps'][0]:,} / {r['steps'][1]:,} (x{r['steps'][0] / r['steps'][1]:.0f}) | "
            f"{r['wall'][0]:.0f} / {r['wall'][2]:.0f} | "
            f"{r['mesh']['rms'] * 100:.3f} % ({r['mesh']['max'] * 100:.2f} %) | "
            f"{r['contact']['rms'] * 100:.3f} % ({r['contact']['max'] * 100:.2f} %) | "
            f"{r['dynamic_factor'][0]:.4f} / {r['dynamic_factor'][1]:.4f} "
            f"({(r['dynamic_factor'][1] / r['dynamic_factor'][0] - 1) * 100:+.2f} %) | "
            f"{pc['counts'][0]} / {pc['counts'][1]}: made {pc['made_max'] * 1e6:.2f} us, broken {pc['broken_max'] * 1e6:.2f} us"
            + (f", {pc['unmatched']} unmatched" if pc["unmatched"] else "")
            + ("; RK4's force touching zero for less than a step: " + ", ".join(
                f"{g * 1e6:.2f} us at {x * 1e6:.0f} us, {d * 1e6:.1f} us after the pair entered (implicit's least "
                f"{lo:.1f} N, RK4's largest {hi:.0f} N)" for x, g, lo, hi, d in pc["lone"]) if pc["lone"] else "") + f" | {sep} | "
            f"{'yes' if r['settled'][0] else 'no'} / {'yes' if r['settled'][1] else 'no'} | {verdict(r)} |")


def summary(rows: list[dict]) -> list[str]:
    """What the table shows, from its numbers."""
    rms = max(max(r["mesh"]["rms"], r["contact"]["rms"]) for r in rows)
    kv = [(r["rpm"], (r["dynamic_factor"][1] / r["dynamic_factor"][0] - 1) * 100) for r in rows]
    ratio = min(r["steps"][0] / r["steps"][1] for r in rows)
    worst = max(rows, key=lambda r: max([abs(x) for x in r["impacts"]["shifts"]] + [r["pair_changes"]["made_max"]]))
    lone = [(r["rpm"], x) for r in rows for x in r["pair_changes"]["lone"]]
    worst_made = max(max([abs(x) for x in r["impacts"]["shifts"]] + [r["pair_changes"]["made_max"]]) for r in rows)
    passed = [r["rpm"] for r in rows if verdict(r) == "all four"]
    return [
        "- **Steps:** the implicit default step is "
        + (f"{ratio:.0f} to " if round(ratio) != round(max(r['steps'][0] / r['steps'][1] for r in rows)) else "")
        + f"{max(r['steps'][0] / r['steps'][1] for r in rows):.0f} times RK4's (at least 20 asked).",
        f"- **Averaged forces:** the 10-µs-averaged mesh and contact forces differ by at most {rms * 100:.2f} % "
        "RMS of RK4's averaged peak over the settled cycles (2 % asked).",
        "- **Settled dynamic factor:** " + ", ".join(f"{d:+.2f} % at {n:,} rpm" for n, d in kv) + " (1 % asked).",
        f"- **Impacts made:** the largest shift of a contact made (a pair entering, or the mesh striking "
        f"again after it separated) is "
        f"{max([abs(x) for x in worst['impacts']['shifts']] + [worst['pair_changes']['made_max']]) * 1e6:.2f} us, "
        f"at {worst['rpm']:,} rpm (2 µs asked). " + " ".join(
            f"At {r['rpm']:,} rpm the mesh separates {r['impacts']['rk4']} times in RK4 and "
            f"{r['impacts']['implicit']} in the implicit run; the impacts after them are "
            + ", ".join(f"{x * 1e6:+.2f}" for x in r["impacts"]["shifts"]) + " us off."
            for r in rows if r["impacts"]["rk4"])
        + " Contacts broken (a pair leaving, not an impact) are within "
        f"{max(r['pair_changes']['broken_max'] for r in rows) * 1e6:.2f} us.",
        "- **RK4's force touching zero for less than one implicit step:** "
        + ("; ".join(f"at {n:,} rpm, {g * 1e6:.2f} us at {x * 1e6:.0f} us, {d * 1e6:.1f} us after the pair "
                     f"entered, where the implicit run's force falls to {lo:.1f} N (RK4's largest around it "
                     f"{hi:.0f} N)" for n, (x, g, lo, hi, d) in lone)
           + ". These are troughs of an entering pair's ring grazing zero: the implicit run stays in "
           "contact at every sample from a step before to a step after, its force down to those few "
           "newtons where RK4's is zero for less than a step. They are listed, not counted as impacts "
           "or as contacts broken; a lift-off of a step or longer, or one across which the implicit "
           "run also lets go, is matched like any other change."
           if lone else "none."),
        "",
        ("So the implicit loop at its default step meets its four criteria at the three speeds "
         f"({', '.join(f'{n:,}' for n in passed)} rpm)." if len(passed) == len(rows) else
         "So the implicit loop at its default step meets its four criteria at "
         + (", ".join(f"{n:,}" for n in passed) or "none of the speeds")
         + " rpm; the others fail as the table says.")
        + f" How narrowly: the largest impact shift is {worst_made * 1e6:.2f} us against the 2 us asked "
        f"(a step is {max(r['dt'][1] for r in rows) * 1e6:.2f} us); contacts broken, reported but not "
        f"impacts, are up to {max(r['pair_changes']['broken_max'] for r in rows) * 1e6:.2f} us off"
        + (f"; and at {', '.join(sorted({f'{n:,}' for n, _ in lone}))} rpm the pass takes RK4's sub-step "
           "zero touches above as troughs, not impacts" if lone else "") + ".",
    ]


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: measure, then write ``docs/sector_rk4_validation.md`` and its numbers."""
    argparse.ArgumentParser(prog="docs/validation sector_rk4_validation",
                            description=__doc__.split("\n\n")[0]).parse_args(argv)
    t0 = time.time()
    pair, run = settings(SPEEDS_RPM[0])
    stiff = highest_frequency(pair, run)
    rows = [compare(rpm) for rpm in SPEEDS_RPM]
    save_figures(DATA, dict(stability=stiff, rows=rows))
    lines = [
        "# The sector model: implicit against RK4",
        "",
        "Written by `docs/validation/sector_rk4.py` (the numbers also in "
        "`sector_rk4_validation.json`). The implicit integrator is asked, on the sector model at "
        "three speeds: at its default step against RK4 at the paper's step (3e-8 s), the 10-µs-averaged "
        "contact force within 2 % RMS of its peak, impacts made within 2 µs, the settled dynamic factor "
        "within 1 %, with a time step at least 20 times RK4's.",
        "",
        "## The reference",
        "",
        "On modal bodies (`run.bodies = \"modal\"`, docs/sector.md 6.6) the residual flexibility acts "
        "without inertia, so at a state `q` the pairs' forces are the solution of a small "
        "complementarity problem `g_r,c + G q + C_s F >= 0, F >= 0, complementary`, `C_s = c_H I + "
        "b_iᵀ R b_j` (eq. 6.1), and the model is the ODE `M q̈ = f − K q − C q̇ + Gᵀ F(q) − Dᵀ C_d D q̇` "
        "with a piecewise-linear `F(q)`. `spurdyn.solvers.sector.rk4` steps it by classical RK4 "
        "(compiled twin `rk4_compiled.py`, NumPy loop for checks), with the implicit loop's pieces: "
        "the modal bodies (their `M⁻¹` in place of `S⁻¹`), the gap table, the strips' loads, the "
        "residual compliance, the complementarity solver, the mesh damper's table, the torques, the "
        "static start and the result (so the settled figures and the dynamic factor are computed "
        "alike). Where an explicit scheme takes the model differently: each stage has its own rows "
        "at its own turn (the implicit loop holds them over a step at the predicted turn); the strips' "
        "half-widths are held over a step at the forces of its start (the implicit loop: the step "
        "before's); the mesh damper's shares are each stage's forces (the implicit loop: the step "
        "before's). It refuses whole bodies, back flanks, torque histories and continuations.",
        "",
        f"**Stability at 3e-8 s.** At the static start ({stiff['pairs_in_contact']} pairs in contact, "
        "held by their compliance), the highest undamped frequency of `M⁻¹ (K + Gᵀ C_s⁻¹ G)` is "
        f"{stiff['f_max_hz'] / 1e6:.2f} MHz (`ω_max` = {stiff['omega_max']:.3g} rad/s; the free bodies' "
        f"highest mode {stiff['free_omega_max'] / (2 * math.pi) / 1e6:.2f} MHz, the Ritz vectors of the "
        f"flank shapes): `ω_max h` = {stiff['omega_dt']:.2f} against RK4's 2.83 on the imaginary axis; "
        "RK4's amplification over the damped system's eigenvalues is at most "
        f"{stiff['rk4_amplification_max']:.10f} (1 for the hubs' free turn). "
        "`tests/test_sector_rk4.py` checks it, and that at a tenth of the implicit default step the "
        "implicit loop and RK4 agree sample for sample over a loaded cycle at 20,000 rpm on 2 × 8 "
        "(pair forces within 0.13 % of the largest, transmission error 5e-4 of its largest, the "
        "contacts made and broken at the same samples).",
        "",
        "## How measured",
        "",
        "The `paper-fig8` case (4 × 14 teeth, 22.25 N m) with `--model sector`, modal bodies of whole "
        f"gears, mesh damper ζ = {ZETA}, the bodies' default damping (2 % at 50 kHz), from the static "
        f"start. Implicit: {CYCLES} cycles at its default step (a tenth of the period of 150 kHz, the highest "
        "mode the modal bodies keep, and at most 1/200 of a mesh cycle: docs/sector.md 6.3), going on "
        "until settled as runs do. RK4: "
        "the same number of cycles at the largest step at or below 3e-8 s that divides the implicit "
        "step, so the implicit samples are RK4 samples and nothing is interpolated. Over the last "
        "cycles (the settled figures' window, 5 cycles): the RMS difference of the 10-µs-averaged "
        "mesh force (sum of the pairs) and contact force (the most loaded pair's, whose averaged peak "
        "is the dynamic factor) against RK4's averaged peak there, the largest difference in "
        "brackets; the settled dynamic factor of each (`results.pairs.steady_figures`). Over the "
        "whole run: the contacts made and broken by each pair (a pair's force becoming positive or "
        "zero: entries and exits) in RK4 and the implicit run, and the largest time between an RK4 "
        "change and the implicit run's nearest, for contacts made (impacts: the 2 µs asked) and "
        "broken (reported); separations of the whole mesh (impacts after them, matched as in "
        "implicit_validation.md). Where RK4's force touches zero for less than one implicit step "
        "and no implicit change is near, the two changes are listed with the implicit run's least "
        "force over them instead (no sample of the implicit run can show them). Wall times: RK4's time loop (compiled) and the "
        "implicit run's whole call (compiled loop; the bodies cached from the first speed).",
        "",
        "| speed (rpm) | cycles | step RK4 / implicit (s) | steps RK4 / implicit | wall RK4 / implicit (s) | "
        "averaged mesh force, RMS (max) | averaged contact force, RMS (max) | dynamic factor RK4 / implicit | "
        "pair contacts made and broken RK4 / implicit, largest shift | mesh separations RK4 / implicit | "
        "settled RK4 / implicit | criteria |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        *[row(r) for r in rows],
        "",
        "## What it shows",
        "",
        *summary(rows),
        "",
        f"(Written in {time.time() - t0:.0f} s.)",
        "",
    ]
    write_page(PAGE, "\n".join(lines))
    return 0
