"""Section 5 of the report: tip relief, the paper's explanation of its NASA comparison."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .context import Ctx
from .figures import pyplot, save_figure, shade_zones
from .helpers import contact_episodes, n0, n2, table
from .settings import RPM
from .spurdyn_api import (NASA_LIKE_TIP_RELIEF, GearPair, gear_torques, mesh_stiffness_table,
                          nasa_like_relief)


def relief_gap(pair: GearPair, amount: float, phi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Separation (m) of the unloaded relieved flanks along the line of action at A's
    rotation ``phi`` (A driving): the sum of both gears' relief depths at the contact point."""
    g = nasa_like_relief(pair.gear_a, amount=amount)
    roll_a = pair.start_roll_a + np.asarray(phi, float)
    roll_b = pair.roll_b_from_roll_a(roll_a)
    ra = pair.gear_a.radius_at_roll_angle(roll_a)
    rb = pair.gear_b.radius_at_roll_angle(roll_b)
    return np.asarray(g.relief_depth(ra)) + np.asarray(g.relief_depth(rb))


def free_approach(ctx: Ctx, phi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Approach (m) along the line of action of two free disks turning at 4,000 rpm under
    the Fig. 7 torques alone (no contact force): ∫∫ (r_bA τ_A/J_A − r_bB τ_B/J_B) dt dt."""
    pair = ctx.pair
    w = 4000 * RPM
    t = np.asarray(phi, float) / w
    ta, tb = gear_torques(pair, ctx.tau0, phi, phi)
    acc = pair.gear_a.base_radius * np.asarray(ta) / pair.gear_a.disk_inertia \
        - pair.gear_b.base_radius * np.asarray(tb) / pair.gear_b.disk_inertia
    v = np.concatenate([[0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * np.diff(t))])
    return np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])


def section_relief(ctx: Ctx) -> str:
    """Section 5: Fig. 8 with tip relief, against the free-disk and quasi-static predictions."""
    plt = pyplot()
    R = ctx.runs
    pair = ctx.pair
    phi = np.linspace(0.0, ctx.theta_s, 4001)
    table_k = mesh_stiffness_table(pair)
    k_phi = table_k(pair.start_roll_a + phi)
    tau_a, _ = gear_torques(pair, ctx.tau0, phi, phi)
    deflection = np.asarray(tau_a) / ctx.rb / np.maximum(k_phi, 1.0)
    approach = free_approach(ctx, phi)
    static_defl = ctx.static / table_k.mean(*pair.single_contact_roll_a)
    rows = []
    fig, axes = plt.subplots(2, 1, figsize=(10, 7.5), sharex=True)
    ax = axes[0]
    shade_zones(ax, ctx)
    colors = {"fig8": "C0", "relief_5um": "C2", "relief_20um": "C3"}
    for name, amount in (("fig8", 0.0), ("relief_5um", 5e-6), ("relief_20um", 20e-6)):
        r = R[name]
        eps = contact_episodes(r["time"], r["angle"], r["contact_force"])
        imps = ctx.impacts(name)
        first = math.degrees(eps[0]["angle_on"]) if eps else float("nan")
        last = math.degrees(eps[-1]["angle_off"]) if eps else float("nan")
        if amount:
            gap = relief_gap(pair, amount, phi)
            pred_free = math.degrees(phi[int(np.argmax(approach >= gap))])
            qs_on = phi[np.argmax(deflection >= gap)]
            late = (phi > pair.theta_s / 2) & (deflection < gap)
            qs_off = phi[np.argmax(late)] if late.any() else float("nan")
            pred = f"{pred_free:.2f}°"
            pred_qs = f"{math.degrees(qs_on):.2f}° – {math.degrees(qs_off):.2f}°"
        else:
            pred = pred_qs = "0° – θs"
        i_on = int(np.argmax(r["contact_force"] > 0))
        v_rel = ctx.rb * (r["omega"][i_on, 0] - r["omega"][i_on, 1])
        rows.append(["none" if not amount else f"{amount * 1e6:.0f} µm" + (" (`nasa_like_relief`)" if amount == NASA_LIKE_TIP_RELIEF else ""),
                     f"{first:.2f}°", pred, pred_qs, f"{last:.2f}°", f"{v_rel:.3f}",
                     len(imps), n0(r["contact_force"].max()), n0(ctx.peak_avg(name)),
                     n2(ctx.peak_avg(name) / ctx.static)])
        lab = "no relief" if not amount else f"tip relief {amount * 1e6:.0f} µm"
        ax.plot(np.degrees(r["angle"]), r["contact_force"], color=colors[name], lw=0.4, alpha=0.35)
        ax.plot(ctx.avg_angle(name), ctx.avg(name)[1], color=colors[name], lw=1.4, label=lab)
        if amount:
            axes[1].plot(np.degrees(phi), relief_gap(pair, amount, phi) * 1e6, color=colors[name],
                         label=f"relief gap, {amount * 1e6:.0f} µm")
    ax.set_ylabel("contact force (N)")
    ax.set_title("Fig. 8 (4,000 rpm) with a linear tip relief on both gears, from the highest "
                 "point of single contact (10-µs averages; raw thin)")
    ax.legend(loc="upper right")
    ax = axes[1]
    ax.plot(np.degrees(phi), deflection * 1e6, color="k", ls="--",
            label="quasi-static deflection τ_A/(r_b k)")
    ax.plot(np.degrees(phi), approach * 1e6, color="0.4", ls=":",
            label="approach of free disks under the torque ramp")
    ax.set_ylim(0, 22)
    ax.set_ylabel("µm along the line of action")
    ax.set_xlabel("rotation of gear A from the start of contact (deg)")
    ax.legend(loc="upper center", ncol=2)
    fig.tight_layout()
    png = save_figure(fig, "validation_relief.png")
    relief_table = table(["tip relief (both gears)", "first contact", "predicted: free disks",
                          "predicted: quasi-static contact", "last contact",
                          "approach speed at first contact (m/s)", "impacts", "raw peak (N)",
                          "peak of 10-µs average (N)", "dynamic factor (of the average)"], rows)
    start_relief = math.degrees(pair.single_contact_roll_a[1])
    text = f"""
## 5. Against the NASA reference: tip relief

The paper compares its Fig. 8 with NASA TM-105326 (Rebbechi et al. 1992) and reports close
agreement except at the start and end of contact, which it puts down to the reference
gears' tip relief. **We do not have the NASA data** (neither the measured loads nor the
relief of those gears), so no quantitative comparison is possible here; what can be
checked is the paper's explanation: does a tip relief move the start and end of contact,
and leave the middle alone? `spurdyn.geometry.nasa_like_relief` gives both gears a
linear relief from the highest point of single-tooth contact (roll angle
{start_relief:.2f}°) to the tip; its amount is an **assumption** (`docs/relief.md`): the
preset's {NASA_LIKE_TIP_RELIEF * 1e6:.0f} µm, typical of a ground relief for the full
design load of a module-3 gear, and a relief sized to this torque, 5 µm (about
{5e-6 / static_defl:.1f} times the static mesh deflection τ0/(r_b k) =
{static_defl * 1e6:.2f} µm).

![tip relief]({png})

{relief_table}

"Predicted: free disks" is where the teeth would meet if the disks moved under the
torque ramp alone until the gap closes; "predicted: quasi-static contact" is where the
relief gap equals the static deflection the ramp's load would produce, i.e. where a
two-pair model (or the real gears) would make and lose contact.

**What the runs show.** The relief moves the start of contact later and the end earlier,
as the paper says of the NASA gears. But in this one-tooth model a relief also makes the
pair **rattle**: with the {NASA_LIKE_TIP_RELIEF * 1e6:.0f} µm relief the teeth first meet at
{rows[2][1]}, approaching at {rows[2][5]} m/s, and bounce ({rows[2][6]} impacts, dynamic
factor {rows[2][9]}); with 5 µm they meet at {rows[1][1]} at {rows[1][5]} m/s
({rows[1][6]} impacts, {rows[1][9]}). Once set going, the bouncing continues through the
single-contact zone, where no relief acts.

**Why: a limitation of the one-tooth model.** The Fig. 7 schedule puts the torque on the
modelled pair's disks from the first degree, as if that pair carried its share of the
load, whatever the flanks do. With a relief the flanks do not touch there, so nothing
holds the disks: the driver's torque speeds A up, the load torque slows B down, and the
two disks close the relief gap in free flight and strike (dotted curve: the first
contacts fall where it crosses the relief gap, {rows[2][2]} and {rows[1][2]}). In real gears the previous pair
would carry the whole load until the new pair's relief gap closed under its deflection
(the quasi-static prediction), and the disks' relative speed would stay small. The same
happens at the end of contact, where the relief on A's tip opens a gap while the ramp
still loads the pair. So the runs show *where* a relief moves the start and end of
contact, but their forces near the ends are an artefact of prescribing the load sharing;
modelling tip relief properly needs the second tooth pair (or a load-sharing rule driven
by the contact itself).

**What could be compared.** Half of the paper's statement can be checked in this model:
without relief the force rises from the very start of the path of contact and falls to
zero at its end; with a relief it starts later and ends earlier. The other half, close
agreement away from the ends, cannot: in the one-tooth model the relief sets off a
rattle that spoils the middle of the engagement too, which says more about the
prescribed load sharing than about the gears. Quantitatively nothing could be compared:
the relief's amount and start, the rig's measured loads, its damping and its shafts are
not available to us.
"""
    return text

