"""Root stress of a run's tooth frames, and ISO 6336's nominal stresses beside it.

:func:`root_stress_variables` recovers the stress along both fillets of each tooth at every
saved tooth frame (:mod:`spurdyn.model.root`) and keeps, per frame and gear, the largest
(tension) and smallest (compression) and where along the fillet they are (their radius).
:func:`iso_figures` gives ISO 6336's nominal tooth-root stress ``sigma_F0`` of each gear
(part 3, method B) and nominal contact stress ``sigma_H0`` (part 2) for the run's pair and
static load. :func:`stress_summary` turns both into the figures of ``summary.json``.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import xarray as xr

from spurdyn.case.file import Case
from spurdyn.model.root import peaks, root_surface
from spurdyn.results.frames import tooth_frames

#: The variables :func:`root_stress_variables` adds: name -> (units, long name).
ROOT_VARIABLES = {
    "root_stress": ("Pa", "largest stress along the fillets of the tooth (tension positive: "
                          "the largest principal stress at the free surface)"),
    "root_stress_position": ("m", "distance from the gear centre of the fillet point of "
                                  "root_stress"),
    "root_stress_compressive": ("Pa", "smallest stress along the fillets of the tooth "
                                      "(compression negative)"),
    "root_stress_compressive_position": ("m", "distance from the gear centre of the fillet "
                                              "point of root_stress_compressive"),
}


def tooth_stress_variables(result: Any) -> dict[str, xr.Variable]:
    """The root stress of every tooth of a result with a
    :class:`~spurdyn.result.ToothStress` (the sector model's): the coordinates
    ``stress_time`` (s), ``tooth_a`` and ``tooth_b`` (the bodies' tooth numbers) and, per
    gear, the variables of :data:`ROOT_VARIABLES` along ``(stress_time, tooth_a|b)``;
    none for a result without it."""
    ts = getattr(result, "tooth_stress", None)
    if ts is None:
        return {}
    out = {"stress_time": xr.Variable(("stress_time",), np.asarray(ts.time, float), {
        "units": "s", "long_name": "time of the root stress's samples (a fixed number a mesh cycle)",
        "samples_per_cycle": int(ts.per_cycle)})}
    for g, gear in enumerate("ab"):
        dim = f"tooth_{gear}"
        out[dim] = xr.Variable((dim,), np.asarray(ts.teeth[g], np.int32), {
            "units": "1", "long_name": f"tooth of gear {gear.upper()}: the model's tooth number, "
            "the driver's tooth k carrying pair k and the driven gear's tooth -k (back flanks "
            "-k+1), both taken round the gear (docs/sector.md, 6.10)"})
        for j, (name, (units, long)) in enumerate(ROOT_VARIABLES.items()):
            out[f"{name}_{gear}"] = xr.Variable(("stress_time", dim), np.asarray(ts.values[g][j], float),
                                                {"units": units, "long_name": long})
    return out


def root_stress_variables(ds: xr.Dataset) -> dict[str, xr.Variable]:
    """The root-stress variables of a run with tooth frames, ``(frame, gear)`` each (gear 0
    is A); an empty dict for a run without frames."""
    if "frame_u" not in ds or ds.sizes.get("frame", 0) == 0:
        return {}
    frames = tooth_frames(ds)
    pair = frames.case.pair
    out = np.full((4, frames.n_frames, 2), np.nan)
    for g, gear in enumerate((pair.gear_a, pair.gear_b)):
        surface = root_surface(frames.meshes[g], gear.form_radius, gear.material,
                               positions=frames.X0[g])
        elastic = frames.elastic_all(g).reshape(frames.n_frames, -1)
        stress = surface.stress(elastic)
        for j, values in enumerate(peaks(stress, surface.radius)):
            out[j, :, g] = values
    return {name: xr.Variable(("frame", "gear"), out[j], {"units": units, "long_name": long})
            for j, (name, (units, long)) in enumerate(ROOT_VARIABLES.items())}


def _rating(case: Case) -> tuple[Any, str]:
    """ISO's rating of the run's pair under its static load (gear A the pinion), or ``None``
    and why not."""
    from spurdyn.iso6336.rating import iso_pair, rate

    pair = case.pair
    torque_a = case.run.torque if pair.driver == "a" else \
        case.run.torque * pair.gear_a.base_radius / pair.gear_b.base_radius
    if not torque_a > 0.0:
        return None, "not computed: the run carries no torque"
    try:
        return rate(iso_pair(pair), torque_a), ""
    except ValueError as err:
        return None, f"not computed: {err}"


def iso_figures(case: Case) -> dict[str, Any]:
    """ISO 6336's nominal stresses for the run's pair under its static load: ``sigma_F0``
    (Pa) of A and B, ``sigma_H0`` (Pa), or ``None`` each and the reason in ``iso6336_note``
    (ISO's formulas here need the standard centre distance)."""
    rating, why = _rating(case)
    if rating is None:
        return {"iso6336_sigma_F0_Pa": None, "iso6336_sigma_H0_Pa": None, "iso6336_note": why}
    return {"iso6336_sigma_F0_Pa": [float(s) for s in rating.sigma_f0],
            "iso6336_sigma_H0_Pa": float(rating.sigma_h0),
            "iso6336_note": "nominal stresses of ISO 6336-3 (method B, Y_F and Y_S at the "
                            "30 deg tangent) and ISO 6336-2 (Z_H Z_E Z_eps) for the static load"}


def safety_figures(case: Case, root_peaks: list[float | None] | None,
                   contact_peak: float | None) -> dict[str, Any]:
    """The safety factors of the gears whose materials give ISO 6336-5's allowable stress
    numbers (``sigma_flim``, ``sigma_hlim``): ``S_F`` and ``S_H`` from the model's dynamic
    peaks (root stress of each tooth; the strip's peak pressure) and from ISO's nominal
    stresses with its ``K_v`` at the run's speed; all other load factors 1 and the life
    and condition factors 1 (``spurdyn.iso6336.safety``). Empty without allowables."""
    from spurdyn.iso6336 import safety
    from spurdyn.iso6336.rating import dynamic_factor_at

    mats = (case.pair.gear_a.material, case.pair.gear_b.material)
    if all(m.sigma_flim is None and m.sigma_hlim is None for m in mats):
        return {}
    rating, why = _rating(case)
    k_v = None if rating is None else float(dynamic_factor_at(rating, case.run.speed_a))
    out: dict[str, Any] = {"iso6336_k_v": k_v}
    root_model, root_iso, contact_model, contact_iso = [], [], [], []
    for g, m in enumerate(mats):
        if m.sigma_flim is None:
            root_model.append(None)
            root_iso.append(None)
        else:
            limit = safety.root_limit(m.sigma_flim)
            peak = None if root_peaks is None else root_peaks[g]
            root_model.append(None if not peak else
                              safety.root_safety(safety.root_stress_from_peak(peak), limit))
            root_iso.append(None if rating is None else safety.root_safety(
                safety.root_stress(rating.sigma_f0[g], k_v=k_v), limit))
        if m.sigma_hlim is None:
            contact_model.append(None)
            contact_iso.append(None)
        else:
            limit = safety.contact_limit(m.sigma_hlim)
            contact_model.append(None if not contact_peak else safety.contact_safety(
                safety.contact_stress_from_peak(contact_peak), limit))
            contact_iso.append(None if rating is None else safety.contact_safety(
                safety.contact_stress(rating.sigma_h0, k_v=k_v,
                                      z_b=rating.z_b if g == 0 else rating.z_d), limit))
    out.update({"safety_root_model": root_model, "safety_root_iso": root_iso,
                "safety_contact_model": contact_model, "safety_contact_iso": contact_iso,
                "safety_note": "S = allowable / stress; model: the run's dynamic peak root "
                               "stress and strip pressure; ISO: sigma_F0 K_v and Z_B|D sigma_H0 "
                               "sqrt(K_v); K_A = K_beta = K_alpha = 1, life and condition "
                               "factors 1" + ("" if rating is not None else f"; ISO {why}")})
    return out


def _stress_window(ds: xr.Dataset) -> tuple[float, float, str]:
    """The times a sector run's root-stress peaks are taken over: a complete steady-state
    run's last cycles (those of its dynamic factor), else the whole run; and what it was."""
    info = json.loads(ds.attrs.get("info", "{}") or "{}")
    steady = info.get("steady")
    if steady and ds.attrs.get("status") == "complete":
        lo, hi = steady["window_s"]
        return float(lo), float(hi), (f"over the last {steady['last_cycles']} mesh cycle(s), "
                                      f"{lo:.6g} to {hi:.6g} s, as the dynamic factor")
    return -np.inf, np.inf, "over the whole run (it was not complete)"


def sector_stress_summary(ds: xr.Dataset) -> dict[str, Any]:
    """The root-stress peaks of a run with every tooth's stress (``root_stress_a`` ...,
    the sector model's): per gear (A, B) the largest stress over its teeth and the samples
    of the settled window (:func:`_stress_window`), its position, tooth and time, and the
    smallest (compressive) one and its position; empty for a run without them."""
    if "root_stress_a" not in ds:
        return {}
    lo, hi, said = _stress_window(ds)
    t = ds["stress_time"].values
    rows = (t >= lo - 1e-12) & (t <= hi + 1e-12)
    keys = ("root_stress_max_Pa", "root_stress_max_position_m", "root_stress_max_tooth",
            "root_stress_max_time_s", "root_stress_compressive_min_Pa",
            "root_stress_compressive_position_m")
    out: dict[str, Any] = {k: [] for k in keys}
    for gear in "ab":
        teeth = ds[f"tooth_{gear}"].values
        found = []
        for name, best in (("root_stress", np.nanargmax), ("root_stress_compressive", np.nanargmin)):
            v = ds[f"{name}_{gear}"].values[rows]
            if not np.isfinite(v).any():
                found.append(None)
                continue
            s, k = np.unravel_index(int(best(v)), v.shape)
            found.append((float(v[s, k]), float(ds[f"{name}_position_{gear}"].values[rows][s, k]),
                          int(teeth[k]), float(t[rows][s])))
        (hi_, lo_) = found
        out["root_stress_max_Pa"].append(None if hi_ is None else hi_[0])
        out["root_stress_max_position_m"].append(None if hi_ is None else hi_[1])
        out["root_stress_max_tooth"].append(None if hi_ is None else hi_[2])
        out["root_stress_max_time_s"].append(None if hi_ is None else hi_[3])
        out["root_stress_compressive_min_Pa"].append(None if lo_ is None else lo_[0])
        out["root_stress_compressive_position_m"].append(None if lo_ is None else lo_[1])
    out["root_stress_note"] = (f"every tooth's fillets on its rim, {said}; sampled "
                               f"{int(ds['stress_time'].attrs.get('samples_per_cycle', 0)) or 'a fixed number of'} "
                               "times a mesh cycle (docs/sector.md, 6.10)")
    return out


def stress_summary(ds: xr.Dataset, case: Case) -> dict[str, Any]:
    """The stress figures of ``summary.json``: per gear (A, B) the largest root stress over
    the frames and its position, the smallest (compressive) one, and ISO's values."""
    out: dict[str, Any] = {}
    if "root_stress" in ds:
        hi, r_hi = ds["root_stress"].values, ds["root_stress_position"].values
        lo, r_lo = ds["root_stress_compressive"].values, ds["root_stress_compressive_position"].values

        def pick(values: np.ndarray, where: np.ndarray, best: Any) -> tuple[list, list]:
            vals, pos = [], []
            for g in (0, 1):
                v = values[:, g]
                if not np.isfinite(v).any():
                    vals.append(None)
                    pos.append(None)
                    continue
                k = int(best(np.where(np.isfinite(v), v, np.nan)))
                vals.append(float(v[k]))
                pos.append(float(where[k, g]))
            return vals, pos

        out["root_stress_max_Pa"], out["root_stress_max_position_m"] = pick(hi, r_hi, np.nanargmax)
        out["root_stress_compressive_min_Pa"], out["root_stress_compressive_position_m"] = \
            pick(lo, r_lo, np.nanargmin)
    out.update(sector_stress_summary(ds))
    out.update(iso_figures(case))
    contact = None
    if "contact_pressure_max" in ds and np.isfinite(ds["contact_pressure_max"].values).any():
        contact = float(np.nanmax(ds["contact_pressure_max"].values))
    out.update(safety_figures(case, out.get("root_stress_max_Pa"), contact))
    return out


__all__ = ["ROOT_VARIABLES", "iso_figures", "root_stress_variables", "safety_figures",
           "sector_stress_summary", "stress_summary", "tooth_stress_variables"]
