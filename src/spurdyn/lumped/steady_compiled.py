"""The steady lumped pair's right-hand side compiled (docs/lumped.md, "The steady state").

SciPy's DOP853 calls the right-hand side a dozen times a step, tens of thousands of steps a
run; in Python each call cost ~20 us, more than the integrator's own work. This is the same
arithmetic in the same order as the Python closure of
:func:`spurdyn.lumped.steady._steady_equations`, its twin (``tests/test_lumped_compiled.py``
holds them equal to the bit), for runs whose torques are constant.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.jit import njit

#: The scalars of :func:`rhs`'s ``par``, in order: the dense table's spacing ``h`` (a
#: sector cycle's; 0 for the single-pair table), A's pitch, the damper's ``2 zeta sqrt(m_e)``,
#: the base radii, the inertias, the driver's sign, the torques, and for the table the start
#: roll and its sense.
PAR = ("h", "pitch", "zeta2_sqrt_me", "ra", "rb", "ja", "jb", "s", "amp_a", "amp_b", "roll0", "droll")


@njit
def table_value(roll, breaks, coefs):
    """The single-pair table at A's roll ``roll``, as
    :meth:`~spurdyn.lumped.model.MeshStiffnessTable.scalar` reads its polynomial pieces
    (``coefs[i]`` the piece after ``breaks[i]``, highest power first); 0 off the path."""
    if roll < breaks[0] or roll > breaks[-1]:
        return 0.0
    i = min(np.searchsorted(breaks, roll, side="right") - 1, breaks.size - 2)
    d = roll - breaks[i]
    out = 0.0
    for c in coefs[i]:
        out = out * d + c
    return out


@njit
def stiffness_at(phi, dense, bounds, par, ks):
    """Every pair's stiffness at A's rotation ``phi`` into ``ks``; their sum. A cycle with
    ``h > 0`` reads its dense table as :meth:`~spurdyn.lumped.cycle.SectorCycle.at` does
    (``dense`` the rows, ``bounds`` their ends); otherwise the single-pair table as
    :meth:`~spurdyn.lumped.cycle.TableCycle.at` (``bounds`` the breaks, ``dense`` the pieces)."""
    h, pitch = par[0], par[1]
    phase = phi - pitch * math.floor(phi / pitch)
    if h == 0.0:
        total = 0.0
        for r in range(ks.size):
            ks[r] = table_value(par[10] + par[11] * (phase + r * pitch), bounds[0], dense)
            total += ks[r]
        return total
    x = phase / h
    i = min(max(int(x), 0), dense.shape[1] - 2)
    w = x - i
    total = 0.0
    for r in range(dense.shape[0]):
        if bounds[r, 0] <= phase <= bounds[r, 1]:
            ks[r] = dense[r, i] + w * (dense[r, i + 1] - dense[r, i])
        else:
            ks[r] = 0.0
        total += ks[r]
    return total


@njit
def rhs(t, y, dense, bounds, par, rows):
    """``dy/dt`` of ``y = (phi_a, omega_a, delta, delta_dot)``; ``par`` the scalars of
    :data:`PAR`, ``rows`` the pairs the path holds (:func:`stiffness_at`'s tables)."""
    zeta2_sqrt_me, ra, rb, ja, jb, s, amp_a, amp_b = par[2], par[3], par[4], par[5], par[6], par[7], par[8], par[9]
    delta, ddelta = y[2], y[3]
    f = 0.0
    if delta > 0.0:
        ks = np.empty(rows)
        k = stiffness_at(y[0], dense, bounds, par, ks)
        if k > 0.0:
            c = zeta2_sqrt_me * math.sqrt(k)
            for kj in ks:
                fj = kj * delta + c * kj / k * ddelta
                if fj > 0.0:
                    f += fj
    acc_a = (amp_a - s * ra * f) / ja
    acc_b = (amp_b + s * rb * f) / jb
    out = np.empty(4)
    out[0] = y[1]
    out[1] = acc_a
    out[2] = ddelta
    out[3] = s * (ra * acc_a - rb * acc_b)
    return out
