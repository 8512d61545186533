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
    x, wq = strip_quadrature()
    ts = strip_coordinates(t_c, b, flank.r0, flank.r_tip, flank.ny, flank.base_radius, x)
    rows = np.minimum(np.floor(ts).astype(np.intp), flank.ny - 1)
    lo, hi = int(rows.min()), int(rows.max())
    acc = np.zeros(2 * (hi - lo) + 3)
    for t, row, wk in zip(ts, rows, wq):
        _, w, _ = flank.locate(float(t))
        acc[2 * (row - lo):2 * (row - lo) + 3] += wk * w
    nodes = flank.side_nodes[2 * lo:2 * hi + 3]
    delta = flank.exact(t_c) - acc @ flank.side_Y[2 * lo:2 * hi + 3]
    return nodes, acc, delta
