"""The contact pair of the implicit step through the compiled search (``backend="numba"``).

The same search as the paper's compiled step (:func:`spurdyn.contact.search_compiled.search`,
the strip's rows of :mod:`spurdyn.contact.strip_compiled`), returned as the NumPy
:class:`~spurdyn.contact.search_numpy.ContactPair` the implicit step reads; its twin is
:func:`spurdyn.solvers.paper.dynamics_numpy.contact_at` (``backend="numpy"``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from spurdyn.contact.constants import FLANK
from spurdyn.contact.search_compiled import contact_rows, search
from spurdyn.contact.search_numpy import ContactPair
from spurdyn.contact.strip_compiled import strip_half_width, strip_rows, virtual_point
from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.paper.dynamics_numpy import strip_law
from spurdyn.solvers.paper.stepper_compiled import pack, strip_slots


class CompiledContact:
    """``at(theta, u, guess, load)``: the contact pair, as ``contact_at`` finds it."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        self.P = pack(system, settings)
        self.na = system.gears[0].mesh.n_nodes
        self.ns = strip_slots(system, settings)
        nd = self.P.fl_nodes.shape[1]
        self.buffers = [np.empty((nd, 2)) for _ in range(4)]
        self.law = strip_law(system) if settings.contact == "hertz" else None

    def at(self, theta: NDArray[np.float64], u: NDArray[np.float64], guess: tuple[float, float],
           load: float = 0.0) -> ContactPair:
        P, ns = self.P, self.ns
        va, vb, ma, mb = self.buffers
        a, b, mode, nx, ny, s = search(P, theta, u, np.array(guess, dtype=float), va, vb, ma, mb)
        cn = np.zeros(2 * ns, dtype=np.int64)
        cw = np.zeros(2 * ns)
        hw = 0.0
        if self.law is not None and mode == FLANK:
            hw = strip_half_width(P, a, b, load, self.law[0], self.law[1])
        if hw > 0.0:
            dax, day, ok_a = strip_rows(P, np.int64(0), a, hw, cn, cw, np.int64(0), np.int64(ns))
            dbx, dby, ok_b = strip_rows(P, np.int64(1), b, hw, cn, cw, np.int64(ns), np.int64(ns))
            if not (ok_a and ok_b):
                raise FloatingPointError("the contact strip spread over more elements than the "
                                         "run allowed for")
            xa, ya = virtual_point(P, np.int64(0), cn, cw, np.int64(0), np.int64(ns), dax, day,
                                   theta[0], u, np.int64(0), 0.0, 0.0)
            xb, yb = virtual_point(P, np.int64(1), cn, cw, np.int64(ns), np.int64(ns), dbx, dby,
                                   theta[1], u, np.int64(0), 0.0, 0.0)
            s = nx * (xa - xb) + ny * (ya - yb)
        else:
            contact_rows(P, a, b, cn, cw)
        keep_a, keep_b = cw[:ns] != 0.0, cw[ns:] != 0.0
        return ContactPair(alpha=float(a), beta=float(b), mode=int(mode), normal=np.array([nx, ny]),
                           s=float(s), nodes_a=cn[:ns][keep_a], weights_a=cw[:ns][keep_a],
                           nodes_b=cn[ns:][keep_b] - self.na, weights_b=cw[ns:][keep_b],
                           delta_a=np.zeros(2), delta_b=np.zeros(2), half_width=hw)
