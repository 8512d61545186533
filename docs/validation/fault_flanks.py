"""``faults_flanks.md``: spalls and chipped tips, the contact lost where it should be and the
signature they leave over the faulty gear's revolution, in the statics and at speed.

The paper's pair (28/28, module 3.175 mm, 20 deg, 6.35 mm face) under its 22.25 N m, the
pinion's tooth 5 faulty: a shallow pit over the single-contact stretch (the statics'
section 5 case of docs/faults.md, over the whole face and over half of it), a pit deeper than
any deflection over the recess's double contact, and a chipped tip. The statics: the
sector model's revolution (``spurdyn stiffness`` with the fault); at speed: the sector model
at 4,000 rpm, three revolutions of the pinion. Some ten minutes (``--quick``: the statics
on a coarse mesh and one run at speed, some three).

``python docs/validation faults_flanks [--quick]``
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from validation.common import DOCS, FIGURES, table, timed, write_page
# the paper's pair in the sector model at ``{rpm}``: the crack page's case
from validation.fault_dynamics import CASE

PAGE = DOCS / "faults_flanks.md"
FIGURE = FIGURES / "fault_flanks.png"
TEETH = 28
TOOTH = 5
RPM = 4000.0
#: Three revolutions of the pinion, exactly.
CYCLES = 3 * TEETH
#: The faults: name, the ``[[fault]]`` table's keys beyond gear and tooth.
FAULTS: dict[str, dict[str, Any]] = {
    "pit 20 um, 18-24 deg, whole face": {"kind": "spall", "roll_deg": [18.0, 24.0], "depth": 2e-5},
    "pit 20 um, 18-24 deg, half the face": {"kind": "spall", "roll_deg": [18.0, 24.0], "depth": 2e-5,
                                            "width_fraction": 0.5},
    "pit 0.2 mm, 24-30 deg, whole face": {"kind": "spall", "roll_deg": [24.0, 30.0], "depth": 2e-4},
    "chip 1 mm high, 0.5 mm wide": {"kind": "chip", "height": 1e-3, "width": 5e-4},
}



def fault_of(keys: dict[str, Any], pair: Any) -> Any:
    """The :class:`~spurdyn.geometry.fault.Fault` of a table's ``keys`` on the pinion's tooth."""
    from spurdyn.case.fault_tables import fault_from_table

    return fault_from_table({"gear": "a", "tooth": TOOTH, **keys}, "fault", pair)


def lost_rolls(fault: Any, pair: Any) -> tuple[float, float]:
    """The pinion's rolls (rad) where its faulty flank can carry less: a pit's, or a chip's
    from its cut to the tip."""
    from spurdyn.geometry.fault import chip_roll

    if fault.roll is not None:
        return fault.roll
    return chip_roll(pair.gear_a, fault), pair.end_roll_a


def static_figures(rev: Any, fault: Any, pair: Any) -> dict[str, Any]:
    """Over the faulty cycles: the faulty tooth's pair force where its flank is in the lost
    stretch, with and without another pair on the path; and the revolution's figures."""
    pitch = 2.0 * math.pi / TEETH
    lo, hi = lost_rolls(fault, pair) if fault is not None else (math.nan, math.nan)
    inside_shared, inside_alone, outside = [], [], []
    for c in range(TEETH):
        j = (c - TOOTH) % TEETH
        at = np.flatnonzero(rev.cycle[:-1] == c)
        if j >= rev.force.shape[1] or at.size == 0:
            continue
        roll = pair.start_roll_a + rev.angle[at] - c * pitch + j * pitch
        f = rev.force[at, j]
        others = rev.force[at].sum(axis=1) - f
        inside = (roll >= lo) & (roll <= hi)
        inside_shared += list(f[inside & (others > 0.0)])
        inside_alone += list(f[inside & (others == 0.0)] / rev.load)
        outside += list(f[~inside & (f > 0.0)])
    s = rev.summary()
    return {"k_min": s["mesh_stiffness_min_N_per_m"], "k_mean": s["mesh_stiffness_mean_N_per_m"],
            "te_pp": s["transmission_error_pp_m"], "lost": s["contact_lost_fraction"],
            "shared_max": max(inside_shared, default=math.nan), "shared_n": len(inside_shared),
            "alone_share": min(inside_alone, default=math.nan), "alone_n": len(inside_alone)}


def run_point(name: str, keys: dict[str, Any] | None, folder: Path) -> tuple[Any, float]:
    """One run at speed through the command line: its result's dataset (loaded) and wall (s)."""
    import xarray as xr

    from spurdyn.cli.main import main

    case = folder / f"{abs(hash(name))}.toml"
    table = "" if keys is None else "\n[[fault]]\n" + "\n".join(
        f"{k} = {v!r}".replace("'", '"') for k, v in {"gear": "a", "tooth": TOOTH, **keys}.items()) + "\n"
    case.write_text(CASE.format(rpm=RPM) + table)
    out = folder / case.stem
    code, wall = timed(main, ["run", str(case), "--out", str(out), "--force", "--quiet", "--cycles", str(CYCLES),
                              "--max-cycles", str(CYCLES)])
    if code not in (0, 1):
        raise RuntimeError(f"spurdyn run {name} failed ({code})")
    with xr.open_dataset(out / "result.nc") as ds:
        return ds.load(), wall


def dynamic_figures(ds: Any, fault: Any, pair: Any) -> dict[str, Any]:
    """The last revolution's faulty tooth: its force where its flank is in the lost stretch
    and another pair carries, and the transmission error's range and the peak force."""
    import json

    from spurdyn.results.vibration import window

    info = json.loads(ds.attrs["info"])
    sel = window(ds, info["steady"], TEETH)
    teeth = ds["pair"].values
    cols = np.flatnonzero(teeth % TEETH == (-TOOTH) % TEETH)
    force = ds["pair_force"].values[sel]
    roll = np.radians(ds["pair_roll_deg"].values[sel])
    f, r = force[:, cols], roll[:, cols]
    others = np.nansum(force, axis=1)[:, None] - f
    lo, hi = lost_rolls(fault, pair) if fault is not None else (math.nan, math.nan)
    inside = (r >= lo) & (r <= hi) & (others > 0.0)
    te = ds["transmission_error"].values[sel]
    return {"shared_max": float(f[inside].max()) if inside.any() else math.nan, "shared_n": int(inside.sum()),
            "zero": float(np.mean(f[inside] == 0.0)) if inside.any() else math.nan,
            "te_pp": float(np.ptp(te)), "peak": float(np.nanmax(force)), "roll": r, "force": f,
            "settled": bool(info["steady"].get("settled", False))}


def balance(faults: tuple[Any, ...]) -> dict[str, float]:
    """Two mesh cycles of the 18-tooth pair meeting ``faults`` (the balance test's run:
    1,000 rpm, 60 N m, ``rho_inf = 1``, nothing damped, 800 steps a cycle, the NumPy loop):
    the energy's largest drift against the largest strain energy, each hub's momentum
    against its torques' impulse, and a crack's faces' largest force and least opening."""
    from dataclasses import replace

    from spurdyn.geometry.pair import GearPair
    from spurdyn.sector.model import SectorModel
    from spurdyn.settings import RPM
    from spurdyn.solvers.check import run_settings
    from spurdyn.solvers.sector.stepper import SectorRecord, make_stepper
    from spurdyn.geometry.presets import paper_pair

    p = paper_pair()
    small = GearPair(gear_a=replace(p.gear_a, teeth=18), gear_b=replace(p.gear_b, teeth=18), driver="a")
    s = run_settings(small, 1000 * RPM, 60.0, model="sector", cycles=1, rho_inf=1.0, faults=faults,
                     damping_ratio=0.0, rayleigh_mass=0.0, rayleigh_stiffness=0.0, backend="numpy", nx=2, ny=6)
    model = SectorModel.build(small, s, dt=2 * math.pi / 18 / s.speed_a / 800)
    record = SectorRecord(model, model.per_cycle * model.cycles, energy=True)
    n = 2 * model.per_cycle
    if make_stepper(model, record, "implicit", "numpy", energy=True).steps(n):
        raise RuntimeError(f"the balance run with {faults} stopped early")
    e = record.energy[:n + 1]
    total = e[:, 0] + e[:, 1] + e[:, 2] - e[:, 3]
    torque = e[:, 6:8] + record.torque[:n + 1]
    impulse = np.concatenate([np.zeros((1, 2)), np.cumsum(0.5 * model.h * (torque[1:] + torque[:-1]), axis=0)])
    mom = e[:, 4:6]
    booked = total - edge_work(model, record, n)
    out = {"energy": float(np.abs(total - total[0]).max() / e[:, 1].max()),
           "booked": float(np.abs(booked - booked[0]).max() / e[:, 1].max()),
           "momentum": float(np.abs(mom - mom[0] - impulse).max() / np.abs(mom[0]).max()),
           "faces_force": math.nan, "faces_open": math.nan}
    if record.faces is not None and any(f.kind == "crack" for f in faults):
        faces = record.faces[:n + 1]
        out.update(faces_force=float(faces[:, 0].max()), faces_open=float(faces[:, 1].min()))
    return out


def edge_work(model: Any, record: Any, n: int) -> np.ndarray:
    """The work the pits' edges do (J, cumulative over the steps): a pit's gap steps by its
    depth where a contact crosses an edge, a change of the rigid gap the rows carry no slope
    of, so the contact's force does work ``-F dg`` the balance does not book (the force at
    the step's end, the one that closes the new gap)."""
    th = record.theta[:n + 1, 0]
    force = np.nan_to_num(record.force[:n + 1])
    rolls = model.roll_0 + th[:, None] + model.c_teeth[None, :] * model.pitch
    pits = np.array([model.pit_gaps(model.c_teeth, model.c_side, r) for r in rolls])
    return np.concatenate([[0.0], np.cumsum(-(force[1:] * np.diff(pits, axis=0)).sum(axis=1))])


#: The balance runs' faults on the 18-tooth pair (docs/faults.md's balance test and more).
def balance_faults() -> dict[str, tuple[Any, ...]]:
    from spurdyn.geometry.fault import Fault

    pit = (math.radians(18.0), math.radians(24.0))
    return {"healthy (a pit of no depth)": (Fault("a", 1, "spall", roll=pit, depth=1e-12),),
            "tooth 1 missing": (Fault("a", 1, "missing"),),
            "tooth 1 missing, tooth 0 cracked 1 mm": (Fault("a", 1, "missing"), Fault("a", 0, "crack", depth=1e-3)),
            "tooth 1 pitted 2 um, 18-24 deg, whole face": (Fault("a", 1, "spall", roll=pit, depth=2e-6),),
            "tooth 1 pitted 20 um, 18-24 deg, whole face": (Fault("a", 1, "spall", roll=pit, depth=2e-5),),
            "tooth 1 pitted 20 um, 18-24 deg, half the face": (Fault("a", 1, "spall", roll=pit, depth=2e-5,
                                                                     width_fraction=0.5),),
            "tooth 1 chipped 1 mm x 0.5 mm": (Fault("a", 1, "chip", depth=1e-3, width=5e-4),)}


def draw(statics: dict[str, Any], runs: dict[str, Any], pair: Any, png: Path) -> None:
    """Left: the mesh stiffness over the faulty tooth's passage, each fault; right: the
    faulty tooth's pair force at speed against its flank's roll, the last revolution."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    pitch = 2.0 * math.pi / TEETH
    for name, (rev, _) in statics.items():
        near = (rev.angle >= (TOOTH - 2) * pitch) & (rev.angle <= (TOOTH + 3) * pitch)
        ax.plot(np.degrees(rev.angle[near]), rev.stiffness[near] / 1e6, lw=1, label=name)
    ax.set(xlabel="pinion turn from the start (deg)", ylabel="mesh stiffness (N/um)",
           title=f"statics: tooth {TOOTH}'s passage")
    ax.legend(fontsize=7)
    for name, (fig_d, _) in runs.items():
        r, f = fig_d["roll"], fig_d["force"]
        ok = np.isfinite(r)
        bx.plot(np.degrees(r[ok]), f[ok], ".", ms=1.5, label=name)
    bx.axvspan(math.degrees(pair.start_roll_a), math.degrees(pair.end_roll_a), color="0.92", zorder=0)
    bx.set(xlabel=f"roll of tooth {TOOTH}'s flank (deg)", ylabel="its pair force (N)",
           title=f"{RPM:,.0f} rpm, the last revolution")
    bx.legend(fontsize=7, markerscale=6)
    fig.savefig(png, dpi=110)
    plt.close(fig)


def _num(x: float, fmt: str) -> str:
    return "-" if x is None or not math.isfinite(x) else format(x, fmt)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python docs/validation faults_flanks", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the statics on a coarse mesh, one fault at speed")
    args = ap.parse_args(argv)
    from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
    from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY
    from spurdyn.sector.faulty import faulty_revolution

    pair = paper_pair()
    mesh = (2, 4) if args.quick else (DEFAULT_NX, DEFAULT_NY)
    faults = {name: fault_of(keys, pair) for name, keys in FAULTS.items()}
    statics = {}
    for name, f in {"healthy": None, **faults}.items():
        # the healthy revolution: a pit of no depth (the healthy pair to round-off, docs/faults.md)
        rev, wall = timed(faulty_revolution, pair, PAPER_TORQUE,
                          (f if f is not None else fault_of({**FAULTS[next(iter(FAULTS))], "depth": 1e-12}, pair),),
                          *mesh)
        statics[name] = (rev, static_figures(rev, f, pair) | {"wall": wall})
    moving = ["healthy", *(list(FAULTS)[:1] if args.quick else FAULTS)]
    with tempfile.TemporaryDirectory() as tmp:
        runs = {}
        for name in moving:
            ds, wall = run_point(name, FAULTS.get(name), Path(tmp))
            runs[name] = (dynamic_figures(ds, faults.get(name), pair) | {"wall": wall}, None)
    draw(statics, runs, pair, FIGURE)
    b_rows = []
    for name, faults in balance_faults().items():
        b, wall = timed(balance, faults)
        b_rows.append([name, f"{b['energy']:.4%}", f"{b['booked']:.4%}", f"{b['momentum']:.2g}", _num(b["faces_force"], ".3g"),
                       _num(b["faces_open"], ".2g"), f"{wall:.0f}"])
    s_rows = [[name, f"{v['k_min'] / 1e6:.2f}", f"{v['k_mean'] / 1e6:.2f}", _num(v["te_pp"] * 1e6, ".3f"),
               f"{v['lost']:.3%}", f"{_num(v['shared_max'], '.3g')} ({v['shared_n']})",
               f"{_num(v['alone_share'], '.4f')} ({v['alone_n']})", f"{v['wall']:.0f}"]
              for name, (_, v) in statics.items()]
    d_rows = [[name, f"{_num(v['shared_max'], '.3g')} ({v['shared_n']})", _num(v["zero"], ".1%"),
               f"{v['te_pp'] * 1e6:.3f}", f"{v['peak']:.1f}", "yes" if v["settled"] else "no", f"{v['wall']:.0f}"]
              for name, (v, _) in runs.items()]
    text = PAGE_TEXT.format(
        quick=" (`--quick`)" if args.quick else "", mesh=f"{mesh[0]} x {mesh[1]}", tooth=TOOTH, rpm=RPM,
        statics=table(["fault", "least k (N/um)", "mean k (N/um)", "TE p-p (um)", "no pair on the path",
                       "tooth's force in the stretch, another pair on (N; positions)",
                       "its share there alone (positions)", "wall (s)"], s_rows),
        moving=table(["fault", "tooth's force in the stretch, another pair on (N; samples)", "of them exactly 0",
                      "TE p-p (um)", "peak pair force (N)", "settled", "wall (s)"], d_rows),
        balances=table(["faults", "energy's largest drift / largest strain energy", "with the pits' edges booked",
                        "momentum less impulse / momentum", "faces' largest force (N)", "faces' least opening (m)",
                        "wall (s)"], b_rows),
        figure=FIGURE.relative_to(DOCS).as_posix())
    write_page(PAGE, text, echo=False)
    return 0


PAGE_TEXT = """# Spalls and chipped tips: the contact lost where it should be, and their signature

Generated by `python docs/validation faults_flanks`{quick} (the script's docstring has the
case); docs/faults.md has the models (section 3 the spall in the statics, section 8 in
motion).

The paper's pair under 22.25 N m, the pinion's tooth {tooth} faulty. The pinion's active
flank runs from roll 10.32 to 31.38 deg; one pair carries alone from 18.53 to 23.18 deg.
A pit's gap is its depth more than the flank's: where another pair is on the path it
touches only if the approach exceeds the depth, and a pit deeper than every deflection
(0.2 mm here, the pair's approach being some 6 um) never does; where the faulty pair is
alone on the path the load goes to the pit's bottom. Over part of the face, the intact part
carries with its own, narrower strip.

## 1. Over the revolution, in the statics

`faulty_revolution` (what `spurdyn stiffness CASE` with the fault runs), the {mesh} tooth
mesh, 41 positions a mesh cycle. "The tooth's force in the stretch": the faulty tooth's pair
force wherever its flank's roll is in the pit (or above the chip's cut) and another pair is
on the path, its largest over those positions; "its share there alone": the least share of
the load it carries where it is alone on the path in that stretch.

{statics}

## 2. At speed

The sector model at {rpm:,.0f} rpm, three revolutions of the pinion, the last one read;
the faulty tooth's pair force over the samples where its flank is in the stretch and another
pair carries.

{moving}

![The mesh stiffness over the faulty tooth's passage, and its pair force at speed]({figure})

Where a pit is deeper than any approach over the recess's double contact (0.2 mm) and above a
chip's cut, the faulty tooth carries exactly nothing whenever another pair is on the path,
in the statics and at speed: the contact is lost where it should be, and nowhere else
(the figure's left: the dip only in the cycles of tooth {tooth}'s passage). Over half the
face the intact half carries on its own, narrower strip, so its force never falls to 0
and the dip is shallow. The whole-face pit of 20 um over the single-contact stretch is
another matter at speed: the pair, alone there, drops into the pit (the transmission
error's range grows by about the pit's depth) and strikes its bottom and, leaving, the
next pair's entry: the impacts reach well above the healthy peak, they carry over into the
stretch's ends where the next pair is already on, and the run has not settled in three
revolutions.

## 3. The balances with the faults in motion

An 18-tooth version of the pair (two mesh cycles meeting the faults, 1,000 rpm, 60 N m,
`rho_inf = 1`, nothing damped, 800 steps a cycle, the NumPy loop, 2 x 6 teeth): the
energy (kinetic, strain, the strips' less the torques' work) and each hub's momentum
against its torques' impulse. The energy's drift is the model's left-out terms (the strip's
sliding along the deformed flank, docs/sector.md 6.5; the healthy run's bound is 4 %), the
momentum's round-off. A fault's balance is as tight as the healthy one's where its row is
at the healthy's figure.

{balances}

A pit's gap steps by its depth at its edges, a change of the rigid gap that the rows carry
no slope of: where the pair is loaded as it crosses an edge, its force does work `-F dg`
the balance does not book (docs/sector.md 6.2 books the smooth gap's through its slope).
Booked with the force at the step's end (`edge_work` in the script), the 2 um pit's drift is
the healthy run's to the digits shown: its edges are all of its excess. The 20 um pit, deeper
than the pair's approach where it carries alone, is entered by a drop and left by an impact
on the edge, whose work the force at the step's end does not measure: part is left. A pit's
edge is a step in the gap, not a modelled edge (docs/faults.md, section 3, leaves the pit's
rim out). The half-face pit of 20 um never closes its strip and its intact strip has no
edge; a chip's lost stretch is a contact not made, with no step in any gap: both balance as
the healthy pair does. The crack's faces close (their force) and never pass through each
other (their least opening is round-off), with the missing tooth's drift all but unchanged.
"""
