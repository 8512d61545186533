"""ISO 6336-2:2019 nominal contact stress of an external spur pair, and the contact ratio.

Pure functions of numbers, SI units (m, rad, N, Pa). Spur gears only: helix angle
``beta = 0``, so ``Z_beta = 1`` and the transverse and normal sections coincide. The
derivations and a worked example are in ``docs/iso6336.md``.

Clauses are those of ISO 6336-2:2019 (5 basic formulae, 6 ``Z_H`` and ``Z_B``/``Z_D``,
7 ``Z_E``, 8 ``Z_eps``);
the standard's text was not at hand, so equations are named by what they compute rather
than by number (``docs/iso6336.md``, section 8, lists what was checked against what).
"""

from __future__ import annotations

import math


def roll_length(radius: float, base_radius: float) -> float:
    """Length ``sqrt(r^2 - r_b^2)`` of the generating line from the base circle to radius ``r``."""
    return math.sqrt(radius * radius - base_radius * base_radius)


def transverse_contact_ratio(z1: int, z2: int, module: float, pressure_angle: float,
                             tip_radius1: float, tip_radius2: float,
                             centre_distance: float | None = None) -> float:
    """Transverse contact ratio ``eps_alpha`` of an external spur pair (ISO 21771, used by ISO 6336-1).

    ``eps_alpha = (sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2) - a sin(alpha_w)) / p_b``
    with ``p_b = pi m cos(alpha)`` and ``cos(alpha_w) = (r_b1 + r_b2) / a``.

    Parameters
    ----------
    z1, z2
        Numbers of teeth.
    module
        Module ``m`` (m).
    pressure_angle
        Pressure angle ``alpha`` of the basic rack (rad).
    tip_radius1, tip_radius2
        Tip radii ``r_a`` (m).
    centre_distance
        Centre distance ``a`` (m); ``None`` is the standard ``m (z1 + z2) / 2``.

    Returns
    -------
    float
        ``eps_alpha``.
    """
    rb1 = 0.5 * module * z1 * math.cos(pressure_angle)
    rb2 = 0.5 * module * z2 * math.cos(pressure_angle)
    a = 0.5 * module * (z1 + z2) if centre_distance is None else centre_distance
    alpha_w = math.acos((rb1 + rb2) / a)
    path = roll_length(tip_radius1, rb1) + roll_length(tip_radius2, rb2) - a * math.sin(alpha_w)
    return path / (math.pi * module * math.cos(pressure_angle))


def zone_factor(pressure_angle: float, working_pressure_angle: float | None = None) -> float:
    """Zone factor ``Z_H`` (ISO 6336-2:2019, clause 6, the ``Z_H`` equation) for a spur pair.

    ``Z_H = sqrt(2 cos(beta_b) cos(alpha_wt) / (cos^2(alpha_t) sin(alpha_wt)))`` with
    ``beta_b = 0``, ``alpha_t = alpha_n``; on the standard centre distance
    (``working_pressure_angle=None``) ``alpha_wt = alpha_t`` and ``Z_H = sqrt(4 / sin(2 alpha))``.

    Parameters
    ----------
    pressure_angle
        ``alpha_t = alpha_n`` (rad).
    working_pressure_angle
        ``alpha_wt`` (rad); ``None`` for the standard centre distance.
    """
    aw = pressure_angle if working_pressure_angle is None else working_pressure_angle
    return math.sqrt(2.0 * math.cos(aw) / (math.cos(pressure_angle) ** 2 * math.sin(aw)))


def elasticity_factor(young1: float, poisson1: float, young2: float, poisson2: float) -> float:
    """Elasticity factor ``Z_E`` (ISO 6336-2:2019, clause 7, the ``Z_E`` equation), in sqrt(Pa).

    ``Z_E = sqrt(1 / (pi ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)))``: Hertz's constant for two
    cylinders. ISO quotes 189.8 sqrt(N/mm^2) for steel on steel with E = 206 GPa; in SI
    that is 1.898e5 sqrt(Pa).
    """
    return math.sqrt(1.0 / (math.pi * ((1.0 - poisson1**2) / young1 + (1.0 - poisson2**2) / young2)))


def contact_ratio_factor(eps_alpha: float) -> float:
    """Contact ratio factor ``Z_eps`` of spur gears (ISO 6336-2:2019, clause 8, spur-gear equation).

    ``Z_eps = sqrt((4 - eps_alpha) / 3)``; 1 at ``eps_alpha = 1`` (one pair carries all).
    """
    return math.sqrt((4.0 - eps_alpha) / 3.0)


def single_pair_contact_factors(z1: int, z2: int, module: float, pressure_angle: float,
                                tip_radius1: float, tip_radius2: float, eps_alpha: float,
                                centre_distance: float | None = None) -> tuple[float, float]:
    """Single pair tooth contact factors ``(Z_B, Z_D)`` of a spur pair (ISO 6336-2:2019, clause 6).

    ``M_1 = tan(alpha_w) / sqrt((tan(alpha_a1) - 2 pi/z1) (tan(alpha_a2) - (eps_alpha - 1) 2 pi/z2))``,
    ``M_2`` the same with 1 and 2 swapped; ``Z_B = max(1, M_1)``, ``Z_D = max(1, M_2)``.
    The brackets are the roll angles of pinion and wheel at the inner point of single
    contact of the pinion (B; of the wheel, D), so ``M_1^2`` is the ratio of the products
    of curvature radii at the pitch point and at B: ``Z_B sigma_H0`` is the Hertz stress
    at B when that exceeds the pitch point's.

    Parameters
    ----------
    z1, z2, module, pressure_angle, tip_radius1, tip_radius2, centre_distance
        As :func:`transverse_contact_ratio`.
    eps_alpha
        The pair's transverse contact ratio.
    """
    a = 0.5 * module * (z1 + z2) if centre_distance is None else centre_distance
    cos_a = math.cos(pressure_angle)
    rb1, rb2 = 0.5 * module * z1 * cos_a, 0.5 * module * z2 * cos_a
    tan_w = math.tan(math.acos((rb1 + rb2) / a))
    tan_a1 = roll_length(tip_radius1, rb1) / rb1
    tan_a2 = roll_length(tip_radius2, rb2) / rb2
    m1 = tan_w / math.sqrt((tan_a1 - 2.0 * math.pi / z1) * (tan_a2 - (eps_alpha - 1.0) * 2.0 * math.pi / z2))
    m2 = tan_w / math.sqrt((tan_a2 - 2.0 * math.pi / z2) * (tan_a1 - (eps_alpha - 1.0) * 2.0 * math.pi / z1))
    return max(1.0, m1), max(1.0, m2)


def nominal_contact_stress(tangential_force: float, pitch_diameter1: float, face_width: float,
                           ratio: float, z_h: float, z_e: float, z_eps: float,
                           z_beta: float = 1.0) -> float:
    """Nominal contact stress ``sigma_H0`` (Pa) at the pitch point (ISO 6336-2:2019, clause 5).

    ``sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t / (d_1 b) (u + 1) / u)``; ``Z_beta = 1``
    for spur gears. The single-pair factors ``Z_B``/``Z_D`` and the load factors enter
    ``sigma_H`` (:func:`spurdyn.iso6336.safety.contact_stress`), not here.

    Parameters
    ----------
    tangential_force
        Nominal tangential force ``F_t`` at the reference circle (N).
    pitch_diameter1
        Reference diameter of the pinion ``d_1`` (m).
    face_width
        Face width ``b`` (m).
    ratio
        Gear ratio ``u = z2 / z1`` (>= 1 by ISO's convention; the formula is symmetric
        in which gear is called the pinion only through ``d_1``).
    """
    return z_h * z_e * z_eps * z_beta * math.sqrt(
        tangential_force / (pitch_diameter1 * face_width) * (ratio + 1.0) / ratio)
