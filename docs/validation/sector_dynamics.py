"""Write docs/sector_dynamics_validation.md: the sector model's dynamic run measured.

    .venv/bin/python docs/validation sector_dynamics_validation [--quick] [--only PART]

Every figure on the page is computed here (about 10 minutes on two cores; ``--quick``: the
coarse 2 x 8 teeth throughout, a few minutes; ``--only rattle`` re-measures one part and keeps
the others' figures from docs/sector_dynamics_validation.json). The derivations are
docs/sector.md, section 6.
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Sequence

import numpy as np

from spurdyn.geometry.presets import paper_pair
from spurdyn.iso6336.dynamics import reduced_mass
from spurdyn.sector.rules import BODY_DAMPING_FREQUENCY, BODY_DAMPING_RATIO
from spurdyn.sector.statics import driving_pair, mesh_cycle
from spurdyn.settings import RPM, SETTLE_CYCLES_FACTOR
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.run import simulate_sector
from validation.common import DOCS, load_figures, save_figures, timed, write_page
from validation.sector_rattle import UNDAMPED, rattle, rattle_lines

PAGE = DOCS / "sector_dynamics_validation.md"
STORE = DOCS / "sector_dynamics_validation.json"
PAIR = paper_pair()
TORQUE = 60.0           # N m on the paper's pair: W = 1,436 N, 84 N/mm... x 2.7 (its line load)


def settled_dynamic_factor(run) -> float:
    """The most loaded pair's 10-us-averaged peak over the settled window against its
    quasi-static value (as summary.json's ``dynamic_factor``)."""
    from spurdyn.results.headline import averaged_peak

    st = run.info["steady"]
    sel = run.time >= st["window_s"][0] - 1e-15
    return averaged_peak(run.time[sel], run.contact_force[sel])[0] / st["static_pair_force_max_N"]


def load_balance(mesh: dict) -> dict:
    """A quasi-static run (10 rpm, 100 steps a cycle: the scheme damps the pair's mode)."""
    s = run_settings(PAIR, 10 * RPM, TORQUE, dt=1e-6, cycles=1, **mesh, **UNDAMPED)
    period = 2 * math.pi / PAIR.gear_a.teeth / s.speed_a
    run = simulate_sector(PAIR, s, dt=period / 100)
    w = run.info["static_force"]
    err = np.abs(run.pair_force.sum(axis=1) / w - 1.0).max()
    cyc = mesh_cycle(PAIR, TORQUE, **mesh, positions=101)
    pitch = 2 * math.pi / PAIR.gear_a.teeth
    phase = (run.theta[:, 0] % pitch) / pitch
    eps = PAIR.contact_ratio % 1.0
    away = (np.abs(phase - eps) > 0.08) & (phase > 0.08) & (phase < 0.92)
    te = np.interp(phase[away] * pitch, cyc.roll - driving_pair(PAIR).start_roll_a, cyc.transmission_error)
    return {"load_balance_max_rel": float(err),
            "te_vs_static_max_rel": float(np.abs(run.transmission_error[away] / te - 1).max()),
            "te_static_mean_um": float(cyc.transmission_error.mean() * 1e6)}


#: The energy study's runs: (rho_inf, step (s), None the default; the half-widths frozen).
ENERGY_RUNS = ((1.0, 2e-6, False), (1.0, 1e-6, False), (1.0, None, False), (1.0, 4e-7, False),
               (1.0, 4e-7, True), (0.8, None, False), (0.8, 4e-7, False))


def _energy_run(mesh: dict, rho: float, dt: float | None, frozen: bool) -> dict:
    """One cycle at 1,000 rpm, undamped bodies and mesh: the balance of kinetic and strain
    energy, the strips' ``c_H F^2/2`` and the torques' work. ``frozen`` spreads the strips at
    the static force throughout (a diagnostic: the run's own half-widths follow the forces of
    the step before), by swapping the model module's half-width function for the run."""
    import spurdyn.sector.model as sector_model
    from spurdyn.model.loading import static_force

    s = run_settings(PAIR, 1000 * RPM, TORQUE, cycles=1, rho_inf=rho, **mesh, **UNDAMPED)
    own = sector_model.half_widths_at
    if frozen:
        w = static_force(PAIR, TORQUE)
        sector_model.half_widths_at = lambda dp, r, f, estar, width: own(dp, r, np.full(np.shape(f), w), estar, width)
    try:
        run = simulate_sector(PAIR, s, energy=True, dt=dt)
    finally:
        sector_model.half_widths_at = own
    e = run.info["energy"]
    total = np.array(e["kinetic_J"]) + np.array(e["strain_J"]) + np.array(e["strip_J"]) - np.array(e["work_J"])
    err = total - total[0]
    # the frequency the mesh force's last 0.3 ms carries most, less its mean
    last = run.time > run.time[-1] - 3e-4
    x = np.nansum(run.pair_force[last], axis=1)
    spec = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size)))
    freq = np.fft.rfftfreq(x.size, run.info["dt_s"])
    return {"rho_inf": rho, "dt_s": run.info["dt_s"], "default_step": dt is None, "frozen": frozen,
            "energy_error_max_J": float(np.abs(err).max()), "energy_error_end_J": float(err[-1]),
            "strain_max_J": float(max(e["strain_J"])), "force_max_N": float(np.nanmax(x)),
            "last_peak_hz": float(freq[1:][np.argmax(spec[1:])])}


def energy(mesh: dict) -> list[dict]:
    return [_energy_run(mesh, rho, dt, frozen) for rho, dt, frozen in ENERGY_RUNS]


RING_RPM = 300.0


def ring(mesh: dict, zeta: float) -> dict:
    """After the exit of a pair at 300 rpm the pair rings alone over the stretch of single
    contact (about seven periods), where the quasi-static mesh force is ``W`` itself: the
    ring's frequency and damping ratio from a damped cosine fitted to the 10-us-averaged mesh force over the
    steps where one pair alone touches (:mod:`spurdyn.results.ring`; docs/sector.md,
    6.5, says why not zero crossings and peaks)."""
    from spurdyn.results.ring import damped_ring, single_contact_window

    from spurdyn.results.headline import moving_average

    s = run_settings(PAIR, RING_RPM * RPM, TORQUE, cycles=1, damping_ratio=zeta, **mesh, **UNDAMPED)
    run = simulate_sector(PAIR, s)
    sel = single_contact_window(run, PAIR)
    w = run.info["static_force"]
    # the 10-us-averaged mesh force: the undamped teeth's own modes ring on the raw one
    mesh_force = moving_average(run.time, run.pair_force.sum(axis=1))[sel] - w
    freq, fitted, misfit = damped_ring(run.time[sel], mesh_force)
    periods = int(freq * (run.time[sel[-1]] - run.time[sel[0]]))
    k_mean = run.info["steady"]["mesh_stiffness_mean_N_per_m"]
    j = [h + b for h, b in zip(run.info["hub_inertia"], run.info["body_inertia"])]
    m_e = reduced_mass(j[0], j[1], PAIR.gear_a.base_radius, PAIR.gear_b.base_radius)
    # the single pair's own stiffness over the stretch, W over its transmission error
    k_single = float(np.median(w / run.transmission_error[sel]))
    # the damper follows the cycle's stiffness: over the stretch of single contact it is the
    # cycle's least (that of one pair)
    c = run.info["mesh_damper_range_N_s_per_m"][0]
    return {"zeta": zeta, "ring_hz": freq, "periods": periods,
            "decay_ratio": fitted if zeta > 0 else None, "fit_misfit": misfit,
            "zeta_single": c / (2 * math.sqrt(k_single * m_e)) if c else 0.0,
            "f_mean_hz": math.sqrt(k_mean / m_e) / (2 * math.pi),
            "f_single_hz": math.sqrt(k_single / m_e) / (2 * math.pi),
            "k_mean": k_mean, "k_single": k_single, "m_e": m_e}


def step_study(mesh: dict, rpm: float) -> dict:
    """The default step against a half and a tenth of it (the reference: the sector model has
    no RK4 twin), 4 cycles: the settled dynamic factor, the 10-us-averaged mesh force's RMS
    difference over the run against its peak, and the contact onsets' times."""
    from spurdyn.results.headline import moving_average
    from spurdyn.solvers.sector.run import steps_per_cycle

    out: dict = {}
    runs = {}
    for label, factor in (("default", 1), ("half", 2), ("tenth", 10)):  # modal bodies
        s = run_settings(PAIR, rpm * RPM, TORQUE, dt=1e-6, cycles=4, max_cycles=4, damping_ratio=0.05, **mesh)
        period = 2 * math.pi / PAIR.gear_a.teeth / s.speed_a
        per = steps_per_cycle(s.speed_a, PAIR.gear_a.teeth)
        run, wall = timed(simulate_sector, PAIR, s, dt=period / (per * factor))
        runs[label] = (factor, run)
        out[label] = {"dt_s": run.info["dt_s"], "dynamic_factor": settled_dynamic_factor(run),
                      "te_rms_um": run.info["steady"]["transmission_error_rms_m"] * 1e6,
                      "wall_s": wall, "steps": run.steps, "n_dof": run.info["n_dof"]}
    _, ref = runs["tenth"]
    ref_mesh = moving_average(ref.time, np.nansum(ref.pair_force, axis=1))
    ref_onsets = _onsets(ref)
    for label in ("default", "half"):
        factor, run = runs[label]
        mesh_force = moving_average(run.time, np.nansum(run.pair_force, axis=1))
        at = ref_mesh[:: 10 // factor][: mesh_force.size]           # the same instants
        out[label]["mesh_rms_rel"] = float(np.sqrt(np.mean((mesh_force - at) ** 2)) / np.nanmax(at))
        onsets = _onsets(run)
        out[label]["onset_max_s"] = float(max((min(abs(t - r) for r in ref_onsets) for t in onsets), default=0.0))
        out[label]["df_vs_tenth_rel"] = out[label]["dynamic_factor"] / out["tenth"]["dynamic_factor"] - 1
    return out


def _onsets(run) -> list[float]:
    """Times a pair starts to touch (its force turns positive)."""
    on = np.nan_to_num(run.pair_force) > 0
    steps, _ = np.nonzero(on[1:] & ~on[:-1])
    return [float(run.time[i + 1]) for i in steps]


def bodies(mesh: dict) -> dict:
    """The same damped run (3,000 rpm, 2 cycles) on the whole bodies and on their modes."""
    s = run_settings(PAIR, 3000 * RPM, TORQUE, dt=1e-6, cycles=2, damping_ratio=0.05, **mesh)
    out = {}
    runs = {}
    for kind in ("full", "modal"):
        runs[kind], wall = timed(simulate_sector, PAIR, s.with_(bodies=kind))
        out[kind] = {"wall_s": wall, "coordinates": runs[kind].info["coordinates"],
                     "modes": runs[kind].info["modes"], "dynamic_factor": settled_dynamic_factor(runs[kind])}
    full, modal = runs["full"], runs["modal"]
    w = full.info["static_force"]
    mf, mm = full.pair_force.sum(axis=1), modal.pair_force.sum(axis=1)
    out["mesh_rms_rel"] = float(np.sqrt(np.mean((mm - mf) ** 2)) / w)
    out["pair_max_rel"] = float(np.abs(modal.pair_force - full.pair_force).max() / full.pair_force.max())
    out["te_max_rel_pp"] = float(np.abs(modal.transmission_error - full.transmission_error).max()
                                 / np.ptp(full.transmission_error))
    return out


#: The bodies' Rayleigh damping of the sweep: a ratio of 0.02 at 5 and 50 kHz. The mesh
#: damper damps the pairs' deflection only; without damping of their own, the bodies' modes
#: (the hubs against the rims, the teeth) settle only through the scheme's dissipation, and
#: a run at 4,000 rpm still changes its peak by 0.5 % a cycle after ten cycles.
SWEEP_RAYLEIGH = (0.02, 5e3, 5e4)


def relief(mesh: dict) -> list[dict]:
    """The paper's Fig. 8 (4,000 rpm, 22.25 N m, undamped) on the sector model, without and
    with the NASA-like 20 um tip relief, over three cycles: the one-tooth model rattles with
    the relief (validation.md, section 5); here each pair should make contact once."""
    from spurdyn.geometry.pair import GearPair
    from spurdyn.geometry.presets import nasa_like_relief

    def relieved(amount: float) -> GearPair:
        return GearPair(gear_a=nasa_like_relief(PAIR.gear_a, amount=amount),
                        gear_b=nasa_like_relief(PAIR.gear_b, amount=amount),
                        centre_distance=PAIR.centre_distance)

    out = []
    for label, pair in (("none", PAIR), ("5 µm", relieved(5e-6)),
                        ("20 µm (nasa_like_relief)", relieved(20e-6))):
        s = run_settings(pair, 4000 * RPM, 22.25, dt=1e-6, cycles=3, max_cycles=3, **mesh, **UNDAMPED)
        run = simulate_sector(pair, s)
        on = run.pair_force > 0
        onsets = (on[1:] & ~on[:-1]).sum(axis=0)
        mesh_f = run.pair_force.sum(axis=1)
        out.append({"relief": label, "onsets_max": int(onsets.max()),
                    "mesh_min_rel": float(mesh_f.min() / run.info["static_force"]),
                    "mesh_max_rel": float(mesh_f.max() / run.info["static_force"]),
                    "dynamic_factor": settled_dynamic_factor(run),
                    "te_pp_um": float(np.ptp(run.transmission_error[run.time >= run.info["steady"]["window_s"][0]]) * 1e6)})
    return out


def settling(mesh: dict) -> list[dict]:
    """5,000 rpm, 20 cycles, zeta = 0.05 (the paper's torque): the peak mesh force cycle by
    cycle with the mesh damper alone, with the bodies' default damping and with Rayleigh's."""
    from spurdyn.solvers.implicit.damping import rayleigh_from_ratio

    a, b = rayleigh_from_ratio(*SWEEP_RAYLEIGH)
    out = []
    for label, extra in (("mesh damper alone", UNDAMPED), ("the bodies' default (0.02 at 50 kHz, stiffness)", {}),
                         (f"Rayleigh {SWEEP_RAYLEIGH[0]:g} at {SWEEP_RAYLEIGH[1] / 1e3:g} and "
                          f"{SWEEP_RAYLEIGH[2] / 1e3:g} kHz", dict(rayleigh_mass=a, rayleigh_stiffness=b))):
        s = run_settings(PAIR, 5000 * RPM, 22.25, dt=1e-6, cycles=20, max_cycles=20, damping_ratio=0.05, **mesh, **extra)
        st = simulate_sector(PAIR, s).info["steady"]
        peaks = np.asarray(st["peak_mesh_force_per_cycle_N"])
        change = np.abs(np.diff(peaks)) / peaks[1:]
        below = np.flatnonzero(change < st["settle_tolerance"])
        # the first cycle from which every change stays below the tolerance
        first = next((int(i) + 2 for i in below if (change[i:] < st["settle_tolerance"]).all()), None)
        out.append({"label": label, "settled": bool(st["settled"]), "last5_min": float(peaks[-5:].min()),
                    "last5_max": float(peaks[-5:].max()), "from_cycle": first})
    return out


def sweep(mesh: dict, rpms: list[float], cycles: int) -> list[dict]:
    from spurdyn.solvers.implicit.damping import rayleigh_from_ratio

    a, b = rayleigh_from_ratio(*SWEEP_RAYLEIGH)
    rows = []
    for rpm in rpms:
        s = run_settings(PAIR, rpm * RPM, TORQUE, dt=1e-6, cycles=cycles, damping_ratio=0.05,
                         rayleigh_mass=a, rayleigh_stiffness=b, **mesh)
        run, wall = timed(simulate_sector, PAIR, s)
        rows.append({"rpm": rpm, "dynamic_factor": settled_dynamic_factor(run),
                     "settled": run.info["steady"]["settled"],
                     "cycles_done": run.info["steady"]["cycles_done"],
                     "te_rms_um": run.info["steady"]["transmission_error_rms_m"] * 1e6,
                     "wall_s": wall, "steps": run.steps})
        print(f"  {rpm:,.0f} rpm: {rows[-1]}", flush=True)
    return rows


#: The parts ``--only`` re-measures (the others' figures are read from the page's JSON).
PARTS = {"rattle": rattle, "energy": energy, "ring": lambda mesh: [ring(mesh, 0.0), ring(mesh, 0.05)]}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: measure (all, or one part), then write the page and its figures."""
    ap = argparse.ArgumentParser(prog="docs/validation sector_dynamics_validation",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="2 x 8 teeth throughout")
    ap.add_argument("--only", choices=sorted(PARTS), help="re-measure this part only")
    args = ap.parse_args(argv)
    fine = dict(nx=2, ny=8) if args.quick else dict(nx=4, ny=14)
    if args.only:
        fig = load_figures(STORE)
        fig[args.only] = PARTS[args.only](fig["mesh_fine"])
        print(args.only, fig[args.only], flush=True)
        save_figures(STORE, fig)
        write_page(PAGE, render(fig), echo=False)
        return 0
    t0 = time.perf_counter()
    fig: dict = {"mesh_fine": fine}
    for name, measure in (("balance", load_balance), ("energy", energy), ("ring", PARTS["ring"])):
        fig[name] = measure(fine)
        print(name, fig[name], flush=True)
    fig["step_rpms"] = [2000.0, 6000.0, 14000.0]
    fig["step"] = {f"{rpm:.0f}": step_study(fine, rpm) for rpm in fig["step_rpms"]}
    print("step", fig["step"], flush=True)
    fig["bodies"] = bodies(fine)
    print("bodies", fig["bodies"], flush=True)
    fig["relief"] = relief(fine)
    print("relief", fig["relief"], flush=True)
    fig["settling"] = settling(fine)
    print("settling", fig["settling"], flush=True)
    from spurdyn.case import resolve_cases
    from spurdyn.sweep.resonance import resonance_estimate

    case = resolve_cases("paper-fig8", {"run.cycles": 2, "run.torque": TORQUE, "mesh.nx": fine["nx"],
                                        "mesh.ny": fine["ny"]}, {})[0]
    res_sector = resonance_estimate(case, "sector")
    res_lumped = resonance_estimate(case, "lumped")
    fig["resonance"] = {"sector_rpm": res_sector.resonance_rpm, "sector_fn_hz": res_sector.natural_frequency_hz,
                        "tooth_rpm": res_lumped.resonance_rpm, "tooth_fn_hz": res_lumped.natural_frequency_hz,
                        "iso_rpm": res_sector.iso_resonance_rpm}
    rpms = [1000.0, 4000.0, 7000.0, 9000.0, 10500.0, 12000.0, 13500.0, 15000.0, 17500.0, 20000.0]
    fig["sweep_cycles"] = 10
    fig["sweep"] = sweep(fine, rpms, fig["sweep_cycles"])
    fig["iso_kv"] = res_sector.iso_kv(rpms)
    fig["rattle"] = rattle(fine)
    print("rattle", fig["rattle"], flush=True)
    fig["wall_s"] = time.perf_counter() - t0
    save_figures(STORE, fig)
    write_page(PAGE, render(fig), echo=False)
    return 0


def render(f: dict) -> str:
    b, e, r0, r5, st, res = f["balance"], f["energy"], f["ring"][0], f["ring"][1], f["step"], f["resonance"]
    mesh = f"{f['mesh_fine']['nx']} x {f['mesh_fine']['ny']}"
    # the energy runs whose balance the growing contact mode broke (over a tenth of the strain energy)
    grow = [r for r in e if r["energy_error_max_J"] > 0.1 * r["strain_max_J"]] or [dict(dt_s=math.nan, last_peak_hz=math.nan)]
    damped = [r for r in e if r["rho_inf"] < 1.0]
    lines = [
        "# The sector model in motion: measured",
        "",
        "Written by `docs/validation/sector_dynamics.py` (figures in "
        "`sector_dynamics_validation.json`); the derivations are docs/sector.md, section 6. The "
        f"paper's pair at {TORQUE:g} N m on the driver, teeth of {mesh} elements unless said.",
        "",
        "## Load balance (quasi-static, 10 rpm, 100 steps a cycle)",
        "",
        f"- The pairs' forces sum to `T / r_b` within **{b['load_balance_max_rel'] * 100:.3f} %** "
        "at every step (the target is 0.5 %).",
        f"- Away from the path's ends the transmission error is the static mesh cycle's at the "
        f"run's phase within {b['te_vs_static_max_rel'] * 100:.2f} % (static mean "
        f"{b['te_static_mean_um']:.2f} µm). Near the ends the run has the tip corners' early "
        "and late contact that the static analysis leaves out.",
        "",
        "## Energy (undamped bodies and mesh, 1,000 rpm, one cycle)",
        "",
        "Kinetic and strain energy, the strips' `c_H F^2/2`, less the torques' work, against the "
        "largest strain energy; the frequency the mesh force carries most over the run's last 0.3 ms:",
        "",
        "| rho_inf | step | strips spread at | largest error (mJ) | at the end (mJ) | of the largest strain energy | largest mesh force (N) | its last 0.3 ms peak at |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ] + [f"| {r['rho_inf']:g} | {r['dt_s'] * 1e6:.3f} µs{' (default)' if r['default_step'] else ''} | "
         f"{'the static force (diagnostic)' if r['frozen'] else 'the forces of the step before'} | "
         f"{r['energy_error_max_J'] * 1e3:.3f} | {r['energy_error_end_J'] * 1e3:+.3f} | "
         f"{r['energy_error_max_J'] / r['strain_max_J'] * 100:.1f} % | {r['force_max_N']:,.0f} | "
         f"{r['last_peak_hz'] / 1e3:,.1f} kHz |" for r in e] + [
        "",
        "With `rho_inf = 1` (no numerical dissipation) and nothing damped, the balance holds to a few "
        "per cent of the strain energy at steps of 1 µs and more, and not below: at "
        + ", ".join(f"{r['dt_s'] * 1e6:.2f} µs" for r in grow)
        + f" an oscillation of the mesh force at {min(r['last_peak_hz'] for r in grow) / 1e3:.0f}-"
        f"{max(r['last_peak_hz'] for r in grow) / 1e3:.0f} kHz grows until it dominates (a "
        "contact mode of the flanks' shapes against the strips). Spreading the strips at a fixed force "
        "removes the growth, so its source is the strips' half-widths following the forces of the step "
        "before: the rows move a step late with the force, which feeds that mode a little each step. "
        "With the default `rho_inf = 0.8` the scheme's dissipation there (ω h ≈ "
        f"{min(2 * math.pi * r['last_peak_hz'] * r['dt_s'] for r in grow):.1f}-"
        f"{max(2 * math.pi * r['last_peak_hz'] * r['dt_s'] for r in grow):.1f}) outweighs it: "
        "the balance holds to "
        + ", ".join(f"{r['energy_error_max_J'] / r['strain_max_J'] * 100:.1f} %" for r in damped)
        + " at " + ", ".join(f"{r['dt_s'] * 1e6:.2f} µs" for r in damped)
        + "; the bodies' default damping (stiffness-proportional, "
        f"{BODY_DAMPING_RATIO:g} at {BODY_DAMPING_FREQUENCY / 1e3:.0f} kHz, so "
        f"{BODY_DAMPING_RATIO * min(r['last_peak_hz'] for r in grow) / BODY_DAMPING_FREQUENCY:.2f} at "
        f"{min(r['last_peak_hz'] for r in grow) / 1e3:.0f} kHz) adds to "
        "it. What is left at 1-2 µs is the strips sliding over the deformed flank (Appendix A's "
        "terms) and the same late half-widths.",
        "",
        "## Natural frequency, damping",
        "",
        f"After a pair leaves at {RING_RPM:,.0f} rpm the pair rings over the stretch of single "
        "contact, where the quasi-static mesh force is `W` itself:",
        "",
        "| | ring (fitted) | from the single pair's stiffness | from the cycle's mean stiffness |",
        "| --- | --- | --- | --- |",
        f"| undamped | {r0['ring_hz'] / 1e3:.2f} kHz | {r0['f_single_hz'] / 1e3:.2f} kHz "
        f"(k = {r0['k_single'] / 1e6:.0f} N/µm) | {r0['f_mean_hz'] / 1e3:.2f} kHz "
        f"(k = {r0['k_mean'] / 1e6:.0f} N/µm) |",
        f"| zeta = 0.05 | {r5['ring_hz'] / 1e3:.2f} kHz | | |",
        "",
        (f"With zeta = 0.05 (the damper's coefficient follows the cycle's mesh stiffness, "
         f"c = 2 zeta sqrt(k(phi) m_e); over the stretch of single contact it is a ratio of "
         f"{r5['zeta_single']:.4f} on the single pair's own stiffness W/e) the damped cosine "
         f"fitted to the 10-µs-averaged ring's {r5['periods']} periods decays at **{r5['decay_ratio']:.4f}** "
         f"({(r5['decay_ratio'] / 0.05 - 1) * 100:+.1f} % of the ratio asked; the check: "
         f"within 10 %; misfit {r5['fit_misfit'] * 100:.1f} % of its amplitude)."
         if r5["decay_ratio"] is not None else "Too few periods to measure the decay."),
        "",
        "## Time step (4 cycles, zeta = 0.05, against a tenth of the default step)",
        "",
        "The sector model has no RK4 twin; its reference is the same scheme at a tenth of the "
        "default step. The measures: the 10-µs-averaged mesh force's RMS difference over "
        "the run against its peak (asked: within 2 %), the contact onsets' times (within 2 µs) "
        "and the settled dynamic factor (within 1 %).",
        "",
        "| rpm | step | dt | settled dynamic factor | against the tenth | averaged force RMS | onsets | TE RMS | wall |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for rpm, study in st.items():
        for k in ("default", "half", "tenth"):
            s = study[k]
            vs = (f"{s['df_vs_tenth_rel'] * 100:+.2f} %", f"{s['mesh_rms_rel'] * 100:.2f} %",
                  f"{s['onset_max_s'] * 1e6:.2f} µs") if k != "tenth" else ("reference", "", "")
            lines.append(f"| {float(rpm):,.0f} | {k} | {s['dt_s'] * 1e6:.3f} µs | {s['dynamic_factor']:.4f} | "
                         f"{vs[0]} | {vs[1]} | {vs[2]} | {s['te_rms_um']:.3f} µm | {s['wall_s']:.1f} s "
                         f"({s['steps']} steps) |")
    worst = max(abs(study["default"]["df_vs_tenth_rel"]) for study in st.values()) * 100
    lines += [
        "",
        f"At the default step the settled dynamic factor is within {worst:.2f} % of the tenth's at "
        "every speed.",
        "",
        "## Modal bodies against the whole ones (3,000 rpm, 2 cycles, zeta = 0.05)",
        "",
        f"The whole bodies: {f['bodies']['full']['coordinates']:,} coordinates, "
        f"{f['bodies']['full']['wall_s']:.1f} s; their modes below 150 kHz and flank shapes with the "
        f"flanks' residual flexibility: {f['bodies']['modal']['coordinates']:,} coordinates "
        f"({f['bodies']['modal']['modes']} modes), {f['bodies']['modal']['wall_s']:.1f} s. Mesh force "
        f"{f['bodies']['mesh_rms_rel'] * 100:.2f} % of `W` apart (RMS), the largest pair-force difference "
        f"{f['bodies']['pair_max_rel'] * 100:.2f} % of the largest pair force, the transmission error "
        f"{f['bodies']['te_max_rel_pp'] * 100:.2f} % of its peak-to-peak; settled dynamic factor "
        f"{f['bodies']['full']['dynamic_factor']:.4f} whole, {f['bodies']['modal']['dynamic_factor']:.4f} modal.",
        "",
        "## Tip relief (Fig. 8: 4,000 rpm, 22.25 N m, undamped, 3 cycles)",
        "",
        "The one-tooth model rattles with both reliefs (validation.md, section 5: 4 impacts, "
        "dynamic factor 2.01 with 5 µm and 2.91 with 20 µm), because its torque ramps load the "
        "pair before the relieved teeth touch. With the teeth on their rims the load passes from "
        "pair to pair, and what a relief does depends on its amount against the load (the static "
        "deflection is about 5 µm here): an onset count of 1 is a clean engagement, a mesh force "
        "of 0 a loss of all contact.",
        "",
        "| relief | contact onsets per pair (most) | mesh force / W: least, largest | dynamic factor (last cycle) | TE peak-to-peak, last cycle (µm) |",
        "| --- | --- | --- | --- | --- |",
        *[f"| {r['relief']} | {r['onsets_max']} | {r['mesh_min_rel']:.3f}, {r['mesh_max_rel']:.3f} | "
          f"{r['dynamic_factor']:.3f} | {r['te_pp_um']:.2f} |" for r in f["relief"]],
        "",
        "A relief sized to the load (5 µm, about its static deflection) makes each pair engage once "
        "and cuts the dynamic transmission error and the dynamic factor; 20 µm, four times the "
        "deflection at this light load, opens a gap the pairs cross in flight: the mesh loses all "
        "contact and rattles, as over-relieved gears do at light load.",
        "",
        f"## Dynamic factor against speed (zeta = 0.05, Rayleigh {SWEEP_RAYLEIGH[0]:g} at "
        f"{SWEEP_RAYLEIGH[1] / 1e3:g} and {SWEEP_RAYLEIGH[2] / 1e3:g} kHz, {f['sweep_cycles']} cycles, modal bodies)",
        "",
        "The mesh damper damps the pairs' deflection (hub to hub); the bodies' own modes (the hubs against the "
        "rims, the teeth) need damping of their own to settle (docs/sector.md 6.3). 5,000 rpm, "
        "22.25 N m, zeta = 0.05, 20 cycles:",
        "",
        "| bodies' damping | settled | peak mesh force, last 5 cycles | cycle-to-cycle change below 1e-3 from cycle |",
        "| --- | --- | --- | --- |",
        *[f"| {r['label']} | {'yes' if r['settled'] else 'no'} | {r['last5_min']:.1f}-{r['last5_max']:.1f} N | "
          f"{r['from_cycle'] if r['from_cycle'] is not None else '-'} |" for r in f["settling"]],
        "",
        "A run settles in time, not in cycles (its transient decays as exp(-zeta omega_n t)), and a mesh cycle "
        "shortens with speed: a steady-state run not settled after its cycles goes on, a cycle at a time, until "
        f"it settles or has run max_cycles (by default {SETTLE_CYCLES_FACTOR} times its cycles). The sweep below "
        f"asks {f['sweep_cycles']} cycles; the column *cycles* gives those each point ran.",
        "",
        f"Resonance from the sector's own mean mesh stiffness: **{res['sector_rpm']:,.0f} rpm** "
        f"(f_n {res['sector_fn_hz'] / 1e3:.2f} kHz); from the paper model's root-clamped tooth "
        f"pair {res['tooth_rpm']:,.0f} rpm ({res['tooth_fn_hz'] / 1e3:.2f} kHz); ISO 6336-1's "
        f"n_E1 {res['iso_rpm']:,.0f} rpm. The paper model's figure is a steady mesh's: two disks on the mean "
        "of both pairs' stiffness over a cycle, 2.76e8 N/m (docs/lumped.md). docs/validation.md, 3.4, finds "
        "15,707 rpm instead: there the mesh frequency meets the ring of the paper's one engagement in its "
        "single-contact zone (7.33 kHz measured, 3.0 % below the 7.56 kHz of two disks on that zone's "
        "mean stiffness, 1.92e8 N/m); the steady mesh's stiffness is 1.44 times the zone's, and "
        "sqrt(1.44) x 7.56 kHz = 9.07 kHz.",
        "",
        "| rpm | dynamic factor | ISO K_v | TE RMS (µm) | settled | cycles | wall (s) |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for row, kv in zip(f["sweep"], f["iso_kv"] or [None] * len(f["sweep"])):
        lines.append(f"| {row['rpm']:,.0f} | {row['dynamic_factor']:.3f} | "
                     f"{'' if kv is None else f'{kv:.3f}'} | {row['te_rms_um']:.3f} | "
                     f"{'yes' if row['settled'] else 'no'} | {row.get('cycles_done', '')} | {row['wall_s']:.0f} |")
    if "rattle" in f:
        lines += rattle_lines(f["rattle"], mesh)
    lines += ["", f"The page's last whole run took {f['wall_s'] / 60:.1f} min (a part re-measured with "
              "--only is not counted).", ""]
    return "\n".join(lines)

