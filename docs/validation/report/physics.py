"""Section 3 of the report: quasi-static limit, momentum and energy balances, stiffness
against ISO 6336-1 and the frequency of the force oscillation."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .context import Ctx, run_cost
from .figures import pyplot, save_figure, shade_zones
from .helpers import (dominant_frequency, ls_spectrum, moving_average, n0, n1, n2, pct, relative,
                      rms, sci, spectrum_peak, table, upct, zero_crossing_frequency)
from .settings import RPM
from .spurdyn_api import (GearPair, RunSettings, build_system, build_tooth, iso_6336_stiffness,
                          pair_stiffness, torsional_natural_frequency)


def single_zone_oscillation(ctx: Ctx, name: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(t, F - tau_A / r_b)`` in the single-contact zone of a run, averaged over 20 us
    (which removes the element-scale ripple and keeps the torsional oscillation)."""
    r = ctx.runs[name]
    t = r["time"]
    d = r["contact_force"] - r["torque"][:, 0] / ctx.rb
    da, ta = moving_average(t, d, 20e-6)
    zone = t[ctx.single(name)]
    sel = (ta >= zone[0]) & (ta <= zone[-1])
    return ta[sel], da[sel]


def oscillation_frequency(ctx: Ctx, name: str) -> tuple[float, int, float]:
    """Frequency of the single-zone oscillation of a run by zero crossings, their
    number, and its RMS amplitude."""
    ta, da = single_zone_oscillation(ctx, name)
    f, n = zero_crossing_frequency(ta, da)
    return f, n, rms(da - da.mean())


def stiffness_along_path(pair: GearPair, nx: int, ny: int,
                         n: int = 201) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rolls of A along the path and the pair's static stiffness there (N/m) on an ``nx`` x ``ny`` mesh."""
    tooth = build_tooth(pair.gear_a, nx, ny)
    roll = np.linspace(pair.start_roll_a, pair.end_roll_a, n)
    return roll, pair_stiffness(pair, tooth, tooth, roll).stiffness


def mean_mesh_stiffness(pair: GearPair, roll: NDArray[np.float64], k: NDArray[np.float64],
                        n: int = 400) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """Mean over one angular pitch of the summed stiffness of the pairs in contact."""
    pitch = 2 * math.pi / pair.gear_a.teeth
    x = pair.start_roll_a + (np.arange(n) + 0.5) * pitch / n
    total = np.interp(x, roll, k)
    second = x + pitch
    inside = second <= pair.end_roll_a
    total[inside] += np.interp(second[inside], roll, k)
    return float(total.mean()), x, total


def section_physics(ctx: Ctx) -> str:
    """Section 3: quasi-static limit, balances, stiffness and frequency; sets their figures."""
    plt = pyplot()
    R = ctx.runs
    pair = ctx.pair
    # -- 3.1 quasi-static -------------------------------------------------------------
    qs = R["qs1000"]
    sel = ctx.single("qs1000")
    qmean = float(qs["contact_force"][sel].mean())
    qmin, qmax = float(qs["contact_force"][sel].min()), float(qs["contact_force"][sel].max())
    lq = R["lumped_qs1000"]
    lmean = float(lq["contact_force"][ctx.single("lumped_qs1000")].mean())
    lqmin = float(lq["contact_force"][ctx.single("lumped_qs1000")].min())
    lqmax = float(lq["contact_force"][ctx.single("lumped_qs1000")].max())
    f8mean = float(R["fig8"]["contact_force"][ctx.single("fig8")].mean())
    ctx.figures["quasi_static"] = relative(qmean, ctx.static)

    # -- 3.4 frequency (computed here, drawn with 3.1) ------------------------------------
    f_fe, n_fe, a_fe = oscillation_frequency(ctx, "qs1000")
    f_lu, n_lu, a_lu = oscillation_frequency(ctx, "lumped_qs1000")
    roll4, k4 = stiffness_along_path(pair, 4, 14)
    roll8, k8 = stiffness_along_path(pair, 8, 28)
    z0, z1 = pair.single_contact_roll_a
    zsel4 = (roll4 >= z0) & (roll4 <= z1)
    k_single = float(k4[zsel4].mean())
    iso = iso_6336_stiffness(pair)
    iso1 = iso_6336_stiffness(pair, correction=1.0)
    face = pair.gear_a.face_width
    c1, cga = iso.per_face_width(face)
    c1t, cgat = iso1.per_face_width(face)
    f_single = torsional_natural_frequency(pair, k_single)
    system = build_system(pair, RunSettings(contact="point", speed_a=1.0, speed_b=1.0, torque=1.0))
    j_tooth = []
    for gb in system.gears:
        y = gb.Y.reshape(-1, 2)
        m = gb.mass.reshape(-1, 2)[:, 0]
        j_tooth.append(float(np.sum(m * np.sum(y * y, axis=1))))
    m_e_teeth = 1.0 / sum(gb.base_radius ** 2 / (gb.inertia + jt) for gb, jt in zip(system.gears, j_tooth))
    f_teeth = math.sqrt(k_single / m_e_teeth) / (2 * math.pi)
    ctx.figures["frequency"] = {"fe": f_fe, "lumped": f_lu, "theory": f_single}

    fig, axes = plt.subplots(2, 1, figsize=(10, 7))
    ax = axes[0]
    shade_zones(ax, ctx)
    ax.plot(np.degrees(qs["angle"]), qs["contact_force"], color="C0", lw=0.6, alpha=0.6, label="FE, raw")
    ax.plot(ctx.avg_angle("qs1000"), ctx.avg("qs1000")[1], color="C0", lw=1.4, label="FE, 10-µs average")
    ax.plot(np.degrees(lq["angle"]), lq["contact_force"], color="C3", lw=1.0, label="lumped model")
    ax.set_ylabel("contact force (N)")
    ax.set_title("Quasi-static limit: 1,000 / 1,000 rpm")
    ax.legend(loc="lower center", ncol=3)
    ax = axes[1]
    for name, color, label in (("qs1000", "C0", f"FE ({f_fe / 1e3:.2f} kHz)"),
                               ("lumped_qs1000", "C3", f"lumped ({f_lu / 1e3:.2f} kHz)")):
        r = R[name]
        d = r["contact_force"] - r["torque"][:, 0] / ctx.rb
        da, ta = moving_average(r["time"], d, 20e-6)
        zone = r["time"][ctx.single(name)]
        s_ = (ta >= zone[0]) & (ta <= zone[-1])
        ax.plot((ta[s_] - zone[0]) * 1e6, da[s_], color=color, label=label)
    ax.set_xlabel("time since the start of the single-contact zone (µs)")
    ax.set_ylabel("F − τ_A/r_b, 20-µs average (N)")
    ax.set_title(f"The oscillation in the single-contact zone; two disks on the FE single-zone "
                 f"stiffness: {f_single / 1e3:.2f} kHz")
    ax.legend(loc="upper right")
    fig.tight_layout()
    png_qs = save_figure(fig, "validation_quasi_static.png")

    # -- 3.2 balances ------------------------------------------------------------------
    brow = []
    bal = {}
    for name, label in (("bal_fig8", "Fig. 8 (4,000 rpm)"), ("bal_fig8_free", "4,000 rpm, no torque"),
                        ("bal_fig9", "Fig. 9 (20,000 rpm)"), ("bal_fig9_free", "20,000 rpm, no torque"),
                        ("bal_fig10", "Fig. 10 (impacts)"), ("bal_fig10_dt15", "Fig. 10, Δt = 1.5 × 10⁻⁸ s"),
                        ("bal_fig10_s241", "Fig. 10, 241 spline points")):
        r = R[name]
        lerr = r["momentum"] - r["momentum"][0] - r["angular_impulse"]
        imp = np.abs(r["angular_impulse"]).max(axis=0)
        eerr = r["energy"] - r["energy"][0] - r["torque_work"] - r["contact_work"]
        bal[name] = {"lerr": np.abs(lerr).max(axis=0), "imp": imp, "eerr": eerr,
                     "strain": float(r["strain"].max()), "t": r["t"], "angle": r["angle"],
                     "cwork": float(np.abs(r["contact_work"]).max()), "E0": float(r["energy"][0])}
        brow.append([label, run_cost(ctx, name),
                     " / ".join(f"{sci(v, 1)}" for v in bal[name]["lerr"]),
                     " / ".join(f"{sci(v, 1)}" for v in imp),
                     n2(float(np.abs(eerr).max()) * 1e6), n2(float(eerr[-1]) * 1e6),
                     n1(bal[name]["strain"] * 1e6), f"{bal[name]['cwork'] * 1e6:.3f}",
                     n0(bal[name]["E0"])])
    bal_table = table(["run", "cost", "largest |ΔL − impulse| A / B (kg m²/s)",
                       "largest |impulse| A / B (kg m²/s)", "largest |energy error| (µJ)",
                       "energy error at the end (µJ)", "largest strain energy (µJ)",
                       "largest |contact work| (µJ)", "total energy (J)"], brow)
    same = max(float(np.max(np.abs(R[b]["contact_force"] - R[a]["contact_force"])))
               for a, b in (("fig8", "bal_fig8"), ("fig9", "bal_fig9"), ("fig10", "bal_fig10")))
    rate8 = float(bal["bal_fig8_free"]["eerr"][-1] / bal["bal_fig8_free"]["t"][-1])
    rate9 = float(bal["bal_fig9_free"]["eerr"][-1] / bal["bal_fig9_free"]["t"][-1])
    w9 = 20000 * RPM
    torque_equiv = rate9 / (2 * w9)

    def excursion(name: str, free: str | None) -> float:
        e = bal[name]["eerr"]
        if free is not None:
            e = e[:min(e.size, bal[free]["eerr"].size)] - bal[free]["eerr"][:min(e.size, bal[free]["eerr"].size)]
        return float(np.abs(e).max())

    def end(name: str, free: str) -> float:
        n = min(bal[name]["eerr"].size, bal[free]["eerr"].size)
        return float(bal[name]["eerr"][n - 1] - bal[free]["eerr"][n - 1])

    end8, end9, end10 = end("bal_fig8", "bal_fig8_free"), end("bal_fig9", "bal_fig9_free"), \
        end("bal_fig10", "bal_fig8_free")
    ex8 = excursion("bal_fig8", "bal_fig8_free")
    ex9 = excursion("bal_fig9", "bal_fig9_free")
    ex10 = excursion("bal_fig10", "bal_fig8_free")
    ex10dt = excursion("bal_fig10_dt15", None)
    ex10s = excursion("bal_fig10_s241", None)
    lrel = max(float((bal[n]["lerr"] / bal[n]["imp"]).max()) for n in ("bal_fig8", "bal_fig9", "bal_fig10"))
    lrel10 = float((bal["bal_fig10"]["lerr"] / bal["bal_fig10"]["imp"]).max())
    lrel10dt = float((bal["bal_fig10_dt15"]["lerr"] / bal["bal_fig10_dt15"]["imp"]).max())
    ctx.figures["balances"] = {"momentum": lrel, "energy_fig8": ex8 / bal["bal_fig8"]["strain"],
                               "energy_fig10": ex10 / bal["bal_fig10"]["strain"]}

    fig, axes = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
    ax = axes[0]
    for i, name in enumerate(("bal_fig8", "bal_fig9", "bal_fig10", "bal_fig10_dt15")):
        b = bal[name]
        r = R[name]
        lerr = (r["momentum"] - r["momentum"][0] - r["angular_impulse"])[:, 0]
        ax.plot(np.degrees(b["angle"]), lerr / b["imp"][0], color=f"C{i}", label=name[4:])
    ax.set_ylabel("(ΔL − impulse) / max |impulse|, gear A")
    ax.set_title("Angular momentum balance of gear A")
    ax.legend(loc="lower left", ncol=4)
    ax = axes[1]
    for i, name in enumerate(("bal_fig8", "bal_fig9", "bal_fig10", "bal_fig10_dt15", "bal_fig10_s241",
                              "bal_fig8_free", "bal_fig9_free")):
        b = bal[name]
        ax.plot(np.degrees(b["angle"]), b["eerr"] * 1e6, color=f"C{i}", label=name[4:],
                ls="--" if name.endswith("free") else "-")
    ax.set_ylabel("E − E₀ − work of torques and contact (µJ)")
    ax.set_xlabel("rotation of gear A (deg)")
    ax.set_title("Energy balance")
    ax.set_xlim(0, math.degrees(ctx.theta_s))
    ax.legend(loc="lower left", ncol=4)
    fig.tight_layout()
    png_bal = save_figure(fig, "validation_balances.png")

    # -- 3.3 stiffness against ISO -----------------------------------------------------
    kmm4, xm, tot4 = mean_mesh_stiffness(pair, roll4, k4)
    kmm8, _, tot8 = mean_mesh_stiffness(pair, roll8, k8)
    zsel8 = (roll8 >= z0) & (roll8 <= z1)
    srows = [
        ["largest single-pair stiffness (ISO c′)", f"{k4.max():.3e}", f"{k8.max():.3e}",
         f"{c1:.3e}", f"{c1t:.3e}", f"{k4.max() / c1:.2f} / {k8.max() / c1:.2f}",
         f"{k4.max() / c1t:.2f} / {k8.max() / c1t:.2f}"],
        ["mean single-pair stiffness, single-contact zone", f"{k4[zsel4].mean():.3e}",
         f"{k8[zsel8].mean():.3e}", "", "", "", ""],
        ["single-pair stiffness at the ends of contact", f"{k4[0]:.3e}", f"{k8[0]:.3e}", "", "", "", ""],
        ["mean mesh stiffness over one pitch (ISO c_γα)", f"{kmm4:.3e}", f"{kmm8:.3e}", f"{cga:.3e}",
         f"{cgat:.3e}", f"{kmm4 / cga:.2f} / {kmm8 / cga:.2f}", f"{kmm4 / cgat:.2f} / {kmm8 / cgat:.2f}"],
    ]
    stiff_table = table(["N/m (b = 6.35 mm)", "model 4 × 14", "model 8 × 28", "ISO 6336-1, C_M = 0.8",
                         "ISO, C_M = 1", "model / ISO (4 × 14 / 8 × 28)", "model / ISO with C_M = 1"], srows)
    mat = pair.gear_a.material
    log_half_plane = 2.0 * (2.0 / (math.pi * mat.young * face)) * math.log(2.0)
    c4 = 1.0 / k4[np.argmin(np.abs(roll4 - pair.pitch_roll_a))]
    c8 = 1.0 / k8[np.argmin(np.abs(roll8 - pair.pitch_roll_a))]
    ctx.figures["iso_ratio"] = k4.max() / c1

    fig, ax = plt.subplots(figsize=(10, 4.2))
    ax.plot(np.degrees(roll4 - pair.start_roll_a), k4, color="C0", label="single pair, FE 4 × 14")
    ax.plot(np.degrees(roll8 - pair.start_roll_a), k8, color="C1", label="single pair, FE 8 × 28")
    ang = np.degrees(xm - pair.start_roll_a)
    for off in (0.0, 360.0 / pair.gear_a.teeth):
        ax.plot(ang + off, tot4, color="C0", ls=":", label="mesh (pairs in contact), 4 × 14" if off == 0 else None)
    ax.axhline(c1, color="k", ls="--", lw=0.8, label=f"ISO c′ b = {c1:.3g} N/m")
    ax.axhline(cga, color="k", ls="-.", lw=0.8, label=f"ISO c_γα b = {cga:.3g} N/m")
    ax.axvspan(0, ctx.zone_deg[0], color="0.92", lw=0)
    ax.axvspan(ctx.zone_deg[1], math.degrees(ctx.theta_s), color="0.92", lw=0)
    ax.set_xlim(0, math.degrees(ctx.theta_s))
    ax.set_ylim(0, None)
    ax.set_xlabel("rotation of gear A from the start of contact (deg)")
    ax.set_ylabel("stiffness along the line of action (N/m)")
    ax.set_title("Static stiffness of the paper's pair against ISO 6336-1 (method B)")
    ax.legend(loc="lower center", ncol=3)
    fig.tight_layout()
    png_k = save_figure(fig, "validation_stiffness.png")

    # The spectrum of the single-zone oscillation (least squares: the zone holds ~6
    # periods, so an FFT's bins, 1 / record length, are ~1.3 kHz wide).
    t_fe, d_fe = single_zone_oscillation(ctx, "qs1000")
    t_lu, d_lu = single_zone_oscillation(ctx, "lumped_qs1000")
    spec_f = np.linspace(1e3, 30e3, 1161)
    spec_fe = ls_spectrum(t_fe, d_fe, spec_f)
    spec_lu = ls_spectrum(t_lu, d_lu, spec_f)
    fs_fe, as_fe = dominant_frequency(t_fe, d_fe, 1e3, 30e3, n=800)
    fs_lu, _ = dominant_frequency(t_lu, d_lu, 1e3, 30e3, n=800)
    fft_fe, _ = spectrum_peak(t_fe, d_fe, 1e3, 30e3)
    bin_fe = 1.0 / float(t_fe[-1] - t_fe[0])
    second = spec_fe[np.abs(spec_f - fs_fe) > 2 * bin_fe].max()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(spec_f / 1e3, spec_fe, color="C0", label="FE model")
    ax.plot(spec_f / 1e3, spec_lu, color="C1", ls="--", label="lumped model")
    for fr, lab, col in ((f_single, "two disks on the FE stiffness", "C2"),
                         (torsional_natural_frequency(pair, c1), "on ISO c′b", "C3"),
                         (torsional_natural_frequency(pair, cga), "on ISO c_γα b", "C4")):
        ax.axvline(fr / 1e3, color=col, lw=1, ls=":", label=f"{lab}: {fr / 1e3:.2f} kHz")
    ax.set_xlabel("frequency (kHz)")
    ax.set_ylabel("amplitude (N)")
    ax.set_title("Spectrum of F − τ_A/r_b in the single-contact zone, 1,000 rpm (least squares)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    png_spec = save_figure(fig, "validation_spectrum.png")

    f_rows = [["FE model, 1,000 rpm, single-contact zone: peak of the spectrum", "—", f"{fs_fe / 1e3:.2f}"],
              ["same record, zero crossings", "—", f"{f_fe / 1e3:.2f}"],
              ["lumped model, same run, peak of the spectrum", "FE table", f"{fs_lu / 1e3:.2f}"],
              ["lumped model, same run, zero crossings", "FE table", f"{f_lu / 1e3:.2f}"],
              ["two disks J, FE mean single-zone stiffness", f"{k_single:.3e}", f"{f_single / 1e3:.2f}"],
              ["same, the teeth' inertia added to the disks", f"{k_single:.3e}", f"{f_teeth / 1e3:.2f}"],
              ["two disks J, FE stiffness at the ends of contact", f"{k4[0]:.3e}",
               f"{torsional_natural_frequency(pair, k4[0]) / 1e3:.2f}"],
              ["two disks J, ISO c′ b", f"{c1:.3e}", f"{torsional_natural_frequency(pair, c1) / 1e3:.2f}"],
              ["two disks J, ISO c_γα b", f"{cga:.3e}", f"{torsional_natural_frequency(pair, cga) / 1e3:.2f}"]]
    freq_table = table(["source", "stiffness (N/m)", "frequency (kHz)"], f_rows)
    mesh_f = [28 * rpm / 60 for rpm in (1000, 4000, 20000)]

    text = f"""
## 3. Physics checks

### 3.1 Quasi-static limit

![quasi-static run]({png_qs})

At 1,000 rpm (mesh frequency {mesh_f[0]:,.0f} Hz, far below the pair's natural frequency)
the mean force over the single-contact zone is {qmean:.1f} N against τ0/r_b =
{ctx.static:.1f} N ({pct(relative(qmean, ctx.static), 2)}); the lumped model gives
{lmean:.1f} N ({pct(relative(lmean, ctx.static), 2)}). At 4,000 rpm the FE mean is
{f8mean:.1f} N ({pct(relative(f8mean, ctx.static), 1)}). Around the mean the force
oscillates between {qmin:.0f} and {qmax:.0f} N (lumped model: {lqmin:.0f}–{lqmax:.0f} N): the
vibration of the two disks on the tooth spring, set off by the Fig. 7 ramp and kept up by
the variation of the stiffness along the path (in the FE model also by its
element-scale ripple, section 2.1), never damped (the model has no damping). Lowering
the speed does not remove it; the mean is what tends to the static force.

### 3.2 Angular momentum and energy

`spurdyn.results.balances` follows a run step by step (the compiled stepper of
`spurdyn.solvers`, the same as `simulate`: the contact forces of these runs equal
those of `simulate` to {same:.1e} N) and books, for each gear about its fixed centre,
the angular momentum of the disk and the tooth nodes against the angular impulse of the
centre torque and of the contact force, and the total energy (disks, tooth nodes, strain)
against the work of the torques and of the contact force (trapezoidal rule over each
step).

![balances]({png_bal})

{bal_table}

* **Angular momentum** balances to {upct(lrel, 2)} of the largest angular impulse in
  every run; the error is of first order in Δt ({upct(lrel10, 3)} in Fig. 10,
  {upct(lrel10dt, 3)} at half the step): it comes from the method holding the
  constraint forces' directions at the start of each step.
* **Energy, without load**: a pair spinning freely gains energy at a steady rate,
  {rate8 * 1e3:.3f} mW at 4,000 rpm and {rate9:.2f} W at 20,000 rpm (ratio
  {rate9 / rate8:.0f}, against (20,000/4,000)⁴ = 625): the centrifugal root forces held in
  direction over a step do work ∝ m r² ω⁴ Δt. It is tiny: at 20,000 rpm it is the work of
  a torque of {torque_equiv:.1e} N m per gear, {torque_equiv / ctx.tau0:.0e} of τ0.
* **Energy, under load**: after the free drift is taken off, the energy balance is off by
  at most {ex8 * 1e6:.1f} µJ in Fig. 8 ({upct(ex8 / bal['bal_fig8']['strain'])} of the
  largest strain energy), {ex9 * 1e6:.1f} µJ in Fig. 9
  ({upct(ex9 / bal['bal_fig9']['strain'])}) and {ex10 * 1e6:.0f} µJ in the impacts of Fig. 10
  ({upct(ex10 / bal['bal_fig10']['strain'])}). These are excursions during contact, not a
  steady gain or loss: at the end of the engagement
  {abs(end8) * 1e6:.1f}, {abs(end9) * 1e6:.1f} and {abs(end10) * 1e6:.1f} µJ remain. They do **not** depend on Δt
  ({ex10dt * 1e6:.0f} µJ at half the step) but do depend on the spline
  ({ex10s * 1e6:.0f} µJ with 241 points): the contact constraint is not exactly workless
  in this method, because the gap is measured between cubic-spline surfaces through the
  data points while the contact force, the velocity and the acceleration constraints act
  through the element edge's shape functions. The booked contact work itself
  (p times the relative normal velocity of the loaded material points) stays below
  {max(b['cwork'] for b in bal.values()) * 1e6:.2f} µJ. An energy error of a few per cent of
  the strain energy corresponds to about half that in force amplitude; it is one of the
  reasons to quote dynamic factors to a few per cent.

### 3.3 Static stiffness against ISO 6336-1

![stiffness]({png_k})

{stiff_table}

The FE pair is {k8.max() / c1:.1f}–{k4.max() / c1:.1f} times as stiff as ISO's c′ (the
8 × 28 and 4 × 14 meshes), and its mean mesh stiffness {kmm8 / cga:.1f}–{kmm4 / cga:.1f}
times ISO's c_γα. The reasons (`docs/stiffness.md` section 5):

* **Rigid disk under the root circle.** The tooth is clamped along its root: no rim, web
  or shaft compliance, the "foundation" deflection that ISO's whole-gear values contain.
* **A point load.** The contact force enters at one point of the element edge; the local
  compliance of a point load on a plane body grows logarithmically as the mesh is refined
  (from 4 × 14 to 8 × 28 the pair compliance at the pitch point grows by
  {(c8 - c4) * 1e9:.3f} × 10⁻⁹ m/N, against {log_half_plane * 1e9:.3f} × 10⁻⁹ m/N for a
  halving of the load's spread on two half-planes), so no mesh reaches the Hertzian
  contact compliance of the real teeth (section 6).
* **ISO's C_M = 0.8** is an empirical factor from theoretical to measured stiffness; the
  model of perfect teeth compares with C_M = 1 (last column), which removes a factor 1.25.
* Plane stress would, if anything, make the model softer than a wide gear.

For the dynamics this means: natural frequencies about √{k4.max() / c1:.1f} ≈
{math.sqrt(k4.max() / c1):.2f} times those of an ISO-stiffness pair, and resonance speeds
higher by the same factor.

### 3.4 Frequency of the force oscillation

{freq_table}

![spectrum]({png_spec})

The spectrum of F − τ_A/r_b in the single-contact zone of the 1,000 rpm run (averaged
over 20 µs, which removes the element-scale ripple of section 2) has one peak, at
{fs_fe / 1e3:.2f} kHz with an amplitude of {as_fe:.0f} N; nothing else in 1–30 kHz reaches
{upct(second / as_fe, 0)} of it outside the peak's own width. The zone lasts
{(t_fe[-1] - t_fe[0]) * 1e3:.3f} ms, about {(t_fe[-1] - t_fe[0]) * fs_fe:.1f} periods, so an FFT's bins
are {bin_fe / 1e3:.1f} kHz wide (its zero-padded Hann peak: {fft_fe / 1e3:.2f} kHz); the spectrum
shown is the least-squares one (a sinusoid, a mean and a linear trend fitted at each
frequency), which locates a peak on such short records, and the zero crossings of the
same record give {f_fe / 1e3:.2f} kHz ({n_fe} crossings). Taking {f_fe / 1e3:.2f} kHz: it lies
{upct(abs(relative(f_fe, f_single)), 1)} {"below" if f_fe < f_single else "above"} the
frequency of two disks J = {pair.gear_a.disk_inertia:.4g} kg m² on the FE model's own mean
single-zone stiffness, and {upct(abs(relative(f_fe, f_lu)), 1)} {"below" if f_fe < f_lu else "above"} the
lumped model measured the same way. Adding the teeth' inertia
({j_tooth[0] * 1e6:.2f} × 10⁻⁶ kg m² each, {upct(j_tooth[0] / pair.gear_a.disk_inertia, 1)} of J)
to the disks explains {upct((f_single - f_teeth) / (f_single - f_fe) if f_single != f_fe else 0, 0)}
of the difference; the rest, a dynamic tooth spring a few per cent softer than the
static point-load stiffness, is not explained here. With ISO's stiffness the pair would
ring at {torsional_natural_frequency(pair, c1) / 1e3:.1f}–{torsional_natural_frequency(pair, cga) / 1e3:.1f} kHz:
the frequency is a direct test of the stiffness (section 3.3), and the FE model's
oscillation matches its own static stiffness, not ISO's. The mesh frequency meets the
measured frequency at {f_fe * 60 / 28:,.0f} rpm, where this pair's main resonance is to be
expected.
"""
    return text

