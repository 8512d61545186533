"""Ready-made gear pairs."""

from __future__ import annotations

import math

from spurdyn.fem.material import Material
from spurdyn.geometry.gear import Gear, GearPair

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
