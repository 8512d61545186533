"""A meshing pair of involute spur gears and the figures of its line of action.

The working geometry (working pressure angle, centre distance from the profile shifts,
backlash) comes from :mod:`spurdyn.geometry.working`; ``docs/geometry.md``, sections 4 and 8.
SI units throughout: m, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from spurdyn.errors import InputError
from spurdyn.geometry import involute as ivl
from spurdyn.geometry import working as wkg
from spurdyn.geometry.gear import Gear, require_positive


def default_centre_distance(gear_a: Gear, gear_b: Gear) -> float:
    """The centre distance of a pair that gives none (m): zero backlash for the nominal
    shifts, exactly ``r_1 + r_2`` without shift."""
    return wkg.zero_backlash_centre_distance(
        gear_a.pitch_radius + gear_b.pitch_radius, gear_a.pressure_angle,
        gear_a.profile_shift + gear_b.profile_shift, gear_a.teeth + gear_b.teeth)


@dataclass(frozen=True)
class GearPair:
    """Two meshing gears, A and B, on a given centre distance.

    Parameters
    ----------
    gear_a, gear_b
        The two gears.
    centre_distance
        Centre distance (m); ``None`` takes the standard one, the sum of pitch radii.
    driver
        ``"a"`` or ``"b"``: which gear drives.
    """

    gear_a: Gear
    gear_b: Gear
    centre_distance: float | None = None
    driver: str = "a"

    def __post_init__(self) -> None:
        ga, gb = self.gear_a, self.gear_b
        if self.centre_distance is None:
            object.__setattr__(self, "centre_distance", default_centre_distance(ga, gb))
        require_positive("centre_distance", self.centre_distance)
        if self.driver not in ("a", "b"):
            raise InputError("driver", f"must be 'a' or 'b' (got {self.driver!r})")
        if not math.isclose(self.gear_a.module, self.gear_b.module, rel_tol=1e-9):
            raise InputError("gear_b.module", "differs from gear_a's; meshing gears need one module")
        if not math.isclose(self.gear_a.pressure_angle, self.gear_b.pressure_angle, rel_tol=1e-9):
            raise InputError("gear_b.pressure_angle", "differs from gear_a's")
        rb = self.gear_a.base_radius + self.gear_b.base_radius
        if self.centre_distance <= rb:
            raise InputError("centre_distance", f"must exceed the sum of base radii {rb:g} m")
        if self.backlash_normal < -1e-12 * self.centre_distance:
            raise InputError("centre_distance", f"{self.centre_distance:.6g} m is too small for "
                             f"these teeth: their flanks would overlap by "
                             f"{-self.backlash_normal * 1e6:.3g} um; use at least "
                             f"{self.tight_centre_distance:.6g} m (no backlash)")
        if self.centre_distance <= self.gear_a.tip_radius + self.gear_b.root_radius or \
                self.centre_distance <= self.gear_b.tip_radius + self.gear_a.root_radius:
            raise InputError("centre_distance", "is too small: a tip would hit the other gear's root")
        if self.path_of_contact <= 0.0:
            raise InputError("centre_distance", "is too large: the tip circles do not reach "
                             "across the line of action, so the gears never touch")
        if self.contact_ratio < 1.0:
            raise InputError("centre_distance", f"gives a contact ratio {self.contact_ratio:.3f} "
                             "below 1; the pair would not mesh continuously")
        for name, gear, start in (("gear_a", self.gear_a, self.start_roll_a),
                                  ("gear_b", self.gear_b, self.start_roll_b)):
            if start * gear.base_radius < float(ivl.roll_length(gear.form_radius, gear.base_radius)) - 1e-12:
                raise InputError(f"{name}.cutter_tip_radius", "the mating tip reaches below the "
                                 "involute into the fillet (interference); use a smaller cutter "
                                 "tip radius, a shorter mating addendum or a positive "
                                 "profile shift on this gear")

    # -- line of action ----------------------------------------------------------------
    @property
    def working_pressure_angle(self) -> float:
        return math.acos((self.gear_a.base_radius + self.gear_b.base_radius) / self.centre_distance)

    @property
    def working_pitch_radii(self) -> tuple[float, float]:
        """Radii (m) of the circles that roll on each other: ``r_b / cos(alpha_w)``."""
        c = math.cos(self.working_pressure_angle)
        return self.gear_a.base_radius / c, self.gear_b.base_radius / c

    def _backlash_args(self) -> tuple[tuple[float, float], tuple[float, float], float]:
        ga, gb = self.gear_a, self.gear_b
        return (ga.base_radius, gb.base_radius), (ga.base_thickness, gb.base_thickness), ga.base_pitch

    @property
    def backlash_normal(self) -> float:
        """Normal backlash ``j_n`` (m): the play along the line of action."""
        return wkg.normal_backlash(self.centre_distance, *self._backlash_args())

    @property
    def backlash_circumferential(self) -> float:
        """Circumferential backlash ``j_t`` (m) on the working pitch circles, ``j_n / cos(alpha_w)``."""
        return self.backlash_normal / math.cos(self.working_pressure_angle)

    @property
    def tight_centre_distance(self) -> float:
        """Centre distance (m) at which these teeth would mesh without backlash."""
        return wkg.tight_centre_distance(*self._backlash_args())

    @property
    def line_of_centres_length(self) -> float:
        """Length of the common tangent of the base circles, ``a sin(alpha_w)``."""
        return self.centre_distance * math.sin(self.working_pressure_angle)

    @property
    def tip_roll_length_a(self) -> float:
        return float(ivl.roll_length(self.gear_a.tip_radius, self.gear_a.base_radius))

    @property
    def tip_roll_length_b(self) -> float:
        return float(ivl.roll_length(self.gear_b.tip_radius, self.gear_b.base_radius))

    @property
    def path_of_contact(self) -> float:
        """Length of the path of contact along the line of action (m)."""
        return self.tip_roll_length_a + self.tip_roll_length_b - self.line_of_centres_length

    @property
    def contact_ratio(self) -> float:
        return self.path_of_contact / self.gear_a.base_pitch

    # Roll lengths on A along the line of action, measured from A's base tangent point:
    # contact runs from B's tip (start, low on A) to A's tip (end) when A drives.
    @property
    def start_roll_length_a(self) -> float:
        return self.line_of_centres_length - self.tip_roll_length_b

    @property
    def end_roll_length_a(self) -> float:
        return self.tip_roll_length_a

    @property
    def start_roll_a(self) -> float:
        """Roll angle of A at the start of its active profile (rad)."""
        return self.start_roll_length_a / self.gear_a.base_radius

    @property
    def start_roll_b(self) -> float:
        """Roll angle of B at the start of its active profile (rad)."""
        return (self.line_of_centres_length - self.tip_roll_length_a) / self.gear_b.base_radius

    @property
    def pitch_roll_a(self) -> float:
        return math.tan(self.working_pressure_angle)

    @property
    def end_roll_a(self) -> float:
        return self.end_roll_length_a / self.gear_a.base_radius

    @property
    def theta_s(self) -> float:
        """Angle of action of gear A: the rotation over the whole contact (rad)."""
        return self.path_of_contact / self.gear_a.base_radius

    @property
    def theta_2(self) -> float:
        """Double-contact angle of gear A at each end of the engagement (rad)."""
        return self.theta_s - 2.0 * math.pi / self.gear_a.teeth

    @property
    def single_contact_angle(self) -> float:
        return self.theta_s - 2.0 * self.theta_2

    @property
    def single_contact_roll_a(self) -> tuple[float, float]:
        """Roll angles of A where single-tooth contact begins and ends (rad)."""
        return self.start_roll_a + self.theta_2, self.end_roll_a - self.theta_2

    def roll_b_from_roll_a(self, roll_a: float | np.ndarray) -> np.ndarray:
        """Roll angle on B of the contact point whose roll angle on A is ``roll_a``."""
        return (self.line_of_centres_length - np.asarray(roll_a) * self.gear_a.base_radius) \
            / self.gear_b.base_radius
