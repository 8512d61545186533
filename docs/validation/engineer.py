"""``engineer_defaults.md``: what a gear engineer gets from a bare case file.

Each design pair of the contact validation (modules 2-5 mm, 20 and 25 deg, 100-450 N/mm) is written as
the least a designer gives (teeth, module, pressure angle, face width, material with its
ISO 6336-5 class, speed, torque) and run by ``spurdyn run`` with nothing else: the sector
model, whole gears, damped, to a settled steady state. Beside it, the lumped model on the
sector's quasi-static stiffness with the same mesh damping, and ISO 6336's own figures from
the same summary. Takes a few minutes (the whole gears' modes of each pair, then their
steady states); the runs' summaries are kept in ``engineer_defaults.json``.

``python docs/validation engineer_defaults [--quick]``
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path
from typing import Any, Sequence

from validation.common import DOCS, table, timed, write_page

PAGE = DOCS / "engineer_defaults.md"
STORE = DOCS / "engineer_defaults.json"

#: (name, teeth A, teeth B, module m, pressure angle deg, face width m, torque N m, rpm of A):
#: the design-load pairs of docs/contact_validation.md and the examples.
PAIRS = (
    ("m2 25deg 23/47", 23, 47, 0.002, 25.0, 0.020, 50.0, 3000.0),
    ("m3 20deg 25/50", 25, 50, 0.003, 20.0, 0.030, 150.0, 1000.0),
    ("m3 20deg 25/50", 25, 50, 0.003, 20.0, 0.030, 500.0, 6000.0),
    ("m4 20deg 19/53", 19, 53, 0.004, 20.0, 0.030, 428.5, 2000.0),
    ("m5 25deg 19/38", 19, 38, 0.005, 25.0, 0.040, 800.0, 2000.0),
)
#: The material every pair is given: case-hardened steel, ISO 6336-5 grade MQ, 700 HV.
MATERIAL = ('young = 210e9\npoisson = 0.3\ndensity = 7800.0\nmaterial_class = "Eh"\n'
            'grade = "MQ"\nhardness_hv = 700\n')


def case_text(z_a: int, z_b: int, m: float, alpha: float, b: float, torque: float, rpm: float) -> str:
    """The bare case file of a pair: nothing a designer would not give."""
    gears = "".join(f"[{g}]\nteeth = {z}\nmodule = {m!r}\npressure_angle_deg = {alpha!r}\n"
                    f"face_width = {b!r}\n\n[{g}.material]\n{MATERIAL}\n"
                    for g, z in (("gear_a", z_a), ("gear_b", z_b)))
    return gears + f"[run]\nspeed_a_rpm = {rpm!r}\ntorque = {torque!r}\n"


def run_summary(path: Path, out: Path, *options: str) -> dict[str, Any]:
    """``spurdyn run path --out out options`` in this process, and its summary."""
    from spurdyn.cli.main import main

    code = main(["run", str(path), "--out", str(out), "--force", "--quiet", *options])
    if code != 0:
        raise RuntimeError(f"spurdyn run {path.name} {' '.join(options)} exited {code}")
    return json.loads((out / "summary.json").read_text())


def contact_peak(folder: Path) -> dict[str, float]:
    """Where a sector run's largest Hertz pressure was: the pressure, the pair's force then
    and the driver's roll of its contact point (deg)."""
    import numpy as np
    import xarray as xr

    with xr.open_dataset(folder / "result.nc") as ds:
        p = ds["pair_contact_pressure"].values
        i, j = np.unravel_index(int(np.nanargmax(p)), p.shape)
        return {"pressure_Pa": float(p[i, j]), "force_N": float(ds["pair_force"].values[i, j]),
                "roll_deg": float(ds["pair_roll_deg"].values[i, j])}


def resonance_rpm(path: Path) -> tuple[float, float | None]:
    """The lumped model's main resonance on the sector's quasi-static stiffness, and ISO
    6336-1's ``n_E1`` (rpm of A)."""
    from dataclasses import replace

    from spurdyn.case import load_case
    from spurdyn.sweep.resonance import resonance_estimate

    case = load_case(path)
    case = replace(case, run=case.run.with_(cycles=5, stiffness="sector"))
    est = resonance_estimate(case, "lumped")
    return 60.0 * est.natural_frequency_hz / est.teeth_a, est.iso_resonance_rpm


def measure(quick: bool) -> list[dict[str, Any]]:
    """Each pair's default (sector) run and the lumped model beside it."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, z_a, z_b, m, alpha, b, torque, rpm) in enumerate(PAIRS[:2] if quick else PAIRS):
            path = Path(tmp) / f"pair{k}.toml"
            path.write_text(case_text(z_a, z_b, m, alpha, b, torque, rpm))
            sector, wall = timed(run_summary, path, Path(tmp) / f"s{k}")
            peak = contact_peak(Path(tmp) / f"s{k}")
            zeta = sector["mesh_damping"]["ratio"]
            lumped = run_summary(path, Path(tmp) / f"l{k}", "--model", "lumped", "--stiffness", "sector",
                                 "--cycles", str(sector["cycles"]), "--damping", str(zeta))
            line_load = torque / (0.5 * m * z_a) / b
            rows.append({"name": name, "torque_Nm": torque, "rpm": rpm, "line_load_N_per_mm": line_load * 1e-3,
                         "pressure_angle_deg": alpha,
                         "wall_s": wall, "case": case_text(z_a, z_b, m, alpha, b, torque, rpm),
                         "sector": sector, "lumped": lumped, "contact_peak": peak,
                         "resonance_rpm": resonance_rpm(path)})
    return rows


def _pair(values: Any, scale: float = 1.0, digits: int = 2) -> str:
    """``A / B`` of a per-gear figure (``-`` where absent)."""
    if values is None:
        return "-"
    return " / ".join("-" if v is None else f"{v * scale:.{digits}f}" for v in values)


def _dynamic_rows(rows: Sequence[dict[str, Any]]) -> list[list[Any]]:
    out = []
    for r in rows:
        s, lump = r["sector"], r["lumped"]
        iso = s.get("rating_iso") or {}
        settled = (f"yes, {s['cycles_done']}" if s["settled"] else f"NOT after {s['cycles_done']}")
        out.append([r["name"], f"{r['torque_Nm']:g}", f"{r['line_load_N_per_mm']:.0f}", f"{r['rpm']:,.0f}",
                    settled, f"{s['dynamic_factor']:.3f}", f"{lump['dynamic_factor']:.3f}",
                    f"{iso.get('K_v', float('nan')):.3f}", f"{r['rpm'] / r['resonance_rpm'][0]:.2f}",
                    "-" if r["resonance_rpm"][1] is None else f"{r['rpm'] / r['resonance_rpm'][1]:.2f}",
                    f"{s['transmission_error_rms_m'] * 1e6:.2f}", f"{r['wall_s']:.0f}"])
    return out


def _contact_rows(rows: Sequence[dict[str, Any]]) -> list[list[Any]]:
    """The model's largest Hertz pressure beside ISO's sigma_H of the pinion, and what the
    load and ISO's contact ratio factor make of the difference."""
    out = []
    for r in rows:
        iso, peak = r["sector"]["rating_iso"], r["contact_peak"]
        f_bn = iso["F_t_N"] / math.cos(math.radians(r["pressure_angle_deg"]))
        expect = math.sqrt(peak["force_N"] / (f_bn * iso["K_v"])) / iso["Z_eps"]
        out.append([r["name"], f"{r['torque_Nm']:g}", f"{peak['pressure_Pa'] * 1e-6:.0f}",
                    f"{peak['roll_deg']:.1f}", f"{peak['force_N']:,.0f}", f"{f_bn * iso['K_v']:,.0f}",
                    f"{iso['sigma_H_Pa'][0] * 1e-6:.0f}", f"{peak['pressure_Pa'] / iso['sigma_H_Pa'][0]:.3f}",
                    f"{iso['Z_eps']:.3f}", f"{expect:.3f}",
                    f"{(peak['pressure_Pa'] / iso['sigma_H_Pa'][0] / expect) ** 2:.2f}"])
    return out


def _stress_rows(rows: Sequence[dict[str, Any]]) -> list[list[Any]]:
    out = []
    for r in rows:
        s = r["sector"]
        iso = s.get("rating_iso") or {}
        f0 = s.get("iso6336_sigma_F0_Pa")
        out.append([r["name"], f"{r['torque_Nm']:g}", _pair(s.get("root_stress_max_Pa"), 1e-6, 0),
                    _pair(f0, 1e-6, 0), _pair(iso.get("sigma_F_Pa"), 1e-6, 0),
                    _pair(s.get("safety_root_model")), _pair(s.get("safety_root_iso")),
                    _pair(s.get("safety_contact_model")), _pair(s.get("safety_contact_iso"))])
    return out


def page(rows: Sequence[dict[str, Any]]) -> str:
    """The page's text."""
    dyn = table(["pair", "torque (N m)", "line load (N/mm)", "rpm (A)", "settled, cycles",
                 "dynamic factor (sector)", "lumped beside", "ISO K_v", "n / n_res lumped", "n / n_E1 ISO",
                 "TE RMS (um)", "wall (s)"], _dynamic_rows(rows))
    contact = table(["pair", "torque (N m)", "model p_max (MPa)", "at roll (deg)", "its pair force (N)",
                     "ISO F_bn K_v (N)", "ISO sigma_H of A (MPa)", "model / ISO", "ISO Z_eps",
                     "sqrt(force / F_bn K_v) / Z_eps", "rest: (ratio / that)^2"], _contact_rows(rows))
    stress = table(["pair", "torque (N m)", "peak root stress, model (MPa, A / B)",
                    "ISO sigma_F0 (MPa)", "ISO sigma_F (MPa)", "S_F model", "S_F ISO", "S_H model",
                    "S_H ISO"], _stress_rows(rows))
    return f"""# What an engineer gets from a bare case file

Regenerated by `python docs/validation engineer_defaults` (the summaries in
`engineer_defaults.json`). Each pair below is a case file holding only teeth, module,
pressure angle, face width, material (steel, ISO 6336-5 class Eh, grade MQ, 700 HV: sigma_Hlim
1,500 MPa, sigma_Flim 425 MPa) and the pinion's speed and torque; `spurdyn run CASE` with no
option ran each. That is the sector model (whole gears of elastic teeth on elastic rims, the
Hertzian strip, generalized-alpha), 5 mesh cycles on to 20 until settled, with the mesh damper
at its default ratio {rows[0]['sector']['mesh_damping']['ratio']} and the bodies' default
structural damping (docs/sector.md, 6.10).

## Dynamic factor and settling

{dyn}

Where each number comes from: *dynamic factor (sector)* is `summary.json` `dynamic_factor`,
the most loaded tooth pair's 10-us-averaged peak force over the last settled cycle against the
largest pair force of the quasi-static mesh cycle; *lumped beside* is `spurdyn run CASE --model
lumped --stiffness sector --cycles N --damping Z` with the sector run's cycles and damping (two
disks on the sector model's quasi-static mesh stiffness, docs/lumped.md); *ISO K_v* is ISO
6336-1 method B for perfect gears at the run's speed (`rating_iso`); *TE RMS* the transmission
error's RMS over the last cycle. The wall time includes building the whole gears' modes (kept
in the mode store for the next run of the same gears) and this machine's load.

## Stresses and safety factors, both ways

{stress}

*Peak root stress, model*: the largest surface stress on the fillets of every tooth of each gear
over the settled cycle (`root_stress_max_Pa`; docs/stress_validation.md for its mesh study
beside ISO); *ISO sigma_F0*: ISO 6336-3 method B's nominal root stress for the static load
(`iso6336_sigma_F0_Pa`), *ISO sigma_F* the same with ISO's load factors (`rating_iso`).
*S_F model* and *S_H model* rate the model's own settled peaks (they already hold the dynamic
factor and the load sharing) against ISO 6336-5's permissible stresses; *S_F ISO* and *S_H ISO*
are ISO's own chain (docs/iso6336.md). A `-` is a figure the run did not compute.

## Why the two ways differ

**Root stress.** The model's settled peak and ISO's sigma_F (its nominal stress with K_v) are
within a few per cent on every pair: the model's peak sits where ISO puts its load (the outer
point of single contact) and on the rim it reaches ISO's notch stress (docs/stress_validation.md,
"Sector model: the root on its rim", where the default rim fillet mesh is shown to read about 3 %
low). The model's S_F is the higher where its dynamic peak is below ISO's K_v-scaled load.

**Contact stress.** The model's S_H is the lower on every pair: its largest Hertz pressure
(every pair, every step of the settled cycle, `contact_pressure_max_Pa`) is above ISO's sigma_H of
the pinion (which ISO moves to the inner point of single contact by Z_B):

{contact}

Two things ISO has and the model has not account for part of each ratio: ISO's sigma_H holds the
contact ratio factor Z_eps < 1, which lowers the stress for the load the pairs share, and its
load is the static one times K_v, where the model's pressure is one pair's under its own force at
that instant. `sqrt(force / F_bn K_v) / Z_eps` is the ratio those two alone would give at the
same curvature (Hertz's pressure goes as the square root of the force over the relative
curvature radius). The last column is what is left, squared: the ratio of the relative curvature
radius ISO takes to the one at the model's peak (and anything else the two do differently).
Where it is near 1 the model's peak is at the inner point of single contact (the roll where one
pair carries the whole load) and the two ways agree but for Z_eps and the dynamic load. Where it
is well above 1 the model's largest pressure comes early in the engagement, at a fraction of the
single-pair load, where the pinion's flank is close to its base circle and its curvature radius
small (and the entering pair, deflected, meets ahead of the rigid path): a pressure ISO's Z_B,
which looks only at the inner point of single contact, does not see. The model's S_H is then the
lower for a reason a designer would want to know (tip relief is the usual remedy); it is not an
error of either figure.

**Dynamic factor.** The three figures are different things. ISO's K_v is method B's
single-degree-of-freedom estimate for perfect gears; the lumped model puts the sector's
quasi-static stiffness between two rigid disks; the sector model has the bodies' own mass and
flexibility, so its main resonance lies below the lumped model's (`n / n_res lumped` is the
speed over the lumped model's resonance: near 1 the lumped model rings where the sector model
does not, as on the 25/50 pair at 6,000 rpm). A dynamic factor below 1 (the most loaded pair's
settled peak below its quasi-static peak) is the inertia filtering the stiffness variation
above the sector model's resonance, not an error of the figure; `spurdyn sweep` shows each
model's curve against speed.
"""


def main(argv: Sequence[str] | None = None) -> int:
    """Measure (or with ``--page-only`` reuse the store) and write the page."""
    parser = argparse.ArgumentParser(prog="python docs/validation engineer_defaults")
    parser.add_argument("--quick", action="store_true", help="the first two pairs only")
    parser.add_argument("--page-only", action="store_true", help="write the page from the store")
    args = parser.parse_args(argv)
    if args.page_only:
        rows = json.loads(STORE.read_text())
    else:
        rows = measure(args.quick)
        STORE.write_text(json.dumps(rows, indent=1, default=lambda x: None if x != x else x) + "\n")
    write_page(PAGE, page(rows), echo=False)
    return 0 if all(math.isfinite(r["sector"]["dynamic_factor"] or math.nan) for r in rows) else 1
