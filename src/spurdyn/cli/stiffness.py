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
    p.add_argument("--fault", action="append", metavar="SPEC", help="a fault, the keys of a "
                   "[[fault]] table, e.g. gear=a,tooth=5,kind=missing or gear=a,tooth=5,kind=spall,"
                   "roll_deg=20:24,depth=2e-5,width_fraction=0.5; kinds missing, spall, crack, chip "
                   "(height=1e-3,width=5e-4) (repeatable; with the case's "
                   "faults the figures cover the faulty gear's revolution)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--png", metavar="FILE", help="draw the cycle (or the revolution) into this picture")
    p.add_argument("--csv", metavar="FILE", help="write k(theta) and the static TE by torque into "
                   "this table (CSV)")
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
    from spurdyn.case.fault_tables import parse_fault_option
    from spurdyn.cli.inputs import meshed_case
    from spurdyn.iso6336.rating import iso_pair, rate
    from spurdyn.lumped.sources import quasi_static_cycle
    from spurdyn.sector.statics import DEFAULT_POSITIONS, driving_pair, pairs_in_path

    if args.positions is None:
        args.positions = DEFAULT_POSITIONS
    if not 3 <= args.positions <= MAX_POSITIONS:
        raise InputError("--positions", f"must be a whole number from 3 to {MAX_POSITIONS} "
                         f"(got {args.positions})")
    case = meshed_case(args, faults=True)
    pair = case.pair
    faults = case.faults + tuple(parse_fault_option(text, pair) for text in (getattr(args, "fault", None) or ()))
    torques = _torques(args, pair)
    refuse_sector_row_grading(case.row_grading)   # a case file's [mesh] row_grading
    if args.teeth is not None and not pairs_in_path(driving_pair(pair)) <= args.teeth:
        raise InputError("--teeth", f"must be at least the {pairs_in_path(pair)} teeth that carry "
                         "load together")
    if faults:
        return _faulty_report(args, case, faults, torques)
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


def _faulty_report(args: argparse.Namespace, case: Any, faults: tuple[Any, ...],
                   torques: list[float]) -> dict[str, Any]:
    """The JSON object of a faulty pair: the revolution at each torque."""
    from spurdyn.cli.stiffness_faults import revolution_row
    from spurdyn.sector.faulty import faulty_revolution

    revs = [faulty_revolution(case.pair, tq, faults, case.nx, case.ny, teeth=args.teeth,
                              positions=args.positions, grading=case.grading) for tq in torques]
    rows = [revolution_row(r) for r in revs]
    return {"case": case.name, "model": "sector", "contact": "hertz", "mesh": [case.nx, case.ny],
            "faults": [{k: v for k, v in vars(f).items()} for f in faults],
            "mesh_stiffness_min_N_per_m": rows[0]["mesh_stiffness_min_N_per_m"],
            "mesh_stiffness_dip": rows[0]["mesh_stiffness_dip"],
            "torques": rows, "_cycles": revs}


def _print_faulty(report: dict[str, Any]) -> None:
    revs = report["_cycles"]
    print(f"{report['case']}: sector model with {len(report['faults'])} fault(s), "
          f"{revs[0].teeth} teeth per gear, over {len(set(revs[0].cycle.tolist()))} mesh cycles "
          f"(a revolution of gear {revs[0].gear}), {revs[0].angle.size} positions")
    for row in report["torques"]:
        lost = row["contact_lost_fraction"]
        print(f"  {row['torque_Nm']:g} N m: mesh stiffness min {row['mesh_stiffness_min_N_per_m'] / 1e6:.1f} "
              f"N/um against the healthy {row['mesh_stiffness_healthy_min_N_per_m'] / 1e6:.1f} "
              f"(dip {100 * row['mesh_stiffness_dip']:.1f} %), mean {row['mesh_stiffness_mean_N_per_m'] / 1e6:.1f}"
              + (f"; no pair carries over {100 * lost:.2f} % of the revolution" if lost > 0 else ""))


def cmd_stiffness(args: argparse.Namespace) -> int:
    png = csv_path = None
    if args.png:
        from spurdyn.cli.inputs import png_target

        png = png_target(args.png)
    if args.csv:
        from spurdyn.cli.inputs import output_target

        csv_path = output_target(args.csv, ".csv", "--csv")
    report = stiffness_report(args)
    cycles = report.pop("_cycles")
    if csv_path is not None:
        from spurdyn.cli.stiffness_faults import write_csv

        write_csv(csv_path, cycles)
    if "faults" in report:
        return _faulty_output(args, report, cycles, png, csv_path)
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
        for target in (png, csv_path):
            if target is not None:
                print(f"-> {target}")
    return 0


def _faulty_output(args: argparse.Namespace, report: dict[str, Any], revs: list[Any],
                   png: Any, csv_path: Any) -> int:
    if png is not None:
        from spurdyn.sector.plot import draw_revolution

        draw_revolution(revs, f"{report['case']}: sector model, faulty gear over its revolution", png)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        _print_faulty(report | {"_cycles": revs})
        for target in (png, csv_path):
            if target is not None:
                print(f"-> {target}")
    return 0


__all__ = ["add_stiffness_parser", "cmd_stiffness", "stiffness_report"]
