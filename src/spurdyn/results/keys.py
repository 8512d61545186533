"""The keys of ``summary.json``, per model: what each means, its unit, and when a model's
summary has it (issue 35: a summary says only what is true of its model).

:data:`KEYS` is the one list. A key a model does not compute is absent from that model's
summary, never a zero: each :class:`Key` names the models that write it and the
conditions of a run under which they do (:data:`CONDITIONS`). :func:`select` is how the
writer (:func:`spurdyn.results.io.summarize`) applies the list: it keeps the figures the
list gives the run, drops those it does not (the pair's angle of action in a steady state
of many cycles), and refuses a figure the list does not know or a required one that is
missing. docs/summary.md is this list as a table (:func:`markdown`; a test keeps them
equal), and :func:`settings_of` keeps a summary's ``settings`` to those its model reads.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any, Iterable, Mapping

from spurdyn.settings import MODEL_NAMES, RunSettings, setting_keys, settings_read_by

#: A run of one engagement (the FE model; the lumped model without ``cycles``).
ENGAGEMENT = "engagement"
#: A steady state over mesh cycles (the sector model; the lumped model with ``cycles``).
STEADY = "steady"
#: The run's dataset holds the root stress of its tooth frames (the FE model keeping frames).
ROOT_STRESS = "root_stress"
#: A gear's material gives ISO 6336-5's allowable stress numbers (``sigma_flim``, ``sigma_hlim``).
STRENGTHS = "strengths"
#: Written where the writer computes it: not required (figures other work adds).
OPTIONAL = "optional"

#: The conditions a key may ask of a run, and what each means.
CONDITIONS = {
    ENGAGEMENT: "a run of one engagement (no cycles)",
    STEADY: "a steady-state run of mesh cycles",
    ROOT_STRESS: "the run kept tooth frames and their root stress was recovered",
    STRENGTHS: "a gear's material gives sigma_flim or sigma_hlim, or an ISO 6336-5 class",
    OPTIONAL: "where the model computes it",
}

#: The conditions every run of a model meets.
MODEL_CONDITIONS: dict[str, frozenset[str]] = {
    "fe": frozenset({ENGAGEMENT}), "lumped": frozenset(), "sector": frozenset({STEADY})}


@dataclass(frozen=True)
class Key:
    """One key of ``summary.json``.

    Attributes
    ----------
    name
        The key.
    unit
        Its unit (SI; ``deg`` and ``rpm`` as the name says; ``1`` a number without unit,
        ``-`` text, a flag or a table).
    meaning
        What it is, in one line.
    when
        Model -> the conditions (all of :data:`CONDITIONS` named) under which its summary has
        the key; ``()`` every run of that model. A model not named never writes it.
    """

    name: str
    unit: str
    meaning: str
    when: Mapping[str, tuple[str, ...]]


_ALL = ("fe", "lumped", "sector")


def _k(name: str, unit: str, meaning: str, models: Iterable[str] = _ALL, *when: str,
       **own: tuple[str, ...]) -> Key:
    """A key written by ``models`` under the conditions ``when`` (every run when none), and
    by each model of ``own`` under its own conditions."""
    table = {m: tuple(when) for m in models}
    table.update(own)
    return Key(name, unit, meaning, {m: table[m] for m in MODEL_NAMES if m in table})


_E, _S = (ENGAGEMENT,), (STEADY,)
_STEADY_MODELS = ("lumped", "sector")

#: Every key a summary may hold, in the order the writer writes them.
KEYS: tuple[Key, ...] = (
    _k("case", "-", "the case's name"),
    _k("status", "-", "complete, or incomplete (stopped early)"),
    _k("reason", "-", "why an incomplete run stopped (empty when complete)"),
    _k("steps", "1", "time steps taken (the lumped model: its adaptive integrator's steps, "
                     "in a steady state the right-hand side's evaluations)"),
    _k("samples", "1", "samples saved in result.nc"),
    _k("frames", "1", "tooth frames saved", ("fe",)),
    _k("dt_s", "s", "the time step (the sector model's own step of accuracy)", ("fe", "sector")),
    _k("wall_s", "s", "wall-clock time of the run"),
    _k("n_dof", "1", "degrees of freedom of the model"),
    _k("speed_a_rpm", "rpm", "initial speed of gear A"),
    _k("speed_b_rpm", "rpm", "initial speed of gear B"),
    _k("torque_Nm", "N m", "torque on the driver"),
    _k("time_s", "s", "time the run reached"),
    _k("angle_deg", "deg", "rotation of gear A the run reached"),
    _k("angle_target_deg", "deg", "rotation of gear A the run set out to cover", ("fe", "lumped"), *_E),
    _k("theta_s_deg", "deg", "the pair's angle of action, which one engagement covers",
       ("fe", "lumped"), *_E),
    _k("single_zone_deg", "deg", "[from, to] rotation of A of the single-contact zone",
       ("fe", "lumped"), *_E),
    _k("peak_force_N", "N", "peak of the contact force averaged over a centred 10-us window "
                            "(a steady state: the most loaded pair's, over its last cycles); "
                            "null when the teeth never touched"),
    _k("peak_angle_deg", "deg", "rotation of A at the centre of that window"),
    _k("peak_force_raw_N", "N", "largest saved contact force (a steady state: over its last cycles)"),
    _k("peak_angle_raw_deg", "deg", "rotation of A at the largest saved contact force"),
    _k("mean_force_single_zone_N", "N", "mean contact force in the single-contact zone; null "
                                        "when the run never reached it", ("fe", "lumped"), *_E),
    _k("static_force_N", "N", "quasi-static force torque / r_b (a steady state: the largest "
                              "pair force of a quasi-static mesh cycle)"),
    _k("dynamic_factor", "1", "peak_force_N / static_force_N; null for a run stopped early"),
    _k("dynamic_factor_raw", "1", "peak_force_raw_N / static_force_N; null for a run stopped early"),
    _k("dynamic_factor_note", "-", "what the dynamic factor is, or why there is none"),
    _k("averaging_window_s", "s", "the averaging window of the peak (1e-05)"),
    _k("first_contact_s", "s", "time the teeth first touched; null if never"),
    _k("contact", "-", "the contact model: point or hertz"),
    _k("integrator", "-", "the time integrator: rk4, implicit, or the lumped model's DOP853"),
    _k("contact_pressure_max_Pa", "Pa", "largest peak Hertzian pressure of the contact force",
       ("fe",), sector=(OPTIONAL,)),
    _k("contact_half_width_max_m", "m", "largest half-width of the Hertzian strip",
       ("fe",), sector=(OPTIONAL,)),
    _k("contact_pressure_note", "-", "why a run has no contact pressure maximum (a pit over part "
                                     "of the face width split a contact)", ("sector",), OPTIONAL),
    _k("separations", "1", "times contact was lost after first being made and the gap opened "
                           "beyond 10 nm"),
    _k("separation_times_s", "s", "the times of those separations"),
    _k("iterations_mean", "1", "per stage of the constraint iteration (the implicit "
                               "integrator: its Newton iteration, displacement), the mean "
                               "iterations a step", ("fe",)),
    _k("residual_max", "-", "per stage, the largest final constraint error (m, m/s, m/s^2)",
       ("fe",)),
    _k("settings", "-", "the case: the pair's tables and the run settings the model reads "
                        "(TOML units)"),
    _k("spurdyn_version", "-", "the version that wrote the run"),
    _k("root_stress_max_Pa", "Pa", "[A, B] largest root stress (tension) over the frames",
       ("fe",), ROOT_STRESS, sector=(OPTIONAL,)),
    _k("root_stress_max_position_m", "m", "[A, B] its distance from the gear centre",
       ("fe",), ROOT_STRESS, sector=(OPTIONAL,)),
    _k("root_stress_compressive_min_Pa", "Pa", "[A, B] smallest (compressive) root stress",
       ("fe",), ROOT_STRESS, sector=(OPTIONAL,)),
    _k("root_stress_compressive_position_m", "m", "[A, B] its distance from the gear centre",
       ("fe",), ROOT_STRESS, sector=(OPTIONAL,)),
    _k("root_stress_max_tooth", "1", "[A, B] the tooth of the largest root stress",
       ("sector",), OPTIONAL),
    _k("root_stress_max_time_s", "s", "[A, B] the time of the largest root stress",
       ("sector",), OPTIONAL),
    _k("root_stress_note", "-", "how the root stress was found", ("sector",), OPTIONAL),
    _k("iso6336_sigma_F0_Pa", "Pa", "[A, B] ISO 6336-3's nominal root stress for the static "
                                    "load; null with the reason in iso6336_note"),
    _k("iso6336_sigma_H0_Pa", "Pa", "ISO 6336-2's nominal contact stress; null with the reason"),
    _k("iso6336_note", "-", "what the ISO figures are, or why there are none"),
    _k("iso6336_k_v", "1", "ISO 6336-1's dynamic factor at the run's speed", _ALL, STRENGTHS),
    _k("safety_root_model", "1", "[A, B] root safety factor from the model's peak root stress",
       ("fe",), ROOT_STRESS, STRENGTHS, sector=(OPTIONAL,)),
    _k("safety_root_iso", "1", "[A, B] root safety factor from ISO's nominal stress",
       _ALL, STRENGTHS),
    _k("safety_contact_model", "1", "[A, B] contact safety factor from the model's peak pressure",
       ("fe",), STRENGTHS, sector=(OPTIONAL,)),
    _k("safety_contact_iso", "1", "[A, B] contact safety factor from ISO's nominal stress",
       _ALL, STRENGTHS),
    _k("safety_note", "-", "how the safety factors were found", _ALL, STRENGTHS),
    _k("rating_iso", "-", "ISO 6336's factor chain: every factor, the stresses, limits and safety factors", _ALL, STRENGTHS),
    _k("cycles", "1", "mesh cycles asked for", _STEADY_MODELS, *_S),
    _k("cycles_done", "1", "mesh cycles run", _STEADY_MODELS, *_S),
    _k("max_cycles", "1", "most cycles the run could go on to until it settled", _STEADY_MODELS, *_S),
    _k("settled", "-", "whether the last cycles repeat within the tolerance", _STEADY_MODELS, *_S),
    _k("settle_tolerance", "1", "the settled test's tolerance", _STEADY_MODELS, *_S),
    _k("transmission_error_rms_m", "m", "RMS of the transmission error over the last cycles",
       _STEADY_MODELS, *_S),
    _k("transmission_error_pp_m", "m", "its peak-to-peak there", _STEADY_MODELS, *_S),
    _k("mesh_stiffness_mean_N_per_m", "N/m", "mean mesh stiffness of a quasi-static cycle",
       _STEADY_MODELS, *_S),
    _k("model", "-", "the model that ran: fe, lumped or sector"),
    _k("start", "-", "how the run started: static or rest", _STEADY_MODELS, *_S),
    _k("torque_history", "-", "the torque history's source; null under constant torques",
       _STEADY_MODELS, *_S),
    _k("back_flanks", "-", "whether the back flanks were contacts, the normal backlash, and "
                           "their peak force and steps in contact", ("sector",)),
    _k("vibration", "-", "condition indicators (RMS, kurtosis, crest factor, FM0, FM4, NA4, sideband energy "
                         "ratio) of the sensors' signals over the settled window's whole revolutions of the "
                         "faulty gear (docs/faults.md)", ("sector",), OPTIONAL),
    _k("crack_faces", "-", "a crack's faces, a unilateral contact in motion: their least opening (m; zero to "
                           "round-off where they touch), largest opening, when the least was, their largest force "
                           "(N, a node pair's) and when, and the share of the steps with faces closed "
                           "(docs/faults.md)",
       ("sector",), OPTIONAL),
    _k("bearings", "-", "the hubs' radial bearings, gear A's and gear B's: stiffness (N/m), damping (N s/m) and the "
                        "gear's translating mass (kg); null for a hub whose centre is held (docs/sector.md, 6.12)",
       ("sector",), OPTIONAL),
    _k("body_damping", "-", "the bodies' Rayleigh damping and whose it was", ("sector",)),
    _k("mesh_damping", "-", "the mesh damper's ratio and whose it was (model default or run)",
       ("sector",)),
)

#: Key name -> :class:`Key`.
BY_NAME: dict[str, Key] = {k.name: k for k in KEYS}


def run_conditions(model: str, steady: bool, root_stress: bool, case: Mapping[str, Any]) -> frozenset[str]:
    """The conditions (:data:`CONDITIONS`) a run of ``model`` meets: a ``steady`` state or
    one engagement, the ``root_stress`` of its frames, the strengths of its ``case``'s
    materials (the stored case, TOML layout)."""
    out = set(MODEL_CONDITIONS[model]) | {STEADY if steady else ENGAGEMENT}
    if root_stress:
        out.add(ROOT_STRESS)
    materials = (case.get(g, {}).get("material", {}) for g in ("gear_a", "gear_b"))
    if any(m.get(k) is not None for m in materials for k in ("sigma_flim", "sigma_hlim", "material_class")):
        out.add(STRENGTHS)
    return frozenset(out)


def required(model: str, conditions: Iterable[str]) -> tuple[str, ...]:
    """The keys a summary of ``model`` has when its run meets ``conditions``, in order."""
    met = set(conditions) | MODEL_CONDITIONS[model]
    return tuple(k.name for k in KEYS if model in k.when and OPTIONAL not in k.when[model]
                 and set(k.when[model]) <= met)


def allowed(model: str, conditions: Iterable[str]) -> tuple[str, ...]:
    """The keys it may have: :func:`required` and the optional ones."""
    met = set(conditions) | MODEL_CONDITIONS[model] | {OPTIONAL}
    return tuple(k.name for k in KEYS if model in k.when and set(k.when[model]) <= met)


def select(figures: Mapping[str, Any], model: str, conditions: Iterable[str]) -> dict[str, Any]:
    """The summary of a run of ``model`` meeting ``conditions``: ``figures`` in their order,
    less those the list does not give the run.

    Raises
    ------
    ValueError
        If a figure's key is not in :data:`KEYS` (declare it there first) or a required
        key is missing (a writer out of step with the list).
    """
    unknown = [name for name in figures if name not in BY_NAME]
    if unknown:
        raise ValueError(f"summary keys {unknown} are not declared in spurdyn.results.keys.KEYS")
    conditions = frozenset(conditions)
    missing = [name for name in required(model, conditions) if name not in figures]
    if missing:
        raise ValueError(f"the {model} model's summary misses {missing} (spurdyn.results.keys)")
    keep = set(allowed(model, conditions))
    return {name: value for name, value in figures.items() if name in keep}


def settings_of(case: Mapping[str, Any], model: str) -> dict[str, Any]:
    """The stored ``case`` (TOML layout) less the ``[run]`` and ``[mesh]`` keys of settings
    ``model`` does not read (:func:`~spurdyn.settings.settings_read_by`)."""
    reads = set(settings_read_by(model))
    unread = {key for f in fields(RunSettings) if f.name not in reads for key in setting_keys(f.name)}
    out = dict(case)
    for table in ("run", "mesh"):
        if table in out:
            out[table] = {k: v for k, v in out[table].items() if f"{table}.{k}" not in unread}
    return out


def markdown() -> str:
    """The list as the table of docs/summary.md: key, unit, meaning, and per model when its
    summary has it."""
    lines = ["| key | unit | meaning | " + " | ".join(MODEL_NAMES) + " |",
             "| --- | --- | --- | " + " | ".join("---" for _ in MODEL_NAMES) + " |"]
    for k in KEYS:
        cells = [("always" if not k.when[m] else ", ".join(k.when[m])) if m in k.when else "-"
                 for m in MODEL_NAMES]
        lines.append(f"| `{k.name}` | {k.unit} | {k.meaning} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


__all__ = ["BY_NAME", "CONDITIONS", "ENGAGEMENT", "KEYS", "Key", "MODEL_CONDITIONS", "OPTIONAL",
           "ROOT_STRESS", "STEADY", "STRENGTHS", "allowed", "markdown", "required",
           "run_conditions", "select", "settings_of"]
