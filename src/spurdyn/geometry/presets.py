"""Ready-made gear pairs."""

from __future__ import annotations

import dataclasses
import math

from spurdyn.fem.material import Material
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair

#: The NASA Lewis test-rig gear of the paper's example (Lee & Jang, section 4).
PAPER_MATERIAL = Material(young=210e9, poisson=0.3, density=7.8e3)


def paper_gear() -> Gear:
    """One gear of the paper's pair: 28 teeth, r_p = 44.45 mm, 20 deg, b = 6.35 mm."""
    return Gear.from_radii(
        teeth=28,
        pitch_radius=0.04445,
        tip_radius=0.047625,
        root_radius=0.04048,
        pressure_angle=math.radians(20.0),
        face_width=0.00635,
        disk_inertia=2.965e-4,
        material=PAPER_MATERIAL,
    )


def paper_pair() -> GearPair:
    """The paper's identical pair on the standard centre distance, gear A driving."""
    g = paper_gear()
    return GearPair(gear_a=g, gear_b=g, driver="a")

#: The paper's external torque tau_0 (N m).
PAPER_TORQUE = 22.25


#: Tip relief amount of :func:`nasa_like_relief` (m). An ASSUMPTION of typical magnitude
#: for a gear of this size (module 3.175 mm), not a value taken from the NASA reports:
#: see ``docs/relief.md``.
NASA_LIKE_TIP_RELIEF = 20e-6


def nasa_like_relief(gear: Gear, mate: Gear | None = None,
                     amount: float = NASA_LIKE_TIP_RELIEF, shape: str = "linear") -> Gear:
    """``gear`` with a typical test-rig tip relief: linear, 20 um, from the HPSTC.

    The relief starts at the highest point of single-tooth contact (HPSTC) of ``gear``
    meshing with ``mate`` (default: an identical gear) on the standard centre distance,
    so that it only acts while two pairs share the load, and removes ``amount`` at the
    tip. For the paper's gear the start is at roll angle 23.18 deg (radius 45.06 mm).

    The NASA Lewis rig gears of the paper's reference had *a* tip relief; its exact
    amount and start are not known to this package. 20 um starting at the HPSTC is an
    assumption of typical magnitude for this gear size, documented as such in
    ``docs/relief.md``; give ``amount``/``shape`` (or build the :class:`Gear` yourself)
    to study others.
    """
    pair = GearPair(gear_a=gear, gear_b=gear if mate is None else mate)
    start = pair.single_contact_roll_a[1]
    return dataclasses.replace(gear, tip_relief=amount, tip_relief_start_roll=start,
                               tip_relief_shape=shape)
