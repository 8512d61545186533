"""Hertz's line contact of two cylinders, and the strip quadrature of the distributed contact.

One home for the formulas the distributed contact (``RunSettings.contact = "hertz"``,
docs/solver.md section 11) and the results read. A line load ``F`` (N) over the face
width ``L`` between cylinders of radii ``rho_A``, ``rho_B`` (``1/R* = 1/rho_A + 1/rho_B``)
and moduli ``1/E* = (1 - nu_A^2)/E_A + (1 - nu_B^2)/E_B`` (plane strain, Hertz's)
presses a strip of half-width

    b = sqrt(4 F R* / (pi E* L))

with the elliptic pressure ``p(xi) = p_max sqrt(1 - xi^2 / b^2)``, ``p_max = 2 F / (pi b L)``.
Nothing here imports spurdyn: the compiled kernels read the same formulas as globals.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: Points of the strip quadrature (Gauss-Chebyshev of the second kind): the weight
#: ``sqrt(1 - xi^2)`` is the elliptic pressure itself, and the rule is exact for
#: polynomials of degree <= 2 * 12 - 1 against it; the shape functions along a strip
#: within one element edge are smooth (quadratic in the flank coordinate, which is
#: nearly linear in arc length), so there it is exact to round-off.
STRIP_POINTS = 12


def effective_modulus(young_a: float, poisson_a: float, young_b: float, poisson_b: float) -> float:
    """``E*`` (Pa) of Hertz's line contact: ``1/E* = (1 - nu_A^2)/E_A + (1 - nu_B^2)/E_B``."""
    return 1.0 / ((1.0 - poisson_a**2) / young_a + (1.0 - poisson_b**2) / young_b)


def involute_curvature_radius(radius: Any, base_radius: float) -> Any:
    """Radius of curvature (m) of an involute at ``radius``: ``sqrt(r^2 - r_b^2)``
    (a scalar or an array of radii)."""
    if np.ndim(radius) == 0:
        return math.sqrt(max(radius * radius - base_radius * base_radius, 0.0))
    r = np.asarray(radius, dtype=float)
    return np.sqrt(np.maximum(r * r - base_radius * base_radius, 0.0))


def half_width(force: Any, rho_a: Any, rho_b: Any, estar: float, face_width: float) -> Any:
    """Hertz half-width ``b`` (m) of the strip under the normal force ``|force|`` (N).

    Scalars or arrays; 0 where there is no force or a radius is not positive."""
    f, ra, rb = (np.asarray(v, dtype=float) for v in (force, rho_a, rho_b))
    ok = (f != 0.0) & (ra > 0.0) & (rb > 0.0)
    r_star = np.where(ok, ra * rb / np.where(ok, ra + rb, 1.0), 0.0)
    b = np.sqrt(4.0 * np.abs(f) * r_star / (math.pi * estar * face_width))
    return float(b) if b.ndim == 0 else b


def peak_pressure(force: Any, b: Any, face_width: float) -> Any:
    """Peak Hertz pressure ``2 F / (pi b L)`` (Pa); 0 without a strip. Scalars or arrays."""
    f, bb = np.asarray(force, dtype=float), np.asarray(b, dtype=float)
    p = np.where(bb > 0.0, 2.0 * np.abs(f) / (math.pi * np.where(bb > 0.0, bb, 1.0) * face_width), 0.0)
    return float(p) if p.ndim == 0 else p


def strip_compliance(estar: float, face_width: float) -> float:
    """``c_H = 1 / (2 pi E* L)`` (m/N): the mean curvature separation over the strip per newton.

    The rigid surfaces part from each other by ``xi^2 / (2 R*)`` at ``xi`` from the
    centre; averaged with the elliptic pressure (``<xi^2> = b^2 / 4``) that is
    ``b^2 / (8 R*) = F / (2 pi E* L)``, whatever the radii (docs/solver.md, section 11).
    """
    return 1.0 / (2.0 * math.pi * estar * face_width)


def strip_quadrature(n: int = STRIP_POINTS) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Points ``xi_k / b`` in (-1, 1) and weights (summing to 1) of the elliptic pressure.

    ``int_{-b}^{b} f(xi) (2 / (pi b)) sqrt(1 - xi^2/b^2) dxi ~= sum_k w_k f(b x_k)`` with
    ``x_k = cos(k pi / (n + 1))``, ``w_k = 2 sin^2(k pi / (n + 1)) / (n + 1)``.
    """
    k = np.arange(1, n + 1)
    ang = k * np.pi / (n + 1)
    return np.cos(ang), 2.0 * np.sin(ang) ** 2 / (n + 1)


def strip_coordinates(t_c: float, b: float, r0: float, r_tip: float, ny: float, base_radius: float,
                      x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Flank coordinates of the strip points ``xi_k = b x_k`` of arc length from ``t_c``.

    The flank coordinate is linear in the involute radius (:class:`spurdyn.model.flank.Flank`)
    and the involute's arc length from the base circle is ``(r^2 - r_b^2) / (2 r_b)``, so
    the point ``xi`` along the flank from radius ``r_c`` lies at ``r^2 = r_c^2 + 2 r_b xi``.
    Points beyond the tip (or below the outline's start) are held there.
    """
    slope = (r_tip - r0) / ny
    r_c = r0 + slope * t_c
    r = np.sqrt(np.maximum(r_c * r_c + 2.0 * base_radius * b * x, 0.0))
    return np.clip((r - r0) / slope, 0.0, ny)
