"""The outline of a structured tooth mesh as its Q8 elements draw it: quadratic edges.

Each boundary edge of a :class:`~spurdyn.mesh.tooth.ToothMesh` runs through three nodes,
corner ``a``, mid-side ``m``, corner ``b``, and the Q8 element draws it as the parabola

    x(xi) = m + xi (b - a) / 2 + xi^2 ((a + b) / 2 - m),      -1 <= xi <= 1,

through ``a`` (``xi = -1``), ``m`` (``xi = 0``) and ``b`` (``xi = 1``). A mesh whose boundary
edges are pieces ``[xi_0, xi_1]`` of these parabolas, with their mid-side nodes at
``x((xi_0 + xi_1) / 2)``, draws exactly the same curve (a linear change of parameter maps
a parabola onto itself), so it encloses the same area: the cracked tooth
(:mod:`spurdyn.mesh.cracked`) is built that way.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from spurdyn.mesh.tooth import ToothMesh

#: Points per quadratic edge when the outline is drawn as a polygon for the inside tests.
POLYGON_POINTS_PER_EDGE = 32


def outline_edges(tooth: ToothMesh) -> NDArray[np.intp]:
    """The structured outline's edges counter-clockwise, ``(n_edges, 3)`` node triples
    ``(a, m, b)``: the bottom curve left to right, the right outline root to tip, the tip
    circle right to left, the left outline tip to root.

    Parameters
    ----------
    tooth
        The structured tooth mesh.

    Returns
    -------
    NDArray
        Corner, mid-side and next corner of each edge; ``b`` of one edge is ``a`` of the next.
    """
    loop = np.concatenate([tooth.root_nodes[:-1], tooth.right_side[:-1],
                           tooth.tip_nodes[::-1][:-1], tooth.left_side[::-1][:-1]])
    corners = loop[0::2]
    return np.stack([corners, loop[1::2], np.roll(corners, -1)], axis=1)


def edge_point(xyz: NDArray[np.float64], xi: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Points ``x(xi)`` of one quadratic edge (module docstring).

    Parameters
    ----------
    xyz
        ``(3, 2)`` coordinates of ``a``, ``m``, ``b``.
    xi
        Edge parameters in ``[-1, 1]``, any shape.

    Returns
    -------
    NDArray
        Shape ``xi.shape + (2,)``.
    """
    a, m, b = xyz
    s = np.asarray(xi, dtype=float)[..., None]
    return m + s * 0.5 * (b - a) + s**2 * (0.5 * (a + b) - m)


def polygon(nodes: NDArray[np.float64], edges: NDArray[np.intp]) -> NDArray[np.float64]:
    """The outline drawn as a closed polygon, ``POLYGON_POINTS_PER_EDGE`` points per edge
    (the first point of each edge; the polygon closes on its first point)."""
    xi = np.linspace(-1.0, 1.0, POLYGON_POINTS_PER_EDGE + 1)[:-1]
    return np.concatenate([edge_point(nodes[e], xi) for e in edges])


def inside(poly: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether each of ``points`` ``(k, 2)`` lies inside the closed polygon ``poly``
    (even-odd rule: a ray toward +x crosses its edges an odd number of times)."""
    p0, p1 = poly, np.roll(poly, -1, axis=0)
    x, y = points[:, 0:1], points[:, 1:2]
    straddle = (p0[:, 1] > y) != (p1[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_cross = p0[:, 0] + (y - p0[:, 1]) * (p1[:, 0] - p0[:, 0]) / (p1[:, 1] - p0[:, 1])
    return (np.count_nonzero(straddle & (x < x_cross), axis=1) % 2) == 1


def crosses(poly: NDArray[np.float64], p: NDArray[np.float64], q: NDArray[np.float64]) -> bool:
    """Whether the segment ``p q`` crosses an edge of the closed polygon ``poly``."""
    a, b = poly, np.roll(poly, -1, axis=0)

    def orient(u: NDArray[np.float64], v: NDArray[np.float64], w: NDArray[np.float64]
               ) -> NDArray[np.float64]:
        return ((v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1])
                - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0]))

    d1, d2 = orient(a, b, p), orient(a, b, q)
    d3, d4 = orient(p, q, a), orient(p, q, b)
    return bool(np.any((d1 * d2 <= 0.0) & (d3 * d4 <= 0.0)))


def distance(poly: NDArray[np.float64], point: NDArray[np.float64]) -> float:
    """The least distance from ``point`` to the edges of the closed polygon ``poly``."""
    a, b = poly, np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - point).T)))


def locate(nodes: NDArray[np.float64], edges: NDArray[np.intp], point: NDArray[np.float64]
           ) -> tuple[int, float, float]:
    """The outline edge nearest ``point``, the parameter of its nearest point, the distance.

    Parameters
    ----------
    nodes, edges
        The structured mesh's nodes and :func:`outline_edges`.
    point
        ``(2,)`` a point near the outline.

    Returns
    -------
    edge, xi, distance
        The edge's row in ``edges``, ``xi`` in ``[-1, 1]``, and ``|x(xi) - point|`` (m).
    """
    return locate_many(nodes, edges, np.asarray(point, dtype=float)[None])[0]


#: Parameters of each edge sampled for the first guess of :func:`locate`.
_GUESS = np.linspace(-1.0, 1.0, 201)


def locate_many(nodes: NDArray[np.float64], edges: NDArray[np.intp], points: NDArray[np.float64]
                ) -> list[tuple[int, float, float]]:
    """:func:`locate` of each of ``points`` ``(m, 2)``, the edges sampled once: the nearest
    sample (a k-d tree) is the guess :func:`project` refines."""
    from scipy.spatial import cKDTree

    pts = np.stack([edge_point(nodes[e], _GUESS) for e in edges])      # (n_edges, 201, 2)
    _, near = cKDTree(pts.reshape(-1, 2)).query(points)
    out = []
    for p, n in zip(points, near):
        k, j = divmod(int(n), _GUESS.size)
        xyz = nodes[edges[k]]
        s = project(xyz, p, float(_GUESS[j]))
        out.append((int(k), s, float(np.hypot(*(edge_point(xyz, s) - p)))))
    return out


def project(xyz: NDArray[np.float64], point: NDArray[np.float64], xi: float) -> float:
    """The parameter in ``[-1, 1]`` of the point of one quadratic edge nearest ``point``,
    by Newton's method on ``(x(s) - p) . x'(s) = 0`` from ``xi`` (the edges are nearly
    straight, so a guess within the edge converges)."""
    a, m, b = xyz
    d2 = 2.0 * (0.5 * (a + b) - m)
    s = xi
    for _ in range(30):
        d1 = 0.5 * (b - a) + s * d2
        r = edge_point(xyz, s) - point
        step = float(r @ d1) / float(d1 @ d1 + r @ d2)
        s = min(max(s - step, -1.0), 1.0)
        if abs(step) < 1e-15:
            break
    return s
