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
            "-k+1), both taken round the gear (docs/sector.md, 6.11)"})
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
    numbers (``sigma_flim``, ``sigma_hlim``), two ways side by side: ``safety_*_model``
    from the model's dynamic peaks (root stress of each tooth; the strip's peak pressure),
    which already hold the dynamics and the load sharing, so only ``K_A = K_beta = 1``
    multiply them; ``safety_*_iso`` from ISO's own chain (method B, ``K_v`` at the run's
    speed, ``K_alpha``), every factor of which is in ``rating_iso``. Life and condition
    factors 1 (:data:`spurdyn.iso6336.chain.UNITY_NOTE`). Empty without allowables."""
    from spurdyn.iso6336 import safety

    mats = (case.pair.gear_a.material, case.pair.gear_b.material)
    if all(m.sigma_flim is None and m.sigma_hlim is None for m in mats):
        return {}
    rating, why = _rating(case)
    chain = None if rating is None else _chain(case, rating)
    out: dict[str, Any] = {"iso6336_k_v": None if chain is None else float(chain.k_v)}
    root_model, contact_model = [], []
    for g, m in enumerate(mats):
        peak = None if root_peaks is None else root_peaks[g]
        root_model.append(None if m.sigma_flim is None or not peak else safety.root_safety(
            safety.root_stress_from_peak(peak), safety.root_limit(m.sigma_flim)))
        contact_model.append(None if m.sigma_hlim is None or not contact_peak else
                             safety.contact_safety(safety.contact_stress_from_peak(contact_peak),
                                                   safety.contact_limit(m.sigma_hlim)))
    none2 = [None, None]
    out.update({"safety_root_model": root_model,
                "safety_root_iso": none2 if chain is None else list(chain.s_f),
                "safety_contact_model": contact_model,
                "safety_contact_iso": none2 if chain is None else list(chain.s_h),
                "safety_note": "S = allowable / stress; model: the run's dynamic peak root "
                               "stress and strip pressure (K_A = K_beta = 1, no K_alpha: the "
                               "model shares the load between pairs itself); ISO: method B "
                               "chain, every factor in rating_iso" + (
                                   "" if rating is not None else f"; ISO {why}"),
                "rating_iso": None if chain is None else _chain_figures(rating, chain, mats)})
    return out


def _chain(case: Case, rating: Any) -> Any:
    """ISO's safety chain for the run: its pinion (gear A) speed and the materials'
    allowables and running-in groups (none for allowables given as numbers)."""
    from spurdyn.iso6336.chain import safety_chain
    from spurdyn.iso6336.materials import LINES

    pair = case.pair
    mats = (pair.gear_a.material, pair.gear_b.material)
    groups = tuple(None if m.iso_class is None else LINES[m.iso_class[0]].running_in
                   for m in mats)
    return safety_chain(rating, case.run.speed_a, (mats[0].sigma_hlim, mats[1].sigma_hlim),
                        (mats[0].sigma_flim, mats[1].sigma_flim),
                        pitch_speed=case.run.speed_a * pair.gear_a.pitch_radius,
                        groups=groups)  # type: ignore[arg-type]


def _chain_figures(rating: Any, chain: Any, mats: tuple[Any, Any]) -> dict[str, Any]:
    """Every factor of ISO's chain under one key of ``summary.json`` (per gear: A, B)."""
    from spurdyn.iso6336.chain import UNITY_NOTE
    from spurdyn.iso6336.materials import LINES
    from spurdyn.iso6336.safety import Y_ST

    def num(values: Any) -> list[float | None]:
        return [None if v is None else float(v) for v in values]

    def source(m: Any) -> str | None:
        if m.iso_class is None:
            return None if m.sigma_hlim is None and m.sigma_flim is None else "given"
        name, grade, hardness = m.iso_class
        return f"ISO 6336-5 {name} {grade} {hardness:g} {LINES[name].scale}"

    return {
        "K_A": chain.k_a, "K_v": float(chain.k_v), "K_Hbeta": chain.k_hbeta,
        "K_Fbeta": chain.k_fbeta, "K_Halpha": chain.k_halpha, "K_Falpha": chain.k_falpha,
        "f_pb_m": 0.0, "y_alpha_m": chain.y_alpha, "eps_alpha": rating.eps_alpha,
        "Z_H": rating.z_h, "Z_E_sqrtPa": rating.z_e, "Z_eps": rating.z_eps, "Z_beta": 1.0,
        "Z_B": rating.z_b, "Z_D": rating.z_d, "Y_F": num(rating.y_f), "Y_S": num(rating.y_s),
        "Y_beta": 1.0, "Y_B": 1.0, "Y_DT": 1.0, "Y_ST": Y_ST,
        "F_t_N": rating.tangential_force, "sigma_H0_Pa": rating.sigma_h0,
        "sigma_F0_Pa": num(rating.sigma_f0), "sigma_H_Pa": num(chain.sigma_h),
        "sigma_F_Pa": num(chain.sigma_f),
        "sigma_Hlim_Pa": num(m.sigma_hlim for m in mats),
        "sigma_Flim_Pa": num(m.sigma_flim for m in mats),
        "allowables": [source(m) for m in mats],
        "sigma_HG_Pa": num(chain.sigma_hg), "sigma_FG_Pa": num(chain.sigma_fg),
        "S_H": num(chain.s_h), "S_F": num(chain.s_f),
        "note": "ISO 6336-2/-3 method B for the run's static torque at its speed; sigma_H "
                "of A with Z_B, of B with Z_D. Taken as 1: " + UNITY_NOTE,
    }


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
                               "times a mesh cycle (docs/sector.md, 6.11)")
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
