"""Measure the distributed (Hertzian) contact beside the paper's point contact.

    .venv/bin/python docs/validation contact_validation [--only PART ...]

Parts: ``stiffness`` (pitch-point pair stiffness against the mesh, even and graded across
and along the tooth), ``presets`` (every preset with both contacts), ``meshes`` (Fig. 8, 9,
10 on finer meshes at their stable steps), ``design`` (pairs at design loads against the lumped model with the same
stiffness), ``energy`` (the energy balance of Fig. 8 under load), ``hertz`` (a
quasi-static run's strip at the pitch point against Hertz). Each part's figures are kept
in ``docs/contact_validation.json``; the page ``docs/contact_validation.md`` is rendered
from all of them, so a part can be re-measured alone.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from spurdyn.case import resolve_cases
from spurdyn.contact.hertz import half_width, peak_pressure, strip_compliance
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.model.system import build_system, system_for
from spurdyn.results.headline import averaged_peak
from spurdyn.simulators import MODELS
from spurdyn.solvers.check import stable_step
from spurdyn.solvers.paper.dynamics_numpy import strip_law
from spurdyn.solvers.paper.statics import static_stiffness
from validation.common import DOCS, ROOT, load_figures, save_figures, timed, write_page
from validation.contact_page import render

STORE = DOCS / "contact_validation.json"
PAGE = DOCS / "contact_validation.md"
#: The meshes of the stiffness study, and of the dynamic runs on finer meshes.
STIFFNESS_MESHES = ((4, 14), (6, 20), (8, 28), (12, 40), (16, 56), (24, 80), (32, 112))
RUN_MESHES = ((6, 20), (8, 28), (12, 40))
#: The grading across the tooth of the graded column of the stiffness study.
GRADING = 6.0
#: The gradings of the series that shows how far grading alone brings 12 x 40 to 16 x 56.
GRADING_SERIES = (1.0, 3.0, 6.0, 12.0, 20.0, 35.0, 50.0)
#: The row grading of the stiffness study's rows-graded columns (with ``GRADING`` across;
#: ``mesh.row_grading``, docs/geometry.md 6.3), and the series of it on 12 x 40 and 16 x 56.
ROW_GRADING = 4.0
ROW_GRADING_SERIES = (1.0, 2.0, 3.0, 4.0, 6.0, 1000.0)
#: Contact positions spread evenly over the one flank row centred on the pitch point, over
#: which the row mean of the stiffness is taken (it takes out where the strip sits in its
#: element).
ROW_POSITIONS = 8
#: Fraction of each mesh's stable step the finer-mesh runs take (as validation.md 2.1).
STEP_FRACTION = 0.9


def _run(spec: str, **over: Any) -> dict[str, Any]:
    """One FE (or lumped) run through the case reader; its headline figures."""
    model = over.pop("model", "fe")
    overrides = {f"run.{k}" if k not in ("mesh.nx", "mesh.ny") else k: v for k, v in over.items()}
    case = resolve_cases(spec, overrides)[0]
    res, wall = timed(MODELS[model], case.pair, case.run)
    f = np.asarray(res.contact_force, float)
    static = float(res.info["static_force"])
    out = {"status": res.status, "reason": res.reason, "steps": int(res.steps), "wall_s": wall,
           "angle_deg": float(np.degrees(res.angle[-1])) if len(res.angle) else 0.0,
           "peak_raw_N": float(np.nanmax(f)) if f.size else float("nan"),
           "peak_avg_N": (averaged_peak(res.time, f) or (float("nan"),))[0], "static_N": static,
           "dt_s": case.run.dt, "contact": case.run.contact}
    if res.contact_pressure_max is not None:
        out["pressure_max_Pa"] = float(np.nanmax(res.contact_pressure_max))
        out["half_width_max_m"] = float(np.nanmax(res.contact_half_width))
    if out["static_N"] > 0:
        out["spikes"] = int(np.sum(f > 3.0 * static))
    return out


def _surface_column_um(system: Any) -> float:
    """Width (µm) of A's outline column at the pitch point: the element under the strip."""
    mesh = system.gears[0].mesh
    pair = system.pair
    side = mesh.right_side[::2]                       # corner nodes of the outline
    r_p = pair.gear_a.base_radius / math.cos(pair.gear_a.pressure_angle)
    corner = side[int(np.argmin(abs(np.hypot(*mesh.nodes[side].T) - r_p)))]
    # the element whose second corner is that node has its first corner inward, same row
    elem = mesh.elements[np.flatnonzero(mesh.elements[:, 1] == corner)[0]]
    return float(np.hypot(*(mesh.nodes[elem[1]] - mesh.nodes[elem[0]])) * 1e6)


def _flank_edge_um(system: Any) -> float:
    """Arc (µm) of one element edge along A's flank at the pitch point (the flank rows' law)."""
    f, pair = system.gears[0].flank, system.pair
    r_p = pair.gear_a.base_radius / math.cos(pair.gear_a.pressure_angle)
    return (f.r_tip - f.r0) / f.ny * r_p / f.base_radius * 1e6


def _row_mean(system: Any, force: float) -> float:
    """The strip's pitch-point stiffness averaged over :data:`ROW_POSITIONS` contact positions
    spread evenly over the one flank row (of A) centred on the pitch point."""
    f, gear = system.gears[0].flank, system.pair.gear_a
    slope = (f.r_tip - f.r0) / f.ny
    t_p = (gear.base_radius / math.cos(gear.pressure_angle) - f.r0) / slope
    k = []
    for i in range(ROW_POSITIONS):
        r = f.r0 + slope * (t_p - 0.5 + (i + 0.5) / ROW_POSITIONS)
        roll = math.sqrt(r * r - gear.base_radius ** 2) / gear.base_radius
        k.append(static_stiffness(system, roll, force, "hertz").stiffness)
    return float(np.mean(k))


def part_stiffness() -> dict[str, Any]:
    pair = paper_pair()
    force = PAPER_TORQUE / pair.gear_a.base_radius
    rows = []
    for nx, ny in STIFFNESS_MESHES:
        row: dict[str, Any] = {"mesh": f"{nx} x {ny}"}
        for tag, grading, row_grading in (("", 1.0, 1.0), ("_graded", GRADING, 1.0),
                                          ("_rows", GRADING, ROW_GRADING)):
            s = system_for(pair, nx, ny, 61, grading, row_grading)
            hz = static_stiffness(s, pair.pitch_roll_a, force, "hertz")
            if tag == "_rows":   # rows graded along the tooth as well as columns across
                row.update(hertz_rows=hz.stiffness, h_um_rows=_flank_edge_um(s),
                           stable_dt_rows=stable_step(s),
                           fillet_rows=s.gears[0].mesh.fillet_rows)
                continue
            row["hertz" + tag] = hz.stiffness
            row["strip_only" + tag] = 1.0 / (hz.compliance_a + hz.compliance_b)
            row["t_um" + tag] = _surface_column_um(s)
            row["stable_dt" + tag] = stable_step(s)
            if not tag:
                row["point"] = static_stiffness(s, pair.pitch_roll_a, force, "point").stiffness
                row["h_um"] = _flank_edge_um(s)  # one edge's arc
                row["b_um"] = hz.half_width * 1e6
        rows.append(row)
        print(f"  stiffness {row['mesh']}: hertz {row['hertz']:.4e}, graded {row['hertz_graded']:.4e}, "
              f"rows graded {row['hertz_rows']:.4e}", flush=True)
    # how far grading alone goes: 12 x 40 against 16 x 56 as the outline columns thin
    series = []
    for grading in GRADING_SERIES:
        k = [static_stiffness(system_for(pair, nx, ny, 61, grading), pair.pitch_roll_a, force,
                              "hertz").stiffness for nx, ny in ((12, 40), (16, 56))]
        series.append({"grading": grading, "12 x 40": k[0], "16 x 56": k[1],
                       "stable_dt_12x40": stable_step(system_for(pair, 12, 40, 61, grading))})
    # rows graded along the tooth (columns graded GRADING): 12 x 40 against 16 x 56 at the
    # pitch point and averaged over one element row about it
    row_series = []
    for row_grading in ROW_GRADING_SERIES:
        entry: dict[str, Any] = {"row_grading": row_grading}
        for nx, ny in ((12, 40), (16, 56)):
            s = system_for(pair, nx, ny, 61, GRADING, row_grading)
            entry[f"{nx} x {ny}"] = static_stiffness(s, pair.pitch_roll_a, force, "hertz").stiffness
            entry[f"{nx} x {ny} row mean"] = _row_mean(s, force)
            entry[f"fillet_rows {nx} x {ny}"] = s.gears[0].mesh.fillet_rows
        row_series.append(entry)
        print(f"  row grading {row_grading:g}: {entry['12 x 40']:.4e} / {entry['16 x 56']:.4e}",
              flush=True)
    from spurdyn.lumped.model import torsional_natural_frequency
    freq = {c: float(torsional_natural_frequency(pair, rows[0][c])) for c in ("point", "hertz")}
    return {"force_N": force, "c_h": strip_compliance(*strip_law(system_for(pair, 4, 14, 61))),
            "grading": GRADING, "row_grading": ROW_GRADING, "row_positions": ROW_POSITIONS,
            "rows": rows, "grading_series": series, "row_grading_series": row_series,
            "frequency_4x14_Hz": freq}


def part_presets() -> dict[str, Any]:
    from spurdyn.case import PRESETS
    return {name: {c: _run(name, contact=c) for c in ("point", "hertz")} for name in PRESETS}


def part_meshes() -> dict[str, Any]:
    out = {}
    pair = paper_pair()
    for nx, ny in RUN_MESHES:
        dt = STEP_FRACTION * stable_step(system_for(pair, nx, ny, 61))
        for name in ("paper-fig8", "paper-fig9", "paper-fig10"):
            key = f"{name} {nx} x {ny}"
            out[key] = {c: _run(name, contact=c, dt=float(f"{dt:.3g}"), **{"mesh.nx": nx, "mesh.ny": ny})
                        for c in ("point", "hertz")}
            print(key, {c: (v["status"], round(v["peak_avg_N"], 1)) for c, v in out[key].items()},
                  flush=True)
    return out


#: Pairs at design loads: (TOML file, torque N m on the driver, speed of A rpm).
DESIGN = (
    ("examples/pinion_23_47.toml", 50.0, 3000.0),
    ("examples/pinion_23_47.toml", 100.0, 3000.0),
    ("examples/pinion_23_47.toml", 100.0, 10000.0),
    ("docs/contact_pairs/m3_20deg.toml", 150.0, 1000.0),
    ("docs/contact_pairs/m3_20deg.toml", 500.0, 6000.0),
    ("docs/contact_pairs/m5_20deg.toml", 125.0, 1500.0),
    ("docs/contact_pairs/m5_20deg.toml", 1200.0, 1500.0),
    ("docs/contact_pairs/m5_25deg.toml", 800.0, 2000.0),
)


def part_design() -> dict[str, Any]:
    out = {}
    for path, torque, rpm in DESIGN:
        case = resolve_cases(str(ROOT / path), {"run.torque": torque, "run.speed_a_rpm": rpm})[0]
        g = case.pair.gear_a
        face = min(case.pair.gear_a.face_width, case.pair.gear_b.face_width)
        key = f"{Path(path).stem} {torque:g} N m {rpm:g} rpm"
        over = {"torque": torque, "speed_a_rpm": rpm}
        fe = _run(str(ROOT / path), **over)
        lumped = _run(str(ROOT / path), model="lumped", **over)
        out[key] = {"module_mm": g.module * 1e3, "pressure_angle_deg": math.degrees(g.pressure_angle),
                    "teeth": [case.pair.gear_a.teeth, case.pair.gear_b.teeth],
                    "load_N_per_mm": fe["static_N"] / (face * 1e3), "fe": fe, "lumped": lumped}
        print(key, fe["status"], round(fe["peak_avg_N"] / fe["static_N"], 3),
              round(lumped["peak_avg_N"] / lumped["static_N"], 3), flush=True)
    return out


def part_energy() -> dict[str, Any]:
    from spurdyn.results.balances import track
    from spurdyn.solvers.loop import make_stepper

    out = {}
    case = resolve_cases("paper-fig8")[0]
    # the strip at half the step too: what is left is first order in the step
    for key, contact, dt in (("point", "point", case.run.dt), ("hertz", "hertz", case.run.dt),
                             ("hertz, half the step", "hertz", 0.5 * case.run.dt),
                             ("hertz, a quarter of the step", "hertz", 0.25 * case.run.dt)):
        run = case.run.with_(contact=contact, dt=dt)
        system = build_system(case.pair, run)
        rec = track(make_stepper(system, run), angle=case.pair.theta_s)
        err = rec.energy_error
        # the same pair spinning free (no torque): validation.md 3.2 takes its drift off,
        # the work of the root constraints' directions held over a step (the paper's method)
        free_run = run.with_(torque=0.0)
        free = track(make_stepper(build_system(case.pair, free_run), free_run), angle=case.pair.theta_s)
        n = min(err.size, free.energy_error.size)
        less = err[:n] - free.energy_error[:n]
        # the contact work is that of G^T p: on the nodes and, for the strip, on the disks
        # (its pair's roll, docs/solver.md 11.3); the strip's curvature compliance stores
        # c_H p^2 / 2 of it
        out[key] = {"energy_error_end_J": float(err[-1]), "energy_error_max_J": float(np.abs(err).max()),
                    "strain_max_J": float(rec.strain.max()), "dt_s": float(dt),
                    "contact_work_end_J": float(rec.contact_work[-1]),
                    "less_free_max_J": float(np.abs(less).max()), "less_free_end_J": float(less[-1]),
                    "free_end_J": float(free.energy_error[n - 1]),
                    "momentum_error_max": float(np.abs(rec.momentum_error).max()),
                    "status": int(rec.status)}
        print(key, out[key], flush=True)
    return out


def part_hertz() -> dict[str, Any]:
    """A slow run (1,000 rpm, the paper's torque) through the single-contact zone: the
    mean force there and the strip it gives at the pitch point against Hertz's for
    tau_0 / r_b (the torsional mode the ramps excite rides on the force; its mean over
    the zone is the quasi-static figure, validation.md section 3.1)."""
    pair = paper_pair()
    z0, z1 = pair.single_contact_roll_a
    angle = math.degrees(z1 - pair.start_roll_a) + 0.1
    case = resolve_cases("paper-fig8", {"run.speed_a_rpm": 1000.0, "run.speed_b_rpm": 1000.0,
                                       "run.contact": "hertz", "run.angle_deg": angle})[0]
    res = MODELS["fe"](case.pair, case.run)
    roll = res.roll[:, 0]
    zone = (roll >= z0) & (roll <= z1)
    mean = float(np.mean(res.contact_force[zone]))
    estar, face = strip_law(system_for(pair, 4, 14, 61))
    rho = pair.gear_a.base_radius * math.tan(pair.gear_a.pressure_angle)
    force = PAPER_TORQUE / pair.gear_a.base_radius
    b = half_width(force, rho, rho, estar, face)
    b_run = half_width(mean, rho, rho, estar, face)
    return {"status": res.status, "force_N": mean, "static_N": force,
            "force_min_N": float(res.contact_force[zone].min()),
            "force_max_N": float(res.contact_force[zone].max()),
            "half_width_m": b_run, "hertz_half_width_m": b,
            "pressure_Pa": peak_pressure(mean, b_run, face),
            "hertz_pressure_Pa": peak_pressure(force, b, face),
            "width_max_m": float(res.contact_half_width[zone].max())}


PARTS: dict[str, Callable[[], dict[str, Any]]] = {
    "stiffness": part_stiffness, "hertz": part_hertz, "energy": part_energy,
    "presets": part_presets, "meshes": part_meshes, "design": part_design,
}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: measure the parts asked for, then render the page from all of them."""
    parser = argparse.ArgumentParser(prog="docs/validation contact_validation",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", action="append", choices=sorted(PARTS), default=[])
    parser.add_argument("--skip", action="append", choices=sorted(PARTS), default=[])
    parser.add_argument("--render", action="store_true", help="only render the page")
    args = parser.parse_args(argv)
    store = load_figures(STORE)
    if not args.render:
        for name in [p for p in (args.only or list(PARTS)) if p not in args.skip]:
            t0 = time.perf_counter()
            store[name] = PARTS[name]()
            store[name]["_seconds"] = time.perf_counter() - t0
            save_figures(STORE, store)
            print(f"{name}: {time.perf_counter() - t0:.0f} s", flush=True)
    write_page(PAGE, render(store), echo=False)
    return 0
