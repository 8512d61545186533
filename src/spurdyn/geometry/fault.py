"""A fault on one tooth of a gear (docs/faults.md): what it is, in SI units.

Teeth are numbered round each whole gear in the order they enter the mesh: tooth 0 of
each gear is the one entering the path of contact at the start of the first mesh cycle
(the two meet there), tooth ``k`` enters ``k`` mesh cycles after it.

Kinds built so far: a **missing** tooth (broken off at its root), a **spall** (a pit
over a stretch of the flank's roll, of a depth, over a fraction of the face width) and a
root **crack** (straight, from the fillet of the loaded flank into the tooth, through the
face width) and a **chip** (the loaded flank's tip corner cut off by a straight cut through
the face width). The kinds the case file knows but no model computes yet are refused by
name where they are read (:data:`PLANNED_KINDS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair

#: Fault kinds a model computes.
KINDS = ("missing", "spall", "crack", "chip")
#: Fault kinds a case file may name that no model computes yet (refused by name).
PLANNED_KINDS: tuple[str, ...] = ()


@dataclass(frozen=True)
class Fault:
    """One fault on one tooth.

    Attributes
    ----------
    gear
        ``"a"`` or ``"b"``.
    tooth
        The tooth, ``0 .. z - 1`` on its gear (module docstring).
    kind
        One of :data:`KINDS`.
    roll
        A spall's stretch of the faulty flank: its gear's own roll angles (rad) at the
        pit's two ends, ``roll[0] < roll[1]``; ``None`` for a missing tooth.
    depth
        A spall's depth normal to the flank, a crack's length, a chip's height (its cut leaves
        the loaded flank at radius ``r_a - depth``) (m): the fault's size; 0 for a missing
        tooth.
    width_fraction
        The share of the face width the spall covers, ``(0, 1]``; 1 for the other kinds.
    angle
        A crack's angle below the horizontal toward the tooth's centre line (rad); ``None``:
        the mesher's default (:func:`spurdyn.mesh.cracked.crack_path`).
    start
        The radius of a crack's mouth on the fillet (m); ``None``: the mesher's default.
    width
        A chip's width (m): the cut meets the top land this far from the loaded flank's
        tip corner, measured along the tip circle's arc.
    """

    gear: str
    tooth: int
    kind: str
    roll: tuple[float, float] | None = None
    depth: float = 0.0
    width_fraction: float = 1.0
    angle: float | None = None
    start: float | None = None
    width: float = 0.0

    def covers(self, roll: float) -> bool:
        """Whether the faulty flank's point at its gear's roll angle ``roll`` (rad) lies in
        the pit (a spall's, ends included); never for other kinds."""
        return self.roll is not None and self.roll[0] <= roll <= self.roll[1]


def active_rolls(pair: GearPair, gear: str) -> tuple[float, float]:
    """The roll angles (rad) of ``gear``'s (``"a"`` or ``"b"``) own flank at the two ends of
    its active profile: from where the mating tip reaches to its own tip."""
    if gear == "a":
        return pair.start_roll_a, pair.end_roll_a
    return pair.start_roll_b, pair.tip_roll_length_b / pair.gear_b.base_radius


def chip_roll(gear: Gear, fault: Fault) -> float:
    """The roll angle (rad) of a chip's cut on its gear's loaded flank: the involute point
    of radius ``r_a - height`` (``fault.depth``); the flank beyond it (toward the tip) is
    gone."""
    r = gear.tip_radius - fault.depth
    return math.sqrt(max(r * r - gear.base_radius ** 2, 0.0)) / gear.base_radius


def tooth_index(tooth: int, teeth: int) -> int:
    """``tooth`` taken round a gear of ``teeth`` teeth: ``0 .. teeth - 1``."""
    return int(tooth) % int(teeth)


def faulty_cycles(teeth: int, other: int, both: bool) -> int:
    """Mesh cycles of the revolution a faulty pair is followed over: the faulty gear's
    teeth, or for faults on both gears the cycles until the two meet again as they
    started (the least common multiple)."""
    return teeth * other // math.gcd(teeth, other) if both else teeth


__all__ = ["Fault", "KINDS", "PLANNED_KINDS", "active_rolls", "chip_roll", "faulty_cycles", "tooth_index"]
