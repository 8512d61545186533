"""A faulty pair's loaded tooth contact analysis over the faulty gear's revolution
(docs/faults.md).

Mesh cycle ``c`` of the revolution starts with tooth ``c`` of each gear entering the path
as pair 0 (:mod:`spurdyn.geometry.fault` numbers the teeth so), and pair ``j`` is tooth
``c - j``. The sector of section 3 of docs/sector.md holds the driver's body teeth
``first_a ..`` (pair ``j`` on body tooth ``j``) and the driven's ``first_b ..`` (pair
``j`` on body tooth ``-j``), so a whole tooth ``k`` of the driver is its body tooth
``c - k`` and of the driven gear ``k - c``, taken round the gear into the sector's range.
A cycle whose sectors hold no faulty tooth is the healthy one, solved once; every other
is solved on its own sectors: a missing tooth's cell without its tooth and no contact on
it, a spalled flank's pair split into the intact face and the pit
(:data:`~spurdyn.sector.statics.Contact`), the pit's contact behind the pit's depth, a
cracked or chipped tooth's cell on its own mesh, and a chipped flank's pair left out where
its point lies beyond the cut.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault, chip_roll, faulty_cycles
from spurdyn.geometry.gear import Gear
from spurdyn.mesh.tooth import tooth_mesh
from spurdyn.geometry.pair import GearPair
from spurdyn.sector.body import SectorBody, body_cell
from spurdyn.sector.statics import (DEFAULT_POSITIONS, Contact, Contacts, ContactLaw, contact_law, default_teeth,
                                    driving_pair, healthy_contacts, sector_bodies, sector_firsts, solve_position)


@dataclass(frozen=True)
class Revolution:
    """The quasi-static mesh of a faulty pair over the faulty gear's revolution (SI).

    Attributes
    ----------
    angle
        ``(n,)`` the turn of the revolution's gear from the start of cycle 0 (rad).
    cycle
        ``(n,)`` the mesh cycle of each position.
    stiffness
        ``(n,)`` mesh stiffness (N/m); 0 where no pair carries the load.
    transmission_error
        ``(n,)`` loaded static transmission error (m); NaN where no pair carries the load
        (the gears part until the next pair's profiles meet, which the path of contact
        does not hold).
    force
        ``(n, P)`` the normal force of each pair ``j`` of the position's cycle (N).
    healthy_stiffness
        ``(n,)`` the healthy pair's mesh stiffness at the same positions (N/m).
    faulty
        The cycles whose sectors hold a faulty tooth.
    gear
        The revolution's gear, ``"a"`` or ``"b"`` (the driver's where both have faults).
    load, torque, teeth, n_dof
        As :class:`~spurdyn.sector.statics.MeshCycle`'s.
    """

    angle: NDArray[np.float64]
    cycle: NDArray[np.intp]
    stiffness: NDArray[np.float64]
    transmission_error: NDArray[np.float64]
    force: NDArray[np.float64]
    healthy_stiffness: NDArray[np.float64]
    faulty: tuple[int, ...]
    gear: str
    load: float
    torque: float
    teeth: int
    n_dof: int

    def summary(self) -> dict[str, Any]:
        """The figures of ``spurdyn stiffness --json`` with faults: the healthy cycle's keys
        over the revolution, and the fault's dip against the healthy pair."""
        k, te = self.stiffness[:-1], self.transmission_error[:-1]
        carried = np.isfinite(te)
        healthy_min = float(self.healthy_stiffness.min())
        return {
            "torque_Nm": self.torque, "load_N": self.load, "teeth_per_gear": self.teeth,
            "n_dof": self.n_dof, "positions": int(self.angle.size), "revolution_of": self.gear,
            "mesh_cycles": int(self.cycle.max()) + 1, "faulty_cycles": list(self.faulty),
            "mesh_stiffness_mean_N_per_m": float(k.mean()),
            "mesh_stiffness_min_N_per_m": float(k.min()),
            "mesh_stiffness_max_N_per_m": float(k.max()),
            "mesh_stiffness_healthy_min_N_per_m": healthy_min,
            "mesh_stiffness_dip": 1.0 - float(k.min()) / healthy_min,
            "contact_lost_fraction": float(1.0 - carried.mean()),
            "transmission_error_mean_m": float(te[carried].mean()) if carried.any() else None,
            "transmission_error_pp_m": float(np.ptp(te[carried])) if carried.any() else None,
            "load_share_max": float(self.force.max() / self.load),
        }


def _wrap(x: int, first: int, count: int, z: int) -> int | None:
    """Body tooth ``x`` taken round a gear of ``z`` teeth into ``first .. first + count - 1``."""
    m = first + (x - first) % z
    return m if m < first + count else None


@dataclass(frozen=True)
class _Cycle:
    """Where a revolution's faults sit in cycle ``c``'s sectors: body teeth per gear."""

    missing: tuple[frozenset[int], frozenset[int]]
    spalls: tuple[tuple[Fault, ...], tuple[Fault, ...]]
    touched: bool
    cracked: tuple[dict[int, Fault], dict[int, Fault]]
    chips: tuple[tuple[Fault, ...], tuple[Fault, ...]] = ((), ())


def _place(faults: tuple[Fault, ...], driver: str, c: int, firsts: tuple[int, int], teeth: int,
           zs: tuple[int, int]) -> _Cycle:
    """The faults of ``faults`` in cycle ``c``'s sectors (module docstring)."""
    missing: tuple[set[int], set[int]] = (set(), set())
    spalls: tuple[list[Fault], list[Fault]] = ([], [])
    cracked: tuple[dict[int, Fault], dict[int, Fault]] = ({}, {})
    chips: tuple[list[Fault], list[Fault]] = ([], [])
    touched = False
    for f in faults:
        g = 0 if f.gear == driver else 1
        m = _wrap(c - f.tooth if g == 0 else f.tooth - c, firsts[g], teeth, zs[g])
        if m is None:
            continue
        touched = True
        if f.kind == "missing":
            missing[g].add(m)
        elif f.kind in ("crack", "chip"):
            # both mesh the tooth's cell again
            cracked[g][m] = f
            if f.kind == "chip":
                chips[g].append(f)
        else:
            spalls[g].append(f)
    return _Cycle((frozenset(missing[0]), frozenset(missing[1])), (tuple(spalls[0]), tuple(spalls[1])),
                  touched, cracked, (tuple(chips[0]), tuple(chips[1])))


def _contacts(c: int, place: _Cycle, zs: tuple[int, int], cuts: dict[Fault, float]) -> Contacts:
    """Cycle ``c``'s contacts: a missing tooth's pair left out, a spalled flank's split, a
    chipped flank's left out where its roll lies beyond the cut's (``cuts``, its gear's
    own roll of the cut: the flank is gone there)."""
    def split(js: list[int], roll_a: NDArray[np.float64], roll_b: NDArray[np.float64]) -> list[Contact]:
        out: list[Contact] = []
        for i, j in enumerate(js):
            if j in place.missing[0] or -j in place.missing[1]:
                continue
            if any((c - j - f.tooth) % zs[g] == 0 and roll > cuts[f] for g, roll in
                   ((0, float(roll_a[i])), (1, float(roll_b[i]))) for f in place.chips[g]):
                continue
            parts = [(j, 1.0, 0.0)]
            for g, roll in ((0, float(roll_a[i])), (1, float(roll_b[i]))):
                for f in place.spalls[g]:
                    if (c - j - f.tooth) % zs[g] == 0 and f.covers(roll):
                        parts = [q for _, s, x in parts for q in ((j, s * (1.0 - f.width_fraction), x),
                                                               (j, s * f.width_fraction, x + f.depth))]
            out += [p for p in parts if p[1] > 0.0]
        return out
    return split


def _solve(law: ContactLaw, rolls: NDArray[np.float64], contacts: Contacts,
           bodies: tuple[SectorBody, SectorBody]) -> tuple[NDArray[np.float64], ...]:
    """Mesh stiffness, transmission error and pair forces at the driver's ``rolls``."""
    k, te = np.zeros(rolls.size), np.full(rolls.size, np.nan)
    force = np.zeros((rolls.size, law.pairs))
    faces = bodies[0].mesh.seams.shape[0] + bodies[1].mesh.seams.shape[0]
    for i, rho in enumerate(rolls):
        js, f, e, c, active = solve_position(law, float(rho), contacts, bodies)
        force[i, js] = f
        if active.any():
            idx = np.flatnonzero(active)
            # the tangent stiffness with the crack's closed faces held: the pairs' block of
            # the active set's inverse (the faces' rows eliminated)
            pairs = idx < c.shape[0] - faces
            k[i] = float(np.sum(np.linalg.inv(c[np.ix_(idx, idx)])[np.ix_(pairs, pairs)]))
            te[i] = e
    return k, te, force


def cracked_mesh(gear: Gear, fault: Fault, nx: int, ny: int, grading: float) -> Any:
    """The cracked cell of a crack fault, its crack from the loaded flank's fillet (the
    tension side: both bodies are loaded on their right flanks), free to run on into the
    rim below the tooth."""
    from spurdyn.mesh.cracked import crack_path, cracked_tooth

    cell = body_cell(gear, nx, ny, grading)
    tooth = tooth_mesh(gear, nx, ny, grading=grading)
    path = crack_path(gear, tooth, "right", fault.depth, fault.angle, fault.start, region=cell)
    return cracked_tooth(gear, cell, path)


def chipped_mesh(gear: Gear, fault: Fault, nx: int, ny: int, grading: float) -> Any:
    """The chipped cell of a chip fault, its corner cut off the loaded flank's tip (the right
    flank: both bodies are loaded on their right flanks); a chip of no height is the cell
    meshed again uncut (the reference of a chip's own effect)."""
    from spurdyn.mesh.chipped import chip_cut, chipped_tooth

    cell = body_cell(gear, nx, ny, grading)
    if fault.depth == 0.0:         # a chip of no size: the cell meshed again, uncut
        return chipped_tooth(cell, None)
    return chipped_tooth(cell, chip_cut(cell, gear.tip_radius, fault.depth, fault.width))


def fault_mesh(gear: Gear, fault: Fault, nx: int, ny: int, grading: float) -> Any:
    """The cell mesh of a crack or a chip fault."""
    return (chipped_mesh if fault.kind == "chip" else cracked_mesh)(gear, fault, nx, ny, grading)


#: Most positions a faulty revolution may solve unasked: each a contact problem of the
#: faulty sectors (5-50 ms on the paper's pair at 4 x 14), so some minutes at most.
MAX_FAULTY_POSITIONS = 20_000


def _check_work(n_cycles: int, touched: int, positions: int) -> None:
    """Refuse, before any work, a revolution whose ``touched`` faulty cycles hold more
    positions than :data:`MAX_FAULTY_POSITIONS` (faults on both gears of coprime tooth
    counts follow the two gears until they meet again: their product of cycles)."""
    if touched * positions > MAX_FAULTY_POSITIONS:
        raise InputError("fault", f"the faults' revolution ({n_cycles:,} mesh cycles, {touched:,} of them "
                         f"with a fault in the mesh) would solve {touched * positions:,} positions (limit "
                         f"{MAX_FAULTY_POSITIONS:,}): give fewer --positions, or the faults of one gear at a time")


def faulty_revolution(pair: GearPair, torque: float, faults: tuple[Fault, ...], nx: int, ny: int,
                      teeth: int | None = None, positions: int = DEFAULT_POSITIONS,
                      grading: float = 1.0) -> Revolution:
    """The loaded tooth contact analysis of ``pair`` with ``faults`` under the driver's
    ``torque`` (N m), ``positions`` positions a mesh cycle, over the faulty gear's revolution
    (module docstring)."""
    dp = driving_pair(pair)
    zs = (dp.gear_a.teeth, dp.gear_b.teeth)
    k_teeth = default_teeth(dp) if teeth is None else int(teeth)
    firsts = sector_firsts(dp, k_teeth)
    gears = {f.gear for f in faults}
    gear = gears.pop() if len(gears) == 1 else pair.driver
    turning = 0 if gear == pair.driver else 1
    n_cycles = faulty_cycles(zs[turning], zs[1 - turning], len({f.gear for f in faults}) == 2)
    places = [_place(faults, pair.driver, c, firsts, k_teeth, zs) for c in range(n_cycles)]
    _check_work(n_cycles, sum(p.touched for p in places), positions)
    healthy = sector_bodies(dp, k_teeth, nx, ny, grading=grading)
    law = contact_law(pair, torque, healthy)
    pitch = 2.0 * math.pi / zs[0]
    rolls = dp.start_roll_a + pitch * np.arange(positions) / (positions - 1)
    gear_of = {f: dp.gear_a if f.gear == pair.driver else dp.gear_b for f in faults}
    meshes = {f: fault_mesh(gear_of[f], f, nx, ny, grading) for f in faults if f.kind in ("crack", "chip")}
    cuts = {f: chip_roll(gear_of[f], f) for f in faults if f.kind == "chip"}
    base = _solve(law, rolls, healthy_contacts, healthy)
    parts, faulty = [], []
    for c, place in enumerate(places):
        if not place.touched:
            parts.append(base)
            continue
        faulty.append(c)
        cracked = tuple({m: meshes[f] for m, f in place.cracked[g].items()} for g in (0, 1))
        bodies = healthy if not any(place.missing) and not any(cracked) else sector_bodies(
            dp, k_teeth, nx, ny, grading=grading, missing=place.missing, cracked=cracked)
        parts.append(_solve(law, rolls, _contacts(c, place, zs, cuts), bodies))
    return _assemble(parts, base, rolls, faulty, gear, turning, zs, law, k_teeth, healthy, torque)


def _assemble(parts: list[tuple[NDArray[np.float64], ...]], base: tuple[NDArray[np.float64], ...],
              rolls: NDArray[np.float64], faulty: list[int], gear: str, turning: int,
              zs: tuple[int, int], law: ContactLaw, k_teeth: int, healthy: tuple[SectorBody, SectorBody],
              torque: float) -> Revolution:
    """The cycles end to end, each without its last position (the next one's first), and
    the first cycle's first position again at the end: a closed revolution."""
    n = len(parts)
    cut = slice(0, rolls.size - 1)
    # the revolution's gear turns a pitch of its own a mesh cycle
    per = (rolls[cut] - rolls[0]) * zs[0] / zs[turning]
    angle = np.concatenate([c * 2.0 * math.pi / zs[turning] + per for c in range(n)] + [[2.0 * math.pi * n / zs[turning]]])
    stack = [np.concatenate([p[i][cut] for p in parts] + [parts[0][i][:1]]) for i in range(3)]
    healthy_k = np.concatenate([base[0][cut]] * n + [base[0][:1]])
    cycle = np.concatenate([np.full(rolls.size - 1, c) for c in range(n)] + [[0]]).astype(np.intp)
    return Revolution(angle=angle, cycle=cycle, stiffness=stack[0], transmission_error=stack[1],
                      force=stack[2], healthy_stiffness=healthy_k, faulty=tuple(faulty), gear=gear,
                      load=law.load, torque=float(torque), teeth=k_teeth,
                      n_dof=healthy[0].mesh.n_dof + healthy[1].mesh.n_dof)


__all__ = ["MAX_FAULTY_POSITIONS", "Revolution", "chipped_mesh", "cracked_mesh", "fault_mesh", "faulty_revolution"]
