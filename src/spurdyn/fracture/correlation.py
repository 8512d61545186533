"""Displacement correlation on quarter-point elements: the cross-check of the interaction
integral (docs/fracture.md, section 4).

Moving the mid-side nodes of the element edges that leave the tip to a quarter of their
length from it (Henshell & Shaw 1975, Barsoum 1976) makes the displacement along those edges
``a + b sqrt(r) + c r``, the near-tip field's ``sqrt(r)``. On the crack's faces, with ``b``
and ``c`` the quarter-point and far nodes of the face's edge of length ``L``, the faces'
relative displacement grows as ``[4 (u_b^+ - u_b^-) - (u_c^+ - u_c^-)] sqrt(r / L)``; the
Williams field's is ``(kappa + 1) / mu sqrt(r / (2 pi)) (K_II, K_I)`` along and across the
crack, so

    (K_II, K_I) = mu / (kappa + 1) sqrt(2 pi / L) [4 (u_b^+ - u_b^-) - (u_c^+ - u_c^-)]
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError
from spurdyn.fem.material import Material
from spurdyn.fracture.williams import kolosov

__all__ = ["displacement_correlation", "quarter_points"]

#: The corners of a Q8 element (rows) and its mid-sides after (column 0) and before (1) each.
_MIDSIDES = np.array([[4, 7], [5, 4], [6, 5], [7, 6]])
_NEXT = np.array([[1, 3], [2, 0], [3, 1], [0, 2]])


def quarter_points(nodes: ArrayLike, elements: ArrayLike, tip: int) -> NDArray[np.float64]:
    """The nodes with the mid-side node of every element edge leaving ``tip`` moved to a
    quarter of the edge from it (the edges are straight)."""
    out = np.array(nodes, dtype=float)
    el = np.asarray(elements)
    for row in el[np.any(el[:, :4] == tip, axis=1)]:
        corner = int(np.flatnonzero(row[:4] == tip)[0])
        for mid, other in zip(_MIDSIDES[corner], _NEXT[corner]):
            out[row[mid]] = 0.75 * out[tip] + 0.25 * out[row[other]]
    return out


def displacement_correlation(nodes: ArrayLike, u: ArrayLike, material: Material, tip: int,
                             ahead: ArrayLike, seam: ArrayLike, normal: ArrayLike
                             ) -> tuple[float, float]:
    """``(K_I, K_II)`` (Pa sqrt(m)) from the crack faces' displacements at the quarter-point
    and far nodes of the faces' edges at ``tip``.

    Parameters
    ----------
    nodes
        ``(N, 2)`` the quarter-point mesh's nodes (:func:`quarter_points`).
    u
        ``(2 N,)`` its displacements, interleaved.
    material, tip, ahead
        As for :func:`spurdyn.fracture.integral.stress_intensity`.
    seam
        ``(S, 2)`` the crack's twin nodes (one face, the other).
    normal
        ``(2,)`` the side of the crack the second face's nodes belong to.

    Raises
    ------
    InputError
        ``seam`` if the faces' nodes nearest the tip are not a quarter-point edge's.
    """
    nd = np.asarray(nodes, dtype=float)
    uu = np.asarray(u, dtype=float).reshape(-1, 2)
    pairs = np.asarray(seam)
    a = np.asarray(ahead, dtype=float) / np.hypot(*ahead)
    rot = np.array([[a[0], a[1]], [-a[1], a[0]]])
    distance = np.hypot(*(nd[pairs[:, 0]] - nd[tip]).T)
    b, c = pairs[np.argsort(distance)[:2]]
    length = float(np.hypot(*(nd[c[0]] - nd[tip])))
    if abs(np.hypot(*(nd[b[0]] - nd[tip])) / length - 0.25) > 1e-6:
        raise InputError("seam", "the crack faces' nodes nearest the tip are not at a quarter "
                         "of their edge: move them with quarter_points first")
    # the upper face (x2 > 0 in the tip's frame) less the lower one
    upper = 1.0 if np.dot(normal, rot[1]) > 0.0 else -1.0
    jump = upper * rot @ (4.0 * (uu[b[1]] - uu[b[0]]) - (uu[c[1]] - uu[c[0]]))
    mu, kappa = kolosov(material)
    scale = mu / (kappa + 1.0) * math.sqrt(2.0 * math.pi / length)
    return float(scale * jump[1]), float(scale * jump[0])
