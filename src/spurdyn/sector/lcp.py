"""The sector run's contacts at a step (:class:`Rows`) and their complementarity problem
(:func:`lcp`; docs/sector.md, 6.3): the NumPy loop's, beside the compiled twin in
:mod:`spurdyn.solvers.sector.step_compiled`."""

from __future__ import annotations

import itertools
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray


class Rows(NamedTuple):
    """The pairs near the path at a step: their indices in the run's teeth, the constant
    parts of their gaps, and per gear the rows' hub coefficients and elastic parts; where a
    pit over part of the face width splits a pair (docs/faults.md, section 8) it is two
    rows, ``on`` naming it twice: per row its ``kind`` (0 whole, 1 the intact strip, 2 the
    pit's), ``share`` of the face width and force of the step before ``held``."""

    on: NDArray[np.intp]
    const: NDArray[np.float64]
    sides: tuple[tuple[NDArray[np.float64], Any], ...]
    kind: NDArray[np.intp] | None = None
    share: NDArray[np.float64] | None = None
    held: NDArray[np.float64] | None = None


def lcp(w: NDArray[np.float64], v: NDArray[np.float64],
        guess: NDArray[np.bool_] | None = None) -> tuple[NDArray[np.float64], bool]:
    """``(F, found)``: ``F >= 0`` with ``W F + v >= 0`` and ``F (W F + v) = 0`` for a small
    positive definite ``W``: the active set ``guess`` (the step before's) tried first, then
    all of them, the fewest contacts first. The solution is unique, so the order changes only
    the cost; none found is a status (``found`` false), as in the compiled twin
    (:func:`~spurdyn.solvers.sector.rows_compiled.lcp_ordered`)."""
    n = v.size
    tol = 1e-12 * max(float(np.abs(v).max()), 1e-300)
    first = [tuple(np.flatnonzero(guess))] if guess is not None else []
    for act in itertools.chain(first, *(itertools.combinations(range(n), m) for m in range(n + 1))):
        f = np.zeros(n)
        if act:
            idx = list(act)
            f[idx] = np.linalg.solve(w[np.ix_(idx, idx)], -v[idx])
            if (f[idx] < 0.0).any():
                continue
        if (w @ f + v >= -tol).all():
            return f, True
    return np.zeros(n), False


#: Block pivots :func:`lcp_pivot` makes without fewer infeasible rows before it turns to
#: single ones (Judice and Pires' safeguard).
BLOCK_TRIES = 3

#: :func:`lcp_pivot` gives up after ``PIVOTS[0] n + PIVOTS[1]`` pivots on ``n`` rows (a
#: P-matrix's problem takes a few; none found is a status, not a hang).
PIVOTS = (50, 100)


def lcp_pivot(w: NDArray[np.float64], v: NDArray[np.float64],
              guess: NDArray[np.bool_]) -> tuple[NDArray[np.float64], bool]:
    """``(F, found)`` of :func:`lcp`'s problem for more unknowns than its enumeration takes
    (the pairs with a crack's faces, docs/faults.md): block principal pivoting from the
    active set ``guess``. Each pivot solves the active rows, then swaps every infeasible
    row (an active one pulling, an inactive one overlapping); where a block swap does not
    lower the count of infeasible rows :data:`BLOCK_TRIES` times running, it swaps the last
    infeasible row alone (Murty's rule, finite on a P-matrix). Twin of
    :func:`~spurdyn.solvers.sector.rows_compiled.lcp_pivot`."""
    n = v.size
    tol = 1e-12 * max(float(np.abs(v).max()) if n else 0.0, 1e-300)
    act = np.asarray(guess, bool).copy()
    best, tries = n + 1, BLOCK_TRIES
    for _ in range(PIVOTS[0] * n + PIVOTS[1]):
        f = np.zeros(n)
        idx = np.flatnonzero(act)
        if idx.size:
            f[idx] = np.linalg.solve(w[np.ix_(idx, idx)], -v[idx])
        bad = np.flatnonzero((act & (f < 0.0)) | (~act & (w @ f + v < -tol)))
        if not bad.size:
            return f, True
        if bad.size < best:
            best, tries = bad.size, BLOCK_TRIES
            act[bad] = ~act[bad]
        elif tries > 0:
            tries -= 1
            act[bad] = ~act[bad]
        else:
            act[bad[-1]] = ~act[bad[-1]]
    return np.zeros(n), False


__all__ = ["BLOCK_TRIES", "PIVOTS", "Rows", "lcp", "lcp_pivot"]
