"""The hubs' translations on their radial bearings in the compiled implicit loop
(docs/sector.md, 6.12): twin of :class:`~spurdyn.sector.bearings.HubBearings` and of the
translations' part of :meth:`~spurdyn.sector.model.SectorModel.compliance` and
``rigid_columns_times``, on a :data:`~spurdyn.sector.packs.BearingPack` (no translations
without bearings: each kernel then does nothing).
"""

from __future__ import annotations

import numpy as np

from spurdyn.jit import njit


@njit
def trans_free(x0, q, v, bear):
    """The bodies' free accelerations ``x0`` followed by the hubs' translations',
    ``S_tt^-1 (-k x - c x_dot)`` (twin of ``HubBearings.free``); ``x0`` itself without bearings."""
    nt = bear.tinv.size
    if nt == 0:
        return x0
    nb = x0.size
    out = np.empty(nb + nt)
    out[:nb] = x0
    for j in range(nt):
        out[nb + j] = bear.tinv[j] * (-bear.k[j] * q[nb + j] - bear.c[j] * v[nb + j])
    return out


@njit
def trans_times(tr, x):
    """``(p,)`` the rows' translation entries ``tr`` ``(p, t)`` times the translations ``x``
    (zeros without bearings: ``t = 0``)."""
    p, nt = tr.shape
    out = np.zeros(p)
    for a in range(p):
        for j in range(nt):
            out[a] += tr[a, j] * x[j]
    return out


@njit
def trans_back(qdd, nb, lam, trans):
    """``qdd[nb:] += S_tt^-1 T^T lam``: loads ``lam`` on the rows ``T`` through the
    translations' block (``trans = (T, S_tt^-1)``; nothing without bearings)."""
    tr, tinv = trans
    for j in range(tinv.size):
        acc = 0.0
        for a in range(lam.size):
            acc += tr[a, j] * lam[a]
        qdd[nb + j] += tinv[j] * acc


__all__ = ["trans_back", "trans_free", "trans_times"]
