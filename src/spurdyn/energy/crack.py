"""A straight root crack as the potential-energy literature draws it (Tian 2004; Wu, Zuo &
Parey 2008; Chen & Shao 2011).

The crack starts on the loaded flank where it meets the base circle (half-height
``h_b = r_b sin(a2)`` from the centre line), runs into the tooth in a straight line at the
angle ``nu`` to the centre line, over the length ``q``, through the whole face width. Its
tip lies ``s = h_b - q sin(nu)`` from the centre line, on the loaded side when ``s > 0``
(the literature's case 1) and past the centre line when ``s < 0`` (case 2). The published
model's "limiting line" runs from the tip parallel to the centre line up the tooth: the
material between it and the cracked flank carries nothing, so a section whose loaded-side
edge lies beyond the line carries ``h + s`` instead of ``2 h``. The assumptions and what
they leave out are in ``docs/faults_energy.md``, section 3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.geometry.gear import Gear
from spurdyn.energy.section import half_height, tip_alpha

#: Default angle between the crack and the tooth's centre line (rad); give the one you study.
DEFAULT_CRACK_ANGLE = math.radians(45.0)


@dataclass(frozen=True)
class Crack:
    """A straight crack from the loaded flank's root at the base circle, through the face.

    Parameters
    ----------
    depth
        Crack length ``q`` along its path (m), ``>= 0``; 0 is no crack.
    angle
        Angle ``nu`` between the crack and the tooth's centre line (rad), in (0, 90 deg].
    """

    depth: float
    angle: float = DEFAULT_CRACK_ANGLE

    def __post_init__(self) -> None:
        for key in ("depth", "angle"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise InputError(key, f"must be a number (got {v!r})")
        if self.depth < 0.0:
            raise InputError("depth", f"must be >= 0 m (got {self.depth!r})")
        if not 0.0 < self.angle <= math.pi / 2.0:
            raise InputError("angle", f"must lie in (0, 90] degrees (got "
                             f"{math.degrees(self.angle):.4g} deg)")

    def tip_offset(self, gear: Gear) -> float:
        """Signed distance ``s = h_b - q sin(nu)`` (m) of the crack tip from the centre line,
        positive on the loaded side; ``inf`` without a crack (no section is cut)."""
        if self.depth == 0.0:
            return math.inf
        h_b = gear.base_radius * math.sin(gear.half_angle_base)
        return h_b - self.depth * math.sin(self.angle)

    def check_fits(self, gear: Gear) -> None:
        """Refuse a crack whose limiting line would leave no section at the tip (the
        published model then cuts the tooth's top off, which it does not describe)."""
        s = self.tip_offset(gear)
        h_tip = float(half_height(tip_alpha(gear), gear.base_radius, gear.half_angle_base))
        if s <= -h_tip:
            deepest = (gear.base_radius * math.sin(gear.half_angle_base) + h_tip) \
                / math.sin(self.angle)
            raise InputError("depth", f"{self.depth:g} m reaches so far past the centre line "
                             f"that the limiting line leaves the tooth below its tip; at "
                             f"this angle at most {deepest:.4g} m")


def carrying_height(h: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    """Height of a section that carries load (m): ``2 h`` without a crack, ``h + min(h, s)``
    with one whose tip lies ``s`` from the centre line (Tian 2004's ``h_x + h_q``)."""
    return h + np.minimum(h, s)


def limit_alpha(gear: Gear, s: float) -> float:
    """``alpha`` at which the loaded flank crosses the limiting line, ``h(alpha) = s``, on
    the tooth's upper part (``alpha <= 0``, where ``h`` falls towards the tip): sections
    below it (larger ``alpha``) are cut. The tip's ``alpha`` when the line lies inside the
    whole tooth (every section cut)."""
    rb, a2 = gear.base_radius, gear.half_angle_base
    lo = tip_alpha(gear)
    if s <= float(half_height(lo, rb, a2)):
        return lo
    from scipy.optimize import brentq  # imported when used: scipy.optimize is slow to load

    return float(brentq(lambda a: float(half_height(a, rb, a2)) - s, lo, 0.0, xtol=1e-15))


__all__ = ["DEFAULT_CRACK_ANGLE", "Crack", "carrying_height", "limit_alpha"]
