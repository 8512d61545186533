"""The fillet-foundation flexibility of Sainsot, Velex & Duverger (2004).

The tooth's root does not sit on a rigid wall: the gear body under it yields. Sainsot,
Velex & Duverger (J. Mech. Des. 126(4), 748-752, 2004) fitted, to finite-element results
of a gear body bored at ``r_int``, the deflection along the line of action

    delta_f = F cos^2(a1) / (E L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2(a1))],

with ``X*(h_f, theta_f) = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F``,
``h_f = r_f / r_int``, ``theta_f`` the tooth's half-angle on the root circle, ``S_f`` the
tooth's thickness there (arc ``2 r_f theta_f``) and ``u_f`` the distance from the root
circle to where the line of action crosses the centre line. ``docs/faults_energy.md``,
section 2.3, says where the coefficients below were read and what they assume.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError
from spurdyn.geometry.gear import Gear
from spurdyn.energy.section import half_height, load_angle, radial_position

#: Sainsot, Velex & Duverger (2004), table of the polynomial coefficients (A, B, C, D, E, F)
#: of ``L*``, ``M*``, ``P*``, ``Q*``.
SAINSOT_COEFFICIENTS = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}


def sainsot_factor(name: str, h_f: float, theta_f: float) -> float:
    """``X*(h_f, theta_f)`` of one of ``"L"``, ``"M"``, ``"P"``, ``"Q"``."""
    a, b, c, d, e, f = SAINSOT_COEFFICIENTS[name]
    return a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + f


def root_half_angle(gear: Gear) -> float:
    """``theta_f`` (rad): the tooth's polar half-angle where its fillet meets the root circle."""
    x, y = gear.fillet_points(np.asarray(0.0))
    return math.atan2(float(x), float(y))


def centre_line_crossing(gear: Gear, roll: ArrayLike) -> NDArray[np.float64]:
    """Distance (m) from the gear centre at which the line of action through the flank
    point of roll angle ``roll`` crosses the tooth's centre line: ``y(-a1) - h(-a1) tan(a1)``."""
    rb, a2 = gear.base_radius, gear.half_angle_base
    a1 = load_angle(gear, roll)
    return radial_position(-a1, rb, a2) - half_height(-a1, rb, a2) * np.tan(a1)


def check_bore(gear: Gear, bore_radius: float, key: str = "bore_radius") -> None:
    """Refuse a bore radius that is not a length between 0 and the root radius."""
    if isinstance(bore_radius, bool) or not isinstance(bore_radius, (int, float)) \
            or not math.isfinite(bore_radius) or not 0.0 < bore_radius < gear.root_radius:
        raise InputError(key, f"must be a radius (m) between 0 and the root radius "
                         f"{gear.root_radius:g} m (got {bore_radius!r})")


def foundation_compliance(gear: Gear, roll: ArrayLike, bore_radius: float,
                          face_width: float | None = None) -> NDArray[np.float64]:
    """The fillet foundation's compliance (m/N) along the line of action at the flank
    points of roll angles ``roll``, the body bored at ``bore_radius`` (m).

    ``face_width`` defaults to the gear's; the material's Young's modulus as published
    (plane stress, as the tooth's beam terms)."""
    check_bore(gear, bore_radius)
    rf = gear.root_radius
    a1 = load_angle(gear, roll)
    u_f = centre_line_crossing(gear, roll) - rf
    theta_f = root_half_angle(gear)
    s_f = 2.0 * rf * theta_f
    h_f = rf / bore_radius
    big_l, big_m, big_p, big_q = (sainsot_factor(n, h_f, theta_f) for n in "LMPQ")
    ratio = u_f / s_f
    width = gear.face_width if face_width is None else face_width
    return np.cos(a1) ** 2 / (gear.material.young * width) * (
        big_l * ratio**2 + big_m * ratio + big_p * (1.0 + big_q * np.tan(a1) ** 2))


__all__ = ["SAINSOT_COEFFICIENTS", "centre_line_crossing", "check_bore", "foundation_compliance", "root_half_angle",
           "sainsot_factor"]
