"""The tooth as a non-uniform cantilever on its base circle (Yang & Lin 1987; Tian 2004).

The angle ``alpha`` runs along the involute flank: the flank point of parameter
``alpha`` is the point whose generating line touches the base circle at the polar angle
``-alpha`` from the tooth's centre line (measured away from that flank). ``alpha = a2``,
the tooth's half-angle on the base circle, is the flank's start on the base circle; the
contact point under a force whose line makes the angle ``a1`` with the perpendicular to
the centre line is ``alpha = -a1``. The derivation is in ``docs/faults_energy.md``,
section 1. Lengths in m, angles in rad.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.geometry.gear import Gear


def half_height(alpha: ArrayLike, base_radius: float, a2: float) -> NDArray[np.float64]:
    """Half-thickness ``h(alpha) = r_b [sin(alpha) + (a2 - alpha) cos(alpha)]`` (m) of the
    section through the flank point ``alpha``, perpendicular to the centre line."""
    a = np.asarray(alpha, dtype=float)
    return base_radius * (np.sin(a) + (a2 - a) * np.cos(a))


def radial_position(alpha: ArrayLike, base_radius: float, a2: float) -> NDArray[np.float64]:
    """Distance ``r_b [cos(alpha) - (a2 - alpha) sin(alpha)]`` (m) from the gear centre,
    along the centre line, of the section through the flank point ``alpha``."""
    a = np.asarray(alpha, dtype=float)
    return base_radius * (np.cos(a) - (a2 - a) * np.sin(a))


def position_rate(alpha: ArrayLike, base_radius: float, a2: float) -> NDArray[np.float64]:
    """``-d(radial_position)/d(alpha) = r_b (a2 - alpha) cos(alpha)`` (m/rad): the length
    of centre line per unit of ``alpha``, positive from the tip (small ``alpha``) down."""
    a = np.asarray(alpha, dtype=float)
    return base_radius * (a2 - a) * np.cos(a)


def load_angle(gear: Gear, roll: ArrayLike) -> NDArray[np.float64]:
    """``a1 = roll - a2`` (rad): the angle between the line of action at the flank point
    of roll angle ``roll`` and the perpendicular to the tooth's centre line."""
    return np.asarray(roll, dtype=float) - gear.half_angle_base


def moment_arm(alpha: NDArray[np.float64], a1: NDArray[np.float64], base_radius: float,
               a2: float) -> NDArray[np.float64]:
    """Bending moment (m, per newton of contact force) at the section ``alpha`` under the
    force at ``-a1``: ``r_b {1 + cos(a1) [(a2 - alpha) sin(alpha) - cos(alpha)]}``.

    The moment of the force's component ``cos(a1)`` across the centre line about the
    section, less that of its component ``sin(a1)`` along it, whose line lies
    ``h(-a1)`` off the centre line; arrays broadcast."""
    return base_radius * (1.0 + np.cos(a1) * ((a2 - alpha) * np.sin(alpha) - np.cos(alpha)))


def tip_alpha(gear: Gear) -> float:
    """``alpha`` of the flank's end on the tip circle: ``a2`` less the tip's roll angle."""
    return gear.half_angle_base - float(gear.roll_angle_at(gear.tip_radius))


__all__ = ["half_height", "load_angle", "moment_arm", "position_rate", "radial_position",
           "tip_alpha"]
