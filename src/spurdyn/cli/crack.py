"""``spurdyn crack CASE``: a root crack grown through a gear's tooth or its rim under the
tooth's worst load over a mesh cycle, until it breaks through; its life by Paris's law
where the constants are given (docs/fracture.md, sections 8 and 9).

Every input is checked before any work; the folder ``--out`` is written only when the
crack has been grown (into a hidden folder first, then moved into place).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from spurdyn.errors import InputError

__all__ = ["add_crack_parser", "cmd_crack", "rim_support"]

#: The first crack's length by default, as a share of the tooth's whole depth.
LENGTH_SHARE = 0.05
#: The increment by default, as a share of the tooth's whole depth.
INCREMENT_SHARE = 0.08
#: Columns of ``path.csv``.
CSV_COLUMNS = ("step", "length_m", "x_m", "y_m", "k_i_Pa_sqrt_m", "k_ii_Pa_sqrt_m",
               "k_eq_Pa_sqrt_m", "turn_deg", "load_roll_deg", "load_force_N", "cycles")


def add_crack_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("crack", help="grow a root crack through a gear's tooth or rim under "
                       "its worst mesh load: path, K, verdict (tooth or rim) and life")
    p.add_argument("case", metavar="CASE", help="'paper', a preset or a TOML file describing a pair")
    p.add_argument("--gear", default="a", metavar="a|b", help="the cracked gear (default a)")
    p.add_argument("--tooth", type=int, default=0, metavar="N",
                   help="the cracked tooth, 0 to z - 1 (default 0; its neighbours are healthy)")
    p.add_argument("--start", type=float, metavar="M", help="the mouth's radius on the drive "
                   "flank's fillet (m; default ISO 6336-3's 30 deg tangent point)")
    p.add_argument("--length", type=float, metavar="M", help="the first crack's length (m), "
                   f"straight along the fillet's normal (default {LENGTH_SHARE:g} of the whole depth)")
    p.add_argument("--increment", type=float, metavar="M", help="the growth increment (m; "
                   f"default {INCREMENT_SHARE:g} of the whole depth)")
    p.add_argument("--backup-ratio", type=float, metavar="MB", help="the cracked gear's rim "
                   "thickness below the root circle over the tooth's whole depth: on a webbed "
                   "blank the web's junction moves there, otherwise the hub is held there "
                   "(default the sector model's rim: the blank's, or 3 whole depths)")
    p.add_argument("--torque", type=float, metavar="NM", help="the driver's torque (default the case's)")
    p.add_argument("--mesh", metavar="NXxNY", help="elements across x along each tooth of the sectors")
    p.add_argument("--grading", type=float, metavar="G", help="grading of each tooth's columns")
    p.add_argument("--positions", type=int, default=7, metavar="N", help="load positions over "
                   "the cracked tooth's stretch of the mesh cycle (default 7, and the single "
                   "contact zone's ends)")
    p.add_argument("--max-increments", type=int, default=200, metavar="K",
                   help="stop undecided after K increments (default 200)")
    p.add_argument("--paris-c", type=float, metavar="C", help="Paris's C, m per cycle at "
                   "1 Pa sqrt(m) (or the case's [crack] paris_c)")
    p.add_argument("--paris-m", type=float, metavar="M", help="Paris's exponent (or [crack] paris_m)")
    p.add_argument("--threshold", type=float, metavar="DK", help="threshold range, Pa sqrt(m) "
                   "(or [crack] threshold; default 0)")
    p.add_argument("--out", required=True, metavar="DIR", help="folder to write")
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    p.set_defaults(func=cmd_crack)


def _positive(flag: str, value: float | None, what: str) -> float | None:
    if value is not None and (not math.isfinite(value) or not value > 0.0):
        raise InputError(flag, f"must be a positive {what} (got {value!r})")
    return value


def _paris(args: argparse.Namespace) -> Any:
    """Paris's law of the options over the case's ``[crack]`` table, ``None`` if neither
    gives a constant; a constant given without the other refused naming the missing one."""
    from spurdyn.case.crack_table import crack_constants
    from spurdyn.fracture.life import ParisLaw

    table: dict[str, float] = {}
    if args.case.endswith(".toml") or Path(args.case).is_file():
        from spurdyn.case.file import read_case_file

        table = crack_constants(read_case_file(args.case))
    given = {"--paris-c": args.paris_c, "--paris-m": args.paris_m, "--threshold": args.threshold}
    keys = {"--paris-c": "paris_c", "--paris-m": "paris_m", "--threshold": "threshold"}
    values = {f: (v if v is not None else table.get(keys[f])) for f, v in given.items()}
    for flag, v in values.items():
        if v is not None and (not math.isfinite(v) or v < 0.0 or (v == 0.0 and flag != "--threshold")):
            raise InputError(flag if given[flag] is not None else f"crack.{keys[flag]}",
                             f"must be {'a number >= 0' if flag == '--threshold' else 'a positive number'} "
                             f"(got {v!r})")
    if all(v is None for v in values.values()):
        return None
    for flag in ("--paris-c", "--paris-m"):
        if values[flag] is None:
            raise InputError(flag, "a crack's life needs both Paris constants: give "
                             f"{flag} (or the case's [crack] {keys[flag]})")
    return ParisLaw(values["--paris-c"], values["--paris-m"], values["--threshold"] or 0.0)


#: The files the command writes (a folder holding only these may be written over).
OWN_FILES = {"summary.json", "path.csv", "crack_path.png", "crack_growth.gif", "crack_growth.png"}


def _out_target(text: str) -> Path:
    out = Path(text)
    if out.exists() and not out.is_dir():
        raise InputError("--out", f"{text!r} is a file, not a folder")
    if out.is_dir() and any(p.name not in OWN_FILES for p in out.iterdir()):
        raise InputError("--out", f"folder {text!r} holds files this command did not write; "
                         "give a new folder")
    if not out.absolute().parent.exists():
        raise InputError("--out", f"folder {str(out.absolute().parent)!r} does not exist")
    return out


def crack_inputs(args: argparse.Namespace) -> dict[str, Any]:
    """Every input of the command, checked (one line naming the flag) before any work."""
    from spurdyn.cli.inputs import case_torque, meshed_case
    from spurdyn.sector.crack_tip import check_gear
    from spurdyn.settings import refuse_sector_row_grading
    from spurdyn.solvers.limits import check_torque

    out = _out_target(args.out)
    gear_name = check_gear(args.gear)
    case = meshed_case(args)
    refuse_sector_row_grading(case.row_grading)     # a case file's [mesh] row_grading
    pair = case.pair
    gear = pair.gear_a if gear_name == "a" else pair.gear_b
    if not 0 <= args.tooth < gear.teeth:
        raise InputError("--tooth", f"gear {gear_name} has teeth 0 to {gear.teeth - 1} (got {args.tooth})")
    depth = gear.tip_radius - gear.root_radius
    length = _positive("--length", args.length, "length in m") or LENGTH_SHARE * depth
    increment = _positive("--increment", args.increment, "length in m") or INCREMENT_SHARE * depth
    if increment > depth:
        raise InputError("--increment", f"must not exceed the tooth's whole depth "
                         f"{depth * 1e3:.4g} mm (got {increment * 1e3:.4g} mm)")
    if args.start is not None:
        _positive("--start", args.start, "radius in m")
    case, gear = _webbed_rim(args, case, gear, gear_name, depth)
    inner = _inner_radius(args, gear, gear_name, depth)
    _first_crack(case, gear, inner, length, args.start)    # --start and --length, before the work

    torque = args.torque if args.torque is not None else case_torque(args.case)
    if torque is None:
        raise InputError("--torque", "the case has no [run] torque: give the driver's torque (N m)")
    _positive("--torque" if args.torque is not None else "run.torque", torque, "torque in N m")
    check_torque(pair, torque, "--torque")
    if not 1 <= args.positions <= 200:
        raise InputError("--positions", f"must be a whole number from 1 to 200 (got {args.positions})")
    if not 1 <= args.max_increments <= 2000:
        raise InputError("--max-increments", f"must be a whole number from 1 to 2000 (got {args.max_increments})")
    return {"out": out, "gear": gear_name, "case": case, "torque": float(torque), "length": length,
            "inner_radius": inner, "backup_ratio": args.backup_ratio,
            "increment": increment, "paris": _paris(args)}


def _webbed_rim(args: argparse.Namespace, case: Any, gear: Any, gear_name: str,
                depth: float) -> tuple[Any, Any]:
    """``--backup-ratio`` on a webbed blank moves the web's junction (the rim's inner radius,
    the blank's ``rim_radius``) to ``MB`` whole depths below the root circle, the hub and the
    web's width kept: the case and the cracked gear so changed (unchanged otherwise)."""
    import dataclasses

    if args.backup_ratio is None or gear.blank is None or not gear.blank.webbed:
        return case, gear
    _positive("--backup-ratio", args.backup_ratio, "ratio")
    rim = gear.root_radius - args.backup_ratio * depth
    hub = gear.blank.hub_radius
    if not rim > hub:
        raise InputError("--backup-ratio", f"puts gear {gear_name}'s web junction at "
                         f"{rim * 1e3:.4g} mm, inside its hub ({hub * 1e3:.4g} mm): "
                         f"give a ratio below {(gear.root_radius - hub) / depth:.4g}")
    _thick_enough(rim, gear, gear_name, depth)
    new = dataclasses.replace(gear, blank=dataclasses.replace(gear.blank, rim_radius=rim),
                              disk_inertia=None)
    pair = dataclasses.replace(case.pair, **{f"gear_{gear_name}": new})
    return dataclasses.replace(case, pair=pair), new


def _inner_radius(args: argparse.Namespace, gear: Any, gear_name: str, depth: float) -> float | None:
    """The cracked gear's held inner radius of ``--backup-ratio`` (m), ``None`` without it or
    on a webbed blank (:func:`_webbed_rim` moved its rim)."""
    if args.backup_ratio is None or (gear.blank is not None and gear.blank.webbed):
        return None
    _positive("--backup-ratio", args.backup_ratio, "ratio")
    inner = gear.root_radius - args.backup_ratio * depth
    _thick_enough(inner, gear, gear_name, depth)
    if not inner > 0.05 * gear.root_radius:
        raise InputError("--backup-ratio", f"leaves no bore: the rim would reach "
                         f"{inner * 1e3:.4g} mm from the centre; give a smaller ratio")
    return inner


def _thick_enough(rim: float, gear: Any, gear_name: str, depth: float) -> None:
    """Refuse naming ``--backup-ratio`` a rim's inner radius ``rim`` (m) that leaves a rim
    thinner than the sector mesh takes (:data:`~spurdyn.mesh.sector.RIM_THICKNESS_MIN`)."""
    from spurdyn.mesh.sector import RIM_THICKNESS_MIN

    if not rim < gear.root_radius - RIM_THICKNESS_MIN:
        raise InputError("--backup-ratio", f"leaves gear {gear_name} a rim of "
                         f"{(gear.root_radius - rim) * 1e6:.3g} um below its root circle, thinner "
                         f"than the mesh takes: give a ratio above {RIM_THICKNESS_MIN / depth:.2g}")


def _first_crack(case: Any, gear: Any, inner: float | None, length: float, start: float | None) -> None:
    """Refuse ``--start`` off the fillet or ``--length`` leaving the cell, on the cracked
    tooth's cell alone (a fraction of a second; the sectors take seconds)."""
    from spurdyn.sector.body import body_cell
    from spurdyn.sector.crack_growth import first_crack

    cell = body_cell(gear, case.nx, case.ny, case.grading, inner)
    first_crack(gear, cell, case.nx, case.ny, case.grading, length, start)


def cmd_crack(args: argparse.Namespace) -> int:
    from spurdyn.sector.crack_growth import grow_crack
    from spurdyn.sector.crack_tip import cracked_sector

    spec = crack_inputs(args)
    case = spec["case"]
    sector = cracked_sector(case.pair, spec["torque"], spec["gear"], case.nx, case.ny,
                            case.grading, positions=args.positions, inner_radius=spec["inner_radius"])
    progress = None if args.json else _printer()
    grown = grow_crack(sector, spec["length"], spec["increment"], args.start,
                       args.max_increments, progress)
    summary = _summary(args, spec, sector, grown)
    _write(spec["out"], args, sector, grown, summary)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        g = summary["verdict"]
        print(f"verdict: breaks through the {g['breaks_through']} at {g['length_m'] * 1e3:.4g} mm"
              if g["breaks_through"] else f"undecided: {g['reason']}")
        if summary["life"] is not None:
            life = summary["life"]
            print(f"life: {life['cycles']:.4g} load cycles" if life["cycles"] is not None
                  else f"life: unbounded ({life['note']})")
        print(f"-> {spec['out']}")
    return 0


def _printer() -> Any:
    def show(step: Any) -> None:
        print(f"  {step.length * 1e3:7.3f} mm: K_I {step.state.k_i / 1e6:7.3f}, K_II "
              f"{step.state.k_ii / 1e6:7.3f}, K_eq {step.state.k_eq / 1e6:7.3f} MPa sqrt(m), "
              f"turn {math.degrees(step.turn):6.2f} deg", flush=True)
    return show


def _life(grown: Any, paris: Any) -> tuple[dict[str, Any] | None, np.ndarray]:
    """The life's summary and the cycles at each tip (NaN without constants)."""
    from spurdyn.fracture.life import paris_cycles

    steps = grown.growth.steps
    if paris is None:
        return None, np.full(len(steps), np.nan)
    length = np.array([s.length for s in steps])
    # R = 0: the tooth is unloaded between its passes, so the range is the worst K_eq
    life = paris_cycles(length, np.array([s.state.k_eq for s in steps]), paris)
    last = float(life.cycles[-1])
    out = {"paris_c": paris.c, "paris_m": paris.m, "threshold_Pa_sqrt_m": paris.threshold,
           "load_ratio": 0.0, "cycles_per_revolution": 1,
           "cycles": last if math.isfinite(last) else None,
           "to_length_m": float(length[-1]),
           "arrested_at_m": life.arrested_at}
    if not math.isfinite(last):
        out["note"] = f"the range falls to the threshold at {life.arrested_at * 1e3:.4g} mm: the crack stops"
    return out, life.cycles


def _summary(args: argparse.Namespace, spec: dict[str, Any], sector: Any, grown: Any) -> dict[str, Any]:
    g = grown.growth
    life, _ = _life(grown, spec["paris"])
    worst = max(g.steps, key=lambda s: s.state.k_eq)
    return {
        "case": spec["case"].name, "gear": spec["gear"], "tooth": args.tooth, "torque_Nm": spec["torque"],
        "mesh": [spec["case"].nx, spec["case"].ny], "teeth_per_gear": sector.teeth,
        "rim_inner_radius_m": _rim_inner(sector),
        "backup_ratio": (sector.gear.root_radius - _rim_inner(sector))
        / (sector.gear.tip_radius - sector.gear.root_radius),
        "rim_support": rim_support(sector.gear),
        "initial_length_m": spec["length"], "increment_m": spec["increment"],
        "tip_size_m": grown.tip_size, "increments": len(g.steps) - 1,
        "load_positions_deg": np.degrees(sector.rolls).tolist(),
        "mouth_m": g.path[0].tolist(),
        "verdict": {"breaks_through": g.verdict, "length_m": g.length,
                    "decided_at_m": g.steps[-1].length,
                    "exit_m": None if g.exit is None else g.exit.tolist(), "reason": g.reason},
        "k_eq_max_Pa_sqrt_m": worst.state.k_eq,
        "closed_faces_near_tip": int(sum(int(np.max(ld.closed_near_tip)) for ld in grown.loads)),
        "closed_faces": int(sum(int(np.max(ld.closed)) for ld in grown.loads)),
        "domain_spread_max": float(max(np.max(ld.spread) for ld in grown.loads)),
        "life": life,
    }


def rim_support(gear: Any) -> str:
    """How the cracked gear's rim is carried below ``backup_ratio``: ``"web"`` on a webbed
    blank (the rim bends on the web), ``"held"`` otherwise (clamped all round its inside)."""
    return "web" if gear.blank is not None and gear.blank.webbed else "held"


def _rim_inner(sector: Any) -> float:
    """The rim's inner radius (m): a web's junction, or the held hub."""
    from spurdyn.sector.crack_growth import sector_region

    return float(sector_region(sector).inner_radius)


def _write(out: Path, args: argparse.Namespace, sector: Any, grown: Any, summary: dict[str, Any]) -> None:
    """The folder's files, written into a hidden folder beside ``out`` and moved into place."""
    from spurdyn.mesh import outline as ol
    from spurdyn.sector.crack_plot import draw_growth, draw_path

    parent = out.absolute().parent
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=parent))
    try:
        _, cycles = _life(grown, _summary_paris(summary))
        _write_csv(tmp / "path.csv", grown, cycles)
        g = grown.growth
        title = f"{summary['case']}: gear {summary['gear']}, tooth {summary['tooth']}"
        body = grown.bodies[sector.g]
        draw_path(body, grown.displacement, sector.cell.nodes, g.path, title, tmp / "crack_path.png")
        outline = ol.polygon(sector.cell.nodes, ol.outline_edges(sector.cell))
        kind = draw_growth(sector.cell.nodes, outline, np.array([s.length for s in g.steps]), g.path,
                           np.array([s.state.k_eq for s in g.steps]), title, tmp / "crack_growth")
        summary["files"] = ["summary.json", "path.csv", "crack_path.png", f"crack_growth.{kind}"]
        (tmp / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
        if out.exists():
            shutil.rmtree(out)
        tmp.rename(out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def _summary_paris(summary: dict[str, Any]) -> Any:
    from spurdyn.fracture.life import ParisLaw

    life = summary["life"]
    return None if life is None else ParisLaw(life["paris_c"], life["paris_m"], life["threshold_Pa_sqrt_m"])


def _write_csv(path: Path, grown: Any, cycles: np.ndarray) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for i, (step, load) in enumerate(zip(grown.growth.steps, grown.loads)):
            k = load.worst
            turn = "" if not math.isfinite(step.turn) else f"{math.degrees(step.turn):.9g}"
            n = "" if not math.isfinite(cycles[i]) else f"{cycles[i]:.9g}"
            w.writerow([i, f"{step.length:.9g}", f"{step.tip[0]:.9g}", f"{step.tip[1]:.9g}",
                        f"{step.state.k_i:.9g}", f"{step.state.k_ii:.9g}", f"{step.state.k_eq:.9g}",
                        turn, f"{math.degrees(step.state.position):.9g}", f"{load.force[k]:.9g}", n])
