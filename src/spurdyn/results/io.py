"""What a run leaves on disk, and reading it back.

A run folder holds

``result.nc``
    The time history as NetCDF (xarray, engine ``netcdf4``): dimension ``time``, one
    variable per quantity with CF ``units`` and ``long_name``; the tooth frames along a
    second dimension ``frame``; the whole case (pair and run settings, TOML units) as the
    JSON global attribute ``case``, the outcome in ``status`` and ``reason``.
``contact_force.csv``
    ``angle_deg,time_s,contact_force_N``.
``contact_force.png``
    The contact force against the rotation of A (see :mod:`spurdyn.results.plots`).
``summary.json``
    The figures of the run (:func:`summarize`), all computed from ``result.nc``.

:func:`load_run` reads ``result.nc`` back, :func:`case_from_run` rebuilds the case.
"""

from __future__ import annotations

import json
import math
from contextlib import nullcontext
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from spurdyn.case.file import Case, case_to_dict
from spurdyn.errors import InputError
from spurdyn.result import STAGES, Result
from spurdyn.results.beside import beside
from spurdyn.results.frames import (
    ToothFrames,
    case_from_run,
    speeds_label,
    tooth_frames,
)
from spurdyn.results.headline import headline
from spurdyn.results.keys import run_conditions, select, settings_of
from spurdyn.results.pairs import info_figures, pair_variables
from spurdyn.results.stress import root_stress_variables, stress_summary
from spurdyn.results.vibration import result_sensors, vibration_figures
from spurdyn.settings import PAPER_MODEL

RESULT_FILE = "result.nc"
CSV_FILE = "contact_force.csv"
PNG_FILE = "contact_force.png"
SUMMARY_FILE = "summary.json"

_STAGE_UNITS = {"displacement": "m", "velocity": "m s-1", "acceleration": "m s-2"}


def _jsonable(value: Any) -> Any:
    """Plain JSON types: numpy scalars and arrays unwrapped, NaN and inf as ``None``."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    if value is None or isinstance(value, str):
        return value
    return str(value)


def _model_figures(result: Result, case: Case) -> dict[str, Any]:
    """``n_dof``, ``theta_s``, ``theta_2``, ``static_force``, ``single_zone``: from the
    solver's ``info`` when it gives them, else from the case."""
    info = result.info
    pair = case.pair
    if "n_dof" in info:
        n_dof = int(info["n_dof"])
    else:
        from spurdyn.mesh.tooth import tooth_mesh

        n_dof = sum(tooth_mesh(g, case.run.nx, case.run.ny).n_dof + 1
                    for g in (pair.gear_a, pair.gear_b))
    theta_s = float(info.get("theta_s", pair.theta_s))
    theta_2 = float(info.get("theta_2", pair.theta_2))
    zone = info.get("single_zone", (theta_2, theta_s - theta_2))
    return {"n_dof": n_dof, "theta_s": theta_s, "theta_2": theta_2,
            "static_force": float(info.get("static_force", case.static_force)),
            "single_zone": (float(zone[0]), float(zone[1]))}


def result_to_dataset(result: Result, case: Case) -> xr.Dataset:
    """The run as an :class:`xarray.Dataset` (what ``result.nc`` holds).

    Parameters
    ----------
    result
        What the solver returned.
    case
        The case that was run; stored whole as the JSON attribute ``case``.
    """
    n = len(result.time)
    data_vars = _time_variables(result, n)
    data_vars.update(_frame_variables(result))
    coords = {"time": xr.Variable(("time",), np.asarray(result.time, float),
                                  {"units": "s", "long_name": "time since the start of contact",
                                   "standard_name": "time"})}
    if "back_pair_force" in data_vars:
        coords["back_pair"] = xr.Variable(("back_pair",), np.asarray(result.info["back_pair_teeth"], np.int32), {
            "units": "1", "long_name": "the driver's tooth of the pair of back flanks (the driven "
            "gear's is -k+1)"})
    if "pair_force" in data_vars and "pair_teeth" in result.info:
        coords["pair"] = xr.Variable(("pair",), np.asarray(result.info["pair_teeth"], np.int32), {
            "units": "1", "long_name": "the driver's tooth of the pair (the driven gear's is its "
            "negative; 0 enters the path at the start, negative ones later)"})
    data_vars.update(result_sensors(result, case.pair.working_pressure_angle))
    return xr.Dataset(data_vars, coords=coords, attrs=_dataset_attrs(result, case))


def _column(a: Any, j: int, n: int) -> NDArray[Any]:
    """Column ``j`` of a per-sample array of ``n`` rows; NaN where the solver gave none."""
    a = np.asarray(a)
    return a[:, j] if a.ndim == 2 and a.shape[0] == n else np.full(n, np.nan)


def _variable(data: Any, units: str, long_name: str, **extra: Any) -> xr.Variable:
    """A variable along ``time`` with its units and long name."""
    return xr.Variable(("time",), np.asarray(data), {"units": units, "long_name": long_name, **extra})


def _time_variables(result: Result, n: int) -> dict[str, Any]:
    """The dataset's variables along ``time``: the gears' motion, the contact, the pairs',
    and the solver's own (:func:`_solver_variables`)."""
    var = _variable
    data_vars: dict[str, Any] = {
        "angle_deg": var(np.degrees(result.angle), "degree",
                         "rotation of gear A since the start of contact"),
        "contact_force": var(result.contact_force, "N",
                             "normal contact force between the teeth, compression positive"),
        "gap": var(result.gap, "m", "normal gap between the contact points, negative "
                   "when the surfaces interpenetrate"),
        "theta_a": var(_column(result.theta, 0, n), "rad", "rotation of gear A since the start "
                       "(clockwise)"),
        "theta_b": var(_column(result.theta, 1, n), "rad", "rotation of gear B since the start "
                       "(counter-clockwise)"),
        "omega_a": var(_column(result.omega, 0, n), "rad s-1", "angular speed of gear A"),
        "omega_b": var(_column(result.omega, 1, n), "rad s-1", "angular speed of gear B"),
        "torque_a": var(_column(result.torque, 0, n), "N m", "external torque on gear A"),
        "torque_b": var(_column(result.torque, 1, n), "N m", "external torque on gear B"),
        "roll_a_deg": var(np.degrees(_column(result.roll, 0, n)), "degree",
                          "roll angle of the contact point on the involute of A"),
        "roll_b_deg": var(np.degrees(_column(result.roll, 1, n)), "degree",
                          "roll angle of the contact point on the involute of B"),
    }
    if result.contact_half_width is not None and result.contact_pressure_max is not None:
        data_vars["contact_half_width"] = var(
            result.contact_half_width, "m", "half-width of the Hertzian contact strip of the "
            "contact force (the strip the hertz contact spreads it over)")
        data_vars["contact_pressure_max"] = var(
            result.contact_pressure_max, "Pa", "peak Hertzian contact pressure of the contact "
            "force (2 F / (pi b L))")
    data_vars.update(pair_variables(result, n))
    data_vars.update(_solver_variables(result, n))
    return data_vars


def _solver_variables(result: Result, n: int) -> dict[str, xr.Variable]:
    """The constraint iteration's final error and iterations of each stage the integrator
    has, and the contact point's corner flag: none for a model that has no such thing
    (:class:`~spurdyn.result.Result`)."""
    out: dict[str, xr.Variable] = {}
    if result.residual is not None and result.iterations is not None:
        residual, iterations = np.asarray(result.residual), np.asarray(result.iterations)
        for j, stage in enumerate(STAGES[:residual.shape[1]]):
            out[f"residual_{stage}"] = _variable(
                _column(residual, j, n), _STAGE_UNITS[stage],
                f"final constraint error of the {stage} stage (max norm)")
            out[f"iterations_{stage}"] = _variable(
                _column(iterations, j, n).astype(np.int32), "1", f"iterations of the {stage} stage")
    if result.corner is not None:
        out["corner"] = _variable(np.asarray(result.corner).astype(np.int8), "1",
                                  "where the contact point is", flag_values=np.array([0, 1, 2], np.int8),
                                  flag_meanings="flank_to_flank tip_corner_of_a tip_corner_of_b")
    return out


def _frame_variables(result: Result) -> dict[str, Any]:
    """The tooth frames' variables along ``frame`` (none where the run kept no frame)."""
    frame_time = np.asarray(result.frame_time, float)
    if not frame_time.size:
        return {}
    f = ("frame",)
    theta = np.asarray(result.frame_theta, float).reshape(frame_time.size, 2)
    return {
        "frame_time": xr.Variable(f, frame_time, {"units": "s", "long_name": "time of the tooth frame"}),
        "frame_theta_a": xr.Variable(f, theta[:, 0], {
            "units": "rad", "long_name": "rotation of gear A since the start at the frame"}),
        "frame_theta_b": xr.Variable(f, theta[:, 1], {
            "units": "rad", "long_name": "rotation of gear B since the start at the frame"}),
        "frame_u": xr.Variable(("frame", "dof"), np.asarray(result.frame_u, float), {
            "units": "m", "long_name": "absolute nodal displacements of both teeth in the "
            "world frame, A's then B's, [u0x, u0y, u1x, ...]"}),
    }


def _dataset_attrs(result: Result, case: Case) -> dict[str, Any]:
    """The dataset's attributes: the case whole (JSON), the run's status and figures, its
    ``info`` (JSON) and the version that wrote it."""
    figures = _model_figures(result, case)
    attrs = {
        "title": f"spurdyn dynamic contact analysis: {case.name}",
        "Conventions": "CF-1.10",
        "source": "spurdyn (Lee & Jang dynamic contact analysis of spur gears)",
        "case_name": case.name,
        "case": json.dumps(_jsonable(case_to_dict(case))),
        "status": result.status,
        "reason": result.reason or "",
        "steps": int(result.steps),
        "wall_s": float(result.wall_s),
        "dt_s": float(result.info.get("dt_s", case.run.dt)),   # a model's own step if it sets one
        # one engagement: the angle it set out to cover (a steady state covers cycles)
        **({} if "steady" in result.info else {"angle_target_deg": math.degrees(case.angle)}),
        "n_dof": figures["n_dof"],
        "theta_s_deg": math.degrees(figures["theta_s"]),
        "theta_2_deg": math.degrees(figures["theta_2"]),
        "single_zone_deg": np.degrees(np.array(figures["single_zone"])),
        "static_force_N": figures["static_force"],
        # the sector model's end state (its whole coordinates, for a continuation's next run)
        # is kept in memory, not in the file; its quasi-static cycle is in variables
        "info": json.dumps(_jsonable({k: v for k, v in result.info.items()
                                             if k not in ("sector_end_state", "static_cycle")})),
    }
    from spurdyn.version import __version__

    attrs["spurdyn_version"] = __version__
    return attrs


def write_netcdf(ds: xr.Dataset, path: Path) -> None:
    """Write ``ds`` as NetCDF-4 (compressed) with the ``netcdf4`` engine."""
    encoding = {name: {"zlib": True, "complevel": 4} for name in ds.data_vars}
    ds.to_netcdf(path, engine="netcdf4", encoding=encoding)


def load_run(directory: str | Path) -> xr.Dataset:
    """Read a run folder's ``result.nc`` into memory (the file is closed again).

    Parameters
    ----------
    directory
        A run folder, or the ``result.nc`` file itself.

    Raises
    ------
    InputError
        If there is no readable ``result.nc``.
    """
    path = Path(directory)
    if path.is_dir():
        path = path / RESULT_FILE
    if not path.is_file():
        raise InputError(str(directory), f"is not a run folder (no {RESULT_FILE})")
    try:
        with xr.open_dataset(path, engine="netcdf4", decode_timedelta=False) as ds:
            return ds.load()
    except (OSError, ValueError) as err:
        raise InputError(str(path), f"cannot be read as NetCDF ({err})") from None


#: Contact lost for good within this fraction of ``theta_s`` of its end is the tip leaving
#: the flank at the end of the engagement, not a separation.
END_OF_ENGAGEMENT = 0.01


def _in_contact(force: NDArray[np.float64]) -> NDArray[np.bool_]:
    return np.nan_to_num(force, nan=0.0) > 0.0


#: A loss of contact counts as a separation only if the gap then opens wider than this
#: (m): ten thousand times the displacement tolerance, and under a hundredth of the
#: micrometre deflection of loaded steel teeth. Narrower partings are the settling of
#: the unloaded teeth in the first microseconds of a run (a 3 nm bounce in paper-fig8,
#: while the ramped torque is still ~0) and the flicker of the spline surfaces where
#: they miss the involute by ~1e-10 m (a 20-tooth pinion; docs/solver.md, section 4).
SEPARATION_GAP = 1e-8


def separation_times(ds: xr.Dataset) -> NDArray[np.float64]:
    """Times (s) where contact was lost after first being made and the teeth separated.

    Contact is a positive contact force; samples whose force is not finite are left out.
    A loss counts when the gap opens beyond :data:`SEPARATION_GAP` before contact is made
    again. A final loss of contact within :data:`END_OF_ENGAGEMENT` of the end of the
    angle of action (the tip leaving the flank) is not counted. With ``save_every > 1``
    only the saved samples are seen, so separations shorter than the saving interval are
    missed.
    """
    force = ds["contact_force"].values.astype(float)
    keep = np.isfinite(force)
    contact = force[keep] > 0.0
    time = ds["time"].values[keep]
    angle = ds["angle_deg"].values[keep]
    gap = np.nan_to_num(ds["gap"].values.astype(float)[keep], nan=np.inf) if "gap" in ds \
        else np.full(contact.size, np.inf)
    lost = np.flatnonzero(contact[:-1] & ~contact[1:]) + 1
    if lost.size and not contact[lost[-1]:].any() and \
            angle[lost[-1]] >= (1.0 - END_OF_ENGAGEMENT) * float(ds.attrs["theta_s_deg"]):
        lost = lost[:-1]
    made = np.flatnonzero(~contact[:-1] & contact[1:]) + 1
    wide = []
    for i in lost:
        j = made[made > i]
        end = int(j[0]) if j.size else contact.size
        wide.append(bool(np.max(gap[i:end]) > SEPARATION_GAP))
    return time[lost[np.array(wide, dtype=bool)]] if lost.size else time[lost]


def _max_or_none(ds: xr.Dataset, name: str) -> float | None:
    """The largest finite value of a variable, ``None`` if it is absent or never finite."""
    if name not in ds:
        return None
    v = ds[name].values.astype(float)
    return float(np.nanmax(v)) if np.isfinite(v).any() else None


def _run_record(ds: xr.Dataset, case: dict[str, Any], time: NDArray[np.float64],
                angle: NDArray[np.float64], zone: NDArray[np.float64]) -> dict[str, Any]:
    """The summary's first figures, in its order: what ran (``case`` to ``single_zone_deg``);
    :func:`spurdyn.results.keys.select` keeps those of its model."""
    target = ds.attrs.get("angle_target_deg")
    return {
        "case": ds.attrs["case_name"],
        "status": ds.attrs["status"],
        "reason": ds.attrs.get("reason", ""),
        "steps": int(ds.attrs["steps"]),
        "samples": int(len(time)),
        "frames": int(ds.sizes.get("frame", 0)),
        "dt_s": float(ds.attrs["dt_s"]),
        "wall_s": float(ds.attrs["wall_s"]),
        "n_dof": int(ds.attrs["n_dof"]),
        "speed_a_rpm": case["run"]["speed_a_rpm"],
        "speed_b_rpm": case["run"]["speed_b_rpm"],
        "torque_Nm": case["run"]["torque"],
        "time_s": float(time[-1]) if len(time) else 0.0,
        "angle_deg": float(angle[-1]) if len(angle) else 0.0,
        **({} if target is None else {"angle_target_deg": float(target)}),
        "theta_s_deg": float(ds.attrs["theta_s_deg"]),
        "single_zone_deg": [float(zone[0]), float(zone[1])],
    }


def _stage_figures(ds: xr.Dataset, time: NDArray[np.float64]) -> dict[str, Any]:
    """``iterations_mean`` and ``residual_max``: per stage the dataset holds, the mean
    iterations over the steps (the first sample left out when there are more) and the
    largest finite residual (``None`` if none); nothing for a model without stages."""
    stages = [s for s in STAGES if f"residual_{s}" in ds]
    if not stages:
        return {}
    steps_rows = slice(1, None) if len(time) > 1 else slice(0, None)
    iterations = {s: float(np.nanmean(ds[f"iterations_{s}"].values[steps_rows]))
                  if len(time) else None for s in stages}
    residual = {}
    for s in stages:
        r = ds[f"residual_{s}"].values.astype(float)
        residual[s] = float(np.nanmax(r)) if np.isfinite(r).any() else None
    return {"iterations_mean": iterations, "residual_max": residual}


def _contact_figures(ds: xr.Dataset) -> dict[str, float | None]:
    """The largest peak pressure and half-width of the Hertzian strip, where the model
    gives them (``None`` if never finite)."""
    if "contact_pressure_max" not in ds:
        return {}
    return {"contact_pressure_max_Pa": _max_or_none(ds, "contact_pressure_max"),
            "contact_half_width_max_m": _max_or_none(ds, "contact_half_width")}


def summarize(ds: xr.Dataset) -> dict[str, Any]:
    """The figures of ``summary.json``, all computed from the dataset.

    Which keys a model's summary has, what each means and its unit is the list of
    :mod:`spurdyn.results.keys` (docs/summary.md); the figures computed here pass through
    its :func:`~spurdyn.results.keys.select`, so a key is absent where the model does not
    compute it, never a zero. Among them: ``peak_force_N`` and ``peak_angle_deg`` (the peak
    of the contact force averaged over a centred 10-us window,
    :mod:`spurdyn.results.headline`; ``None`` when the teeth never touched),
    ``dynamic_factor`` (``None`` for an incomplete run, whose largest force may be the spike
    that stopped it) and ``separations`` (:func:`separation_times`).
    """
    force = ds["contact_force"].values.astype(float)
    angle = ds["angle_deg"].values.astype(float)
    time = ds["time"].values.astype(float)
    complete = ds.attrs["status"] == "complete"
    zone = np.asarray(ds.attrs["single_zone_deg"], float).reshape(2)
    in_zone = np.isfinite(force) & (angle >= zone[0]) & (angle <= zone[1])
    static = float(ds.attrs["static_force_N"])
    head = headline(time, angle, force, static, complete, str(ds.attrs.get("reason", "")))
    seps = separation_times(ds)
    contact = _in_contact(force)
    first = time[np.argmax(contact)] if contact.any() else None
    case = json.loads(ds.attrs["case"])
    info = json.loads(ds.attrs.get("info", "{}") or "{}")
    model = str(info.get("model", PAPER_MODEL))
    summary = {
        **_run_record(ds, case, time, angle, zone),
        "peak_force_N": head.peak_force,
        "peak_angle_deg": head.peak_angle_deg,
        "peak_force_raw_N": head.peak_force_raw,
        "peak_angle_raw_deg": head.peak_angle_raw_deg,
        "mean_force_single_zone_N": float(np.mean(force[in_zone])) if in_zone.any() else None,
        "static_force_N": static,
        "dynamic_factor": head.dynamic_factor,
        "dynamic_factor_raw": head.dynamic_factor_raw,
        "dynamic_factor_note": head.note,
        "averaging_window_s": head.window_s,
        "first_contact_s": None if first is None else float(first),
        # a model that fixes these says so in its info (the sector model: strips, implicit)
        "contact": info.get("contact", case["run"].get("contact", "point")),
        "integrator": info.get("integrator", case["run"].get("integrator", "rk4")),
        **_contact_figures(ds),
        "separations": int(len(seps)),
        "separation_times_s": [float(x) for x in seps],
        **_stage_figures(ds, time),
        "settings": settings_of(case, model),
        "spurdyn_version": ds.attrs.get("spurdyn_version", ""),
    }
    # root stress along the fillets (runs with tooth frames) and ISO's nominal stresses
    summary.update(stress_summary(ds, case_from_run(ds)))
    summary.update(info_figures(ds, info, complete))
    summary.update(vibration_figures(ds, info, (int(case["gear_a"]["teeth"]), int(case["gear_b"]["teeth"]))))
    conditions = run_conditions(model, "steady" in info, "root_stress" in ds, case)
    return _jsonable(select(summary, model, conditions))


def write_csv(ds: xr.Dataset, path: Path) -> None:
    """Write ``angle_deg,time_s,contact_force_N``, one row per saved step."""
    # csv.writer's lines (CRLF) built at once from floats: half a row-by-row writer's time
    columns = (ds[name].values.tolist() for name in ("angle_deg", "time", "contact_force"))
    with open(path, "w", newline="", encoding="utf-8") as fh:
        fh.write("angle_deg,time_s,contact_force_N\r\n")
        fh.writelines([f"{a:.9g},{t:.9g},{f:.9g}\r\n" for a, t, f in zip(*columns)])


def write_summary(summary: dict[str, Any], path: Path) -> None:
    path.write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")


def write_run(result: Result, case: Case, directory: str | Path, *, png: bool = True,
              vtu: bool = False) -> dict[str, Any]:
    """Write everything a run leaves into ``directory`` (which must exist).

    Returns
    -------
    dict
        The summary written to ``summary.json``.
    """
    directory = Path(directory)
    ds = result_to_dataset(result, case)
    ds = ds.assign(root_stress_variables(ds))

    pairs = "pair_force" in ds       # a model of several pairs: their forces, the TE, the teeth

    def picture() -> None:
        from spurdyn.results.plots import plot_contact_force

        plot_contact_force([ds], directory / PNG_FILE)
        if pairs:
            from spurdyn.results.mesh_plot import plot_pair_pictures

            plot_pair_pictures(ds, directory, part=0)

    # The picture is drawn in a child process on the other core meanwhile (done when the
    # block ends; without a child, drawn here after the rest); a run of several pairs has
    # the other part of its pictures drawn here after the files, about as long.
    with beside(picture) if png else nullcontext():
        write_netcdf(ds, directory / RESULT_FILE)
        write_csv(ds, directory / CSV_FILE)
        summary = summarize(ds)
        write_summary(summary, directory / SUMMARY_FILE)
        if png and pairs:
            from spurdyn.results.mesh_plot import plot_pair_pictures

            plot_pair_pictures(ds, directory, part=1)
    if vtu and "frame_u" in ds:
        from spurdyn.results.vtu import write_vtu_series

        write_vtu_series(ds, directory)
    return summary


__all__ = [
    "RESULT_FILE", "CSV_FILE", "PNG_FILE", "SUMMARY_FILE", "ToothFrames", "case_from_run",
    "load_run", "result_to_dataset", "separation_times", "speeds_label", "summarize",
    "tooth_frames", "write_csv", "write_netcdf", "write_run", "write_summary",
]
