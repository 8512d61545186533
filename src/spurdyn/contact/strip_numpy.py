"""The distributed contact's strip on one flank, in NumPy: the twin of :mod:`spurdyn.contact.strip_compiled`.

The contact force of a pair is spread over the Hertzian strip of half-width ``b`` around
its contact point with the elliptic pressure, and the gap the pair constrains is the
average over the same strip with the same weights (docs/solver.md, section 11). Both are
linear in the nodal positions through the *strip-averaged* shape functions
``N_bar = sum_k w_k N(t_k)``, so a strip is, to the solver, one virtual material point
with more nodes: ``x_bar = c + N_bar (Y + u) + R delta_bar`` with
``delta_bar = Y_exact(t_c) - N_bar Y``. For a rigid rotation this is the rotated exact
involute point at the centre; its departure from the centre's own material point is the
strip-averaged elastic displacement. ``b = 0`` gives the point contact's rows exactly.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from spurdyn.contact.hertz import strip_coordinates, strip_quadrature
from spurdyn.fem.element import edge_weights
from spurdyn.model.flank import Flank


def strip_rows(flank: Flank, t_c: float, b: float) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
    """Nodes, strip-averaged shape weights and ``delta_bar`` of the strip around ``t_c``.

    ``b`` is the half-width (m); 0 gives :meth:`Flank.locate` and :meth:`Flank.delta` at
    ``t_c`` (the point contact). The nodes are a contiguous run of the flank's outline
    nodes, root to tip; the weights sum to one.
    """
    if b <= 0.0:
        nodes, w, _ = flank.locate(t_c)
        return nodes, w, flank.delta(t_c)
    weights = strip_weights(flank, np.array([t_c]), np.array([b]))[0]
    used = np.flatnonzero(weights)
    lo, hi = used[0] // 2 * 2, min((used[-1] + 1) // 2 * 2, 2 * flank.ny)
    acc = weights[lo:hi + 1]
    nodes = flank.side_nodes[lo:hi + 1]
    delta = flank.exact(t_c) - acc @ flank.side_Y[lo:hi + 1]
    return nodes, acc, delta


def strip_weights(flank: Flank, t_c: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(p, 2 ny + 1)`` strip-averaged shape weights ``N_bar`` on the flank's outline nodes
    (root to tip) of ``p`` strips around ``t_c`` with half-widths ``b`` (m; 0: the point
    at ``t_c``). Each row sums to one."""
    t_c, b = np.atleast_1d(t_c), np.atleast_1d(b)
    x, wq = strip_quadrature()
    ny = flank.ny
    ts = strip_coordinates(t_c[:, None], b[:, None], flank.r0, flank.r_tip, ny, flank.base_radius, x[None, :])
    rows = np.minimum(np.floor(ts).astype(np.intp), ny - 1)
    w = edge_weights(2.0 * (ts - rows) - 1.0) * wq            # (3, p, points)
    n = 2 * ny + 1
    at = (2 * rows + n * np.arange(t_c.size)[:, None])[None] + np.arange(3)[:, None, None]
    return np.bincount(at.ravel(), w.ravel(), minlength=n * t_c.size).reshape(t_c.size, n)
