"""Damping forces of the implicit integrator (docs/implicit.md, section 3).

Rayleigh damping ``C = a M + b K`` of a tooth acts on its deformation rate seen from its
disk, ``w_dot = R^T u_dot - s theta_dot Jz (w + Y)``, so that a rigid rotation is not
damped; its generalised forces are ``-(dw/dq)^T C w_dot``:

    f_u = -R C w_dot,        Q_theta = s sum_i (w_i + Y_i) x (C w_dot)_i.

The mesh damper is a dashpot along the line of action between the two base circles,
``F_d = c_m (r_bA theta_dot_A - r_bB theta_dot_B)``, acting while the teeth are in contact,
with ``c_m = 2 zeta sqrt(k m_e)`` for a damping ratio ``zeta`` of the pair's torsional mode
(:func:`~spurdyn.model.damper.mesh_damper_coefficient`, which the sector model's damper
reads too).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from spurdyn.geometry.involute import rot
from spurdyn.model.system import GearBody


def rayleigh_forces(gb: GearBody, theta: float, omega: float, u: NDArray[np.float64],
                    v: NDArray[np.float64], a: float, b: float) -> tuple[float, NDArray[np.float64]]:
    """``(Q_theta, f_u)`` of Rayleigh damping ``a M + b K`` on one gear's tooth."""
    r = rot(gb.sense * theta)
    y = (gb.Y + u).reshape(-1, 2)
    wy = y @ r                                 # R^T (Y + u) = w + Y, node by node
    wd = v.reshape(-1, 2) @ r                  # R^T u_dot
    wd[:, 0] += gb.sense * omega * wy[:, 1]    # - s theta_dot Jz (w + Y)
    wd[:, 1] -= gb.sense * omega * wy[:, 0]
    wd_flat = wd.ravel()
    d = (a * gb.mass * wd_flat if a else 0.0) + (b * (gb.stiffness @ wd_flat) if b else 0.0)
    d2 = np.asarray(d).reshape(-1, 2)
    f = -(d2 @ r.T).ravel()
    q = gb.sense * float(np.sum(wy[:, 0] * d2[:, 1] - wy[:, 1] * d2[:, 0]))
    return q, f


def rayleigh_from_ratio(zeta: float, f1: float, f2: float) -> tuple[float, float]:
    """Rayleigh's ``(a, b)`` that give the damping ratio ``zeta`` at the frequencies ``f1``
    and ``f2`` (Hz): ``zeta(omega) = a / (2 omega) + b omega / 2``."""
    w1, w2 = 2.0 * math.pi * f1, 2.0 * math.pi * f2
    return 2.0 * zeta * w1 * w2 / (w1 + w2), 2.0 * zeta / (w1 + w2)
