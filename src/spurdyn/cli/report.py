"""What ``spurdyn info`` reports about a pair: derived geometry, meshes, time step, stiffness."""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

from spurdyn.model.stiffness import iso_6336_stiffness, pair_stiffness
from spurdyn.model.tooth import build_tooth
from spurdyn.case.pair_tables import MeshedPair
from spurdyn.geometry.fault import Fault, active_rolls
from spurdyn.model.system import system_for
from spurdyn.settings import PAPER_DT, RunSettings
from spurdyn.solvers.check import DT_FRACTION, default_dt, stable_step
from spurdyn.solvers.paper.statics import static_stiffness


def _per(f: Callable[[str], Any]) -> dict[str, Any]:
    """``f`` of each gear, ``{"a": f("a"), "b": f("b")}``."""
    return {k: f(k) for k in ("a", "b")}


def _single_pair_stiffness(case: MeshedPair, teeth: dict[str, Any], rolls: list[float],
                           contact: str, force: float | None
                           ) -> tuple[Sequence[float], dict[str, float]]:
    """The static single-pair stiffness at each of ``rolls``, and the Hertzian strip's figures.

    Parameters
    ----------
    case
        The meshed pair.
    teeth
        The two teeth (:func:`~spurdyn.model.tooth.build_tooth`), by gear.
    rolls
        Roll angles of A: start, single-contact start and end, end, pitch point.
    contact
        ``"point"`` or ``"hertz"``.
    force
        The normal force (N) the Hertzian strip spreads (required for ``"hertz"``).

    Returns
    -------
    stiff
        The stiffness (N/m) at each roll angle.
    strip
        The force and the strip's half-width and compliance at the pitch point (``"hertz"``),
        or nothing.
    """
    pair = case.pair
    if contact == "hertz":
        if force is None:
            raise ValueError("the Hertzian strip's stiffness needs the normal force")
        system = system_for(pair, case.nx, case.ny, RunSettings.n_spline, case.grading,
                            case.row_grading)
        statics = [static_stiffness(system, r, force, "hertz") for r in rolls]
        stiff = [s.stiffness for s in statics]
        strip = {"contact_force_N": force, "strip_half_width_pitch_m": statics[4].half_width,
                 "strip_compliance_m_per_N": statics[4].compliance_strip}
    else:
        stiff = pair_stiffness(pair, teeth["a"], teeth["b"], rolls).stiffness
        strip = {}
    return stiff, strip


def _geometry_figures(case: MeshedPair) -> dict[str, Any]:
    """The pair's geometry for :func:`pair_info`: ``case`` to ``roll_angle_a_deg``."""
    pair = case.pair
    gears = {"a": pair.gear_a, "b": pair.gear_b}
    return {
        "case": case.name,
        "centre_distance_m": pair.centre_distance,
        "driver": pair.driver,
        "teeth": _per(lambda k: gears[k].teeth),
        "module_m": pair.gear_a.module,
        "pressure_angle_deg": math.degrees(pair.gear_a.pressure_angle),
        "working_pressure_angle_deg": math.degrees(pair.working_pressure_angle),
        "pitch_radius_m": _per(lambda k: gears[k].pitch_radius),
        "base_radius_m": _per(lambda k: gears[k].base_radius),
        "tip_radius_m": _per(lambda k: gears[k].tip_radius),
        "root_radius_m": _per(lambda k: gears[k].root_radius),
        "form_radius_m": _per(lambda k: gears[k].form_radius),
        "tip_thickness_m": _per(lambda k: gears[k].tip_thickness),
        "profile_shift": _per(lambda k: gears[k].profile_shift),
        "thickness_allowance_m": _per(lambda k: gears[k].thickness_allowance),
        "basic_rack": _per(lambda k: gears[k].basic_rack.name),
        "cutter_tip_radius_m": _per(lambda k: gears[k].cutter_tip_radius),
        "working_pitch_radius_m": dict(zip("ab", pair.working_pitch_radii)),
        "disk_inertia_kg_m2": _per(lambda k: gears[k].disk_inertia),
        "disk_inertia_source": _per(lambda k: gears[k].inertia_source),
        # For the sector model's back-flank contact (a later issue) and the designer.
        "backlash_circumferential_m": pair.backlash_circumferential,
        "backlash_normal_m": pair.backlash_normal,
        "tight_centre_distance_m": pair.tight_centre_distance,
        "base_pitch_m": pair.gear_a.base_pitch,
        "path_of_contact_m": pair.path_of_contact,
        "contact_ratio": pair.contact_ratio,
        "theta_s_deg": math.degrees(pair.theta_s),
        "theta_2_deg": math.degrees(pair.theta_2),
        "single_contact_deg": math.degrees(pair.single_contact_angle),
        "roll_angle_a_deg": {
            "start_of_contact": math.degrees(pair.start_roll_a),
            "single_contact_start": math.degrees(pair.single_contact_roll_a[0]),
            "pitch_point": math.degrees(pair.pitch_roll_a),
            "single_contact_end": math.degrees(pair.single_contact_roll_a[1]),
            "end_of_contact": math.degrees(pair.end_roll_a),
        },
    }


def pair_info(case: MeshedPair, contact: str = "point", force: float | None = None) -> dict[str, Any]:
    """Collect the figures of ``spurdyn info`` as one JSON-ready dictionary.

    The pair stiffness is the one of the ``contact`` model; the Hertzian strip's depends on
    the normal ``force`` (N) it spreads (required for ``"hertz"``).
    """
    pair = case.pair
    teeth = {"a": build_tooth(pair.gear_a, case.nx, case.ny, case.grading, case.row_grading),
             "b": build_tooth(pair.gear_b, case.nx, case.ny, case.grading, case.row_grading)}
    steps = {k: t.stable_step() for k, t in teeth.items()}
    # the stable step a run checks against and takes its default from (the run's system)
    stable = stable_step(system_for(pair, case.nx, case.ny, RunSettings.n_spline, case.grading,
                                    case.row_grading))
    rolls = [pair.start_roll_a, *pair.single_contact_roll_a, pair.end_roll_a, pair.pitch_roll_a]
    stiff, strip = _single_pair_stiffness(case, teeth, rolls, contact, force)
    ka = pair.gear_a.face_width
    iso = iso_6336_stiffness(pair)
    iso_single, iso_mesh = iso.per_face_width(min(pair.gear_a.face_width, pair.gear_b.face_width))
    return {
        **_geometry_figures(case),
        "mesh": {"nx": case.nx, "ny": case.ny, "grading": case.grading,
                 "row_grading": case.row_grading,
                 "fillet_rows": _per(lambda k: teeth[k].mesh.fillet_rows),
                 "nodes": _per(lambda k: teeth[k].mesh.n_nodes),
                 "elements": _per(lambda k: teeth[k].mesh.n_elements)},
        # A gear's degrees of freedom: its disk's rotation and two per tooth node.
        "n_dof": _per(lambda k: teeth[k].mesh.n_dof + 1),
        "tooth_mass_kg": _per(lambda k: teeth[k].tooth_mass),
        "omega_max_rad_s": _per(lambda k: steps[k].omega_max),
        "stable_dt_s": stable,
        "stable_dt_central_s": min(s.dt_central for s in steps.values()),
        "paper_dt_stable": stable >= PAPER_DT,
        "default_dt_s": default_dt(stable),
        "contact": contact,
        **strip,
        "pair_stiffness_N_per_m": {
            "start_of_contact": float(stiff[0]),
            "single_contact_start": float(stiff[1]),
            "single_contact_end": float(stiff[2]),
            "end_of_contact": float(stiff[3]),
        },
        "pair_stiffness_pitch_N_per_m": float(stiff[4]),
        "pair_stiffness_pitch_N_per_mm_um": float(stiff[4]) / (ka * 1e3) * 1e-6,
        "iso_6336_single_pair_N_per_m": iso_single,
        "iso_6336_mesh_N_per_m": iso_mesh,
        "active_roll_deg": _per(lambda k: [math.degrees(v) for v in active_rolls(pair, k)]),
        "faults": [_fault_words(f) for f in case.faults],
    }


def _fault_words(f: Fault) -> str:
    """One fault in words, SI with degrees for its roll."""
    what = {"missing": "missing", "crack": f"a root crack {f.depth * 1e3:.3g} mm long",
            "chip": f"its tip chipped {f.depth * 1e3:.3g} mm down the drive flank, {f.width * 1e3:.3g} mm "
                    "across the top land",
            "spall": (f"a spall {f.depth * 1e6:.3g} um deep over {100 * f.width_fraction:.3g} % of the "
                      f"face, roll {math.degrees(f.roll[0]):.3g}-{math.degrees(f.roll[1]):.3g} deg"
                      if f.roll is not None else "a spall")}[f.kind]
    return f"gear {f.gear.upper()} tooth {f.tooth}: {what}"


def _um(x: float) -> str:
    """Metres as micrometres to 0.01, without a minus sign on a round-off zero."""
    return f"{round(x * 1e6, 2) + 0.0:.2f}"


def format_info(info: dict[str, Any]) -> str:
    """Human-readable rendering of :func:`pair_info`."""
    a, b = "a", "b"
    r = info["roll_angle_a_deg"]
    k = info["pair_stiffness_N_per_m"]
    lines = [
        f"spurdyn info: {info['case']}",
        "",
        "geometry                      gear A        gear B",
        f"  teeth                     {info['teeth'][a]:>8d}      {info['teeth'][b]:>8d}",
        *(f"  {label:<24}{info[key][a] * 1e3:>10.4f}    {info[key][b] * 1e3:>10.4f}  mm"
          for label, key in (("pitch radius", "pitch_radius_m"), ("base radius", "base_radius_m"),
                             ("tip radius", "tip_radius_m"), ("root radius", "root_radius_m"),
                             ("form radius (fillet end)", "form_radius_m"),
                             ("tip land", "tip_thickness_m"),
                             ("cutter tip radius", "cutter_tip_radius_m"),
                             ("working pitch radius", "working_pitch_radius_m"))),
        f"  profile shift x            {info['profile_shift'][a]:>8.4f}      {info['profile_shift'][b]:>8.4f}",
        f"  thickness allowance      {info['thickness_allowance_m'][a] * 1e6:>8.2f}      "
        f"{info['thickness_allowance_m'][b] * 1e6:>8.2f}    um",
        f"  basic rack: gear A {info['basic_rack'][a]}; gear B {info['basic_rack'][b]}",
        f"  module {info['module_m'] * 1e3:.4g} mm, pressure angle {info['pressure_angle_deg']:.4g} deg"
        f" (working {info['working_pressure_angle_deg']:.4g} deg), centre distance "
        f"{info['centre_distance_m'] * 1e3:.4f} mm, gear {info['driver'].upper()} drives",
        f"  backlash: circumferential {_um(info['backlash_circumferential_m'])} um, normal "
        f"{_um(info['backlash_normal_m'])} um (none at centre distance "
        f"{info['tight_centre_distance_m'] * 1e3:.4f} mm)",
        *(f"  disk inertia {g.upper()} {info['disk_inertia_kg_m2'][g]:.4e} kg m^2 "
          f"({info['disk_inertia_source'][g]})" for g in (a, b)),
        "",
        "contact",
        f"  base pitch {info['base_pitch_m'] * 1e3:.4f} mm, path of contact "
        f"{info['path_of_contact_m'] * 1e3:.4f} mm, contact ratio {info['contact_ratio']:.4f}",
        f"  angle of action theta_s {info['theta_s_deg']:.3f} deg, double contact theta_2 "
        f"{info['theta_2_deg']:.3f} deg, single contact {info['single_contact_deg']:.3f} deg",
        f"  roll angle of A: start {r['start_of_contact']:.2f}, single {r['single_contact_start']:.2f}"
        f"-{r['single_contact_end']:.2f}, pitch {r['pitch_point']:.2f}, end {r['end_of_contact']:.2f} deg",
        "",
        f"tooth model ({info['mesh']['nx']} x {info['mesh']['ny']} Q8 elements per tooth"
        + (f", graded {info['mesh']['grading']:g}:1 toward the outlines"
           if info['mesh']['grading'] != 1 else "")
        + (f", fillet rows {info['mesh']['row_grading']:g} times as tall as flank rows "
           f"({info['mesh']['fillet_rows'][a]} / {info['mesh']['fillet_rows'][b]} of "
           f"{info['mesh']['ny']} in the fillets)"
           if info['mesh'].get('row_grading', 1) != 1 else "") + ")",
        f"  nodes {info['mesh']['nodes'][a]} / {info['mesh']['nodes'][b]}, DOFs per gear "
        f"(disk + tooth) {info['n_dof'][a]} / {info['n_dof'][b]}",
        f"  tooth mass {info['tooth_mass_kg'][a] * 1e3:.4f} / {info['tooth_mass_kg'][b] * 1e3:.4f} g",
        f"  stable RK4 step {info['stable_dt_s']:.3e} s (central difference "
        f"{info['stable_dt_central_s']:.3e} s); the paper's 3e-8 s is "
        + ("stable" if info["paper_dt_stable"] else "NOT stable: use a smaller --dt or a coarser mesh"),
        f"  a case without dt runs at {info['default_dt_s']:.3g} s ({DT_FRACTION:g} of the stable "
        "step, rounded down)",
        "",
        f"static single-pair stiffness (teeth clamped at the root; {info['contact']} contact"
        + (f" under {info['contact_force_N']:,.1f} N, strip half-width "
           f"{info['strip_half_width_pitch_m'] * 1e6:.1f} um at the pitch point"
           if info['contact'] == 'hertz' else "") + ")",
        f"  pitch point {info['pair_stiffness_pitch_N_per_m']:.4e} N/m "
        f"({info['pair_stiffness_pitch_N_per_mm_um']:.2f} N/(mm um))",
        f"  ISO 6336-1 for comparison: c'b {info['iso_6336_single_pair_N_per_m']:.3e} N/m, "
        f"c_gamma_alpha b {info['iso_6336_mesh_N_per_m']:.3e} N/m (see docs/stiffness.md)",
        f"  start of contact {k['start_of_contact']:.3e}, single-contact zone "
        f"{k['single_contact_start']:.3e} to {k['single_contact_end']:.3e}, end {k['end_of_contact']:.3e} N/m",
        f"  active flanks' roll: gear A {info['active_roll_deg'][a][0]:.2f}-{info['active_roll_deg'][a][1]:.2f}, "
        f"gear B {info['active_roll_deg'][b][0]:.2f}-{info['active_roll_deg'][b][1]:.2f} deg",
    ]
    if info["faults"]:
        lines += ["", "faults (spurdyn stiffness follows them over the revolution; docs/faults.md)",
                  *(f"  {words}" for words in info["faults"])]
    return "\n".join(lines)
