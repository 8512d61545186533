"""Contact off the path: a tip corner against the mating involute (docs/sector.md, 6.2).

On the path of contact two involutes touch on the line of action and their rigid gap is
zero. Before the start of the path the driven gear's tip corner approaches the driver's
flank, and after its end the driver's tip corner leaves the driven gear's flank; a loaded
pair, whose driver runs ahead by the transmission error, touches there early and leaves
late. This module gives the rigid gap of those corners at the driver's roll angle ``rho``
(the roll of the point where the two involutes, extended, would meet on the line of action):
:func:`corner_contacts` over an array of rolls, in NumPy (a table of the gap takes some
20,000 rolls, issue 34), :func:`corner_contact` at one roll, through it.

Frame: the line of action is the x axis from A's base tangency point ``T_A = (0, 0)`` to B's
``T_B = (L, 0)``, ``L`` the line of centres' tangent length; ``O_A = (0, -r_bA)``,
``O_B = (L, r_bB)``. A flank point of roll ``s`` lies on the tangent to its base circle at
the angle ``phi`` from its centre, ``r_b s`` along ``t(phi) = (sin phi, -cos phi)``; the point
of roll ``s`` on A is at ``phi = pi/2 + (s - rho_A)``, on B at ``phi = -pi/2 + (s - rho_B)``,
``rho_A = rho`` and ``rho_B = (L - r_bA rho) / r_bB`` the rolls on the line of action. A
point ``P`` is ``d = sqrt(|P - O|^2 - r_b^2)`` along the tangent from its tangency angle
``phi_T = atan2(P - O) + atan(d / r_b)``, where the flank's own point is at ``r_b s`` with
``s`` from ``phi_T``; the gap is ``d - r_b s`` (positive outside the tooth). On the path the
corner is the contact point and the gap is zero.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.geometry.pair import GearPair

Floats = NDArray[np.float64]


def _tangent_points(s: float | Floats, rho: float | Floats, centre: tuple[float, float], rb: float,
                    phi0: float) -> tuple[Floats, Floats]:
    """``(x, y)``: the flank points of roll ``s`` of a gear whose line-of-action roll is ``rho``
    (module docstring), either or both arrays (broadcast)."""
    phi = phi0 + (s - rho)
    c, n = np.cos(phi), np.sin(phi)
    return centre[0] + rb * c + rb * s * n, centre[1] + rb * n + rb * s * -c


def _gaps_to_flank(x: Floats, y: Floats, centre: tuple[float, float], rb: float, rho: Floats,
                   phi0: float) -> tuple[Floats, Floats]:
    """``(gap, s)``: the gaps from the points ``(x, y)`` to the flank along its normal, and
    the rolls ``s`` of the flank points there."""
    rx, ry = x - centre[0], y - centre[1]
    d = np.sqrt(np.maximum(rx * rx + ry * ry - rb * rb, 0.0))
    phi_t = np.arctan2(ry, rx) + np.arctan2(d, rb)
    s = rho + (phi_t - phi0 + math.pi) % (2 * math.pi) - math.pi
    return d - rb * s, s


def corner_contacts(pair: GearPair, rho: ArrayLike) -> tuple[Floats, Floats, Floats]:
    """``(gap, r_a, r_b)`` of the pair at the driver's rolls ``rho`` (rad; A drives), each an
    array of ``rho``'s shape: on the path zero and the two involutes' radii there; before
    it the driven gear's tip corner against the driver's flank, after it the driver's tip
    corner against the driven gear's flank, the gap (m) along the flank's normal and the
    radii of the two points.

    Parameters
    ----------
    pair
        The pair, gear A the driver.
    rho
        The driver's rolls (rad).

    Returns
    -------
    gap, r_a, r_b
        The rigid gaps (m) and the contact radii on A and B (m).
    """
    rho = np.asarray(rho, dtype=float)
    ga, gb = pair.gear_a, pair.gear_b
    ra, rb = ga.base_radius, gb.base_radius
    length = pair.line_of_centres_length
    rho_b = (length - ra * rho) / rb
    o_a, o_b = (0.0, -ra), (length, rb)
    gap = np.zeros_like(rho)
    r_a = np.array(ga.radius_at_roll_angle(rho), dtype=float)
    r_b = np.array(gb.radius_at_roll_angle(rho_b), dtype=float)
    before = rho < pair.start_roll_a           # B's tip corner on A's flank
    if before.any():
        s_tip = math.sqrt(max(gb.tip_radius**2 - rb * rb, 0.0)) / rb
        x, y = _tangent_points(s_tip, rho_b[before], o_b, rb, -math.pi / 2)
        gap[before], s = _gaps_to_flank(x, y, o_a, ra, rho[before], math.pi / 2)
        r_a[before], r_b[before] = ra * np.sqrt(1.0 + s * s), gb.tip_radius
    after = rho > pair.end_roll_a              # A's tip corner on B's flank
    if after.any():
        s_tip = math.sqrt(max(ga.tip_radius**2 - ra * ra, 0.0)) / ra
        x, y = _tangent_points(s_tip, rho[after], o_a, ra, math.pi / 2)
        gap[after], s = _gaps_to_flank(x, y, o_b, rb, rho_b[after], -math.pi / 2)
        r_a[after], r_b[after] = ga.tip_radius, rb * np.sqrt(1.0 + s * s)
    return gap, r_a, r_b


def corner_contact(pair: GearPair, rho: float) -> tuple[float, float, float]:
    """``(gap, r_a, r_b)`` of the pair at the driver's roll ``rho`` (rad; A drives): one roll
    of :func:`corner_contacts`.

    Parameters
    ----------
    pair
        The pair, gear A the driver.
    rho
        The driver's roll (rad).

    Returns
    -------
    gap, r_a, r_b
        The rigid gap (m) and the contact radii on A and B (m).
    """
    gap, r_a, r_b = corner_contacts(pair, np.array([float(rho)]))
    return float(gap[0]), float(r_a[0]), float(r_b[0])


__all__ = ["corner_contact", "corner_contacts"]
