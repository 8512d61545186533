"""What a sweep leaves in its folder, written so that nothing finished is ever lost.

``DIR/points/<stem>.json``
    One file per finished point (:func:`write_point`), written the moment its result
    reaches the client, atomically (a temporary file renamed into place). ``<stem>`` is
    :attr:`PointKey.stem`: model, speed, torque and settings hash.
``DIR/runs/<stem>/``
    With ``--keep-runs``: the point's whole run folder, as ``spurdyn run`` writes it.
``DIR/sweep_<model>.nc``
    One model's last sweep (:func:`sweep_dataset`): dimension ``rpm`` and, when torques
    were given, ``torque``.
``DIR/sweep.nc``
    Every model in the folder along a ``model`` dimension (:func:`combine`).

Status codes (variable ``status``, CF ``flag_values``/``flag_meanings`` and a ``legend``
attribute): see :data:`STATUS_CODES`.
"""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np
import xarray as xr

from spurdyn.results.headline import AVERAGING_WINDOW_S
from spurdyn.sweep.point import COMPLETE, FAILED, FIGURES, INCOMPLETE, PointOutcome
from spurdyn.sweep.spec import MODELS, PointKey, SweepPlan, settings_dict

POINTS_DIR = "points"
RUNS_DIR = "runs"
SWEEP_FILE = "sweep.nc"
PNG_FILE = "dynamic_factor.png"
NOT_RUN, NOT_REQUESTED = "not_run", "not_requested"

#: Status of a point in ``sweep.nc``: name -> code.
STATUS_CODES: dict[str, int] = {COMPLETE: 0, INCOMPLETE: 1, FAILED: 2, NOT_RUN: 3,
                                NOT_REQUESTED: 4}
STATUS_LEGEND = (
    "0 complete; 1 incomplete (the run stopped early: non-convergence, NaN; see reason; "
    "no dynamic factor); "
    "2 failed (an error, see reason; computed again by the next run of the command); "
    "3 not_run (interrupted, lost with its worker, or not computed yet; computed by the "
    "next run of the command); 4 not_requested (sweep.nc only: this model's sweep did not "
    "ask for this speed and torque)")

#: Points with these statuses are final: a rerun does not compute them again.
FINAL = (COMPLETE, INCOMPLETE)

#: A figure that point files and sweep files have had since the dynamic factor became
#: that of the 10-us-averaged force (:mod:`spurdyn.results.headline`). Files without it
#: hold the raw peak's factor under that name: their points are computed again and their
#: sweeps left out of ``sweep.nc`` until they are, rather than mixed with today's.
CURRENT_FIGURE = "dynamic_factor_raw"


def sweep_file(model: str) -> str:
    """``sweep_<model>.nc``."""
    return f"sweep_{model}.nc"


def point_path(out: Path, key: PointKey) -> Path:
    return out / POINTS_DIR / f"{key.stem}.json"


def run_path(out: Path, key: PointKey) -> Path:
    return out / RUNS_DIR / key.stem


def _clean(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    return value


def write_text_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file renamed into place."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)


def point_record(outcome: PointOutcome, settings: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The JSON object of a point file."""
    from spurdyn.version import __version__

    record = {**outcome.key.as_dict(), "status": outcome.status, "reason": outcome.reason,
              **{name: outcome.figures.get(name) for name in FIGURES},
              "worker": outcome.worker, "finished": outcome.finished,
              "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(outcome.finished)),
              "spurdyn_version": __version__}
    if "signals" in outcome.figures:      # a fault sweep's (spurdyn.sweep.faults)
        record["signals"] = outcome.figures["signals"]
    if settings is not None:
        record["settings"] = settings
    return _clean(record)


def write_point(out: Path, outcome: PointOutcome,
                settings: Mapping[str, Any] | None = None) -> Path:
    """Write one finished point to ``out/points/`` (atomically); return the file."""
    path = point_path(out, outcome.key)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(path, json.dumps(point_record(outcome, settings), indent=1) + "\n")
    return path


def read_point(out: Path, key: PointKey) -> dict[str, Any] | None:
    """The stored record of a point, or ``None`` (no file, one that cannot be read, or
    one written before the headline became the averaged force: :data:`CURRENT_FIGURE`)."""
    path = point_path(out, key)
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(record, dict) or record.get("status") not in STATUS_CODES:
        return None
    if record["status"] != FAILED and CURRENT_FIGURE not in record:
        return None
    return record


def stored_points(out: Path, keys: Iterable[PointKey]) -> dict[PointKey, dict[str, Any]]:
    """The records of those ``keys`` that have a point file."""
    found = {}
    for key in keys:
        record = read_point(out, key)
        if record is not None:
            found[key] = record
    return found


# -- the sweep data set ----------------------------------------------------------------

def headline_attrs() -> dict[str, Any]:
    """Global attributes saying what ``dynamic_factor`` is (the same in every sweep file)."""
    return {"averaging_window_s": AVERAGING_WINDOW_S,
            "dynamic_factor_note": (
                "dynamic_factor is the peak of the contact force averaged over a centred "
                f"{AVERAGING_WINDOW_S * 1e6:g} us moving window over the quasi-static force "
                "torque / r_b (spurdyn.results.headline); dynamic_factor_raw is the raw "
                "step-to-step peak's, which is not converged. Both are NaN where the run "
                "stopped early (status 1, incomplete) or has no result.")}


def _status_attrs() -> dict[str, Any]:
    return {"long_name": "outcome of the point",
            "flag_values": np.array(list(STATUS_CODES.values()), np.int8),
            "flag_meanings": " ".join(STATUS_CODES), "legend": STATUS_LEGEND}


def _point_grids(plan: SweepPlan, records: Mapping[PointKey, Mapping[str, Any]],
                 missing_reason: Mapping[PointKey, str]
                 ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]:
    """The points' figures, status codes and reasons on the ``(rpm, torque)`` grid.

    Parameters
    ----------
    plan
        The sweep (its grids).
    records
        Point records by key.
    missing_reason
        Why a point without a record was not run.

    Returns
    -------
    values
        Each of :data:`FIGURES`, NaN where a point has none.
    status
        The int8 codes (:data:`STATUS_CODES`), ``not_run`` where a point has no record.
    reason
        Why a point is not complete ("" when it is), as objects.
    """
    shape = (len(plan.rpms), len(plan.torque_values))
    values = {name: np.full(shape, np.nan) for name in FIGURES}
    status = np.full(shape, STATUS_CODES[NOT_RUN], np.int8)
    reason = np.full(shape, "", dtype=object)
    for key in plan.keys():
        i, j = plan.rpms.index(key.rpm), plan.torque_values.index(key.torque)
        record = records.get(key)
        if record is None:
            reason[i, j] = missing_reason.get(key, "not computed yet")
            continue
        status[i, j] = STATUS_CODES[record["status"]]
        reason[i, j] = record.get("reason") or ""
        for name in FIGURES:
            v = record.get(name)
            if v is not None:
                values[name][i, j] = float(v)
    return values, status, reason


def _figure_variables(values: dict[str, np.ndarray], status: np.ndarray, reason: np.ndarray
                      ) -> dict[str, Any]:
    """The data set's variables of :data:`FIGURES` (whole numbers -1 where a point has no
    result), ``status`` and ``reason``, over ``("rpm", "torque")``."""
    separations = np.where(np.isfinite(values["separations"]), values["separations"], -1)
    data_vars: dict[str, Any] = {}
    for name, (units, long_name) in FIGURES.items():
        data = separations.astype(np.int32) if name == "separations" else \
            (np.where(np.isfinite(values["steps"]), values["steps"], -1).astype(np.int64)
             if name == "steps" else values[name])
        attrs = {"units": units, "long_name": long_name}
        if name in ("separations", "steps"):
            attrs["missing_value_note"] = "-1 where the point has no result"
        data_vars[name] = (("rpm", "torque"), data, attrs)
    data_vars["status"] = (("rpm", "torque"), status, _status_attrs())
    data_vars["reason"] = (("rpm", "torque"), reason.astype(str),
                           {"long_name": "why the point is not complete (empty when it is)"})
    return data_vars


def _sweep_attrs(plan: SweepPlan, points: int, teeth_a: int) -> dict[str, Any]:
    """The data set's global attributes: the case, the model, its settings and hash, the
    headline's note, the version and the time made (UTC); ``points`` on the grid."""
    from spurdyn.version import __version__

    return {
        "title": f"spurdyn speed sweep: {plan.case.name} ({plan.model})",
        "source": "spurdyn (Lee & Jang dynamic contact analysis of spur gears)",
        "case_name": plan.case.name,
        "model": plan.model,
        "settings_hash": plan.settings,
        "settings": json.dumps(_clean(settings_dict(plan.case)), sort_keys=True),
        "speed_ratio_b_to_a": float(plan.case.run.speed_b / plan.case.run.speed_a),
        "teeth_a": teeth_a,
        "torque_dimension": int(plan.torques is not None),
        "points": points,
        "status_legend": STATUS_LEGEND,
        **headline_attrs(),
        "spurdyn_version": __version__,
        "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }


def sweep_dataset(plan: SweepPlan, records: Mapping[PointKey, Mapping[str, Any]],
                  missing_reason: Mapping[PointKey, str] | None = None,
                  extra_attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """One model's sweep as a data set: every point of ``plan``, stored or not.

    Parameters
    ----------
    plan
        The sweep (grids, case, model).
    records
        Point records (:func:`point_record`) by key; keys of ``plan`` without a record are
        ``not_run``.
    missing_reason
        Why a point without a record was not run (e.g. ``"interrupted"``).
    extra_attrs
        More global attributes (the natural-frequency estimate).

    Returns
    -------
    xarray.Dataset
        Dimensions ``rpm`` and, when ``plan.torques`` is given, ``torque`` (else ``torque``
        is a scalar coordinate). Variables: :data:`FIGURES`, ``status`` (int8 code, see
        :data:`STATUS_CODES`), ``reason``, ``iso_kv`` where ISO's figures apply;
        coordinate ``mesh_frequency`` (Hz).
    """
    missing_reason = missing_reason or {}
    rpms, torques = np.asarray(plan.rpms, float), np.asarray(plan.torque_values, float)
    values, status, reason = _point_grids(plan, records, missing_reason)
    data_vars = _figure_variables(values, status, reason)
    from spurdyn.sweep.resonance import iso_kv_grid

    kv = iso_kv_grid(plan.case, rpms, torques)
    if kv is not None:
        data_vars["iso_kv"] = (("rpm", "torque"), kv, {
            "units": "1", "long_name": "ISO 6336-1 dynamic factor K_v (method B, perfect "
            "gears, no tip relief) at the speed and torque"})
    teeth_a = plan.case.pair.gear_a.teeth
    coords = {
        "rpm": ("rpm", rpms, {"units": "rpm", "long_name": "initial speed of gear A"}),
        "torque": ("torque", torques, {"units": "N m", "long_name": "external torque on the driver"}),
        "mesh_frequency": ("rpm", teeth_a * rpms / 60.0,
                           {"units": "Hz", "long_name": "tooth mesh frequency z_a rpm / 60"}),
    }
    attrs = _sweep_attrs(plan, int(rpms.size * torques.size), teeth_a)
    attrs.update(extra_attrs or {})
    ds = xr.Dataset(data_vars, coords=coords, attrs=attrs)
    if plan.torques is None:
        ds = ds.squeeze("torque")  # torque stays as a scalar coordinate
    return ds


def write_dataset(ds: xr.Dataset, path: Path) -> None:
    """Write ``ds`` as NetCDF-4 through a temporary file renamed into place."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    encoding: dict[str, Any] = {}
    for name, var in ds.data_vars.items():
        if var.dtype.kind in "fiu":
            encoding[name] = {"zlib": True, "complevel": 4}
        if var.dtype.kind == "f":
            encoding[name]["_FillValue"] = np.nan
        elif var.dtype.kind in "iu":
            encoding[name]["_FillValue"] = None
    ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
    os.replace(tmp, path)


def load_dataset(path: Path) -> xr.Dataset:
    """Read a sweep file into memory (the file is closed again)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


def model_datasets(out: Path) -> dict[str, xr.Dataset]:
    """The ``sweep_<model>.nc`` files in ``out``, by model (unreadable ones and those
    written before the headline became the averaged force left out)."""
    found = {}
    for model in MODELS:
        path = out / sweep_file(model)
        if path.is_file():
            try:
                ds = load_dataset(path)
            except (OSError, ValueError):
                continue
            if CURRENT_FIGURE in ds:
                found[model] = ds
    return found


def combine(datasets: Mapping[str, xr.Dataset]) -> xr.Dataset:
    """Every model's sweep along a ``model`` dimension (outer join of the grids).

    Speeds (and torques) that one model's sweep did not ask for are
    ``status = not_requested`` with no figures. A sweep without a ``torque`` dimension
    gets one of length 1 when another has it.
    """
    models = list(datasets)
    parts = [datasets[m] for m in models]
    with_torque = any("torque" in ds.dims for ds in parts)
    aligned = []
    for ds in parts:
        if with_torque and "torque" not in ds.dims:
            ds = ds.expand_dims("torque")
        ds = ds.drop_vars("mesh_frequency")
        ds.attrs = {}
        aligned.append(ds)
    aligned = list(xr.align(*aligned, join="outer", fill_value={
        "status": STATUS_CODES[NOT_REQUESTED], "reason": "", "separations": -1, "steps": -1}))
    combined = xr.concat(aligned, dim=xr.Variable("model", models), data_vars="all",
                         coords="minimal", compat="override", join="outer")
    combined["status"] = combined["status"].astype(np.int8)
    combined["status"].attrs = _status_attrs()
    combined["separations"] = combined["separations"].astype(np.int32)
    combined["steps"] = combined["steps"].astype(np.int64)
    for name, (units, long_name) in FIGURES.items():
        combined[name].attrs = {"units": units, "long_name": long_name}
    combined["reason"] = combined["reason"].astype(str)
    teeth = int(parts[0].attrs.get("teeth_a", 0))
    combined = combined.assign_coords(mesh_frequency=("rpm", teeth * combined["rpm"].values / 60.0,
                                                      {"units": "Hz", "long_name":
                                                       "tooth mesh frequency z_a rpm / 60"}))
    for key in ("settings_hash", "settings", "case_name", "created_utc"):
        combined[key] = ("model", np.array([str(ds.attrs.get(key, "")) for ds in parts]),
                         {"long_name": f"{key} of each model's sweep"})
    first = parts[0].attrs
    combined.attrs = {
        "title": "spurdyn speed sweep: " + ", ".join(
            f"{ds.attrs.get('case_name', '')} ({m})" for m, ds in zip(models, parts)),
        "source": first.get("source", ""),
        "teeth_a": teeth,
        "status_legend": STATUS_LEGEND,
        "models": " ".join(models),
        "same_settings": int(len({ds.attrs.get("settings_hash") for ds in parts}) == 1),
        **headline_attrs(),
        "spurdyn_version": first.get("spurdyn_version", ""),
    }
    for key in ("natural_frequency_hz", "mesh_stiffness_mean", "resonance_rpm",
                "equivalent_mass"):
        if key in first:
            combined.attrs[key] = first[key]
    return combined


def statuses(ds: xr.Dataset) -> dict[str, int]:
    """How many points of a one-model sweep have each status."""
    codes = np.asarray(ds["status"].values).ravel()
    return {name: int(np.sum(codes == code)) for name, code in STATUS_CODES.items()}


def write_sweep_files(out: Path, ds: xr.Dataset) -> tuple[Path, Path]:
    """Write ``sweep_<model>.nc`` and the combined ``sweep.nc``; return both paths."""
    model = str(ds.attrs["model"])
    own = out / sweep_file(model)
    write_dataset(ds, own)
    others = {m: d for m, d in model_datasets(out).items() if m != model}
    combined = combine({m: (ds if m == model else others[m]) for m in MODELS
                        if m == model or m in others})
    path = out / SWEEP_FILE
    write_dataset(combined, path)
    return own, path


__all__ = ["POINTS_DIR", "RUNS_DIR", "SWEEP_FILE", "PNG_FILE", "STATUS_CODES", "STATUS_LEGEND",
           "FINAL", "CURRENT_FIGURE", "combine", "load_dataset", "model_datasets", "point_path", "point_record",
           "read_point", "run_path", "stored_points", "statuses", "sweep_dataset",
           "sweep_file", "write_dataset", "write_point", "write_sweep_files"]
