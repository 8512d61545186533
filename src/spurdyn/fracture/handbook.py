"""The handbook's stress intensity factors the finite elements are checked against
(docs/fracture.md, section 5): ``K = F sigma sqrt(pi a)``.

- Edge crack of depth ``a`` in a strip of width ``W`` under uniform tension ``sigma``, ends
  free to turn: Tada, Paris & Irwin's closed form, good to 0.5 % for any ``a / W``, and Brown
  & Srawley's polynomial (0.5 % for ``a / W <= 0.6``).
- The same strip under a pure bending moment, ``sigma = 6 M / W^2`` per unit thickness: Brown
  & Srawley's polynomial (0.2 % for ``a / W <= 0.6``) and Tada, Paris & Irwin's closed form
  as textbooks quote it (1.7 to 2.2 % below Brown & Srawley and the finite elements for
  ``0.2 <= a / W <= 0.4``; section 5.1).
- A centre crack of half-length ``a`` at ``beta`` to the line across uniaxial tension
  ``sigma`` in an infinite plate: ``K_I = sigma sqrt(pi a) cos^2 beta``,
  ``K_II = sigma sqrt(pi a) sin beta cos beta`` (the crack's line carries the normal and shear
  stress of the remote field resolved on it), and Feddersen's width factor
  ``sqrt(sec(pi a / W))`` of a straight one in a strip of width ``W``.
"""

from __future__ import annotations

import math

__all__ = ["bending_brown_srawley", "bending_tada", "centre_crack", "feddersen",
           "tension_brown_srawley", "tension_tada"]


def _secant_part(ratio: float) -> tuple[float, float]:
    """``sqrt(tan(t) / t)`` and ``cos t`` at ``t = pi a / (2 W)``: Tada's forms' shared part."""
    t = 0.5 * math.pi * ratio
    return math.sqrt(math.tan(t) / t), math.cos(t)


def tension_tada(ratio: float) -> float:
    """F of an edge crack in a strip under tension (Tada, Paris & Irwin, 0.5 %)."""
    root, cos = _secant_part(ratio)
    sin = math.sqrt(1.0 - cos * cos)
    return root * (0.752 + 2.02 * ratio + 0.37 * (1.0 - sin) ** 3) / cos


def bending_tada(ratio: float) -> float:
    """F of an edge crack in a strip under pure bending, ``sigma = 6 M / W^2`` (Tada, Paris &
    Irwin's closed form)."""
    root, cos = _secant_part(ratio)
    sin = math.sqrt(1.0 - cos * cos)
    return root * (0.923 + 0.199 * (1.0 - sin) ** 4) / cos


def tension_brown_srawley(ratio: float) -> float:
    """F of an edge crack in a strip under tension (Brown & Srawley, ``a / W <= 0.6``)."""
    return 1.12 + ratio * (-0.231 + ratio * (10.55 + ratio * (-21.72 + ratio * 30.39)))


def bending_brown_srawley(ratio: float) -> float:
    """F of an edge crack in a strip under pure bending (Brown & Srawley, ``a / W <= 0.6``)."""
    return 1.122 + ratio * (-1.40 + ratio * (7.33 + ratio * (-13.08 + ratio * 14.0)))


def centre_crack(stress: float, half_length: float, angle: float) -> tuple[float, float]:
    """``(K_I, K_II)`` (Pa sqrt(m)) of a centre crack at ``angle`` (rad) to the line across
    uniaxial tension ``stress`` (Pa) in an infinite plate."""
    k = stress * math.sqrt(math.pi * half_length)
    return k * math.cos(angle) ** 2, k * math.sin(angle) * math.cos(angle)


def feddersen(ratio: float) -> float:
    """Feddersen's factor ``sqrt(sec(pi a / W))`` of a centre crack of half-length ``a`` in
    a strip of width ``W`` under tension across it (``ratio = a / W``)."""
    return math.sqrt(1.0 / math.cos(math.pi * ratio))
