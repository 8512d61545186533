"""The accelerated iteration of Appendix B, compiled with Numba.

The twin of :mod:`spurdyn.solvers.paper.iteration_numpy` (the formulas are stated
there); tests/test_paper_iteration.py checks it against it at round-off.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.jit import njit
from spurdyn.solvers.paper.dynamics_compiled import assign


@njit
def apply_c(C1, b, k, v, out):
    if k == 1:
        assign(out, C1 @ v)
        return
    w = np.empty_like(v)
    apply_c(C1, b, k - 1, v, w)
    z = b[k] * v - w
    apply_c(C1, b, k - 1, z, out)


@njit
def apply_a(C1, b, n, e, out):
    if n == 1:
        assign(out, e)
        return
    z = np.empty_like(e)
    apply_a(C1, b, n - 1, e, z)
    w = np.empty_like(e)
    apply_c(C1, b, n - 1, z, w)
    assign(out, b[n] * z - w)


@njit
def band_value(e, tol, margin):
    """Where the displacement stage aims the contact error ``e`` (the twin of
    :func:`spurdyn.solvers.paper.iteration_numpy.band_value`)."""
    a = abs(e)
    if a <= tol:
        return e
    inset = min(tol, max(a - tol, margin * tol))
    return math.copysign(tol - inset, e)


@njit
def accelerated_update(x, e, C, scale, n, eps_root, Cp, work, active_p, pp_add):
    """One iteration ``x <- x - b_bar A_n e / ||C'||``; ``p <- min(0, p)``.

    ``C`` is ``G M^-1 G^T``; the stage's coefficient ``scale`` multiplies it, and
    ``pp_add`` is added to its contact diagonal (the strip compliance ``c_H`` in the
    displacement stage of the distributed contact, else 0). ``eps_root``
    is the smallest eigenvalue of the root block of ``G M^-1 G^T`` (constant over a
    run: the disk rotations only rotate it), so ``eps_1`` needs no eigen-solve here.
    ``active_p`` keeps the contact row in ``C'`` (the root rows always are); a row held at
    its target has a zero ``e`` there and stays in ``C'``.
    """
    m = x.size
    norm = 0.0
    for i in range(m):
        acc = 0.0
        if i == m - 1 and not active_p:
            continue
        for j in range(m):
            if j == m - 1 and not active_p:
                Cp[i, j] = 0.0
                continue
            Cp[i, j] = C[i, j] * scale
            if i == m - 1 and j == m - 1:
                Cp[i, j] += pp_add
            acc += abs(Cp[i, j])
        if acc > norm:
            norm = acc
    if not active_p:
        for j in range(m):
            Cp[m - 1, j] = 0.0
    lam_min = eps_root * scale
    if active_p and Cp[m - 1, m - 1] < lam_min:
        lam_min = Cp[m - 1, m - 1]
    eps1 = min(max(lam_min / norm, 1e-12), 1.0)
    for i in range(m):
        for j in range(m):
            Cp[i, j] /= norm
    b = np.zeros(n + 1)
    om, ep = 1.0, eps1
    for k in range(2, n + 1):
        b[k] = ep + om
        om, ep = b[k] * b[k] / 4.0, ep * om
    bbar = 2.0 / (om + ep)
    ee = e.copy()
    if not active_p:
        ee[m - 1] = 0.0
    apply_a(Cp, b, n, ee, work)
    for i in range(m):
        x[i] -= bbar * work[i] / norm
    if x[m - 1] > 0.0:
        x[m - 1] = 0.0
