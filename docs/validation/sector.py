"""The sector model's quasi-static mesh cycle against ISO 6336-1 and its own limits:
writes docs/sector_validation.md.

    .venv/bin/python docs/validation sector_validation        # ~2 min

For the paper's pair, the example 23/47 pair and a 23/47 pair with a thin rim on a web:
the mean mesh stiffness and the single-pair maximum against ISO 6336-1's ``c_gamma_alpha b``
and ``c' b`` (method B, with ISO's low-load correction at the pair's load); then, for the
paper's pair, the sector's cut ends (free faces against the full rim, K against K + 2),
the hub radius, the tooth mesh, a web against the annulus' twist, and the NASA-like tip
relief's static transmission error at three torques.
"""

from __future__ import annotations

import argparse
import dataclasses
import inspect
import math
import time
from typing import Sequence

from spurdyn.case import load_pair
from spurdyn.geometry.blank import Blank
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, nasa_like_relief, paper_pair
from spurdyn.iso6336.dynamics import single_pair_stiffness
from spurdyn.iso6336.rating import iso_pair, rate
from spurdyn.sector.body import sector_body
from spurdyn.sector.statics import default_teeth, mesh_cycle, pairs_in_path
from validation.common import DOCS, ROOT, write_page

PAGE = DOCS / "sector_validation.md"
#: ISO 6336-1's ``C_M``, theoretical to measured stiffness (the rating's, the default of
#: :func:`spurdyn.iso6336.dynamics.single_pair_stiffness`).
C_M = inspect.signature(single_pair_stiffness).parameters["c_m"].default


def with_blank(pair: GearPair, blank: Blank) -> GearPair:
    ga = dataclasses.replace(pair.gear_a, blank=blank, disk_inertia=None)
    gb = dataclasses.replace(pair.gear_b, blank=blank, disk_inertia=None)
    return GearPair(ga, gb, pair.centre_distance, pair.driver)


def iso_row(name: str, pair: GearPair, torque: float) -> str:
    mc = mesh_cycle(pair, torque, 4, 14)
    r = rate(iso_pair(pair), torque)
    b = min(pair.gear_a.face_width, pair.gear_b.face_width)
    cg, c1 = r.mesh * b, r.single_pair * b
    ra, rb = mc.inner_radius
    return (f"| {name} | {torque:g} | {r.line_load / 1e3:.0f} | {ra * 1e3:.3g} / {rb * 1e3:.3g} | "
            f"{mc.stiffness_mean / 1e6:.1f} | {cg / 1e6:.1f} | {100 * (mc.stiffness_mean / cg - 1):+.1f} % | "
            f"{mc.single_pair_max / 1e6:.1f} | {c1 / 1e6:.1f} | {100 * (mc.single_pair_max / c1 - 1):+.1f} % | "
            f"{mc.transmission_error_pp * 1e6:.2f} |")


def plane_strain(pair: GearPair) -> GearPair:
    """The pair whose plane-stress bodies behave as plane-strain ones of its material: ``E / (1 -
    nu^2)`` and ``nu / (1 - nu)`` (exact for the bodies; the Hertzian strip's compliance, already
    a plane-strain one, then falls by ``(1 - 2 nu) / (1 - nu)^2``, 18 % at nu = 0.3)."""
    def gear(g):
        e, nu = g.material.young, g.material.poisson
        material = dataclasses.replace(g.material, young=e / (1 - nu * nu), poisson=nu / (1 - nu))
        # a gear on a blank takes its inertia from it again (the same density)
        return dataclasses.replace(g, material=material, **({"disk_inertia": None} if g.blank is not None else {}))
    return GearPair(gear(pair.gear_a), gear(pair.gear_b), pair.centre_distance, pair.driver)


def iso_sources_row(name: str, pair: GearPair, torque: float) -> str:
    """The single-pair maximum in plane stress (as run) and plane strain against ISO's
    ``c' b`` and its theoretical ``c'_th b = c' b / C_M``."""
    stress = mesh_cycle(pair, torque, 4, 14)
    strain = mesh_cycle(plane_strain(pair), torque, 4, 14)
    r = rate(iso_pair(pair), torque)
    c1 = r.single_pair * min(pair.gear_a.face_width, pair.gear_b.face_width)
    th = c1 / C_M
    out = [f"| {name} | {torque:g} | {stress.single_pair_max / 1e6:.1f} | {strain.single_pair_max / 1e6:.1f} | "
           f"{100 * (strain.single_pair_max / stress.single_pair_max - 1):+.1f} % | {c1 / 1e6:.1f} | {th / 1e6:.1f} |"]
    for k in (stress.single_pair_max, strain.single_pair_max):
        out.append(f" {100 * (k / c1 - 1):+.1f} % | {100 * (k / th - 1):+.1f} % |")
    return "".join(out)


def twist(gear, r_in: float, r_out: float, width: float) -> float:
    """Compliance (m/N along the line of action) of a plane annulus' twist, one gear."""
    g = gear.material.young / (2.0 * (1.0 + gear.material.poisson))
    return gear.base_radius**2 / (4.0 * math.pi * g * width) * (1.0 / r_in**2 - 1.0 / r_out**2)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: measure, then write ``docs/sector_validation.md``."""
    argparse.ArgumentParser(prog="docs/validation sector_validation",
                            description=__doc__.split("\n\n")[0]).parse_args(argv)
    t0 = time.time()
    pair = paper_pair()
    example = load_pair(ROOT / "examples" / "pinion_23_47.toml").pair
    thin = with_blank(example, Blank(hub_radius=0.012, rim_radius=example.gear_a.root_radius - 3 * 0.002,
                                     web_width=0.006))
    lines = [
        "# The sector model's quasi-static mesh cycle",
        "",
        f"Written by `docs/validation/sector.py` ({time.strftime('%Y-%m-%d')}, "
        "{seconds} s on this 2-core machine); the model and its derivation are in docs/sector.md. "
        "Default 4 x 14 tooth meshes, the teeth that carry load and a neighbour each side on the "
        "full rim, the Hertzian strips, 41 positions over one mesh cycle.",
        "",
        "## 1. Against ISO 6336-1",
        "",
        "ISO's `c_gamma_alpha b` (mean mesh stiffness) and `c' b` (single-pair stiffness) by "
        "method B for solid gears (`C_R = 1` unless a web is given, `C_B = 1`, `C_M = 0.8`), "
        "with ISO's reduction below 100 N/mm of line load; the model's mean of `k` over the "
        "cycle and its largest `k` where one pair carries the load.",
        "",
        "| pair | torque (N m) | F_t / b (N/mm) | hub radii (mm) | k mean (N/um) | ISO c_ga b | "
        "difference | single pair max (N/um) | ISO c' b | difference | static TE p-p (um) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        iso_row("paper 28/28, m 3.175, 20 deg, b 6.35 mm", pair, PAPER_TORQUE),
        iso_row("paper 28/28", pair, 60.0),
        iso_row("example 23/47, m 2, 25 deg, b 20 mm", example, 50.0),
        iso_row("example 23/47", example, 200.0),
        iso_row("23/47, web 6 mm wide, rim 3 m deep", thin, 200.0),
        "",
    ]
    # ISO's rim factor for the thin rim
    s_r = example.gear_a.root_radius - (example.gear_a.root_radius - 3 * 0.002)
    c_r = 1.0 + math.log(0.006 / 0.020) / (5.0 * math.exp(s_r / (5.0 * 0.002)))
    lines += [
        f"The thin-rim pair: ISO's rim factor `C_R = 1 + ln(b_s/b) / (5 exp(s_R / 5 m))` = "
        f"{c_r:.3f} for `s_R` = 3 m and `b_s/b` = 0.3; ISO applies it to `c'` (the table's ISO "
        "column leaves it out: multiply by it to compare).",
        "",
    ]

    lines += [
        "## 1b. Plane stress and ISO's C_M, in numbers",
        "",
        "The model's bodies are plane stress over the face width (as the paper's teeth); a wide "
        "gear is nearer plane strain, which the same bodies give with `E / (1 - nu^2)` and "
        "`nu / (1 - nu)`. ISO's `c'` is its theoretical `c'_th` times `C_M` = "
        f"{C_M:g}, a correction toward measured stiffness. The single-pair maximum in both states "
        "against both:",
        "",
        "| pair | torque (N m) | plane stress (N/um) | plane strain (N/um) | change | ISO c' b | "
        "ISO c'_th b | stress vs c' b | stress vs c'_th b | strain vs c' b | strain vs c'_th b |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        iso_sources_row("paper 28/28", pair, 60.0),
        iso_sources_row("example 23/47", example, 200.0),
        "",
    ]

    # 2. cut ends
    lines += ["## 2. The sector's cut ends", "",
              "Mean mesh stiffness of the paper's pair with K teeth per gear, the rim stopping at "
              "free radial faces half a pitch beyond the end teeth, or going all the way round "
              "(the default; the cells without a tooth end at the teeth's bottom curves):", "",
              "| K | free cut ends (N/um) | full rim (N/um) | full rim: change from K |", "| --- | --- | --- | --- |"]
    k_def = default_teeth(pair)
    prev = None
    for k in (k_def, k_def + 2, pair.gear_a.teeth):
        full = mesh_cycle(pair, PAPER_TORQUE, 4, 14, teeth=k).stiffness_mean
        if k < pair.gear_a.teeth:
            n = pairs_in_path(pair)
            extra = k - n
            before = (extra + 1) // 2
            cut = (sector_body(pair.gear_a, k, 4, 14, first=-before, full_rim=False),
                   sector_body(pair.gear_b, k, 4, 14, first=-(n - 1) - (extra - before), full_rim=False))
            free = f"{mesh_cycle(pair, PAPER_TORQUE, 4, 14, teeth=k, bodies=tuple(cut)).stiffness_mean / 1e6:.1f}"
        else:
            free = "(the whole gear)"
        change = "" if prev is None else f"{100 * (full / prev - 1):+.2f} %"
        lines.append(f"| {k} | {free} | {full / 1e6:.2f} | {change} |")
        prev = prev or full
    lines.append("")

    # 3. hub radius
    lines += ["## 3. The hub radius", "",
              "The paper's pair on solid blanks from the hub radius up (both gears alike). The "
              "column 'less twist' takes off the twist of a plane annulus from the hub to the "
              "root circle, `r_b^2 / (4 pi G b) (1/r_in^2 - 1/r_f^2)` per gear:", "",
              "| hub radius (mm) | k mean (N/um) | annulus twist, both gears (um/kN) | k mean less twist (N/um) |",
              "| --- | --- | --- | --- |"]
    g = pair.gear_a
    for r_in in (0.2 * g.root_radius, 0.3 * g.root_radius, None, 0.6 * g.root_radius, 0.75 * g.root_radius):
        mc = mesh_cycle(pair, PAPER_TORQUE, 4, 14, inner_radius=(r_in, r_in))
        r = mc.inner_radius[0]
        tw = 2 * twist(g, r, g.root_radius, g.face_width)
        lines.append(f"| {r * 1e3:.2f}{' (default)' if r_in is None else ''} | {mc.stiffness_mean / 1e6:.1f} | "
                     f"{tw * 1e9:.3f} | {1 / (1 / mc.stiffness_mean - tw) / 1e6:.1f} |")
    lines.append("")

    # 4. tooth mesh
    lines += ["## 4. The tooth mesh", "", "| mesh | DOFs | k mean (N/um) | single pair max (N/um) | static TE p-p (um) |",
              "| --- | --- | --- | --- | --- |"]
    for nx, ny in ((4, 14), (6, 20), (8, 28), (12, 40)):
        mc = mesh_cycle(pair, PAPER_TORQUE, nx, ny)
        lines.append(f"| {nx} x {ny} | {mc.n_dof:,} | {mc.stiffness_mean / 1e6:.1f} | "
                     f"{mc.single_pair_max / 1e6:.1f} | {mc.transmission_error_pp * 1e6:.3f} |")
    lines.append("")

    # 5. web
    lines += ["## 5. A web", "",
              "The paper's pair on a hub of 15 mm radius, solid (web as wide as the face) or with "
              "a thin web from the hub to 33 mm; the extra compliance against the extra twist "
              "of the thinner annulus alone (both gears):", "",
              "| web width (mm) | k mean (N/um) | extra compliance (um/kN) | extra annulus twist (um/kN) | ratio |",
              "| --- | --- | --- | --- | --- |"]
    base = None
    for ww in (g.face_width, 3e-3, 1.5e-3, 0.6e-3):
        p = with_blank(pair, Blank(hub_radius=0.015, rim_radius=0.033, web_width=ww))
        k = mesh_cycle(p, PAPER_TORQUE, 4, 14).stiffness_mean
        if base is None:
            base = k
            lines.append(f"| {ww * 1e3:.2f} (solid) | {k / 1e6:.1f} | | | |")
            continue
        extra = 1 / k - 1 / base
        tw = 2 * (twist(g, 0.015, 0.033, ww) - twist(g, 0.015, 0.033, g.face_width))
        lines.append(f"| {ww * 1e3:.2f} | {k / 1e6:.1f} | {extra * 1e9:.2f} | {tw * 1e9:.2f} | {extra / tw:.3f} |")
    lines.append("")

    # 6. relief
    relieved = GearPair(nasa_like_relief(pair.gear_a, pair.gear_b), nasa_like_relief(pair.gear_b, pair.gear_a))
    lines += ["## 6. Tip relief", "",
              "The NASA-like relief (linear, 20 um at the tip, from the highest point of single "
              "contact; docs/relief.md) on both gears: the static transmission error's "
              "peak-to-peak over the cycle (um):", "",
              "| torque (N m) | F_t / b (N/mm) | unmodified | relieved |", "| --- | --- | --- | --- |"]
    for tq in (5.0, PAPER_TORQUE, 60.0, 100.0, 150.0):
        a = mesh_cycle(pair, tq, 4, 14).transmission_error_pp
        b = mesh_cycle(relieved, tq, 4, 14).transmission_error_pp
        lines.append(f"| {tq:g} | {tq / g.pitch_radius / g.face_width / 1e3:.0f} | {a * 1e6:.3f} | {b * 1e6:.3f} |")
    lines.append("")
    text = "\n".join(lines).replace("{seconds}", f"{time.time() - t0:.0f}")
    write_page(PAGE, text, echo=False)
    return 0
