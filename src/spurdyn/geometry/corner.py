"""Contact off the path: a tip corner against the mating involute (docs/sector.md, 6.2).

On the path of contact two involutes touch on the line of action and their rigid gap is
zero. Before the start of the path the driven gear's tip corner approaches the driver's
flank, and after its end the driver's tip corner leaves the driven gear's flank; a loaded
pair, whose driver runs ahead by the transmission error, touches there early and leaves
late. This module gives the rigid gap of those corners at the driver's roll angle ``rho``
(the roll of the point where the two involutes, extended, would meet on the line of action).

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

from spurdyn.geometry.pair import GearPair


def _tangent_point(s: float, rho: float, centre: np.ndarray, rb: float, phi0: float) -> np.ndarray:
    phi = phi0 + (s - rho)
    return centre + rb * np.array([math.cos(phi), math.sin(phi)]) \
        + rb * s * np.array([math.sin(phi), -math.cos(phi)])


def _gap_to_flank(p: np.ndarray, centre: np.ndarray, rb: float, rho: float,
                  phi0: float) -> tuple[float, float]:
    """``(gap, s)``: the gap from ``p`` to the flank along its normal, and the roll ``s`` of the
    flank point there."""
    rel = p - centre
    d = math.sqrt(max(float(rel @ rel) - rb * rb, 0.0))
    phi_t = math.atan2(rel[1], rel[0]) + math.atan2(d, rb)
    s = rho + (phi_t - phi0 + math.pi) % (2 * math.pi) - math.pi
    return d - rb * s, s


def corner_contact(pair: GearPair, rho: float) -> tuple[float, float, float]:
    """``(gap, r_a, r_b)`` of the pair at the driver's roll ``rho`` (rad; A drives): on the
    path zero and the two involutes' radii there; before it the driven gear's tip corner
    against the driver's flank, after it the driver's tip corner against the driven gear's
    flank, the gap (m) along the flank's normal and the radii of the two points."""
    ga, gb = pair.gear_a, pair.gear_b
    ra, rb = ga.base_radius, gb.base_radius
    length = pair.line_of_centres_length
    rho_b = (length - ra * rho) / rb
    o_a, o_b = np.array([0.0, -ra]), np.array([length, rb])
    if rho < pair.start_roll_a:            # B's tip corner on A's flank
        s_tip = math.sqrt(max(gb.tip_radius**2 - rb * rb, 0.0)) / rb
        corner = _tangent_point(s_tip, rho_b, o_b, rb, -math.pi / 2)
        gap, s = _gap_to_flank(corner, o_a, ra, rho, math.pi / 2)
        return gap, ra * math.sqrt(1.0 + s * s), gb.tip_radius
    if rho > pair.end_roll_a:              # A's tip corner on B's flank
        s_tip = math.sqrt(max(ga.tip_radius**2 - ra * ra, 0.0)) / ra
        corner = _tangent_point(s_tip, rho, o_a, ra, math.pi / 2)
        gap, s = _gap_to_flank(corner, o_b, rb, rho_b, -math.pi / 2)
        return gap, ga.tip_radius, rb * math.sqrt(1.0 + s * s)
    return 0.0, float(ga.radius_at_roll_angle(rho)), float(gb.radius_at_roll_angle(rho_b))


__all__ = ["corner_contact"]
