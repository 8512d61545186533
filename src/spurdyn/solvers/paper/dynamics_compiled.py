"""Equations of motion and constraint forces of the paper's model, compiled with Numba.

The twin of :mod:`spurdyn.solvers.paper.dynamics_numpy` (and, for :func:`torque`, of
:func:`spurdyn.model.loading.gear_torques`); tests/test_paper_dynamics.py checks each
function against it at round-off.

Conventions: ``u``-vectors stack both teeth (A's nodes first, node ``n`` owns DOFs
``2n``, ``2n+1``); ``theta``, ``omega`` are ``(2,)``; ``x = [lambda_A, lambda_B, p]``;
``P`` is the packed model (:class:`spurdyn.solvers.layout.Packed`).
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.jit import njit


@njit
def rotation(P, theta, g):
    """``(cos, sin)`` of gear ``g``'s world rotation ``sense theta``."""
    sg = P.sense[g]
    return math.cos(sg * theta[g]), math.sin(sg * theta[g])


@njit
def assign(out, values):
    """``out[:] = values``, element by element.

    The same copy, but Numba's slice assignment from an array also compiles the message of
    its shape error, with string formatting: about 5 % of a first run's compiling.
    """
    for i in range(out.size):
        out[i] = values[i]


@njit
def max_abs(e):
    """``max |e_i|``, NaN if any entry is NaN (Python's ``max`` would drop it)."""
    r = 0.0
    for i in range(e.size):
        a = abs(e[i])
        if a > r or a != a:
            r = a
    return r


@njit
def bsr_matvec(indptr, indices, data, v, out):
    """``out = K v`` for ``K`` in 2 x 2 block rows (one per node): ``data (nb, 2, 2)``."""
    n = indptr.size - 1
    for i in range(n):
        a0 = 0.0
        a1 = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            v0 = v[2 * j]
            v1 = v[2 * j + 1]
            a0 += data[k, 0, 0] * v0 + data[k, 0, 1] * v1
            a1 += data[k, 1, 0] * v0 + data[k, 1, 1] * v1
        out[2 * i] = a0
        out[2 * i + 1] = a1


@njit
def torque(tpar, g, th):
    """Torque on gear ``g`` at its rotation ``th`` (Fig. 7), and its slope d tau / d theta."""
    amp, ts, t2 = tpar[g, 0], tpar[g, 1], tpar[g, 2]
    a = th / t2
    b = (ts - th) / t2
    f = min(a, b)
    if f <= 0.0:
        return 0.0, 0.0
    if f >= 1.0:
        return amp, 0.0
    if a <= b:
        return amp * f, amp / t2
    return amp * f, -amp / t2


# -- equations of motion ------------------------------------------------------------------

@njit
def elastic(theta, u, Y, node_gear, sense, indptr, indices, data, keep, w, kw, f_u, q):
    """Elastic forces ``f_u = -R K w`` and disk torques ``q = sense sum w x Kw``.

    ``w``, ``kw`` are work arrays (n_u,) left holding ``w`` and ``K w``.
    """
    nn = node_gear.size
    c = np.empty(2)
    s = np.empty(2)
    for g in range(2):
        c[g] = math.cos(sense[g] * theta[g])
        s[g] = math.sin(sense[g] * theta[g])
    for i in range(nn):
        g = node_gear[i]
        yx = Y[2 * i] + u[2 * i]
        yy = Y[2 * i + 1] + u[2 * i + 1]
        # R^T y - Y
        w[2 * i] = c[g] * yx + s[g] * yy - Y[2 * i]
        w[2 * i + 1] = -s[g] * yx + c[g] * yy - Y[2 * i + 1]
    bsr_matvec(indptr, indices, data, w, kw)
    q[0] = 0.0
    q[1] = 0.0
    for i in range(nn):
        g = node_gear[i]
        kx, ky = kw[2 * i], kw[2 * i + 1]
        f_u[2 * i] = -(c[g] * kx - s[g] * ky)
        f_u[2 * i + 1] = -(s[g] * kx + c[g] * ky)
        if keep:
            q[g] += w[2 * i] * ky - w[2 * i + 1] * kx
    q[0] *= sense[0]
    q[1] *= sense[1]


@njit
def accelerations(theta, u, f_th, f_u, P, w, kw, el, q, alpha, a):
    """``alpha = (tau + Q + f_theta) / J``, ``a = (f_el + f_u) / m``."""
    elastic(theta, u, P.Y, P.node_gear, P.sense, P.indptr, P.indices, P.data, P.keep, w, kw, el, q)
    for g in range(2):
        tau, _ = torque(P.tpar, g, theta[g])
        alpha[g] = (tau + q[g] + f_th[g]) / P.J[g]
    for i in range(a.size):
        a[i] = (el[i] + f_u[i]) / P.mass[i]


# -- constraint forces ----------------------------------------------------------------------

@njit
def root_phi_theta(P, theta, k):
    """``dPhi_k/dtheta`` of root node ``k``: ``-sense R Jz Y``."""
    g = P.rgear[k]
    i = P.rnode[k]
    sg = P.sense[g]
    c, s = math.cos(sg * theta[g]), math.sin(sg * theta[g])
    jx, jy = -P.Y[2 * i + 1], P.Y[2 * i]
    return -sg * (c * jx - s * jy), -sg * (s * jx + c * jy)


@njit
def constraint_force(P, theta, cn, cw, normal, gth, x, f_th, f_u):
    """``G^T x``: root forces ``-lambda`` on the root nodes and their torques on the disks,
    and the contact force ``p n`` through the weights ``cw`` of nodes ``cn`` (A's half, then
    B's: 3 each for the point contact, the strip's slots for the distributed one) with its
    torques ``gth p`` on the disks (the contact row's disk entries: zero for the point
    contact, the strip's pair's roll, docs/solver.md section 11.3)."""
    f_th[0] = 0.0
    f_th[1] = 0.0
    f_u[:] = 0.0
    for k in range(P.rnode.size):
        i = P.rnode[k]
        lx, ly = x[2 * k], x[2 * k + 1]
        f_u[2 * i] -= lx
        f_u[2 * i + 1] -= ly
        px, py = root_phi_theta(P, theta, k)
        f_th[P.rgear[k]] -= px * lx + py * ly
    p = x[x.size - 1]
    f_th[0] += gth[0] * p
    f_th[1] += gth[1] * p
    half = cn.size // 2
    for j in range(cn.size):
        sign = 1.0 if j < half else -1.0
        i = cn[j]
        f_u[2 * i] += sign * cw[j] * normal[0] * p
        f_u[2 * i + 1] += sign * cw[j] * normal[1] * p


@njit
def gram(P, theta, cn, cw, normal, gth, C):
    """``G M^-1 G^T`` (dense, ``n_x`` square) for the constraint directions at ``theta``."""
    nr = P.rnode.size
    C[:, :] = 0.0
    for k in range(nr):
        pk = root_phi_theta(P, theta, k)
        gk = P.rgear[k]
        for l in range(nr):
            if P.rgear[l] != gk:
                continue
            pl = root_phi_theta(P, theta, l)
            for a in range(2):
                for b in range(2):
                    C[2 * k + a, 2 * l + b] = pk[a] * pl[b] / P.J[gk]
        i = P.rnode[k]
        C[2 * k, 2 * k] += 1.0 / P.mass[2 * i]
        C[2 * k + 1, 2 * k + 1] += 1.0 / P.mass[2 * i + 1]
    gram_contact(P, theta, cn, cw, normal, gth, C)


@njit
def gram_contact(P, theta, cn, cw, normal, gth, C):
    """Refresh the contact row and column of ``G M^-1 G^T`` for new contact rows (and its
    coupling with a root node that carries the contact: never on an ordinary flank, kept
    for completeness), its disk entries ``gth`` coupling it with every root row of the
    gear through the disk's inertia."""
    nr = P.rnode.size
    nx = 2 * nr + 1
    for k in range(nx):
        C[nx - 1, k] = 0.0
        C[k, nx - 1] = 0.0
    half = cn.size // 2
    for k in range(nr):
        i = P.rnode[k]
        for j in range(cn.size):
            if cn[j] == i:
                sign = 1.0 if j < half else -1.0
                for a in range(2):
                    v = -sign * cw[j] * normal[a] / P.mass[2 * i + a]
                    C[2 * k + a, nx - 1] += v
                    C[nx - 1, 2 * k + a] += v
    for k in range(nr):
        gk = P.rgear[k]
        if gth[gk] != 0.0:
            px, py = root_phi_theta(P, theta, k)
            C[2 * k, nx - 1] -= px * gth[gk] / P.J[gk]
            C[nx - 1, 2 * k] -= px * gth[gk] / P.J[gk]
            C[2 * k + 1, nx - 1] -= py * gth[gk] / P.J[gk]
            C[nx - 1, 2 * k + 1] -= py * gth[gk] / P.J[gk]
    cpp = gth[0] * gth[0] / P.J[0] + gth[1] * gth[1] / P.J[1]
    for j in range(cn.size):
        for j2 in range(cn.size):
            if cn[j] == cn[j2] and ((j < half) == (j2 < half)):
                cpp += cw[j] * cw[j2] / P.mass[2 * cn[j]]
    C[nx - 1, nx - 1] = cpp
