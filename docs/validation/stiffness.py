"""Print the tables of ``docs/stiffness.md`` from the code.

Run from the repository root::

    .venv/bin/python docs/validation stiffness

Everything printed is computed here, with the paper's pair (``spurdyn.geometry.paper_pair``):
the pitch-point pair stiffness and the stable explicit step for five mesh densities, the
stiffness along the path of contact, the mean mesh stiffness over one base pitch, and the
ISO 6336-1 figures they are compared with. It takes a few seconds.
"""

from __future__ import annotations

import argparse
import math
from typing import Sequence

import numpy as np

from spurdyn.geometry import paper_pair
from spurdyn.model import build_tooth, iso_6336_stiffness, pair_stiffness, pitch_point_stiffness

DENSITIES = [(3, 10), (4, 14), (6, 20), (8, 28), (12, 40)]
PAPER_DT = 3e-8


def per_mm_um(k: float, face_width: float) -> float:
    """N/m to N/(mm um) per unit face width."""
    return k / (face_width * 1e3) * 1e-6


def mesh_table(pair) -> None:
    face = pair.gear_a.face_width
    c_single, _ = iso_6336_stiffness(pair).per_face_width(face)
    print("| mesh nx x ny | nodes | elements | smallest flank edge (mm) | omega_max (rad/s) "
          "| stable dt RK4 (s) | stable dt CD (s) | RK4 stable at 3e-8 s | k pitch (N/m) "
          "| k pitch (N/(mm um)) | k / (c' b) | change |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    previous = None
    for nx, ny in DENSITIES:
        tooth = build_tooth(pair.gear_a, nx, ny)
        step = tooth.stable_step()
        k = pitch_point_stiffness(pair, tooth, tooth)
        side = tooth.mesh.nodes[tooth.mesh.right_side[::2]]
        edge = float(np.min(np.linalg.norm(np.diff(side, axis=0), axis=1)))
        change = "" if previous is None else f"{k / previous - 1:+.1%}"
        print(f"| {nx} x {ny} | {tooth.mesh.n_nodes} | {tooth.mesh.n_elements} | {edge * 1e3:.3f} "
              f"| {step.omega_max:.3e} | {step.dt_rk4:.3e} | {step.dt_central:.3e} "
              f"| {'yes' if step.dt_rk4 >= PAPER_DT else 'no'} | {k:.4e} "
              f"| {per_mm_um(k, face):.2f} | {k / c_single:.2f} | {change} |")
        previous = k


def path_table(pair, nx: int, ny: int) -> None:
    g = pair.gear_a
    tooth = build_tooth(g, nx, ny)
    names = ["start of contact", "single contact starts", "pitch point",
             "single contact ends", "end of contact"]
    rolls = np.array([pair.start_roll_a, pair.single_contact_roll_a[0], pair.pitch_roll_a,
                      pair.single_contact_roll_a[1], pair.end_roll_a])
    res = pair_stiffness(pair, tooth, tooth, rolls)
    print(f"Mesh {nx} x {ny}:\n")
    print("| point | roll angle A (deg) | radius on A (mm) | radius on B (mm) "
          "| c_A (m/N) | c_B (m/N) | k (N/m) | k / k pitch |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    k_pitch = res.stiffness[2]
    r_a = g.radius_at_roll_angle(rolls)
    r_b = pair.gear_b.radius_at_roll_angle(pair.roll_b_from_roll_a(rolls))
    for i, name in enumerate(names):
        print(f"| {name} | {math.degrees(rolls[i]):.2f} | {r_a[i] * 1e3:.2f} | {r_b[i] * 1e3:.2f} "
              f"| {res.compliance_a[i]:.3e} | {res.compliance_b[i]:.3e} "
              f"| {res.stiffness[i]:.4e} | {res.stiffness[i] / k_pitch:.3f} |")
    # The mesh ripple: sampled finely over the single-contact zone, the stiffness is
    # not smooth but dips wherever the load crosses an element corner node.
    single = np.linspace(*pair.single_contact_roll_a, 81)
    k = pair_stiffness(pair, tooth, tooth, single).stiffness
    print(f"\nSingle-contact zone, {single.size} samples: k from {k.min():.4e} to {k.max():.4e} N/m "
          f"({(k.max() - k.min()) / k.mean():.1%} of the mean, {k.mean():.4e} N/m).")
    print()


def mean_mesh_stiffness(pair, nx: int, ny: int, samples: int = 400) -> tuple[float, float, float]:
    """Mean, minimum and maximum of the summed pair stiffness over one base pitch.

    Roll angle ``s`` of the leading pair runs over one angular pitch from the start of
    contact; the pair one pitch ahead (``s + 2 pi / z``) is in contact while it has not
    passed the end of contact.
    """
    tooth = build_tooth(pair.gear_a, nx, ny)
    pitch = 2.0 * math.pi / pair.gear_a.teeth
    s = pair.start_roll_a + (np.arange(samples) + 0.5) / samples * pitch
    k = pair_stiffness(pair, tooth, tooth, s).stiffness
    ahead = s + pitch
    inside = ahead <= pair.end_roll_a
    k2 = np.zeros_like(k)
    if inside.any():
        k2[inside] = pair_stiffness(pair, tooth, tooth, ahead[inside]).stiffness
    total = k + k2
    return float(total.mean()), float(total.min()), float(total.max())


def iso_table(pair) -> None:
    face = pair.gear_a.face_width
    iso = iso_6336_stiffness(pair)
    iso_th = iso_6336_stiffness(pair, correction=1.0)
    single, mesh = iso.per_face_width(face)
    single_th, mesh_th = iso_th.per_face_width(face)
    print("| ISO 6336-1 method B | N/(mm um) | N/m (b = 6.35 mm) |")
    print("| --- | --- | --- |")
    print(f"| c' = c'_th C_M C_B (C_M = 0.8) | {iso.single_pair:.2f} | {single:.3e} |")
    print(f"| c'_th C_B (C_M = 1) | {iso_th.single_pair:.2f} | {single_th:.3e} |")
    print(f"| c_gamma_alpha = c' (0.75 eps + 0.25) | {iso.mesh:.2f} | {mesh:.3e} |")
    print(f"| c_gamma_alpha with C_M = 1 | {iso_th.mesh:.2f} | {mesh_th:.3e} |")
    print()
    print("| model | mean mesh k (N/m) | min (N/m) | max (N/m) | mean / c_gamma_alpha "
          "| mean / (c_gamma_alpha with C_M = 1) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for nx, ny in [(4, 14), (8, 28)]:
        mean, lo, hi = mean_mesh_stiffness(pair, nx, ny)
        print(f"| {nx} x {ny} | {mean:.4e} | {lo:.4e} | {hi:.4e} | {mean / mesh:.2f} "
              f"| {mean / mesh_th:.2f} |")
    print()


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: print the tables of ``docs/stiffness.md``."""
    argparse.ArgumentParser(prog="docs/validation stiffness",
                            description=__doc__.split("\n\n")[0]).parse_args(argv)
    pair = paper_pair()
    print(f"Paper pair: contact ratio {pair.contact_ratio:.4f}, face width "
          f"{pair.gear_a.face_width * 1e3:.2f} mm, E = {pair.gear_a.material.young:.3g} Pa, "
          f"nu = {pair.gear_a.material.poisson}\n")
    print("## Pitch-point stiffness and stable step against mesh density\n")
    mesh_table(pair)
    print("\n## Stiffness along the path of contact\n")
    for nx, ny in [(4, 14), (8, 28)]:
        path_table(pair, nx, ny)
    print("## ISO 6336-1 and the mean mesh stiffness\n")
    iso_table(pair)
    return 0
