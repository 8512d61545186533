"""The accelerated iteration of Appendix B, as pure NumPy functions.

For a stage with constraint errors ``e(x)`` and a positive-definite estimate ``C`` of
``de/dx``, one iteration is

    x <- x - b_bar A_n e / ||C'||_inf,   then p <- min(0, p),

with ``C' = E C E`` (rows and columns of zero errors removed), ``C_1 = C' / ||C'||_inf``,
``C_k = C_{k-1} (b_k I - C_{k-1})``, ``A_k = (b_k I - C_{k-1}) A_{k-1}``, ``A_1 = I``,
``b_k = eps_{k-1} + om_{k-1}``, ``om_k = b_k^2 / 4``, ``eps_k = eps_{k-1} om_{k-1}``,
``om_1 = 1``, ``eps_1`` the smallest eigenvalue of ``C_1``, and ``b_bar = 2 / (om_n + eps_n)``.
Since ``A_n C_1 = C_n``, the error of the linear model contracts as ``(I - b_bar C_n) e``.
``A_n e`` is applied recursively with ``2^(n-1) - 1`` products by ``C_1`` and never formed.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray


def coefficients(n: int, eps1: float) -> tuple[NDArray[np.float64], float, float, float]:
    """``b_k`` (k = 2..n, stored at index k), ``om_n``, ``eps_n`` and ``b_bar``."""
    b = np.zeros(n + 1)
    om, eps = 1.0, eps1
    for k in range(2, n + 1):
        b[k] = eps + om
        om, eps = b[k] * b[k] / 4.0, eps * om
    return b, om, eps, 2.0 / (om + eps)


def apply_c(c1: NDArray[np.float64], b: NDArray[np.float64], k: int, v: NDArray[np.float64]) -> NDArray[np.float64]:
    """``C_k v``."""
    if k == 1:
        return c1 @ v
    w = apply_c(c1, b, k - 1, v)
    return apply_c(c1, b, k - 1, b[k] * v - w)


def apply_a(c1: NDArray[np.float64], b: NDArray[np.float64], n: int, e: NDArray[np.float64]) -> NDArray[np.float64]:
    """``A_n e``."""
    if n == 1:
        return e.copy()
    z = apply_a(c1, b, n - 1, e)
    return b[n] * z - apply_c(c1, b, n - 1, z)


def smallest_eigenvalue(c1: NDArray[np.float64], active: NDArray[np.bool_]) -> float:
    """``eps_1``: the smallest eigenvalue of ``C_1`` over its active rows."""
    sub = c1[np.ix_(active, active)]
    return float(np.linalg.eigvalsh(sub)[0]) if sub.size else 1.0


def band_value(e: float, tol: float, margin: float) -> float:
    """Where the displacement stage aims the contact error (docs/solver.md, section 7).

    A penetration (or gap) already inside the tolerance band ``|e| <= tol`` is held where
    it is: the constraint is satisfied to tolerance, and removing it within one step
    would take a force ``m_c e / (dt^2 / 2)``, which grows as ``1/dt^2``. One outside is
    brought to the band's edge less a margin equal to its excess (at least
    ``margin * tol``, at most ``tol``: aim at zero), so the iteration lands inside the band.

    Parameters
    ----------
    e
        The contact error of the stage's first iterate (m).
    tol
        The displacement tolerance (m).
    margin
        The smallest margin, a fraction of ``tol``.

    Returns
    -------
    float
        The contact error the iteration aims at (m).
    """
    a = abs(e)
    if a <= tol:
        return e
    inset = min(tol, max(a - tol, margin * tol))
    return math.copysign(tol - inset, e)


def accelerated_update(x: NDArray[np.float64], e: NDArray[np.float64], c: NDArray[np.float64],
                       n: int, active: NDArray[np.bool_] | None = None) -> NDArray[np.float64]:
    """One iteration of eq. (19)-(21): the new ``x = [lambda; p]`` (``p`` last, ``<= 0``).

    ``active`` marks the rows of ``C'`` (default: the nonzero errors); a row held at its
    target has a zero ``e`` but stays in ``C'``, so the update keeps it where it is.
    """
    if active is None:
        active = e != 0.0
    e = np.where(active, e, 0.0)
    cp = np.where(np.outer(active, active), c, 0.0)
    norm = float(np.abs(cp).sum(axis=1).max())
    if norm == 0.0:
        return x.copy()
    c1 = cp / norm
    eps1 = min(max(smallest_eigenvalue(c1, active), 1e-12), 1.0)
    b, _, _, bbar = coefficients(n, eps1)
    x = x - bbar * apply_a(c1, b, n, e) / norm
    x[-1] = min(0.0, x[-1])
    return x
