"""Print the tables of ``docs/fracture.md``, section 5, from the code.

Run from the repository root::

    .venv/bin/python docs/validation fracture

Everything printed is computed here: the edge-cracked strip in tension and bending against
Tada, Paris & Irwin and Brown & Srawley for a/W = 0.1 to 0.6 on the tests' mesh and a fine
one, a mesh study, the strip's length, the domains (rings), the inclined centre crack in two
plate sizes, displacement correlation on quarter-point elements, and a root crack in the
paper's gear (tooth 0's cell) with its growth direction. It takes about a minute and a half.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from typing import Sequence

import numpy as np

from spurdyn.fem.assembly import assemble_stiffness
from spurdyn.fem.factor import factor_spd
from spurdyn.fem.material import STEEL
from spurdyn.fracture import (
    centre_crack_plate, edge_crack_strip, end_load, equivalent_k, growth_angle, solve,
    stress_intensity,
)
from spurdyn.fracture import handbook as hb
from spurdyn.fracture.correlation import displacement_correlation, quarter_points
from spurdyn.geometry.presets import paper_gear
from spurdyn.mesh.cracked import crack_path, cracked_tooth
from spurdyn.mesh.sector import cell_mesh
from spurdyn.mesh.tooth import tooth_mesh

WIDTH = 0.01
STRESS = 100e6
RATIOS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6)
#: (element size / W, tip size / min(a, size)): the tests' mesh and a fine one.
TEST_MESH, FINE_MESH = (0.1, 0.05), (0.03, 0.02)
LOADS = {"tension": (lambda x: np.full(len(x), STRESS), hb.tension_tada, hb.tension_brown_srawley),
         "bending": (lambda x: STRESS * (1.0 - 2.0 * x[:, 0] / WIDTH), hb.bending_tada,
                     hb.bending_brown_srawley)}


def _strip(ratio: float, mesh: tuple[float, float], half_height: float = 2.0):
    depth, size = ratio * WIDTH, mesh[0] * WIDTH
    return edge_crack_strip(WIDTH, half_height * WIDTH, depth, size, mesh[1] * min(depth, size))


def _f(plate, load: str, ratio: float, rings: tuple[int, ...] = (2, 3)):
    """F = K_I / (sigma sqrt(pi a)) of each domain, and the displacements."""
    u = solve(plate, STEEL, end_load(plate, LOADS[load][0]))
    k = stress_intensity(plate.nodes, plate.elements, u, STEEL, int(plate.tips[0]),
                         plate.ahead[0], rings)
    return k.k_i / (STRESS * math.sqrt(math.pi * ratio * WIDTH)), k, u


def strip_table() -> None:
    print("| load | a/W | Tada | Brown & Srawley | FE, tests' mesh (nodes) | vs Tada | vs B&S "
          "| FE, fine mesh (nodes) | vs Tada | vs B&S |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for load, (_, tada, bs) in LOADS.items():
        for ratio in RATIOS:
            cells = [load, f"{ratio:.1f}", f"{tada(ratio):.4f}", f"{bs(ratio):.4f}"]
            for mesh in (TEST_MESH, FINE_MESH):
                plate = _strip(ratio, mesh)
                f = float(np.mean(_f(plate, load, ratio)[0]))
                cells += [f"{f:.4f} ({plate.nodes.shape[0]})", f"{f / tada(ratio) - 1:+.2%}",
                          f"{f / bs(ratio) - 1:+.2%}"]
            print("| " + " | ".join(cells) + " |")


def mesh_study() -> None:
    print("| size / W | tip size / a | nodes | F tension | F bending |")
    print("|---|---|---|---|---|")
    for size in (0.2, 0.1, 0.05, 0.03):
        for share in (0.1, 0.05, 0.02):
            plate = _strip(0.3, (size, share))
            ft = float(np.mean(_f(plate, "tension", 0.3)[0]))
            fb = float(np.mean(_f(plate, "bending", 0.3)[0]))
            print(f"| {size} | {share * min(0.3, size / 1.0) / 0.3:.4f} | {plate.nodes.shape[0]} "
                  f"| {ft:.4f} | {fb:.4f} |")


def length_table() -> None:
    print("| a/W | h/W | F tension | F bending |")
    print("|---|---|---|---|")
    for ratio in (0.3, 0.6):
        for half in (1.0, 2.0, 4.0):
            plate = _strip(ratio, FINE_MESH, half)
            print(f"| {ratio} | {half} | {np.mean(_f(plate, 'tension', ratio)[0]):.4f} "
                  f"| {np.mean(_f(plate, 'bending', ratio)[0]):.4f} |")


def ring_table() -> None:
    rings = (1, 2, 3, 4, 5)
    print("| case | " + " | ".join(f"ring {r}" for r in rings) + " |")
    print("|---|" + "---|" * len(rings))
    for ratio, mesh in ((0.3, TEST_MESH), (0.3, FINE_MESH)):
        plate = _strip(ratio, mesh)
        f, k, _ = _f(plate, "tension", ratio, rings)
        print(f"| strip a/W = 0.3, tension, {plate.nodes.shape[0]} nodes: F | "
              + " | ".join(f"{v:.4f}" for v in f) + " |")
        print("| (domain radius / a) | " + " | ".join(f"{r / (ratio * WIDTH):.3f}"
                                                      for r in k.radius) + " |")
    a, beta = 1e-3, math.radians(45.0)
    plate = centre_crack_plate(40 * a, 40 * a, a, beta, 2 * a, 0.05 * a)
    u = solve(plate, STEEL, end_load(plate, LOADS["tension"][0]))
    k = stress_intensity(plate.nodes, plate.elements, u, STEEL, int(plate.tips[0]),
                         plate.ahead[0], rings)
    k0 = STRESS * math.sqrt(math.pi * a)
    print("| centre crack 45 deg: K_I / (s sqrt(pi a)) (exact 0.5) | "
          + " | ".join(f"{v / k0:.4f}" for v in k.k_i) + " |")
    print("| K_II / (s sqrt(pi a)) (exact 0.5) | " + " | ".join(f"{v / k0:.4f}" for v in k.k_ii)
          + " |")
    print("| (domain radius / a) | " + " | ".join(f"{r / a:.3f}" for r in k.radius) + " |")


def centre_table() -> None:
    a = 1e-3
    k0 = STRESS * math.sqrt(math.pi * a)
    print("| beta (deg) | plate / a | nodes | K_I / k0 exact | tip 1 | tip 2 | K_II / k0 exact "
          "| tip 1 | tip 2 | theta_c (deg) | K_eq / k0 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for degrees in (0.0, 15.0, 30.0, 45.0, 60.0, 75.0):
        beta = math.radians(degrees)
        k_i, k_ii = hb.centre_crack(STRESS, a, beta)
        for side in (40.0, 80.0):
            plate = centre_crack_plate(side * a, side * a, a, beta, 2 * a, 0.05 * a)
            u = solve(plate, STEEL, end_load(plate, LOADS["tension"][0]))
            ks = [stress_intensity(plate.nodes, plate.elements, u, STEEL, int(t), d)
                  for t, d in zip(plate.tips, plate.ahead)]
            ki = [float(np.mean(k.k_i)) for k in ks]
            kii = [float(np.mean(k.k_ii)) for k in ks]
            print(f"| {degrees:g} | {side:g} | {plate.nodes.shape[0]} | {k_i / k0:.4f} "
                  f"| {ki[0] / k0:.4f} | {ki[1] / k0:.4f} | {k_ii / k0:.4f} | {kii[0] / k0:.4f} "
                  f"| {kii[1] / k0:.4f} | {math.degrees(growth_angle(ki[0], kii[0])):.2f} "
                  f"| {equivalent_k(ki[0], kii[0]) / k0:.4f} |")
    print(f"\nFeddersen's width factor of a straight crack, a/W = 1/40: "
          f"{hb.feddersen(1 / 40):.5f}; 1/80: {hb.feddersen(1 / 80):.5f}")


def correlation_table() -> None:
    print("| case | interaction integral K_I / ref, K_II / k0 | quarter-point correlation "
          "K_I / ref, K_II / k0 |")
    print("|---|---|---|")
    for ratio in (0.1, 0.3, 0.5):
        plate = _strip(ratio, TEST_MESH)
        tip = int(plate.tips[0])
        qp = dataclasses.replace(plate, nodes=quarter_points(plate.nodes, plate.elements, tip))
        f, k, u = _f(qp, "tension", ratio)
        k0 = STRESS * math.sqrt(math.pi * ratio * WIDTH)
        ref = k0 * hb.tension_tada(ratio)
        dc = displacement_correlation(qp.nodes, u, STEEL, tip, qp.ahead[0], qp.seam, qp.normal)
        print(f"| strip a/W = {ratio}, tension | {np.mean(k.k_i) / ref:.4f}, "
              f"{np.mean(k.k_ii) / k0:+.4f} | {dc[0] / ref:.4f}, {dc[1] / k0:+.4f} |")
    a = 1e-3
    for degrees in (30.0, 60.0):
        beta = math.radians(degrees)
        plate = centre_crack_plate(40 * a, 40 * a, a, beta, 2 * a, 0.05 * a)
        nodes = plate.nodes
        for t in plate.tips:
            nodes = quarter_points(nodes, plate.elements, int(t))
        qp = dataclasses.replace(plate, nodes=nodes)
        u = solve(qp, STEEL, end_load(qp, LOADS["tension"][0]))
        k_i, k_ii = hb.centre_crack(STRESS, a, beta)
        k0 = STRESS * math.sqrt(math.pi * a)
        t, d = int(qp.tips[0]), qp.ahead[0]
        k = stress_intensity(qp.nodes, qp.elements, u, STEEL, t, d)
        dc = displacement_correlation(qp.nodes, u, STEEL, t, d, qp.seam, qp.normal)
        print(f"| centre crack {degrees:g} deg, tip 1 | {np.mean(k.k_i) / k_i:.4f}, "
              f"{np.mean(k.k_ii) / k_ii:.4f} (K_II / exact) | {dc[0] / k_i:.4f}, "
              f"{dc[1] / k_ii:.4f} (K_II / exact) |")


def tooth_table() -> None:
    """A root crack in the paper's gear: tooth 0's cell (the tooth on its rim down to the
    hub, held at the hub) cracked as the faults crack it, 1 kN on the right flank."""
    gear = paper_gear()
    tooth, cell = tooth_mesh(gear), cell_mesh(gear)
    side = tooth.right_side[2 * len(tooth.right_side) // 3]
    radius = float(np.hypot(*tooth.nodes[side]))
    print(f"1 kN normal to the right flank at r = {radius * 1e3:.2f} mm; the mouth at ISO "
          f"6336-3's 30 deg tangent point; tip size depth / 20; K in MPa sqrt(m), domains "
          "of 2, 3 and 4 rings\n")
    print("| depth (mm) | angle below the line across (deg) | nodes | K_I | K_II "
          "| theta_c (deg) | new direction (deg from +x) |")
    print("|---|---|---|---|---|---|---|")
    for depth in (0.1e-3, 0.3e-3, 1e-3):
        for degrees in (30.0, 45.0, 60.0):
            path = crack_path(gear, tooth, "right", depth, math.radians(degrees), region=cell)
            cracked = cracked_tooth(gear, cell, path, tip_size=depth / 20)
            n = cracked.nodes.shape[0]
            held = cracked.structured[cell.root_nodes]
            free = np.setdiff1d(np.arange(2 * n), np.concatenate([2 * held, 2 * held + 1]))
            k = assemble_stiffness(cracked.nodes, cracked.elements, gear.material,
                                   gear.face_width)
            node = int(np.argmin(np.hypot(*(cracked.nodes - tooth.nodes[side]).T)))
            f = np.zeros(2 * n)
            f[2 * node:2 * node + 2] = -1e3 * np.asarray(gear.flank_normal(np.asarray(radius)))
            u = np.zeros(2 * n)
            u[free] = factor_spd(k[free][:, free]).solve(f[free])
            ahead = (path[1] - path[0]) / np.hypot(*(path[1] - path[0]))
            ks = stress_intensity(cracked.nodes, cracked.elements, u, gear.material,
                                  cracked.tip, ahead, (2, 3, 4))
            theta = growth_angle(float(ks.k_i[-1]), float(ks.k_ii[-1]))
            turned = (math.degrees(math.atan2(ahead[1], ahead[0]) + theta)) % 360.0
            print(f"| {depth * 1e3:g} | {degrees:g} | {n} | "
                  + ", ".join(f"{v / 1e6:.3f}" for v in ks.k_i) + " | "
                  + ", ".join(f"{v / 1e6:.3f}" for v in ks.k_ii)
                  + f" | {math.degrees(theta):.1f} | {turned:.1f} |")


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: print the tables of ``docs/fracture.md``."""
    argparse.ArgumentParser(prog="docs/validation fracture",
                            description=__doc__.split("\n\n")[0]).parse_args(argv)
    print(f"E = {STEEL.young:.3g} Pa, nu = {STEEL.poisson}, plane stress; W = {WIDTH} m, "
          f"sigma = {STRESS:.3g} Pa; K from the domains of 2 and 3 rings, their mean\n")
    for title, table in (("Edge crack in a strip", strip_table), ("Mesh study, a/W = 0.3",
                                                                  mesh_study),
                         ("The strip's length", length_table), ("Domains", ring_table),
                         ("Inclined centre crack", centre_table),
                         ("Displacement correlation", correlation_table),
                         ("A root crack in the paper's gear", tooth_table)):
        print(f"## {title}\n")
        table()
        print()
    return 0
