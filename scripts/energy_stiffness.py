"""The figures of docs/faults_energy.md: the potential-energy mesh stiffness of the paper's
pair, healthy (beside ISO 6336-1 and the sector model) and with a root crack of growing depth.

Usage::

    python scripts/energy_stiffness.py            # print the page's tables (markdown)
    python scripts/energy_stiffness.py --figure docs/figures/faults_energy_crack.png

The sector model's figures are quoted from docs/sector_validation.md (table 1: 4 x 14
tooth meshes, hub radius 19.05 mm, 22.25 N m), not recomputed (that takes minutes).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from spurdyn.energy import Crack, mean_mesh_stiffness, mesh_cycle, pair_compliance
from spurdyn.energy.crack import limit_alpha
from spurdyn.energy.tooth import tooth_compliance
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.iso6336 import iso_pair, rate
from spurdyn.mesh.sector import default_inner_radius

#: docs/sector_validation.md, table 1, paper 28/28 at 22.25 N m: k mean, single-pair max (N/um).
SECTOR_MEAN, SECTOR_SINGLE = 110.1, 85.9
DEPTHS_MM = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0)
ANGLE = math.radians(45.0)


def single_range(pair, n: int = 401) -> np.ndarray:
    lo, hi = pair.single_contact_roll_a
    return np.linspace(lo, hi, n)


def annulus_twist(gear, bore: float) -> float:
    """Twist compliance (m/N, along the line of action) of a plane annulus from the bore to
    the root circle: ``r_b^2 / (4 pi G b) (1/r_in^2 - 1/r_f^2)`` (docs/sector_validation.md, 3)."""
    g = gear.material.young / (2.0 * (1.0 + gear.material.poisson))
    return gear.base_radius**2 / (4 * math.pi * g * gear.face_width) * (
        1.0 / bore**2 - 1.0 / gear.root_radius**2)


def shared_twist_mean(pair, bores, root_segment: bool, n: int = 4000) -> float:
    """Mean mesh stiffness (N/m) with both gears' annulus twist taken out of each pair's
    branch and put in series with the whole mesh, where two pairs share it: a diagnostic
    of the method's parallel springs, not a variant of the method."""
    twist = annulus_twist(pair.gear_a, bores[0]) + annulus_twist(pair.gear_b, bores[1])
    pitch = 2 * math.pi / pair.gear_a.teeth
    xi = pair.start_roll_a + (np.arange(n) + 0.5) * pitch / n
    branches = np.zeros(n)
    for j in range(0, math.ceil(pair.contact_ratio) + 1):
        on = xi + j * pitch <= pair.end_roll_a
        c = pair_compliance(pair, xi[on] + j * pitch, bore_radii=bores,
                            root_segment=root_segment).total
        branches[on] += 1.0 / (c - twist)
    return float(np.mean(1.0 / (twist + 1.0 / branches)))


def healthy_table(pair, bores) -> list[str]:
    """Mean and single-pair figures of the method's variants against ISO and the sector."""
    b = pair.gear_a.face_width
    iso = rate(iso_pair(pair), PAPER_TORQUE)
    iso_mean, iso_single = iso.mesh * b / 1e6, iso.single_pair * b / 1e6
    rows = ["| variant | k pitch (N/um) | k mean (N/um) | single-pair max (N/um) | mean vs "
            f"sector {SECTOR_MEAN} | single vs sector {SECTOR_SINGLE} | mean vs ISO c_ga b "
            f"{iso_mean:.1f} | single vs ISO c' b {iso_single:.1f} | mean, twist shared "
            "(N/um) |", "|---|---|---|---|---|---|---|---|---|"]
    for name, bore, seg in (("teeth on their base circles only (no foundation)", None, False),
                            ("teeth down to the root circle (no foundation)", None, True),
                            ("published: base circles + fillet foundation", bores, False),
                            ("extension: root circles + fillet foundation", bores, True)):
        pitch = pair_compliance(pair, [pair.pitch_roll_a], bore_radii=bore,
                                root_segment=seg).stiffness[0] / 1e6
        mean = mean_mesh_stiffness(pair, bore_radii=bore, root_segment=seg) / 1e6
        single = pair_compliance(pair, single_range(pair), bore_radii=bore,
                                 root_segment=seg).stiffness.max() / 1e6
        shared = "" if bore is None else f"{shared_twist_mean(pair, bore, seg) / 1e6:.1f}"
        rows.append(f"| {name} | {pitch:.1f} | {mean:.1f} | {single:.1f} | "
                    f"{mean / SECTOR_MEAN - 1:+.1%} | {single / SECTOR_SINGLE - 1:+.1%} | "
                    f"{mean / iso_mean - 1:+.1%} | {single / iso_single - 1:+.1%} | {shared} |")
    twist = annulus_twist(pair.gear_a, bores[0]) + annulus_twist(pair.gear_b, bores[1])
    rows.append(f"\nISO c'_th b (c' b without C_M = 0.8): {iso_single / 0.8:.1f} N/um; "
                f"annulus twist, both gears: {twist * 1e9:.3f} um/kN.")
    return rows


def parts_table(pair, bores) -> list[str]:
    """One tooth's compliances (um/kN = 1e-9 m/N) at three contact positions."""
    rows = ["| contact on A | bending | shear | axial | foundation | below base circle | "
            "both teeth + Hertz (um/kN) | pair k (N/um) |", "|---|---|---|---|---|---|---|---|"]
    for name, roll in (("lowest", pair.start_roll_a), ("pitch point", pair.pitch_roll_a),
                       ("tip", pair.end_roll_a)):
        t = tooth_compliance(pair.gear_a, [roll], bore_radius=bores[0])
        seg = tooth_compliance(pair.gear_a, [roll], bore_radius=bores[0], root_segment=True)
        below = (seg.total - t.total)[0]
        pc = pair_compliance(pair, [roll], bore_radii=bores)
        rows.append(f"| {name} (roll {math.degrees(roll):.2f} deg) | {t.bending[0] * 1e9:.3f} | "
                    f"{t.shear[0] * 1e9:.3f} | {t.axial[0] * 1e9:.4f} | "
                    f"{t.foundation[0] * 1e9:.3f} | ({below * 1e9:.3f}) | "
                    f"{pc.total[0] * 1e9:.3f} (Hertz {pc.hertz * 1e9:.3f}) | "
                    f"{pc.stiffness[0] / 1e6:.1f} |")
    return rows


def crack_table(pair, bores) -> list[str]:
    """The cracked tooth pair and the mesh over its engagement, against the depth."""
    gear = pair.gear_a
    roll = np.linspace(pair.start_roll_a, pair.end_roll_a, 801)
    healthy = mesh_cycle(pair, roll, bore_radii=bores)
    pitch = pair_compliance(pair, [pair.pitch_roll_a], bore_radii=bores).stiffness[0]
    rows = ["| q (mm) | case | tip offset s (mm) | cut up to roll (deg) | pair k at pitch point "
            "(N/um) | change | mesh k mean over the engagement (N/um) | mesh k min (N/um) |",
            "|---|---|---|---|---|---|---|---|"]
    for q in DEPTHS_MM:
        crack = Crack(q * 1e-3, ANGLE)
        cycle = mesh_cycle(pair, roll, crack_a=crack, bore_radii=bores)
        k_pitch = pair_compliance(pair, [pair.pitch_roll_a], crack, bore_radii=bores).stiffness[0]
        s = crack.tip_offset(gear)
        case = "-" if q == 0 else ("1" if s >= 0 else "2")
        cut = "-" if q == 0 else \
            f"{math.degrees(gear.half_angle_base - limit_alpha(gear, s)):.2f}"
        offset = "-" if q == 0 else f"{s * 1e3:.3f}"
        rows.append(f"| {q:.1f} | {case} | {offset} | {cut} | "
                    f"{k_pitch / 1e6:.1f} | {k_pitch / pitch - 1:+.1%} | "
                    f"{np.mean(cycle.mesh) / 1e6:.1f} | {cycle.mesh.min() / 1e6:.1f} |")
    rows.append(f"\nHealthy mesh over the same positions: mean {np.mean(healthy.mesh) / 1e6:.1f}, "
                f"min {healthy.mesh.min() / 1e6:.1f} N/um.")
    return rows


def convergence_table(pair, bores) -> list[str]:
    """Largest relative difference from 1024 Gauss points over nine contact positions."""
    roll = np.linspace(pair.start_roll_a, pair.end_roll_a, 9)
    rows = ["| crack | 12 | 24 | 48 | 96 |", "|---|---|---|---|---|"]
    for name, crack in (("none", None), ("1.5 mm, 45 deg", Crack(1.5e-3)),
                        ("4.5 mm, 60 deg", Crack(4.5e-3, math.radians(60.0))),
                        ("5.3 mm, 45 deg", Crack(5.3e-3))):
        ref = tooth_compliance(pair.gear_a, roll, crack, bores[0], points=1024).total
        errs = [np.max(np.abs(tooth_compliance(pair.gear_a, roll, crack, bores[0], points=n).total
                              / ref - 1)) for n in (12, 24, 48, 96)]
        rows.append(f"| {name} | " + " | ".join(f"{e:.1e}" for e in errs) + " |")
    return rows


def figure(pair, bores, path: str) -> None:
    """The mesh stiffness over the cracked tooth's engagement, depth by depth."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    roll = np.linspace(pair.start_roll_a, pair.end_roll_a, 801)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    for q in DEPTHS_MM[::2]:
        cycle = mesh_cycle(pair, roll, crack_a=Crack(q * 1e-3, ANGLE), bore_radii=bores)
        ax.plot(np.degrees(roll), cycle.mesh / 1e6, label=f"q = {q:.0f} mm")
        bx.plot(np.degrees(roll), cycle.pair / 1e6, label=f"q = {q:.0f} mm")
    ax.set(xlabel="roll angle of the cracked tooth's contact on A (deg)",
           ylabel="mesh stiffness (N/um)", title="mesh, neighbours healthy")
    bx.set(xlabel="roll angle of the cracked tooth's contact on A (deg)",
           ylabel="cracked pair's stiffness (N/um)", title="the cracked tooth pair")
    ax.legend(fontsize=8)
    fig.suptitle("Energy method, paper's 28/28 pair, crack at 45 deg, fillet foundation "
                 "(bore 19.05 mm)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", help="write the crack picture to this PNG")
    args = parser.parse_args()
    pair = paper_pair()
    bore = default_inner_radius(pair.gear_a)
    bores = (bore, default_inner_radius(pair.gear_b))
    print(f"bore (the sector's default hub radius): {bore * 1e3:.3f} mm, "
          f"contact ratio {pair.contact_ratio:.4f}\n")
    for table in (healthy_table, parts_table, crack_table, convergence_table):
        print("\n".join(table(pair, bores)), end="\n\n")
    if args.figure:
        figure(pair, bores, args.figure)


if __name__ == "__main__":
    main()
