"""Pure functions of the involute flank and the trochoidal root fillet.

Frame: the gear's own frame, centre at the origin, the tooth's centre line along +y.
Polar angles ``chi`` are measured from +y towards +x (clockwise), so the tooth's
*right* flank lies at ``chi > 0``; the left flank is its mirror image. All lengths in m,
angles in rad. The derivations are in ``docs/geometry.md``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def inv(alpha: ArrayLike) -> NDArray[np.float64]:
    """Involute function ``tan(alpha) - alpha``."""
    a = np.asarray(alpha, dtype=float)
    return np.tan(a) - a


def pressure_angle_at(r: ArrayLike, base_radius: float) -> NDArray[np.float64]:
    """Profile pressure angle ``alpha_r = arccos(r_b / r)`` at radius ``r >= r_b``."""
    return np.arccos(np.clip(base_radius / np.asarray(r, dtype=float), -1.0, 1.0))


def half_angle(r: ArrayLike, base_radius: float, half_angle_base: float) -> NDArray[np.float64]:
    """Polar half-angle of the tooth at radius ``r`` on the involute.

    ``half_angle_base`` is the half-angle at the base circle, ``s_p / (2 r_p) + inv(alpha)``.
    """
    return half_angle_base - inv(pressure_angle_at(r, base_radius))


def roll_length(r: ArrayLike, base_radius: float) -> NDArray[np.float64]:
    """Length of the generating line from the base circle to the involute point at ``r``."""
    r = np.asarray(r, dtype=float)
    return np.sqrt(np.maximum(r * r - base_radius**2, 0.0))


def radius_at_roll(length: ArrayLike, base_radius: float) -> NDArray[np.float64]:
    """Radius of the involute point whose roll length is ``length``."""
    length = np.asarray(length, dtype=float)
    return np.sqrt(base_radius**2 + length * length)


def right_flank_point(
    r: ArrayLike, base_radius: float, half_angle_base: float
) -> NDArray[np.float64]:
    """Points ``(..., 2)`` of the right involute flank at radii ``r``."""
    chi = half_angle(r, base_radius, half_angle_base)
    r = np.asarray(r, dtype=float)
    return np.stack([r * np.sin(chi), r * np.cos(chi)], axis=-1)


def right_flank_normal(
    r: ArrayLike, base_radius: float, half_angle_base: float
) -> NDArray[np.float64]:
    """Outward unit normals ``(..., 2)`` of the right involute flank at radii ``r``.

    The normal of an involute is its generating line, tangent to the base circle at
    polar angle ``chi_T = chi_b - tan(alpha_r)``; it points from that tangent point to
    the flank point, which is out of the tooth.
    """
    alpha_r = pressure_angle_at(r, base_radius)
    chi_t = half_angle_base - np.tan(alpha_r)
    # The generating line is perpendicular to the radius of its tangent point, turned
    # towards increasing chi (clockwise): direction (cos chi_T, -sin chi_T).
    return np.stack([np.cos(chi_t), -np.sin(chi_t)], axis=-1)


def rot(phi: float) -> NDArray[np.float64]:
    """The rotation matrix ``R(phi)``, counter-clockwise by ``phi`` (``R p`` turns ``p`` as
    :func:`rotate` does): the one NumPy home of this matrix, which the solvers and the
    balances read (the compiled twins use its cosine and sine)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def rotate(points: NDArray[np.float64], angle: float) -> NDArray[np.float64]:
    """Rotate points ``(..., 2)`` counter-clockwise by ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def cutter_tip_centre(
    module: float, pressure_angle: float, dedendum: float, tip_radius: float,
    shift: float = 0.0,
) -> tuple[float, float]:
    """Centre ``(x_c, y_c)`` of the rack cutter's tip rounding, in the rack frame.

    Rack frame: x along the pitch line, y away from the gear centre, origin on the
    pitch line at the centre of the gear tooth being cut (a cutter space). The cutter's
    datum line lies ``shift * module`` above the pitch line; its flank through
    ``(pi m / 4, shift m)`` leans outwards with depth; the tip line is at
    ``y = -dedendum`` (the gear's dedendum below its pitch circle). The rounding circle
    touches both.
    """
    ca, sa = np.cos(pressure_angle), np.sin(pressure_angle)
    y_c = -dedendum + tip_radius
    # The flank's depth below the datum line at the tip line is dedendum + shift * module.
    x_c = np.pi * module / 4.0 + (dedendum + shift * module) * sa / ca \
        + tip_radius * (1.0 - sa) / ca
    return float(x_c), float(y_c)


def fillet_point(
    phi: ArrayLike,
    pitch_radius: float,
    centre: tuple[float, float],
    tip_radius: float,
) -> NDArray[np.float64]:
    """Points ``(..., 2)`` of the right trochoidal fillet, generated at rack roll ``phi``.

    The gear turns clockwise by ``phi`` while the rack moves ``r_p phi`` along +x. The
    enveloping point of the rounding circle is where the circle's normal passes through
    the instantaneous centre (the pitch point, at ``(-r_p phi, 0)`` in the rack frame).
    Valid for ``phi`` between ``(y_c cot(alpha) - x_c) / r_p`` (tangent to the involute)
    and ``-x_c / r_p`` (the root circle).
    """
    phi = np.asarray(phi, dtype=float)
    x_c, y_c = centre
    dx = x_c + pitch_radius * phi
    dy = np.full_like(dx, y_c)
    n = np.hypot(dx, dy)
    px = x_c + tip_radius * dx / n
    py = y_c + tip_radius * dy / n
    # Rack point to gear frame: translate by the rack's travel, undo the gear's turn.
    world = np.stack([px + pitch_radius * phi, pitch_radius + py], axis=-1)
    return rotate(world, phi)


def fillet_phi_at_normal_angle(
    angle_from_root: ArrayLike, pitch_radius: float, centre: tuple[float, float]
) -> NDArray[np.float64]:
    """Rack roll ``phi`` at which the fillet's normal is ``angle_from_root`` off -y.

    ``angle_from_root = 0`` is the root circle, ``pi/2 - alpha`` the involute junction.
    """
    x_c, y_c = centre
    a = np.asarray(angle_from_root, dtype=float)
    # (x_c + r_p phi, y_c) points at angle 270 deg - a: its x/y ratio is tan(a).
    return (y_c * np.tan(a) - x_c) / pitch_radius
