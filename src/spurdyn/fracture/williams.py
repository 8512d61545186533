"""The near-tip fields of Williams (1957) for a unit stress intensity factor, plane stress:
the auxiliary fields of the interaction integral (docs/fracture.md, section 3).

Frame: the crack tip at the origin, the crack along the negative ``x1`` axis, ``x2`` across
it; polar ``(r, theta)`` with ``theta = +-pi`` on the crack's faces. Mode I with ``K_I = 1``,
mode II with ``K_II = 1``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.fem.material import Material

__all__ = ["MODES", "effective_modulus", "kolosov", "williams_fields"]

#: The two modes of a plane crack, in the order of every pair ``(K_I, K_II)`` here.
MODES = ("I", "II")


def kolosov(material: Material) -> tuple[float, float]:
    """Shear modulus ``mu`` (Pa) and Kolosov's constant ``kappa = (3 - nu) / (1 + nu)`` of plane
    stress, the state of :func:`spurdyn.fem.material.plane_stress_matrix`."""
    nu = material.poisson
    return material.young / (2.0 * (1.0 + nu)), (3.0 - nu) / (1.0 + nu)


def effective_modulus(material: Material) -> float:
    """``E'`` of Irwin's ``J = (K_I^2 + K_II^2) / E'``: Young's modulus in plane stress (Pa)."""
    return material.young


def _angular(h: NDArray[np.float64], kappa: float, mode: str
             ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                        NDArray[np.float64], NDArray[np.float64]]:
    """Of half the angle ``h = theta / 2``: the stresses' ``(s11, s22, s12)`` times
    ``sqrt(2 pi r)``, the displacements' ``(g1, g2)`` times ``2 mu sqrt(2 pi / r)``, and
    ``d g / d theta``."""
    s, c = np.sin(h), np.cos(h)
    s3, c3 = np.sin(3.0 * h), np.cos(3.0 * h)
    if mode == "I":
        stress = (c * (1.0 - s * s3), c * (1.0 + s * s3), c * s * c3)
        g = (c * (kappa - 1.0 + 2.0 * s * s), s * (kappa + 1.0 - 2.0 * c * c))
        dg = (0.5 * s * (4.0 * c * c - kappa + 1.0 - 2.0 * s * s),
              0.5 * c * (kappa + 1.0 - 2.0 * c * c + 4.0 * s * s))
    else:
        stress = (-s * (2.0 + c * c3), s * c * c3, c * (1.0 - s * s3))
        g = (s * (kappa + 1.0 + 2.0 * c * c), -c * (kappa - 1.0 - 2.0 * s * s))
        dg = (0.5 * c * (kappa + 1.0 + 2.0 * c * c - 4.0 * s * s),
              0.5 * s * (kappa - 1.0 - 2.0 * s * s + 4.0 * c * c))
    return np.stack(stress, axis=-1), g[0], g[1], dg[0], dg[1]


def williams_fields(x: ArrayLike, mode: str, material: Material
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Displacement, displacement gradient and stress of the unit mode's near-tip field.

    Parameters
    ----------
    x
        ``(..., 2)`` points in the tip's frame (m), off the tip.
    mode
        ``"I"`` or ``"II"``.
    material
        Elastic constants (plane stress).

    Returns
    -------
    u
        ``(..., 2)`` displacement (m per Pa sqrt(m) of K).
    grad
        ``(..., 2, 2)`` ``grad[..., i, j] = d u_i / d x_j``.
    stress
        ``(..., 3)`` ``(s11, s22, s12)`` (Pa per Pa sqrt(m)).

    Notes
    -----
    ``u_i = sqrt(r / (2 pi)) g_i(theta) / (2 mu)``, so with ``d/dx1 = cos t d/dr - sin t / r
    d/dt`` and ``d/dx2 = sin t d/dr + cos t / r d/dt``,
    ``d u_i / d x1 = (g_i cos t / 2 - g_i' sin t) / (2 mu sqrt(2 pi r))`` and
    ``d u_i / d x2 = (g_i sin t / 2 + g_i' cos t) / (2 mu sqrt(2 pi r))``.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES} (got {mode!r})")
    x = np.asarray(x, dtype=float)
    r = np.hypot(x[..., 0], x[..., 1])
    t = np.arctan2(x[..., 1], x[..., 0])
    mu, kappa = kolosov(material)
    stress, g1, g2, d1, d2 = _angular(0.5 * t, kappa, mode)
    root = np.sqrt(2.0 * math.pi * r)
    u = np.stack([g1, g2], axis=-1) * (r / root / (2.0 * mu))[..., None]
    ct, st = np.cos(t), np.sin(t)
    grad = np.stack([np.stack([0.5 * g * ct - d * st, 0.5 * g * st + d * ct], axis=-1)
                     for g, d in ((g1, d1), (g2, d2))], axis=-2)
    grad /= (2.0 * mu * root)[..., None, None]
    return u, grad, stress / root[..., None]
