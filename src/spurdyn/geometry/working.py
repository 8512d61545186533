"""Working geometry of a pair of (profile-shifted) involute gears: numbers in, numbers out.

``docs/geometry.md``, section 8, derives these. With ``s_b = 2 r_b psi_b`` the base
thickness of a tooth (``psi_b`` its polar half-angle at the base circle) and ``p_b`` the
base pitch, the normal backlash on centre distance ``a`` is

    j_n = p_b - s_b1 - s_b2 + 2 (r_b1 + r_b2) inv(alpha_w),   cos(alpha_w) = (r_b1 + r_b2) / a,

and the circumferential backlash on the working pitch circles is ``j_t = j_n / cos(alpha_w)``.
Setting ``j_n = 0`` for teeth of nominal thickness gives the classical
``inv(alpha_w) = 2 tan(alpha) (x1 + x2) / (z1 + z2) + inv(alpha)``.
"""

from __future__ import annotations

import math

from spurdyn.geometry import involute as ivl


def inv_inverse(y: float) -> float:
    """The angle ``a`` in ``[0, pi/2)`` with ``tan(a) - a = y`` (``y >= 0``), by Newton."""
    if y <= 0.0:
        return 0.0
    a = min((3.0 * y) ** (1.0 / 3.0), 1.5)   # inv(a) ~ a^3 / 3 for small a
    for _ in range(60):
        t = math.tan(a)
        step = (t - a - y) / (t * t)          # d inv / da = tan^2(a)
        a -= step
        if abs(step) < 1e-16 * max(a, 1.0):
            break
    return a


def working_pressure_angle(pressure_angle: float, shift_sum: float, teeth_sum: int) -> float:
    """``alpha_w`` (rad) of a zero-backlash pair: ``inv alpha_w = 2 tan alpha sum(x)/sum(z) + inv alpha``."""
    y = 2.0 * math.tan(pressure_angle) * shift_sum / teeth_sum + float(ivl.inv(pressure_angle))
    return inv_inverse(y)


def zero_backlash_centre_distance(pitch_radius_sum: float, pressure_angle: float,
                                  shift_sum: float, teeth_sum: int) -> float:
    """Centre distance (m) at which teeth of shifts summing to ``shift_sum`` mesh without play.

    ``a = (r_1 + r_2) cos(alpha) / cos(alpha_w)``; exactly ``r_1 + r_2`` without shift.
    """
    if shift_sum == 0.0:
        return pitch_radius_sum
    aw = working_pressure_angle(pressure_angle, shift_sum, teeth_sum)
    return pitch_radius_sum * math.cos(pressure_angle) / math.cos(aw)


def normal_backlash(centre_distance: float, base_radii: tuple[float, float],
                    base_thicknesses: tuple[float, float], base_pitch: float) -> float:
    """Normal backlash ``j_n`` (m) along the line of action; negative if the teeth overlap."""
    rb = base_radii[0] + base_radii[1]
    aw = math.acos(rb / centre_distance)
    return base_pitch - base_thicknesses[0] - base_thicknesses[1] + 2.0 * rb * float(ivl.inv(aw))


def tight_centre_distance(base_radii: tuple[float, float],
                          base_thicknesses: tuple[float, float], base_pitch: float) -> float:
    """Centre distance (m) at which these teeth mesh with no backlash (``j_n = 0``)."""
    rb = base_radii[0] + base_radii[1]
    y = (base_thicknesses[0] + base_thicknesses[1] - base_pitch) / (2.0 * rb)
    return rb / math.cos(inv_inverse(y))
