"""The explicit stable time step of a finite-element model.

The largest stable step of an explicit scheme is its stability limit along the
imaginary axis over the highest natural frequency ``omega_max`` of the undamped
model, the square root of the largest eigenvalue of ``M^-1 K`` (docs/fem.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike

__all__ = ["RK4_STABILITY_LIMIT", "CENTRAL_DIFFERENCE_STABILITY_LIMIT", "StableStep",
           "stable_time_step"]

RK4_STABILITY_LIMIT: float = 2.0 * math.sqrt(2.0)
"""Extent of the classical RK4 stability region along the imaginary axis.

For an undamped mode ``x'' = -w^2 x`` the eigenvalues are ``+-i w``; RK4 is
stable when ``w dt <= 2 sqrt(2) ~= 2.8284``.
"""

CENTRAL_DIFFERENCE_STABILITY_LIMIT: float = 2.0
"""Courant limit ``w dt <= 2`` of the (undamped) central-difference scheme."""

@dataclass(frozen=True)
class StableStep:
    """Largest natural frequency and the explicit stability limits it implies.

    Attributes
    ----------
    omega_max : float
        Largest circular frequency ``sqrt(lambda_max(M^-1 K))`` [rad/s].
    dt_rk4 : float
        ``RK4_STABILITY_LIMIT / omega_max`` = ``2 sqrt(2) / omega_max`` [s].
    dt_central : float
        ``CENTRAL_DIFFERENCE_STABILITY_LIMIT / omega_max`` = ``2 / omega_max`` [s].

    Notes
    -----
    These are the undamped limits with no safety factor; apply one (typically
    0.8-0.9) at the call site.
    """

    omega_max: float
    dt_rk4: float
    dt_central: float


def _largest_eigenvalue(a: sp.csr_matrix) -> float:
    """Largest algebraic eigenvalue of a symmetric sparse matrix."""
    n = a.shape[0]
    if n < 3:
        # ARPACK needs k < n; tiny systems go dense.
        return float(scipy.linalg.eigvalsh(a.toarray())[-1])
    # Deterministic start vector: reproducible, and a random vector is not
    # orthogonal to the top mode (a constant one can be, by mesh symmetry).
    v0 = np.random.default_rng(12345).standard_normal(n)
    try:
        vals = spla.eigsh(a, k=1, which="LA", v0=v0, tol=1e-10, return_eigenvectors=False)
        return float(vals[-1])
    except (spla.ArpackNoConvergence, spla.ArpackError):
        pass
    if n <= 4000:
        return float(scipy.linalg.eigvalsh(a.toarray())[-1])
    # Gershgorin bound >= lambda_max, so the step it gives is conservative.
    return float(abs(a).sum(axis=1).max())


def stable_time_step(stiffness: ArrayLike | sp.spmatrix, lumped_mass: ArrayLike) -> StableStep:
    """Stable explicit time step from the largest eigenvalue of ``M^-1 K``.

    The symmetric similarity transform ``A = M^-1/2 K M^-1/2`` (``M``
    diagonal) has the same eigenvalues ``omega^2`` as ``M^-1 K``; its largest
    algebraic eigenvalue is found with :func:`scipy.sparse.linalg.eigsh`,
    falling back to a dense solve (small systems) or the Gershgorin upper
    bound (large systems) if ARPACK fails.

    Parameters
    ----------
    stiffness : sparse matrix or array_like, shape (n, n)
        Symmetric stiffness [N/m].  May be singular (free body): only the
        largest eigenvalue matters.
    lumped_mass : array_like, shape (n,)
        Diagonal mass [kg]; all entries must be > 0.

    Returns
    -------
    StableStep
        ``omega_max`` [rad/s] and the RK4 and central-difference limits [s].
    """
    m = np.asarray(lumped_mass, dtype=float)
    k = sp.csr_matrix(stiffness, dtype=float)
    if m.ndim != 1 or k.shape != (m.size, m.size):
        raise ValueError(
            f"stiffness {k.shape} and lumped_mass {m.shape} sizes do not match"
        )
    if not (m > 0).all():
        raise ValueError("lumped_mass must be > 0 for every DOF")
    s = sp.diags(1.0 / np.sqrt(m))
    a = (s @ k @ s).tocsr()
    lam = _largest_eigenvalue(a)
    if not lam > 0:
        raise ValueError(f"largest eigenvalue of M^-1 K is not positive ({lam})")
    omega = math.sqrt(lam)
    return StableStep(
        omega_max=omega,
        dt_rk4=RK4_STABILITY_LIMIT / omega,
        dt_central=CENTRAL_DIFFERENCE_STABILITY_LIMIT / omega,
    )

