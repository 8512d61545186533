"""What a model of several tooth pairs adds to a run's files (the sector model, and the
lumped model's steady state): the pairs' forces, shares and rolls and the back flanks' forces
as variables of ``result.nc``, and the settled figures and the back flanks' figures of
``summary.json`` (docs/sector.md 6.4, 6.7; docs/lumped.md)."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from spurdyn.result import Result
from spurdyn.results.headline import averaged_peak
from spurdyn.results.stress import tooth_stress_variables
from spurdyn.settings import PAPER_MODEL


def pair_variables(result: Result, n: int) -> dict[str, xr.Variable]:
    """The tooth pairs' forces, roll angles and load shares, the mesh force and the
    transmission error of a model of several teeth (none for a model of one pair)."""
    out: dict[str, xr.Variable] = tooth_stress_variables(result)
    if result.transmission_error is not None:
        out["transmission_error"] = xr.Variable(("time",), np.asarray(result.transmission_error, float), {
            "units": "m", "long_name": "transmission error along the line of action: r_b,driver "
            "theta_driver - r_b,driven theta_driven less its rigid kinematic value, positive where "
            "the driver runs ahead (the teeth yield)"})
    if result.pair_force is None:
        return out
    out.update(static_cycle_variables(result.info.get("static_cycle")))
    force = np.asarray(result.pair_force, float).reshape(n, -1)
    mesh = force.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(mesh[:, None] > 0, force / mesh[:, None], np.nan)
    dims = ("time", "pair")
    out["pair_force"] = xr.Variable(dims, force, {
        "units": "N", "long_name": "normal force of each tooth pair, compression positive"})
    out["mesh_force"] = xr.Variable(("time",), mesh, {
        "units": "N", "long_name": "total normal force of the mesh along the line of action"})
    out["load_share"] = xr.Variable(dims, share, {
        "units": "1", "long_name": "each tooth pair's share of the mesh force (NaN with no contact)"})
    if result.pair_roll is not None:
        out["pair_roll_deg"] = xr.Variable(dims, np.degrees(np.asarray(result.pair_roll, float)), {
            "units": "degree", "long_name": "driver's roll angle of each tooth pair's contact "
            "point on its extended path of contact (NaN away from it)"})
    for name, value, units, long in (
            ("pair_contact_pressure", result.pair_contact_pressure, "Pa",
             "peak Hertzian pressure of each tooth pair (2 F / (pi b L); NaN out of contact)"),
            ("pair_contact_half_width", result.pair_contact_half_width, "m",
             "half-width of each tooth pair's Hertzian strip (NaN out of contact)")):
        if value is not None:
            out[name] = xr.Variable(dims, np.asarray(value, float).reshape(n, -1),
                                    {"units": units, "long_name": long})
    if result.back_force is not None:
        back = np.asarray(result.back_force, float).reshape(n, -1)
        out["back_pair_force"] = xr.Variable(("time", "back_pair"), back, {
            "units": "N", "long_name": "normal force of each pair of back flanks (the driver's "
            "tooth k on the driven gear's -k+1) along the back line of action, compression positive"})
        out["back_mesh_force"] = xr.Variable(("time",), back.sum(axis=1), {
            "units": "N", "long_name": "total normal force on the back flanks along the back line "
            "of action (the driver's torque from the mesh is r_b (mesh_force - back_mesh_force))"})
    return out


def static_cycle_variables(cycle: dict[str, Any] | None) -> dict[str, xr.Variable]:
    """The quasi-static mesh cycle a model ran beside (the sector model's ``info["static_cycle"]``,
    :func:`spurdyn.solvers.sector.output.static_cycle`) along ``cycle_position``: the first
    pair's roll, each pair's force along ``static_pair`` and the static transmission error;
    none without one."""
    if not cycle:
        return {}
    force = np.asarray(cycle["force"], float)
    at = ("cycle_position",)
    return {
        "cycle_roll_deg": xr.Variable(at, np.degrees(np.asarray(cycle["roll"], float)), {
            "units": "degree", "long_name": "driver's roll angle of the first pair's contact point "
            "at each position of the quasi-static mesh cycle (one pitch, both ends included)"}),
        "static_pair_force": xr.Variable(at + ("static_pair",), force, {
            "units": "N", "long_name": "quasi-static normal force of the pairs on the path: pair j's "
            "contact point is j pitches further along it than the first's (0 off the path)"}),
        "static_transmission_error": xr.Variable(at, np.asarray(cycle["transmission_error"], float), {
            "units": "m", "long_name": "loaded static transmission error along the line of action "
            "over the quasi-static mesh cycle"}),
    }


def back_flank_figures(ds: xr.Dataset, info: dict[str, Any]) -> dict[str, Any]:
    """``summary.json``'s ``back_flanks``: whether they were contacts, the normal backlash,
    and where they were, their peak force, the steps with a back contact and the steps with no
    drive contact."""
    back: dict[str, Any] = {"contacts": bool(info["back_flanks"]),
                            "backlash_normal_m": info.get("backlash_normal_m")}
    if "back_mesh_force" in ds:
        bf = ds["back_mesh_force"].values
        back.update(peak_force_N=float(np.nanmax(bf, initial=0.0)),
                    steps_in_contact=int((bf > 0).sum()),
                    steps_without_drive_contact=int((ds["mesh_force"].values <= 0).sum()))
    return back


def steady_figures(ds: xr.Dataset, steady: dict[str, Any], complete: bool) -> dict[str, Any]:
    """The settled figures of a steady-state run (docs/lumped.md): the dynamic factor of
    the most loaded tooth pair's 10-us-averaged force over the last cycles against the
    largest pair force of a quasi-static cycle, where A had turned at that peak, the
    transmission error's RMS and peak-to-peak there, and whether the run settled."""
    time = ds["time"].values.astype(float)
    force = ds["contact_force"].values.astype(float)
    angle = ds["angle_deg"].values.astype(float)
    lo, _ = steady["window_s"]
    sel = time >= lo - 1e-15
    static = float(steady["static_pair_force_max_N"])
    peak = averaged_peak(time[sel], force[sel])
    touched = sel & np.isfinite(force)
    raw_at = int(np.flatnonzero(touched)[np.argmax(force[touched])]) if touched.any() else None
    raw = None if raw_at is None else float(force[raw_at])
    ok = complete and peak is not None and static > 0
    m = steady["last_cycles"]
    return {
        "peak_force_N": None if peak is None else peak[0],
        "peak_angle_deg": None if peak is None else float(np.interp(peak[1], time, angle)),
        "peak_force_raw_N": raw,
        "peak_angle_raw_deg": None if raw_at is None else float(angle[raw_at]),
        "cycles": steady["cycles"],
        "cycles_done": steady["cycles_done"],
        "max_cycles": steady.get("max_cycles"),
        "settled": bool(steady["settled"]) and complete,
        "settle_tolerance": steady["settle_tolerance"],
        "static_force_N": static,
        "dynamic_factor": peak[0] / static if ok else None,
        "dynamic_factor_raw": raw / static if ok and raw is not None else None,
        "dynamic_factor_note": (f"the most loaded tooth pair's 10-us-averaged force over the last "
                                f"{m} mesh cycle(s) against its largest quasi-static value"
                                + ("" if steady["settled"] else "; the run had not settled: "
                                   "its cycle-to-cycle change was above the tolerance")
                                if ok else _no_factor(complete, peak is not None)),
        "transmission_error_rms_m": steady["transmission_error_rms_m"],
        "transmission_error_pp_m": steady["transmission_error_pp_m"],
        "mesh_stiffness_mean_N_per_m": steady["mesh_stiffness_mean_N_per_m"],
    }


def _no_factor(complete: bool, touched: bool) -> str:
    """Why a steady run's summary has no dynamic factor, in the headline's words
    (:func:`spurdyn.results.headline.headline`): stopped early, no contact, else no load."""
    if not complete:
        return "none: the run stopped early"
    if not touched:
        return "none: the teeth never touched"
    return "none: no quasi-static force (zero torque)"


def info_figures(ds: xr.Dataset, info: dict[str, Any], complete: bool) -> dict[str, Any]:
    """The summary's figures a model's ``info`` asks for: the steady state, the model, the
    start and torques, the back flanks, and the bodies' and the mesh damper's damping with
    whose each was."""
    out: dict[str, Any] = {}
    if "steady" in info:
        out.update(steady_figures(ds, info["steady"], complete))
    out["model"] = info.get("model", PAPER_MODEL)   # the FE model's info names none
    if "start" in info:         # a run of mesh cycles: how it started, what torques it carried
        out["start"] = info["start"]
        out["torque_history"] = info.get("torque_history")
    if "back_flanks" in info:   # the sector model: whether the back flanks were contacts
        out["back_flanks"] = back_flank_figures(ds, info)
    if "rayleigh" in info:
        a, b = info["rayleigh"]
        out["body_damping"] = {"rayleigh_mass": a, "rayleigh_stiffness": b,
                               "source": "model default" if info.get("rayleigh_default") else "run"}
    if "contact_pressure_note" in info:     # a pit over part of the width split a contact
        out["contact_pressure_note"] = info["contact_pressure_note"]
    if "crack_faces" in info:   # a crack's faces in motion (docs/faults.md, section 8)
        out["crack_faces"] = info["crack_faces"]
    if "bearings" in info:      # the hubs on bearings (docs/sector.md, 6.12)
        out["bearings"] = info["bearings"]
    if "damping_ratio_source" in info:
        out["mesh_damping"] = {"ratio": info["damping_ratio"], "source": info["damping_ratio_source"]}
    return out


__all__ = ["back_flank_figures", "info_figures", "pair_variables", "static_cycle_variables", "steady_figures"]
