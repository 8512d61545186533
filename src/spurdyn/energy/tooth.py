"""One tooth's compliance along the line of action by the potential-energy method.

The tooth is a cantilever clamped on its base circle, loaded at its contact point by a
unit force along the line of action. Its bending, shear and axial compressive strain
energies give three compliances (Yang & Lin 1987; Tian 2004; Wu, Zuo & Parey 2008):

    c_b = int M^2 / (E I) dy,   c_s = int 1.2 cos^2(a1) / (G A) dy,
    c_a = int sin^2(a1) / (E A) dy,

over the centre line from the contact point's section to the base circle, ``I = L H^3/12``
and ``A = L H`` for the section's carrying height ``H`` (``2 h``, or less under a crack:
:mod:`spurdyn.energy.crack`). The integrals are taken in the flank angle ``alpha``
(:mod:`spurdyn.energy.section`) by Gauss-Legendre, all contact positions at once, the
interval split where a crack's limiting line meets the flank (the integrand has a kink
there). ``docs/faults_energy.md``, sections 1-3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.geometry.gear import Gear
from spurdyn.energy.crack import Crack, carrying_height, limit_alpha
from spurdyn.energy.foundation import foundation_compliance
from spurdyn.energy.section import (half_height, load_angle, moment_arm, position_rate,
                                   radial_position)

#: Gauss-Legendre points on each part of the integral (docs/faults_energy.md, section 5:
#: on the paper's gear 48 agree with 1024 to 2e-13, the deepest cracks included).
DEFAULT_POINTS = 48

#: Timoshenko's shear factor of a rectangular section, as the method uses it.
SHEAR_FACTOR = 1.2


@dataclass(frozen=True)
class ToothCompliance:
    """One tooth's compliances (m/N) along the line of action, by contact position.

    ``foundation`` is ``None`` when the fillet foundation was left out (no bore given).
    """

    roll: NDArray[np.float64]
    bending: NDArray[np.float64]
    shear: NDArray[np.float64]
    axial: NDArray[np.float64]
    foundation: NDArray[np.float64] | None

    @property
    def total(self) -> NDArray[np.float64]:
        """The sum of the terms computed (m/N)."""
        beam = self.bending + self.shear + self.axial
        return beam if self.foundation is None else beam + self.foundation


def gauss_segments(lo: NDArray[np.float64], hi: NDArray[np.float64],
                   n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre nodes and weights ``(m, n)`` on the intervals ``[lo_i, hi_i]``."""
    x, w = np.polynomial.legendre.leggauss(n)
    half = 0.5 * (hi - lo)[:, None]
    return 0.5 * (hi + lo)[:, None] + half * x[None, :], half * w[None, :]


def beam_integrals(alpha: NDArray[np.float64], weight: NDArray[np.float64],
                   a1: NDArray[np.float64], height: NDArray[np.float64], gear: Gear,
                   face_width: float) -> tuple[NDArray[np.float64], ...]:
    """Bending, shear and axial compliances (m/N) of one part of the tooth: the sums over
    the nodes ``alpha`` (weights ``weight``) of the section of carrying ``height``."""
    rb, a2 = gear.base_radius, gear.half_angle_base
    young = gear.material.young
    shear_modulus = young / (2.0 * (1.0 + gear.material.poisson))
    dy = weight * position_rate(alpha, rb, a2)
    a1 = a1[:, None]
    inertia = face_width * height**3 / 12.0
    area = face_width * height
    bending = np.sum(moment_arm(alpha, a1, rb, a2) ** 2 / (young * inertia) * dy, axis=1)
    shear = np.sum(SHEAR_FACTOR * np.cos(a1) ** 2 / (shear_modulus * area) * dy, axis=1)
    axial = np.sum(np.sin(a1) ** 2 / (young * area) * dy, axis=1)
    return bending, shear, axial


def root_segment_integrals(gear: Gear, a1: NDArray[np.float64],
                           face_width: float) -> tuple[NDArray[np.float64], ...]:
    """Bending, shear and axial compliances (m/N) of the tooth between the root circle and
    the base circle's section, as a beam of the constant height ``2 r_b sin(a2)``: the
    extension ``root_segment=True`` of :func:`tooth_compliance` (zero when the root circle
    lies above that section). Gauss's two points are exact: the integrands are quadratic."""
    rb, a2 = gear.base_radius, gear.half_angle_base
    y_base = float(radial_position(a2, rb, a2))
    length = y_base - gear.root_radius
    if length <= 0.0:
        return tuple(np.zeros_like(a1) for _ in range(3))
    y, weight = gauss_segments(np.full_like(a1, gear.root_radius), np.full_like(a1, y_base), 2)
    # The same beam, in the centre line's length: the moment of the force at (h_c, y_c).
    arm = np.cos(a1)[:, None] * (radial_position(-a1, rb, a2)[:, None] - y) \
        - np.sin(a1)[:, None] * half_height(-a1, rb, a2)[:, None]
    height = np.full_like(y, 2.0 * rb * math.sin(a2))
    young = gear.material.young
    shear_modulus = young / (2.0 * (1.0 + gear.material.poisson))
    inertia, area = face_width * height**3 / 12.0, face_width * height
    bending = np.sum(weight * arm**2 / (young * inertia), axis=1)
    cos2 = np.cos(a1[:, None]) ** 2
    shear = np.sum(weight * SHEAR_FACTOR * cos2 / (shear_modulus * area), axis=1)
    axial = np.sum(weight * np.sin(a1[:, None]) ** 2 / (young * area), axis=1)
    return bending, shear, axial


def tooth_compliance(gear: Gear, roll: ArrayLike, crack: Crack | None = None,
                     bore_radius: float | None = None, face_width: float | None = None,
                     points: int = DEFAULT_POINTS, root_segment: bool = False) -> ToothCompliance:
    """The compliances of ``gear``'s tooth at the flank points of roll angles ``roll``.

    Parameters
    ----------
    gear
        The gear (its involute, base circle, material, face width).
    roll
        Roll angles (rad) of the contact points on this gear's flank, ``> 0``.
    crack
        A root crack on the loaded flank (:class:`~spurdyn.energy.crack.Crack`), or none.
    bore_radius
        The body's bore radius (m) for the fillet foundation; ``None`` leaves it out.
    face_width
        The width carrying the load (m); the gear's by default.
    points
        Gauss-Legendre points on each part of the integral.
    root_segment
        Add the tooth between the root circle and the base circle's section as a beam of
        constant section (not in the published form, which clamps the tooth on its base
        circle; a crack does not cut it; ``docs/faults_energy.md``, sections 6-7).
    """
    roll = np.atleast_1d(np.asarray(roll, dtype=float))
    width = gear.face_width if face_width is None else face_width
    rb, a2 = gear.base_radius, gear.half_angle_base
    a1 = load_angle(gear, roll)
    s = math.inf if crack is None else crack.tip_offset(gear)
    if crack is not None:
        crack.check_fits(gear)
    # Above the limiting line's crossing the section is whole; below it, cut.
    split = -a1 if math.isinf(s) else np.clip(limit_alpha(gear, s), -a1, a2)
    terms = np.zeros((3, roll.size))
    for lo, hi in ((-a1, split), (split, np.full_like(a1, a2))):
        alpha, weight = gauss_segments(lo, hi, points)
        height = carrying_height(half_height(alpha, rb, a2), s)
        terms += np.array(beam_integrals(alpha, weight, a1, height, gear, width))
    if root_segment:
        terms += np.array(root_segment_integrals(gear, a1, width))
    foundation = None if bore_radius is None else \
        foundation_compliance(gear, roll, bore_radius, width)
    return ToothCompliance(roll=roll, bending=terms[0], shear=terms[1], axial=terms[2],
                           foundation=foundation)


__all__ = ["DEFAULT_POINTS", "SHEAR_FACTOR", "ToothCompliance", "beam_integrals",
           "gauss_segments", "tooth_compliance"]
