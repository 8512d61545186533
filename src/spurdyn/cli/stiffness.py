"""``spurdyn stiffness CASE``: the sector model's quasi-static mesh cycle (issue 15).

The loaded static transmission error, the mesh stiffness ``k(theta)``, the single-pair
stiffness and the load share over one mesh cycle at one or several torques, beside
ISO 6336-1's ``c' b`` and ``c_gamma_alpha b``; ``--json`` prints them as one object,
``--png`` draws them.
"""

from __future__ import annotations

import argparse
import json
import math

from typing import Any

import numpy as np

from spurdyn.errors import InputError
from spurdyn.settings import refuse_sector_row_grading

#: Most positions of a mesh cycle.
MAX_POSITIONS = 2001


def add_stiffness_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("stiffness", help="quasi-static mesh cycle of the sector model: mesh "
                       "stiffness, static transmission error and load share")
    p.add_argument("case", metavar="CASE", help="'paper', a preset or a TOML file describing a pair")
    p.add_argument("--torque", metavar="NM[,NM...]",
                   help="the driver's torque(s) (default: the case's)")
    p.add_argument("--teeth", type=int, metavar="K",
                   help="teeth per gear (default: those that carry load and a neighbour each side)")
    p.add_argument("--positions", type=int, default=41, metavar="N",
                   help="positions over one mesh cycle (default 41)")
    p.add_argument("--mesh", metavar="NXxNY", help="elements across x along each tooth")
    p.add_argument("--grading", type=float, metavar="G", help="grading of each tooth's columns "
                   "toward its outlines (default 1: even)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--png", metavar="FILE", help="draw the cycle into this picture")
    p.set_defaults(func=cmd_stiffness)


def _torques(args: argparse.Namespace, pair: Any) -> list[float]:
    """The driver's torques of the command: ``--torque``'s, else the case's (read as ``run``
    reads it), each refused beyond the elastic tooth as ``run`` refuses it."""
    from spurdyn.cli.inputs import case_torque
    from spurdyn.solvers.limits import check_torque

    field = "--torque"
    if args.torque is not None:
        try:
            values = [float(v) for v in str(args.torque).split(",")]
        except ValueError:
            raise InputError("--torque", f"must be torques in N m separated by commas (got "
                             f"{args.torque!r})") from None
    else:
        t = case_torque(args.case)
        if t is None:
            raise InputError("--torque", "the case has no [run] torque: give the driver's "
                             "torque (N m) with --torque")
        values, field = [t], "run.torque"
    for v in values:
        if not math.isfinite(v) or v <= 0:
            raise InputError(field, f"must be positive torques in N m (got {v!r})")
        check_torque(pair, v, field)
    return values


def stiffness_report(args: argparse.Namespace) -> dict[str, Any]:
    """Compute the mesh cycle(s) of the command's case; the JSON object it prints."""
    from spurdyn.cli.inputs import meshed_case
    from spurdyn.iso6336.rating import iso_pair, rate
    from spurdyn.lumped.sources import quasi_static_cycle
    from spurdyn.sector.statics import DEFAULT_POSITIONS, driving_pair, pairs_in_path

    if args.positions is None:
        args.positions = DEFAULT_POSITIONS
    if not 3 <= args.positions <= MAX_POSITIONS:
        raise InputError("--positions", f"must be a whole number from 3 to {MAX_POSITIONS} "
                         f"(got {args.positions})")
    case = meshed_case(args)
    pair = case.pair
    torques = _torques(args, pair)
    refuse_sector_row_grading(case.row_grading)   # a case file's [mesh] row_grading
    if args.teeth is not None and not pairs_in_path(driving_pair(pair)) <= args.teeth:
        raise InputError("--teeth", f"must be at least the {pairs_in_path(pair)} teeth that carry "
                         "load together")
    cycles, rows = [], []
    for tq in torques:
        mc = quasi_static_cycle(pair, tq, case.nx, case.ny, args.teeth, case.grading,
                                args.positions)          # shared within a process (a report)
        cycles.append(mc)
        iso: dict[str, Any] = {}
        try:
            r = rate(iso_pair(pair), tq)
        except ValueError as err:
            iso = {"iso6336_note": f"ISO 6336-1's stiffness does not apply: {err}"}
        else:
            b = min(pair.gear_a.face_width, pair.gear_b.face_width)
            iso = {"iso6336_single_pair_N_per_m": r.single_pair * b,
                   "iso6336_mesh_N_per_m": r.mesh * b}
        rows.append(mc.summary() | iso | {
            "roll_deg": np.degrees(mc.roll).tolist(),
            "mesh_stiffness_N_per_m": mc.stiffness.tolist(),
            "transmission_error_m": mc.transmission_error.tolist(),
            "pair_force_N": mc.force.tolist(),
            "single_pair_stiffness_N_per_m": [[None if v != v else v for v in row] for row in mc.single_pair.tolist()],
        })
    first = rows[0]
    out = {"case": case.name, "model": "sector", "contact": "hertz", "mesh": [case.nx, case.ny],
           "mesh_stiffness_mean_N_per_m": first["mesh_stiffness_mean_N_per_m"],
           "single_pair_stiffness_max_N_per_m": first["single_pair_stiffness_max_N_per_m"],
           "transmission_error_pp_m": first["transmission_error_pp_m"],
           "torques": rows}
    out["_cycles"] = cycles
    return out


def cmd_stiffness(args: argparse.Namespace) -> int:
    png = None
    if args.png:
        from spurdyn.cli.inputs import png_target

        png = png_target(args.png)
    report = stiffness_report(args)
    cycles = report.pop("_cycles")
    if png is not None:
        from spurdyn.sector.plot import draw_mesh_cycle

        iso = [(row["iso6336_single_pair_N_per_m"], row["iso6336_mesh_N_per_m"])
               if "iso6336_mesh_N_per_m" in row else None for row in report["torques"]]
        draw_mesh_cycle(cycles, f"{report['case']}: sector model, quasi-static mesh cycle", png, iso)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        print(f"{report['case']}: sector model ({cycles[0].teeth} teeth per gear on their rims, "
              f"hubs at {cycles[0].inner_radius[0] * 1e3:.4g} / {cycles[0].inner_radius[1] * 1e3:.4g} mm, "
              f"{cycles[0].n_dof:,} DOFs), Hertzian strips, {cycles[0].roll.size} positions")
        for row in report["torques"]:
            iso = (f"; ISO 6336-1: c'b {row['iso6336_single_pair_N_per_m'] / 1e6:.1f}, "
                   f"c_ga b {row['iso6336_mesh_N_per_m'] / 1e6:.1f} N/um"
                   if "iso6336_mesh_N_per_m" in row else "")
            print(f"  {row['torque_Nm']:g} N m: mesh stiffness mean {row['mesh_stiffness_mean_N_per_m'] / 1e6:.1f} "
                  f"N/um (min {row['mesh_stiffness_min_N_per_m'] / 1e6:.1f}, max "
                  f"{row['mesh_stiffness_max_N_per_m'] / 1e6:.1f}), single pair max "
                  f"{row['single_pair_stiffness_max_N_per_m'] / 1e6:.1f} N/um{iso}; static TE "
                  f"mean {row['transmission_error_mean_m'] * 1e6:.3f} um, peak-to-peak "
                  f"{row['transmission_error_pp_m'] * 1e6:.3f} um")
        if png is not None:
            print(f"-> {png}")
    return 0


__all__ = ["add_stiffness_parser", "cmd_stiffness", "stiffness_report"]
