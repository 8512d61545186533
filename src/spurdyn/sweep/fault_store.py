"""A fault sweep's data set, ``DIR/fault_sweep.nc`` (docs/sweep.md, "Fault datasets").

One CF NetCDF file: dimensions ``rpm``, ``torque`` (when ``--torque`` was given, else a
scalar coordinate), ``fault_size`` (the fault's sizes; not for a missing tooth) and
``angle`` (the samples of a revolution of the faulty gear). Per point: every figure of a
speed sweep (:data:`spurdyn.sweep.point.FIGURES`), ``status`` and ``reason``, and per
sensor signal (:data:`spurdyn.sweep.faults.SIGNALS`) its indicators
``<signal>_<indicator>`` and its time-synchronous average ``<signal>_tsa`` along
``angle``. The fault's kind, gear and tooth are scalar coordinates; ``faulty`` along
``fault_size`` says which sizes are the healthy pair.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr

from spurdyn.sweep.faults import INDICATORS, SIGNAL_UNITS, SIGNALS, FaultAxis
from spurdyn.sweep.point import FIGURES
from spurdyn.sweep.spec import PointKey, SweepPlan, settings_dict
from spurdyn.sweep.store import (NOT_RUN, STATUS_CODES, STATUS_LEGEND, _clean, _status_attrs,
                                 headline_attrs, write_dataset)

FAULT_FILE = "fault_sweep.nc"
#: The point grid's dimensions (``angle`` follows for the averages).
GRID = ("rpm", "torque", "fault_size")
#: Whole-number figures, -1 where a point has none.
WHOLE = {"separations": np.int32, "steps": np.int64, "revolutions": np.int32}


def _empty(plan: SweepPlan) -> tuple[tuple[int, ...], dict[str, np.ndarray]]:
    """The grid's shape and its arrays, every value missing."""
    axis = plan.faults
    assert axis is not None
    shape = (len(plan.rpms), len(plan.torque_values), len(axis.sizes))
    grids = {name: np.full(shape, np.nan) for name in FIGURES}
    grids["revolutions"] = np.full(shape, np.nan)
    grids["shaft_frequency"] = np.full(shape, np.nan)
    grids["build_s"] = np.full(shape, np.nan)
    for signal in SIGNALS:
        for ind in INDICATORS:
            grids[f"{signal}_{ind}"] = np.full(shape, np.nan)
        grids[f"{signal}_tsa"] = np.full((*shape, axis.samples), np.nan)
    grids["status"] = np.full(shape, STATUS_CODES[NOT_RUN], np.int8)
    grids["reason"] = np.full(shape, "", dtype=object)
    return shape, grids


def _fill(grids: dict[str, np.ndarray], at: tuple[int, int, int], record: Mapping[str, Any]) -> None:
    """One point's record into the grids at index ``at``."""
    grids["status"][at] = STATUS_CODES[record["status"]]
    reason = record.get("reason") or ""
    for name in FIGURES:
        if record.get(name) is not None:
            grids[name][at] = float(record[name])
    signals = record.get("signals") or {}
    if signals.get("reason") and not reason:
        reason = f"no indicators: {signals['reason']}"
    grids["reason"][at] = reason
    if signals.get("build_s") is not None:
        grids["build_s"][at] = signals["build_s"]
    if signals.get("revolutions") is not None:
        grids["revolutions"][at] = signals["revolutions"]
        grids["shaft_frequency"][at] = signals["shaft_frequency_Hz"]
    for signal in SIGNALS:
        figures = signals.get(signal) or {}
        for ind in INDICATORS:
            if figures.get(ind) is not None:
                grids[f"{signal}_{ind}"][at] = float(figures[ind])
        if figures.get("tsa") is not None:
            grids[f"{signal}_tsa"][at] = np.array([np.nan if v is None else v for v in figures["tsa"]], float)


def fault_grids(plan: SweepPlan, records: Mapping[PointKey, Mapping[str, Any]],
                missing_reason: Mapping[PointKey, str]) -> dict[str, np.ndarray]:
    """Every point's figures, indicators, averages, status and reason on the grid
    ``(rpm, torque, fault_size[, angle])``; missing where a point has no record."""
    axis = plan.faults
    assert axis is not None
    _, grids = _empty(plan)
    for key in plan.keys():
        at = (plan.rpms.index(key.rpm), plan.torque_values.index(key.torque), axis.sizes.index(key.size))
        record = records.get(key)
        if record is None:
            grids["reason"][at] = missing_reason.get(key, "not computed yet")
        else:
            _fill(grids, at, record)
    return grids


def _variables(grids: dict[str, np.ndarray]) -> dict[str, Any]:
    """The data set's variables, with their units and long names."""
    out: dict[str, Any] = {}
    whole_note = {"missing_value_note": "-1 where the point has no result"}
    for name, (units, long_name) in FIGURES.items():
        out[name] = (GRID, grids[name], {"units": units, "long_name": long_name})
    out["revolutions"] = (GRID, grids["revolutions"], {
        "units": "1", "long_name": "whole revolutions of the faulty gear the averages and indicators are over"})
    out["shaft_frequency"] = (GRID, grids["shaft_frequency"], {
        "units": "Hz", "long_name": "the faulty gear's mean turns a second over the window"})
    out["build_s"] = (GRID, grids["build_s"], {
        "units": "s", "long_name": "wall-clock time of the model's build on its worker, of wall_s"})
    for name, dtype in WHOLE.items():
        values = np.where(np.isfinite(grids[name]), grids[name], -1).astype(dtype)
        out[name] = (GRID, values, {**out[name][2], **whole_note})
    for signal in SIGNALS:
        unit = SIGNAL_UNITS[signal]
        for ind, (units, long_name) in INDICATORS.items():
            out[f"{signal}_{ind}"] = (GRID, grids[f"{signal}_{ind}"], {
                "units": units or unit, "long_name": f"{signal}: {long_name}"})
        out[f"{signal}_tsa"] = ((*GRID, "angle"), grids[f"{signal}_tsa"], {
            "units": unit, "long_name": f"{signal}: time-synchronous average over a revolution of the "
                                        "faulty gear (its orders below half the angle samples)"})
    out["status"] = (GRID, grids["status"], _status_attrs())
    out["reason"] = (GRID, grids["reason"].astype(str),
                     {"long_name": "why the point is not complete or has no indicators (empty otherwise)"})
    return out


def _coords(plan: SweepPlan, axis: FaultAxis) -> dict[str, Any]:
    """The grid's coordinates and the fault's parameters as scalar coordinates."""
    rpms = np.asarray(plan.rpms, float)
    sizes = np.asarray([np.nan if s is None else s for s in axis.sizes], float)
    f = axis.fault
    coords: dict[str, Any] = {
        "rpm": ("rpm", rpms, {"units": "rpm", "long_name": "initial speed of gear A"}),
        "torque": ("torque", np.asarray(plan.torque_values, float),
                   {"units": "N m", "long_name": "external torque on the driver"}),
        "fault_size": ("fault_size", sizes, {
            "units": "m", "long_name": f"size of the fault: a {f.kind}'s "
            f"{'length' if f.kind == 'crack' else 'depth'}; 0 the healthy pair, run by the healthy model"}),
        "faulty": ("fault_size", (np.nan_to_num(sizes, nan=1.0) > 0.0).astype(np.int8), {
            "long_name": "whether the point's pair has the fault", "flag_values": np.array([0, 1], np.int8),
            "flag_meanings": "healthy faulty"}),
        "angle": ("angle", 2.0 * np.pi * np.arange(axis.samples) / axis.samples, {
            "units": "rad", "long_name": "angle of the faulty gear along its rotation from its position at the "
            "start of the run, modulo a revolution"}),
        "mesh_frequency": ("rpm", plan.case.pair.gear_a.teeth * rpms / 60.0,
                           {"units": "Hz", "long_name": "tooth mesh frequency z_a rpm / 60"}),
        "fault_kind": ((), f.kind, {"long_name": "kind of the fault (crack, spall, missing)"}),
        "fault_gear": ((), f.gear, {"long_name": "gear carrying the fault (a or b)"}),
        "fault_tooth": ((), np.int32(f.tooth), {"units": "1", "long_name": "faulty tooth, counted in the "
                                                 "order the teeth enter the mesh from 0 (docs/faults.md)"}),
    }
    if f.kind == "spall":
        coords["fault_roll"] = (("roll_end",), np.asarray(f.roll, float), {
            "units": "rad", "long_name": "the spall's ends in its gear's own roll angle"})
        coords["fault_width_fraction"] = ((), f.width_fraction, {"units": "1", "long_name": "share of the face "
                                                                 "width the spall covers"})
    return coords


def fault_dataset(plan: SweepPlan, records: Mapping[PointKey, Mapping[str, Any]],
                  missing_reason: Mapping[PointKey, str] | None = None,
                  extra_attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """A fault sweep as one data set: every point of ``plan``, stored or not (module
    docstring); ``torque`` a scalar coordinate without ``--torque``, ``fault_size`` one for a
    missing tooth."""
    axis = plan.faults
    assert axis is not None
    grids = fault_grids(plan, records, missing_reason or {})
    ds = xr.Dataset(_variables(grids), coords=_coords(plan, axis), attrs=_attrs(plan, axis, extra_attrs))
    if plan.torques is None:
        ds = ds.squeeze("torque")
    if axis.sizes == (None,):
        ds = ds.squeeze("fault_size").drop_vars(["fault_size", "faulty"])
    return ds


def _attrs(plan: SweepPlan, axis: FaultAxis, extra: Mapping[str, Any] | None) -> dict[str, Any]:
    from spurdyn.version import __version__

    f = axis.fault
    return {
        "Conventions": "CF-1.8",
        "title": f"spurdyn fault sweep: {plan.case.name} ({plan.model}), {f.kind} on tooth {f.tooth} of gear {f.gear}",
        "source": "spurdyn (sector model of spur gears in mesh, faulty teeth)",
        "case_name": plan.case.name,
        "model": plan.model,
        "settings_hash": plan.settings,
        "settings": json.dumps(_clean(settings_dict(axis.hashed_case(plan.case))), sort_keys=True),
        "faulty_teeth": axis.teeth,
        "angle_samples": axis.samples,
        "torque_dimension": int(plan.torques is not None),
        "points": len(plan.keys()),
        "status_legend": STATUS_LEGEND,
        "comment": "Indicators and averages follow the faulty gear over the whole revolutions from the "
                   "first revolution's last mesh cycle (summary.json's vibration); fault_size 0 is the "
                   "healthy pair over the same revolutions. docs/sweep.md, Fault datasets.",
        **headline_attrs(),
        **(extra or {}),
        "spurdyn_version": __version__,
        "history": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()) + " written by spurdyn sweep",
    }


def write_fault_sweep(plan: SweepPlan, records: Mapping[PointKey, Mapping[str, Any]],
                      missing_reason: Mapping[PointKey, str], extra_attrs: Mapping[str, Any]
                      ) -> tuple[xr.Dataset, tuple[Path, ...]]:
    """Write ``DIR/fault_sweep.nc``; the data set and the file."""
    ds = fault_dataset(plan, records, missing_reason, extra_attrs)
    path = plan.out / FAULT_FILE
    write_dataset(ds, path)
    return ds, (path,)


__all__ = ["FAULT_FILE", "fault_dataset", "fault_grids", "write_fault_sweep"]
