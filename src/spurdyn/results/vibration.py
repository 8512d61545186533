"""What sensors see of a sector run, and the condition indicators a gear-diagnostics study
reads from it (docs/faults.md, section 9; the processing: docs/diagnostics.md).

The signals, in ``result.nc`` along ``time``:

- ``hub_acceleration_a``, ``hub_acceleration_b``: each hub's angular acceleration (what an
  encoder's speed differentiated or a torsional accelerometer reads), the central
  differences of the hub's speed (second order; one-sided at the ends);
- ``mesh_force`` (the pairs' total normal force, written by :mod:`spurdyn.results.pairs`);
- ``bearing_force_separating`` and ``bearing_force_transverse``: the force each hub's
  bearing carries, along the line of centres (pushing the gears apart) and across it, from
  the contacts' forces on their two lines of action: ``(F_d + F_b) sin alpha_w`` and
  ``(F_d - F_b) cos alpha_w``, ``F_d`` the drive flanks' total and ``F_b`` the back flanks'
  (the two hubs' are equal and opposite; the bodies' own inertia, whose centre of mass the
  deformation moves by micrometres, is left out). With the hubs on bearings (docs/sector.md,
  6.12) they are the force the followed gear's bearing carries instead, ``k x + c x_dot``
  (their ``source`` attribute says which), and each hub's own are beside them:
  ``hub_displacement_separating_a`` ... and ``bearing_force_separating_a`` ... (a hub whose
  centre is held: the contacts' force).

The indicators (``summary.json``'s ``vibration``) are taken over the whole revolutions of
the faulty gear (of the driver on a healthy pair) from the last mesh cycle of its first
(:func:`window`), each signal's time-synchronous average on that gear's turn; absent where
the run holds no whole revolution there.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from spurdyn import diagnostics as dg

#: The sensors' variables this module adds: name -> (units, long name).
SENSOR_VARIABLES = {
    "hub_acceleration_a": ("rad s-2", "angular acceleration of gear A's hub (central differences of omega_a)"),
    "hub_acceleration_b": ("rad s-2", "angular acceleration of gear B's hub (central differences of omega_b)"),
    "bearing_force_separating": ("N", "force on each hub's bearing along the line of centres, pushing the "
                                      "gears apart: (F_drive + F_back) sin(alpha_w)"),
    "bearing_force_transverse": ("N", "force on each hub's bearing across the line of centres: "
                                      "(F_drive - F_back) cos(alpha_w)"),
}
#: The signals the indicators are computed for.
SIGNALS = ("mesh_force", "hub_acceleration_a", "hub_acceleration_b", "bearing_force_transverse")
#: Sidebands each side of the mesh frequency the sideband energy ratio sums.
SER_SIDEBANDS = 6


def sensor_variables(time: NDArray[np.float64], omega: NDArray[np.float64], drive: NDArray[np.float64],
                     back: NDArray[np.float64] | None, alpha_w: float) -> dict[str, xr.Variable]:
    """The variables of :data:`SENSOR_VARIABLES` from the hubs' speeds ``omega`` ``(n, 2)``
    (rad/s, A's and B's), the drive flanks' total force ``drive`` ``(n,)`` and the back
    flanks' ``back`` (N; ``None`` without back contacts) at ``time`` (s)."""
    data: dict[str, NDArray[np.float64]] = {}
    for g, name in enumerate(("hub_acceleration_a", "hub_acceleration_b")):
        data[name] = np.gradient(omega[:, g], time) if time.size > 1 else np.full(time.size, np.nan)
    fd = np.nan_to_num(drive)
    fb = np.zeros_like(fd) if back is None else np.nan_to_num(back)
    data["bearing_force_separating"] = (fd + fb) * math.sin(alpha_w)
    data["bearing_force_transverse"] = (fd - fb) * math.cos(alpha_w)
    return {k: xr.Variable(("time",), v, {"units": SENSOR_VARIABLES[k][0], "long_name": SENSOR_VARIABLES[k][1]})
            for k, v in data.items()}


def result_sensors(result: Any, alpha_w: float) -> dict[str, xr.Variable]:
    """:func:`sensor_variables` of a sector run's :class:`~spurdyn.result.Result` (none for
    another model's, or a run without samples); with the hubs on bearings,
    :func:`bearing_variables` in place of the rigid hubs' bearing forces."""
    if result.info.get("model") != "sector" or result.pair_force is None or not len(result.time):
        return {}
    back = None if result.back_force is None else np.nansum(np.asarray(result.back_force, float), axis=1)
    out = sensor_variables(np.asarray(result.time, float), np.asarray(result.omega, float),
                           np.nansum(np.asarray(result.pair_force, float), axis=1), back, alpha_w)
    if result.hub_translation is not None:
        gear = result.info.get("fault_gear") or result.info.get("driver", "a")
        out.update(bearing_variables(np.asarray(result.hub_translation, float), result.info["bearings"], out, gear))
    return out


#: The hubs' own variables with bearings: name -> (units, long name), ``{g}`` the gear.
BEARING_VARIABLES = {
    "hub_displacement_separating_{g}": ("m", "gear {G}'s hub's translation along the line of centres, away from "
                                             "the other gear"),
    "hub_displacement_transverse_{g}": ("m", "gear {G}'s hub's translation across the line of centres (the side "
                                             "the drive flanks' force on it points to)"),
    "bearing_force_separating_{g}": ("N", "force gear {G}'s bearing carries along the line of centres"),
    "bearing_force_transverse_{g}": ("N", "force gear {G}'s bearing carries across the line of centres"),
}


def bearing_variables(hubs: NDArray[np.float64], bearings: list[Any], rigid: dict[str, xr.Variable],
                      gear: str) -> dict[str, xr.Variable]:
    """Each hub's translation and the force its bearing carries, ``k x + c x_dot`` in its
    gear's frame (the contacts' force, ``rigid``'s, on a hub whose centre is held), from
    ``hubs`` ``(n, 8)`` (:attr:`~spurdyn.result.Result.hub_translation`) and ``bearings``
    (the result's record, A's and B's); ``bearing_force_separating`` and
    ``bearing_force_transverse`` then the followed ``gear``'s."""
    out: dict[str, xr.Variable] = {}
    for j, (g, b) in enumerate(zip("ab", bearings)):
        x, v = hubs[:, 2 * j:2 * j + 2], hubs[:, 4 + 2 * j:6 + 2 * j]
        values = [x[:, 0], x[:, 1]]
        if b is None:
            source = "the contacts' force (this hub's centre is held)"
            values += [rigid["bearing_force_separating"].values, rigid["bearing_force_transverse"].values]
        else:
            source = f"gear {g.upper()}'s bearing: k x + c x_dot, k = {b['stiffness']:g} N/m, c = {b['damping']:g} N s/m"
            values += list((b["stiffness"] * x + b["damping"] * v).T)
        for (name, (units, long)), value in zip(BEARING_VARIABLES.items(), values):
            attrs = {"units": units, "long_name": long.format(G=g.upper())}
            if name.startswith("bearing"):
                attrs["source"] = source
            out[name.format(g=g)] = xr.Variable(("time",), np.array(value, float), attrs)
        if g == gear:
            for name in ("bearing_force_separating", "bearing_force_transverse"):
                own = out[f"{name}_{g}"]
                out[name] = xr.Variable(("time",), own.values.copy(), {
                    "units": "N", "long_name": f"force on gear {g.upper()}'s bearing (the followed gear's) "
                    + ("along the line of centres" if "separating" in name else "across the line of centres"),
                    "source": source})
    return out


def window(ds: xr.Dataset, steady: dict[str, Any], teeth: int) -> NDArray[np.bool_]:
    """The samples the indicators read: from the last mesh cycle of the first revolution
    (the start's transient before it) of a run of two and more (a revolution: a faulty
    pair's period, else the ``teeth`` mesh cycles of the gear followed), else the settled
    window."""
    time = ds["time"].values.astype(float)
    lo = float(steady["window_s"][0])
    turn = int(steady.get("period_mesh_cycles", teeth))
    done = int(steady["cycles_done"])
    if done >= 2 * turn:
        # from a mesh cycle before the first revolution's end: a whole revolution after it
        # whatever the gear's lag on its nominal turn
        lo = min(lo, float(time[-1]) * (turn - 1) / done)
    return time >= lo - 1e-15


def synchronous(signal: NDArray[np.float64], angle: NDArray[np.float64], teeth: int) -> dg.SynchronousAverage:
    """The time-synchronous average of ``signal`` over the whole revolutions from the
    window's start (``angle``'s first value; rad), turned so that its point ``i`` is at the
    gear's angle ``2 pi i / N`` round a revolution (the average is periodic: turned by the
    nearest point)."""
    points = tsa_points(angle, teeth)
    tsa = dg.synchronous_average(signal, angle - angle[0], points)
    shift = int(round((float(angle[0]) % (2.0 * math.pi)) / (2.0 * math.pi) * points)) % points
    return dg.SynchronousAverage(np.roll(tsa.signal, shift), tsa.revolutions)


def tsa_points(angle: NDArray[np.float64], teeth: int) -> int:
    """Points a revolution of the time-synchronous average: the power of two at or above the
    samples a revolution (no aliasing in the resampling) and four a tooth."""
    per_rev = angle.size * 2.0 * math.pi / max(abs(float(angle[-1] - angle[0])), 1e-300)
    return int(2 ** math.ceil(math.log2(max(per_rev, 4 * teeth))))


def signal_indicators(signal: NDArray[np.float64], angle: NDArray[np.float64], teeth: int) -> dict[str, Any]:
    """The indicators of one signal over whole revolutions of the gear of ``teeth`` teeth
    turning by ``angle`` (rad): RMS, kurtosis and crest factor of the signal about its
    mean; FM0, FM4, NA4 and the sideband energy ratio (six shaft orders each side of the
    mesh order) of its time-synchronous average."""
    return average_indicators(signal, synchronous(signal, angle, teeth), teeth)


def average_indicators(signal: NDArray[np.float64], tsa: dg.SynchronousAverage, teeth: int) -> dict[str, Any]:
    """:func:`signal_indicators` of ``signal`` and its time-synchronous average ``tsa`` (any
    turn of it round the revolution: the indicators do not depend on where it starts)."""
    x = signal - signal.mean()
    finite = {
        "rms": dg.rms(x), "kurtosis": dg.kurtosis(x), "crest_factor": dg.crest_factor(x),
        "fm0": dg.fm0(tsa.signal, teeth), "fm4": dg.fm4(tsa.signal, teeth), "na4": dg.na4(tsa.signal, teeth),
        # on the average's shaft orders: a record of a revolution or two puts a spectrum's
        # bins a shaft frequency apart, the sidebands in the mesh tone's leakage
        "sideband_energy_ratio": dg.order_sideband_energy_ratio(tsa.signal, teeth, SER_SIDEBANDS),
    }
    out: dict[str, Any] = {k: (float(v) if math.isfinite(v) else None) for k, v in finite.items()}
    out["revolutions"] = int(tsa.revolutions)
    return out


class Followed(NamedTuple):
    """The gear a diagnostics study follows and the samples it reads: ``gear`` (``"a"`` or
    ``"b"``), its ``teeth``, the window ``sel``, the gear's ``angle`` (rad) and the ``time``
    (s) there, and its shaft frequency ``f_shaft`` (Hz) over them."""

    gear: str
    teeth: int
    sel: NDArray[np.bool_]
    angle: NDArray[np.float64]
    time: NDArray[np.float64]
    f_shaft: float


def followed(ds: xr.Dataset, info: dict[str, Any], teeth: tuple[int, int]) -> Followed | None:
    """The faulty gear (the driver on a healthy pair; ``teeth`` A's and B's) and its
    :func:`window`; ``None`` where the run has no sensors' signals or the window holds less
    than one revolution."""
    steady = info.get("steady")
    if steady is None or any(name not in ds for name in SIGNALS):
        return None
    gear = info.get("fault_gear") or info.get("driver", "a")
    z = teeth[0 if gear == "a" else 1]
    sel = window(ds, steady, z)
    angle = ds[f"theta_{gear}"].values.astype(float)[sel]
    time = ds["time"].values.astype(float)[sel]
    if angle.size < 8 or abs(angle[-1] - angle[0]) < 2.0 * math.pi:
        return None
    f_shaft = abs(angle[-1] - angle[0]) / (time[-1] - time[0]) / (2.0 * math.pi)
    return Followed(gear, z, sel, angle, time, f_shaft)


def vibration_figures(ds: xr.Dataset, info: dict[str, Any], teeth: tuple[int, int]) -> dict[str, Any]:
    """``{"vibration": ...}`` for ``summary.json``: per signal of :data:`SIGNALS` the
    indicators of :func:`signal_indicators` over the :func:`followed` gear's window; empty
    where there is none."""
    f = followed(ds, info, teeth)
    if f is None:
        return {}
    signals = {name: signal_indicators(ds[name].values.astype(float)[f.sel], f.angle, f.teeth) for name in SIGNALS}
    return {"vibration": {"gear": f.gear, "shaft_frequency_Hz": f.f_shaft, "mesh_frequency_Hz": f.teeth * f.f_shaft,
                          "window_s": [float(f.time[0]), float(f.time[-1])], "signals": signals}}

__all__ = ["BEARING_VARIABLES", "SENSOR_VARIABLES", "bearing_variables", "SIGNALS", "Followed", "average_indicators", "followed", "result_sensors", "sensor_variables", "signal_indicators",
           "synchronous", "tsa_points", "vibration_figures", "window"]
