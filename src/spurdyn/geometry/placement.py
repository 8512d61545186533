"""Where the two teeth sit in the meshing plane.

World frame: gear A's centre at the origin, gear B's at ``(0, a)``. A's tooth points up
(+y) and A turns clockwise; B's tooth points down and B turns counter-clockwise. With A
driving, both teeth touch on their own *right* outline (``x > 0`` in the gear frame) and
the contact point runs along the line of action from lower left to upper right:
``Q(L) = T_A + L (cos alpha_w, sin alpha_w)``, ``L`` the roll length on A.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from spurdyn.geometry import involute as ivl
from spurdyn.geometry.pair import GearPair


def line_of_action_point(pair: GearPair, roll_a: float) -> NDArray[np.float64]:
    """World position of the contact point at roll angle ``roll_a`` (rad) of gear A."""
    aw = pair.working_pressure_angle
    rb = pair.gear_a.base_radius
    tangent = rb * np.array([-math.sin(aw), math.cos(aw)])
    return tangent + roll_a * rb * np.array([math.cos(aw), math.sin(aw)])


def mesh_angles(pair: GearPair, roll_a: float) -> tuple[float, float]:
    """Rotations ``(theta_a, theta_b)`` (rad; A clockwise, B counter-clockwise) that put
    the right flanks of both teeth in contact at roll angle ``roll_a`` of A.

    The tooth frame maps to the world as ``R(-theta_a) x`` for A and
    ``c_B + R(pi + theta_b) x`` for B.
    """
    ga, gb = pair.gear_a, pair.gear_b
    q = line_of_action_point(pair, roll_a)
    r_a = float(np.hypot(*q))
    chi_a = ivl.half_angle(r_a, ga.base_radius, ga.half_angle_base)
    theta_a = math.atan2(q[0], q[1]) - float(chi_a)
    v = q - np.array([0.0, pair.centre_distance])
    r_b = float(np.hypot(*v))
    chi_b = ivl.half_angle(r_b, gb.base_radius, gb.half_angle_base)
    theta_b = float(chi_b) - math.atan2(v[0], v[1]) - math.pi
    theta_b = (theta_b + math.pi) % (2.0 * math.pi) - math.pi
    return theta_a, theta_b


def to_world_a(points: NDArray[np.float64], theta_a: float) -> NDArray[np.float64]:
    """Gear-A frame points to the world at rotation ``theta_a`` (clockwise)."""
    return ivl.rotate(points, -theta_a)


def to_world_b(points: NDArray[np.float64], theta_b: float, centre_distance: float) -> NDArray[np.float64]:
    """Gear-B frame points to the world at rotation ``theta_b`` (counter-clockwise)."""
    return ivl.rotate(points, math.pi + theta_b) + np.array([0.0, centre_distance])
