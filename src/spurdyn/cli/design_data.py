"""The numbers of ``spurdyn report``: gathered from the results they come from.

Every figure is taken as it is from its source, never recomputed: a speed point's from
its run folder's ``summary.json`` (the sweep store's ``DIR/sweep/runs/``), the geometry
from :func:`spurdyn.cli.report.pair_info` (``spurdyn info``), the quasi-static mesh cycle
from :func:`spurdyn.cli.stiffness.stiffness_report` (``spurdyn stiffness``), the
resonance speeds from :func:`spurdyn.sweep.resonance.resonance_estimate` (``spurdyn
sweep``). A figure a source does not give is absent (``None``), never zero.
"""

from __future__ import annotations

import argparse
import json
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from spurdyn.version import __version__

#: Figures of a speed point copied from its ``summary.json`` (docs/summary.md).
POINT_KEYS = ("dynamic_factor", "settled", "cycles_done", "separations",
              "transmission_error_rms_m", "transmission_error_pp_m", "root_stress_max_Pa",
              "contact_pressure_max_Pa", "safety_root_model", "safety_root_iso",
              "safety_contact_model", "safety_contact_iso", "iso6336_k_v", "peak_force_N",
              "static_force_N", "n_dof", "wall_s")

#: Orders ``k`` of the super-harmonic resonances marked: the speeds whose mesh frequency's
#: k-th harmonic is the main resonance's ``f_n`` (``n_res / k``; docs/report.md).
SUPERHARMONIC_ORDERS = (2, 3, 4)

#: A resonance this close outside the speed range (fraction of its ends) is "near" it.
NEAR = 0.25

#: What every model of spurdyn leaves out (docs/report.md, part 7).
LIMITS = (
    "Spur gears only: a plane model of one transverse section, the face width a thickness "
    "(plane stress); no helix, no lead crowning, no misalignment (K_beta = 1).",
    "No friction on the flanks; no lubricant film (the contact is dry, elastic, Hertzian).",
    "Perfect involutes unless the case gives profile relief; no pitch or profile errors, so "
    "the transmission error is the elastic one under load.",
    "Shafts, bearings and housings are rigid beyond the gears' hubs; the drive and the load "
    "are constant torques.",
    "Root stress from the plane finite-element model at the fillets; ISO 6336's nominal "
    "stresses (method B) beside it for comparison, not a substitute.",
)

#: The validation pages a reader should know of (docs/).
VALIDATION_PAGES = ("validation.md", "sector_validation.md", "sector_dynamics_validation.md",
                    "stress_validation.md", "contact_validation.md", "iso6336.md",
                    "engineer_defaults.md")


def _clean(value: Any) -> Any:
    """JSON-ready: NaN and infinities become ``None``, NumPy scalars Python numbers."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def point_rows(plan: Any, sweep: Any) -> list[dict[str, Any]]:
    """One row per speed point (speed-major): status and reason from the sweep, every
    figure of :data:`POINT_KEYS` from the point's ``summary.json`` (absent: ``None``)."""
    from spurdyn.sweep.store import run_path

    status, reason = _statuses(plan, sweep)
    rows = []
    for key in plan.keys():
        i, j = plan.rpms.index(key.rpm), plan.torque_values.index(key.torque)
        folder = run_path(plan.out, key)
        summary: dict[str, Any] = {}
        if (folder / "summary.json").is_file():
            summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
        row = {"rpm": key.rpm, "torque_Nm": key.torque, "status": status[i, j],
               "reason": str(reason[i, j] or ""),
               "summary": str(folder.relative_to(plan.out.parent) / "summary.json")
               if summary else None}
        row |= {k: summary.get(k) for k in POINT_KEYS}
        row["_rating_iso"] = summary.get("rating_iso")
        row["_sources"] = {k: summary.get(k) for k in ("mesh_damping", "body_damping")}
        rows.append(row)
    return rows


#: Figures of a point of the lumped model beside: report key -> key of its point record
#: (``DIR/sweep/points/<point>.json``, docs/sweep.md).
BESIDE_KEYS = {"dynamic_factor": "dynamic_factor", "settled": "settled",
               "cycles_done": "cycles_done", "separations": "separations",
               "transmission_error_rms_m": "transmission_error_rms",
               "transmission_error_pp_m": "transmission_error_pp", "wall_s": "wall_s"}


def _statuses(plan: Any, sweep: Any) -> tuple[Any, Any]:
    """The points' status names and reasons from the sweep's data set (speed x torque)."""
    from spurdyn.sweep.store import STATUS_CODES

    names = {code: name for name, code in STATUS_CODES.items()}
    shape = (len(plan.rpms), len(plan.torque_values))
    status = np.asarray(sweep.dataset["status"].values).reshape(shape)
    reason = np.asarray(sweep.dataset["reason"].values, dtype=object).reshape(shape)
    return np.vectorize(lambda c: names[int(c)], otypes=[object])(status), reason


def beside(plan: Any, sweep: Any, why_not: str | None) -> dict[str, Any]:
    """The lumped model's points beside the sector model's: per point its status and
    reason (the sweep's), the figures of :data:`BESIDE_KEYS` from its point record
    unchanged (``settled`` as a yes or no), and that record's path in ``DIR``; or why
    there are none."""
    from spurdyn.sweep.store import read_point, point_path

    if plan is None or sweep is None:
        return {"absent": why_not or "the lumped model's sweep did not run"}
    status, reason = _statuses(plan, sweep)
    rows = []
    for key in plan.keys():
        i, j = plan.rpms.index(key.rpm), plan.torque_values.index(key.torque)
        record = read_point(plan.out, key) or {}
        row = {"rpm": key.rpm, "torque_Nm": key.torque, "status": status[i, j],
               "reason": str(reason[i, j] or ""),
               "record": str(point_path(plan.out, key).relative_to(plan.out.parent))
               if record else None}
        row |= {k: record.get(src) for k, src in BESIDE_KEYS.items()}
        if row["settled"] is not None:
            row["settled"] = bool(row["settled"])
        rows.append(row)
    run = plan.case.run
    return {"model": plan.model, "settings": {
        "stiffness": run.stiffness, "damping_ratio": run.damping_ratio, "cycles": run.cycles,
        "max_cycles": run.cycles_limit, "mesh": f"{run.nx}x{run.ny}"}, "points": rows}


def _extreme(rows: list[dict[str, Any]], key: str, gear: int | None, largest: bool
             ) -> dict[str, Any] | None:
    """The largest (or smallest) figure ``key`` (of gear ``gear``) over the rows, and where."""
    best = None
    for row in rows:
        v = row.get(key)
        if v is not None and gear is not None:
            v = v[gear]
        if v is None or not math.isfinite(v):
            continue
        if best is None or (v > best["value"] if largest else v < best["value"]):
            best = {"value": v, "rpm": row["rpm"], "torque_Nm": row["torque_Nm"]}
    return best


def _resonance_place(rpm: float | None, lo: float, hi: float) -> str | None:
    if rpm is None:
        return None
    if lo <= rpm <= hi:
        return "in the range"
    if lo * (1 - NEAR) <= rpm <= hi * (1 + NEAR):
        return "near the range"
    return "above the range" if rpm > hi else "below the range"


def verdict(rows: list[dict[str, Any]], resonance: Any, rpms: tuple[float, ...],
            ring: dict[str, Any] | None = None) -> dict[str, Any]:
    """The figures an engineer decides on, and the warnings in words; the super-harmonic
    resonance speeds from the ``ring`` measured on a run (:func:`ring_of`), else from the
    estimate's ``n_res``."""
    out: dict[str, Any] = {"dynamic_factor_max": _extreme(rows, "dynamic_factor", None, True)}
    for key in ("safety_root_model", "safety_root_iso", "safety_contact_model",
                "safety_contact_iso"):
        out[f"{key}_min"] = {g: _extreme(rows, key, i, False) for i, g in enumerate("AB")}
    lo, hi = min(rpms), max(rpms)
    res = {"model_rpm": resonance.resonance_rpm, "model_natural_frequency_hz":
           resonance.natural_frequency_hz, "iso_rpm": resonance.iso_resonance_rpm}
    res["ring"] = ring
    base = ring["resonance_rpm"] if ring is not None else resonance.resonance_rpm
    res["superharmonic_rpm"] = {str(k): base / k for k in SUPERHARMONIC_ORDERS}
    res["model_place"] = _resonance_place(res["model_rpm"], lo, hi)
    res["iso_place"] = _resonance_place(res["iso_rpm"], lo, hi)
    out["resonance"] = res
    warnings = []
    for row in rows:
        if row["status"] != "complete":
            warnings.append(f"{row['rpm']:g} rpm, {row['torque_Nm']:g} N m: "
                            f"{row['status'].replace('_', ' ')}"
                            + (f" ({row['reason']})" if row["reason"] else ""))
    warnings += _grouped(rows, lambda r: r.get("settled") is False,
                         lambda r: r.get("cycles_done") or 0,
                         "not settled after {} mesh cycles at {}: their figures are of a "
                         "transient, not a steady state")
    warnings += _grouped(rows, lambda r: bool(r.get("separations")),
                         lambda r: r["separations"] or 0, "contact lost up to {} times a run "
                         "(rattle) at {}")
    for key, what in (("safety_root_model", "root"), ("safety_contact_model", "flank")):
        for g, m in out[f"{key}_min"].items():
            if m is not None and m["value"] < 1.0:
                warnings.append(f"gear {g}: {what} safety factor {m['value']:.2f} < 1 at "
                                f"{m['rpm']:g} rpm, {m['torque_Nm']:g} N m (the model's)")
    for name, place in (("model", res["model_place"]), ("iso", res["iso_place"])):
        if place in ("in the range", "near the range"):
            who = "ISO 6336-1" if name == "iso" else "the model"
            warnings.append(f"the main mesh resonance ({who}: {res[name + '_rpm']:,.0f} rpm) "
                            f"is {place}")
    top = out["dynamic_factor_max"]
    if top is not None and len(rpms) > 1 and top["rpm"] == hi:
        warnings.append(f"the largest dynamic factor ({top['value']:.3f}) is at the top of "
                        f"the range, {hi:g} rpm: it may be larger above it")
    out["warnings"] = warnings
    return out


def ring_of(plan: Any, rows: list[dict[str, Any]], eps: float, resonance: Any
            ) -> dict[str, Any] | None:
    """The pair's ring measured on the slowest complete point of the first torque
    (:func:`spurdyn.cli.design_ring.measured_ring`) with that point's speed and summary,
    or ``None`` (no such point, or its ring not readable)."""
    from spurdyn.cli.design_ring import measured_ring

    done = [r for r in rows if r["status"] == "complete" and r["summary"] is not None
            and r["torque_Nm"] == plan.torque_values[0]]
    if not done:
        return None
    row = min(done, key=lambda r: r["rpm"])
    nc = plan.out.parent / Path(row["summary"]).parent / "result.nc"
    ring = measured_ring(nc, eps, plan.case.pair.gear_a.teeth, resonance.natural_frequency_hz)
    return None if ring is None else ring | {"rpm": row["rpm"], "torque_Nm": row["torque_Nm"],
                                             "summary": row["summary"]}


def _grouped(rows: list[dict[str, Any]], hit: Any, count: Any, words: str) -> list[str]:
    """One warning per torque for the complete points where ``hit(row)``: ``words``
    formatted with the largest ``count(row)`` and the speeds."""
    out = []
    for tq in dict.fromkeys(r["torque_Nm"] for r in rows):
        mine = [r for r in rows if r["torque_Nm"] == tq and r["status"] == "complete" and hit(r)]
        if mine:
            speeds = ", ".join(f"{r['rpm']:,.6g}" for r in mine)
            out.append(words.format(max(count(r) for r in mine),
                                    f"{speeds} rpm ({tq:g} N m)"))
    return out


def case_inputs(spec: str, case: Any, rows: list[dict[str, Any]], info: dict[str, Any],
                options: dict[str, str], model: str) -> dict[str, Any]:
    """The case as given, each setting of the case marked given (in the file, or by the
    option named in ``options``, dotted key -> option) or taken by default."""
    from spurdyn.case.file import case_to_dict
    from spurdyn.simulators import MODELS

    text, given = None, {}
    if Path(spec).is_file():
        from spurdyn.case.files import read_text

        text = read_text(Path(spec), spec)      # the one reader of a file the user named
        given = tomllib.loads(text)
    full = case_to_dict(case)
    settings = []
    unread = set(MODELS[model].unread)
    for table, values in full.items():
        for key, value in _leaves(values):
            name = f"{table}.{key}"
            if table == "run" and key.removesuffix("_rpm").removesuffix("_deg") in unread:
                continue            # a setting this model does not read (another model's)
            mine = _lookup(given, [table, *key.split(".")])
            source = (f"given ({options[name]})" if name in options else "given"
                      if mine is not None else "default (docs/engineer_defaults.md)")
            settings.append({"key": name, "value": value, "source": source})
    sources = next((r["_sources"] for r in rows if r["_sources"].get("mesh_damping")), {})
    return {"case_file": spec if text is not None else None, "case_text": text,
            "settings": settings, "damping": sources,
            "disk_inertia_source": info.get("disk_inertia_source"), "version": __version__}


def _leaves(table: Any, prefix: str = "") -> list[tuple[str, Any]]:
    if not isinstance(table, dict):
        return [(prefix, table)]
    out = []
    for k, v in table.items():
        out += _leaves(v, f"{prefix}.{k}" if prefix else str(k))
    return out


def _lookup(table: Any, path: list[str]) -> Any:
    for part in path:
        if not isinstance(table, dict) or part not in table:
            return None
        table = table[part]
    return table


def commands(spec: str, rpm: str, torques: tuple[float, ...], mesh: str, out: str) -> list[str]:
    """The commands that reproduce every figure of the page."""
    tq = ",".join(f"{t:g}" for t in torques)
    return [f"spurdyn report {spec} --rpm {rpm} --torque {tq} --mesh {mesh} --out {out}",
            f"spurdyn info {spec} --mesh {mesh} --json",
            f"spurdyn stiffness {spec} --torque {tq} --mesh {mesh} --json",
            f"spurdyn mesh {spec} --mesh {mesh} --png mesh.png",
            f"spurdyn sweep {spec} --rpm {rpm} --torque {tq} --mesh {mesh} --keep-runs "
            f"--out {out}/sweep",
            f"spurdyn run {spec} --speed-a RPM --torque T --mesh {mesh}   (one point)"]


def mesh_cycle(args: argparse.Namespace, torques: tuple[float, ...]) -> dict[str, Any]:
    """The quasi-static mesh cycle at each torque (``spurdyn stiffness``), or why not."""
    from spurdyn.cli.stiffness import stiffness_report
    from spurdyn.errors import InputError

    ns = argparse.Namespace(case=args.case, torque=",".join(repr(t) for t in torques if t > 0),
                            teeth=None, positions=None, mesh=args.mesh, grading=None)
    if not ns.torque:
        return {"absent": "no positive torque: a quasi-static cycle needs a load"}
    try:
        report = stiffness_report(ns)
    except (InputError, ValueError) as err:
        return {"absent": f"the quasi-static mesh cycle could not be computed: {err}"}
    return report


def gather(plan: Any, sweep: Any, resonance: Any, args: argparse.Namespace, rpm: str,
           lumped: tuple[Any, Any, str | None] = (None, None, None)) -> dict[str, Any]:
    """Every number of the page, by part (the dictionary ``report.json`` holds; keys that
    start with ``_`` are the page's, not written); ``lumped`` the plan and sweep of the
    lumped model beside, or why none (:func:`beside`)."""
    from spurdyn.case.pair_tables import MeshedPair
    from spurdyn.cli.report import pair_info
    from spurdyn.sweep.resonance import iso_kv_grid

    case, run = plan.case, plan.case.run
    meshed = MeshedPair(pair=case.pair, nx=run.nx, ny=run.ny, name=case.name,
                        grading=run.grading, row_grading=run.row_grading)
    info = pair_info(meshed)
    rows = point_rows(plan, sweep)
    cycle = mesh_cycle(args, plan.torque_values)
    cycles = cycle.pop("_cycles", None)
    kv = iso_kv_grid(case, plan.rpms, plan.torque_values)
    mesh = f"{run.nx}x{run.ny}"
    data = {
        "case": case.name, "model": plan.model, "version": __version__,
        "rpm": list(plan.rpms), "torques_Nm": list(plan.torque_values),
        "verdict": verdict(rows, resonance, plan.rpms,
                           ring_of(plan, rows, info["contact_ratio"], resonance)),
        "inputs": case_inputs(args.case, case, rows, info, _options(args), plan.model) | {
            "commands": commands(args.case, rpm, plan.torque_values, mesh, args.out)},
        "geometry": info,
        "mesh_cycle": cycle,
        "speed": {"points": [{k: v for k, v in r.items() if not k.startswith("_")}
                             for r in rows],
                  "iso_k_v": None if kv is None else kv.tolist(),
                  "lumped": beside(*lumped),
                  "resonance": resonance.attrs()},
        "rating": rating(rows, plan.torque_values),
        "limits": {"model": plan.model, "mesh": mesh, "n_dof": next(
            (r["n_dof"] for r in rows if r["n_dof"] is not None), None),
            "limits": list(LIMITS), "validation_pages": list(VALIDATION_PAGES)},
    }
    lumped_points = data["speed"]["lumped"].get("points")
    if lumped_points is not None:
        data["verdict"]["dynamic_factor_max_lumped"] = _extreme(lumped_points, "dynamic_factor",
                                                                None, True)
    data = _clean(data)
    data["_pictures"] = pictures(meshed, cycles, data["mesh_cycle"])
    return data


def pictures(meshed: Any, cycles: Any, cycle: dict[str, Any]) -> dict[str, str | None]:
    """The meshed teeth (``spurdyn mesh``) and the mesh cycle (``spurdyn stiffness
    --png``) as inline PNGs; a picture that cannot be drawn is left out."""
    import tempfile

    from spurdyn.cli.design_page import file_uri
    from spurdyn.results.pictures import draw_mesh_position
    from spurdyn.sector.plot import draw_mesh_cycle

    out: dict[str, str | None] = {"mesh": None, "cycle": None}
    with tempfile.TemporaryDirectory() as tmp:
        png = Path(tmp) / "mesh.png"
        draw_mesh_position(meshed, png)
        out["mesh"] = file_uri(png)
        if cycles:
            png = Path(tmp) / "cycle.png"
            iso = [(r["iso6336_single_pair_N_per_m"], r["iso6336_mesh_N_per_m"])
                   if r.get("iso6336_mesh_N_per_m") is not None else None
                   for r in cycle["torques"]]
            draw_mesh_cycle(cycles, f"{meshed.name}: quasi-static mesh cycle", png, iso)
            out["cycle"] = file_uri(png)
    return out


def _options(args: argparse.Namespace) -> dict[str, str]:
    """The case keys the report's options set (the speed is set per point by --rpm)."""
    out = {"run.speed_a_rpm": "--rpm", "run.speed_b_rpm": "--rpm (the case's ratio)"}
    if args.mesh is not None:
        out |= {"mesh.nx": "--mesh", "mesh.ny": "--mesh"}
    if args.torque is not None:
        out["run.torque"] = "--torque"
    return out


def rating(rows: list[dict[str, Any]], torques: tuple[float, ...]) -> list[dict[str, Any]]:
    """ISO 6336's factor chain at each torque, at the speed where its root safety factor
    is smallest (the largest K_v): the ``rating_iso`` of that point's summary."""
    out = []
    for tq in torques:
        rated = [r for r in rows if r["torque_Nm"] == tq and r["_rating_iso"]]
        if not rated:
            continue
        row = min(rated, key=lambda r: min(r["safety_root_iso"] or [math.inf]))
        out.append({"torque_Nm": tq, "rpm": row["rpm"], "summary": row["summary"],
                    "rating_iso": row["_rating_iso"]})
    return out


__all__ = ["POINT_KEYS", "gather", "point_rows", "verdict"]
