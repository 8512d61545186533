"""A Q8 mesh of one tooth (or its whole cell) with its right tip corner chipped off.

The cut is a straight line from the right outline's point at radius ``r_a - height`` to the
tip circle's point ``width`` along the tip circle's arc from the right tip corner
(docs/faults.md, "A chipped tip"). The region is the structured outline's quadratic edges
(:mod:`spurdyn.mesh.outline`) below the cut and the cut itself, meshed by gmsh as the cracked
tooth is (:mod:`spurdyn.mesh.cracked`, the same element sizes, the same full-quad
recombination), but with no seam: every structured outline node below the cut keeps its
place; those above it are gone (:attr:`CrackedTooth.structured` -1 there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.mesh import outline as ol
from spurdyn.mesh.cracked import (CURVE_POINTS, RETRY_SHARES, SAME_PLACE, CrackedTooth, _onto_outline,
                                  _point_at_radius, counter_clockwise, default_size)
from spurdyn.mesh.gmsh_quads import GmshQuads, mesh_region
from spurdyn.mesh.tooth import ToothMesh

#: Edge parameters closer than this are one point of the outline (a cut on a node).
SAME_PARAMETER = 1e-9
#: Largest relative difference between the mesh's area and its outline's (the outline
#: sampled finely, :func:`_enclosed`): beyond it a node was put on the wrong side.
AREA_TOLERANCE = 1e-6


@dataclass(frozen=True)
class ChippedTooth(CrackedTooth):
    """A chipped tooth's mesh: a :class:`~spurdyn.mesh.cracked.CrackedTooth` with no seam,
    and ``stand_in``: its ``structured`` map with the right outline's nodes above the cut
    (gone) mapped to the node at the cut's flank end, which stands in for them where a
    contact's strip reaches past the cut (docs/faults.md, "A chipped tip"). The sector mesh's
    tooth rows hold ``stand_in``; ``structured`` keeps -1 there (the outline's ties).
    ``ties`` ``(T, 4)`` (node, three parents) and ``tie_weights`` ``(T, 3)``: the nodes
    gmsh put on the flank edge the cut splits, held to the quadratic through its lower
    corner, a middle node and the cut's node (as the structured edges' extra nodes are held
    to theirs, :func:`~spurdyn.mesh.cracked.outline_ties`)."""

    stand_in: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, dtype=np.intp))
    ties: NDArray[np.intp] = field(default_factory=lambda: np.zeros((0, 4), dtype=np.intp))
    tie_weights: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))


def chip_cut(tooth: ToothMesh, tip_radius: float, height: float, width: float) -> NDArray[np.float64]:
    """The cut's two ends ``(2, 2)``: on the right outline's quadratic edges at radius
    ``tip_radius - height``, and on the tip edges at the polar angle ``width / tip_radius``
    beyond the right tip corner's (toward the tooth's centre line).

    Raises
    ------
    InputError
        ``fault.height`` if the cut's radius is off the right outline's span,
        ``fault.width`` if the top land is not wider than ``width``.
    """
    right = tooth.nodes[tooth.side("right")]
    r = tip_radius - height
    radii = np.hypot(*right.T)
    if not (height > 0.0 and radii[0] < r < radii[-1]):
        raise InputError("fault.height", f"must put the cut on the flank: between 0 and "
                         f"{(tip_radius - radii[0]) * 1e3:.4g} mm (got {height * 1e3:.4g} mm)")
    flank = _point_at_radius(tooth, "right", r)
    corner = math.atan2(right[-1, 1], right[-1, 0])
    tip = tooth.nodes[tooth.tip_nodes]
    angles = np.arctan2(tip[:, 1], tip[:, 0])               # left to right: falling
    phi = corner + width / tip_radius
    if not (width > 0.0 and phi < angles[0]):
        raise InputError("fault.width", f"must lie within the top land, below "
                         f"{(angles[0] - corner) * tip_radius * 1e3:.4g} mm (got {width * 1e3:.4g} mm)")
    edges = ol.outline_edges(tooth)
    k, xi, _ = ol.locate(tooth.nodes, edges, tip_radius * np.array([math.cos(phi), math.sin(phi)]))
    from scipy.optimize import brentq

    xyz = tooth.nodes[edges[k]]

    def turn(s: float) -> float:
        p = ol.edge_point(xyz, s)
        return math.atan2(p[1], p[0]) - phi

    if turn(-1.0) * turn(1.0) <= 0.0:
        xi = brentq(turn, -1.0, 1.0, xtol=1e-15)
    return np.array([flank, ol.edge_point(xyz, xi)])


def _polygon(tooth: ToothMesh, cut: NDArray[np.float64] | None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The polygon gmsh meshes: every structured outline node below the cut, the cut's ends
    (with no cut, every structured outline node).

    Returns ``points`` ``(P, 2)`` counter-clockwise and ``sides`` ``(P, 3)``: each side's
    structured edge and its ends' parameters, or ``(-1, 0, 1)`` for the cut (a straight
    line from its first point to the next)."""
    nodes, edges = tooth.nodes, ol.outline_edges(tooth)
    if cut is None:             # no chip: the whole outline, meshed again (the reference)
        marks0 = [(e, x) for e in range(edges.shape[0]) for x in (-1.0, 0.0)]
        return (np.array([ol.edge_point(nodes[edges[e]], x) for e, x in marks0]),
                np.array([(e, x, 0.0 if x < 0.0 else 1.0) for e, x in marks0]))
    (kf, xf, df), (kt, xt, dt) = ol.locate_many(nodes, edges, cut)
    r_tip = float(np.max(np.hypot(*nodes.T)))
    if max(df, dt) > 1e-9 * r_tip or not kf < kt:
        raise InputError("fault.cut", "the cut's ends must lie on the right outline and then the tip "
                         "(chip_cut puts them there)")
    # an end on an edge's far corner is the next edge's near corner (no side of no length)
    kf, xf = (kf + 1, -1.0) if xf > 1.0 - SAME_PARAMETER else (kf, xf)
    kt, xt = (kt + 1, -1.0) if xt > 1.0 - SAME_PARAMETER else (kt, xt)
    marks: list[tuple[int, float]] = []        # (edge, parameter) of the polygon's points
    for e in range(edges.shape[0]):
        if e < kf or e > kt:
            marks += [(e, -1.0), (e, 0.0)]
        elif e == kf:
            marks += [(e, x) for x in (-1.0, 0.0) if x < xf - SAME_PARAMETER] + [(e, xf)]
        elif e == kt:
            marks += [(e, xt)] + [(e, 0.0)] * (xt < -SAME_PARAMETER)
    points = np.array([ol.edge_point(nodes[edges[e]], x) for e, x in marks])
    sides = []
    for i, (e, x) in enumerate(marks):
        e1, x1 = marks[(i + 1) % len(marks)]
        if e == kf and e1 == kt:
            sides.append((-1.0, 0.0, 1.0))
        else:
            sides.append((e, x, x1 if e1 == e else 1.0))
    return points, np.array(sides)


def _curves(tooth: ToothMesh, points: NDArray[np.float64], sides: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Each side as ``CURVE_POINTS`` points: its structured edge's parabola, or the cut's line."""
    edges = ol.outline_edges(tooth)
    s = np.linspace(0.0, 1.0, CURVE_POINTS)
    return [points[i] + s[:, None] * (points[(i + 1) % len(points)] - points[i]) if e < 0 else
            ol.edge_point(tooth.nodes[edges[int(e)]], np.linspace(x0, x1, CURVE_POINTS))
            for i, (e, x0, x1) in enumerate(sides)]


def _onto_cut(nodes: NDArray[np.float64], inner: NDArray[np.intp], p: NDArray[np.float64],
              q: NDArray[np.float64]) -> None:
    """Put gmsh's nodes ``inner`` of the cut ``p q`` on the line, each mid-side node halfway
    between its corners (in place)."""
    d = q - p
    u = (nodes[inner] - p) @ d / float(d @ d)
    order = np.argsort(u)
    u = np.concatenate([[0.0], u[order], [1.0]])
    u[1::2] = 0.5 * (u[:-1:2] + u[2::2])
    nodes[inner[order]] = p + u[1:-1, None] * d


def _mesh(tooth: ToothMesh, points: NDArray[np.float64], sides: NDArray[np.float64],
          size: float) -> tuple[GmshQuads, NDArray[np.float64], NDArray[np.intp]]:
    """gmsh's mesh of the polygon at ``size`` put on the outline (:func:`_placed`), or at a
    smaller share of it if gmsh's full-quad recombination refuses or the placed mesh is bad
    (as :func:`spurdyn.mesh.cracked._mesh`); the last refusal raised."""
    curves = _curves(tooth, points, sides)
    enclosed = _enclosed(tooth, points, sides)
    for i, share in enumerate(RETRY_SHARES):
        try:
            quads = mesh_region(curves, share * size, "fault.size")
            nodes, elements = _placed(tooth, quads, points, sides, enclosed)
            return quads, nodes, elements
        except InputError:
            if i == len(RETRY_SHARES) - 1:
                raise
    raise AssertionError("unreachable")


def _enclosed(tooth: ToothMesh, points: NDArray[np.float64], sides: NDArray[np.float64],
              per_side: int = 400) -> float:
    """The polygon's area (m^2) on its parabolas and the cut: the shoelace formula on
    ``per_side`` points of each side."""
    edges = ol.outline_edges(tooth)
    ring = np.concatenate([points[i][None] if e < 0 else
                           ol.edge_point(tooth.nodes[edges[int(e)]], np.linspace(x0, x1, per_side + 1)[:-1])
                           for i, (e, x0, x1) in enumerate(sides)])
    x, y = ring.T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _placed(tooth: ToothMesh, quads: GmshQuads, points: NDArray[np.float64], sides: NDArray[np.float64],
            enclosed: float) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """gmsh's nodes put on the outline's parabolas and the cut, the elements counter-clockwise;
    ``fault.size`` if a Jacobian is not positive or the mesh's area is not the polygon's
    ``enclosed`` (a node gmsh gave the wrong side would fold the mesh over)."""
    structured = sides[:, 0] >= 0
    nodes = _onto_outline(replace(quads, sides=tuple(s for s, k in zip(quads.sides, structured) if k)),
                          tooth, points, sides[structured])
    for line in np.flatnonzero(~structured):
        _onto_cut(nodes, quads.sides[line], points[line], points[(line + 1) % len(points)])
    elements = counter_clockwise(nodes, quads.elements)
    det = jacobian_determinants(nodes, elements)
    from spurdyn.fem.element import gauss_2d

    if not np.all(det > 0.0) or abs(float((det * gauss_2d(3)[1]).sum()) / enclosed - 1.0) > AREA_TOLERANCE:
        raise InputError("fault.size", "the chipped mesh has a non-positive Jacobian or does not fill its "
                         "outline; try another element size")
    return nodes, elements


def chipped_tooth(tooth: ToothMesh, cut: NDArray[np.float64] | None, size: float | None = None) -> ChippedTooth:
    """Mesh ``tooth``'s outline again with its right tip corner cut off along ``cut``
    (:func:`chip_cut`): a :class:`ChippedTooth`, no seam (``tip`` -1), its ``structured``
    map -1 at the structured nodes the chip took (and inside).
    ``cut`` ``None`` meshes the whole outline so: the chip of no size, the reference a
    chip's own effect is measured from (the finer mesh alone softens the cell).

    Raises
    ------
    InputError
        ``fault.size`` for a size out of range or a mesh gmsh could not make of quads with
        positive Jacobians.
    """
    points, sides = _polygon(tooth, None if cut is None else np.asarray(cut, dtype=float))
    size = default_size(tooth) if size is None else float(size)
    if not size > 0.0:
        raise InputError("fault.size", f"must be above 0 (got {size!r})")
    quads, nodes, elements = _mesh(tooth, points, sides, size)
    structured_map = _structured_map(tooth, nodes, points)
    stand_in = structured_map.copy()
    ties, weights = np.zeros((0, 4), dtype=np.intp), np.zeros((0, 3))
    if cut is not None:
        right = tooth.side("right")
        corner = int(np.argmin(np.hypot(*(nodes - np.asarray(cut, dtype=float)[0]).T)))
        stand_in[right[structured_map[right] < 0]] = corner
        ties, weights = _split_ties(tooth, nodes, quads, points, sides)
    return ChippedTooth(nodes=nodes, elements=elements, structured=structured_map,
                        seam=np.zeros((0, 2), dtype=np.intp), normal=np.zeros((0, 2)), tip=-1,
                        stand_in=stand_in, ties=ties, tie_weights=weights)


def _split_ties(tooth: ToothMesh, nodes: NDArray[np.float64], quads: GmshQuads, points: NDArray[np.float64],
                sides: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """The ties of the split flank edge's nodes (:class:`ChippedTooth`): each node gmsh put
    on the edge's kept piece ``[-1, xi_cut]`` as the quadratic (Lagrange) interpolation in
    the edge's parameter through the lower corner, the middle (the structured mid-side
    node if kept, else gmsh's node nearest the piece's middle) and the cut's node."""
    from scipy.spatial import cKDTree

    line = int(np.flatnonzero(sides[:, 0] < 0)[0])
    k = int(sides[line - 1, 0])
    mine = [i for i in range(len(sides)) if int(sides[i, 0]) == k]
    xyz = tooth.nodes[ol.outline_edges(tooth)[k]]
    at = cKDTree(nodes).query(points[mine + [line]])[1]          # the pieces' ends, the cut's node
    inner = np.concatenate([quads.sides[i] for i in mine] + [at[1:-1]]).astype(np.intp)
    xi = np.array([ol.project(xyz, nodes[n], 0.0) for n in inner])
    s_cut = float(sides[line - 1, 2])
    if len(mine) > 1:
        middle, s_mid = int(at[1]), 0.0
    else:
        j = int(np.argmin(np.abs(xi - 0.5 * (s_cut - 1.0))))
        middle, s_mid = int(inner[j]), float(xi[j])
    keep = inner != middle
    inner, xi = inner[keep], xi[keep]
    knots = np.array([-1.0, s_mid, s_cut])
    w = np.stack([np.prod([(xi - knots[b]) / (knots[a] - knots[b]) for b in range(3) if b != a], axis=0)
                  for a in range(3)], axis=1)
    parents = np.tile([int(at[0]), middle, int(at[-1])], (inner.size, 1))
    return np.column_stack([inner, parents]).astype(np.intp), w


def _structured_map(tooth: ToothMesh, nodes: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.intp]:
    """For each structured node the node at the same place, -1 if none; checks that every
    structured outline node among the polygon's points maps."""
    from scipy.spatial import cKDTree

    tol = SAME_PLACE * float(np.max(np.hypot(*tooth.nodes.T)))
    dist, near = cKDTree(nodes).query(tooth.nodes)
    out = np.where(dist <= tol, near, -1).astype(np.intp)
    kept = cKDTree(points).query(tooth.nodes)[0] <= tol
    if np.any(out[kept] < 0):
        raise RuntimeError("an outline node of the structured mesh below the cut was lost")
    return out


def chip_area(tooth: ToothMesh, cut: NDArray[np.float64], per_edge: int = 4000) -> float:
    """The area the chip takes from ``tooth``'s structured outline (m^2): the region between
    the cut and the outline's quadratic edges above it, by the shoelace formula on
    ``per_edge`` points an edge (for checks)."""
    points, sides = _polygon(tooth, cut)
    edges = ol.outline_edges(tooth)
    line = int(np.flatnonzero(sides[:, 0] < 0)[0])
    (kf, xf), (kt, xt) = sides[line - 1, 0::2].astype(float), sides[line + 1, :2]
    pieces = [ol.edge_point(tooth.nodes[edges[int(kf)]], np.linspace(xf, 1.0, per_edge))]
    pieces += [ol.edge_point(tooth.nodes[edges[e]], np.linspace(-1.0, 1.0, per_edge))
               for e in range(int(kf) + 1, int(kt))]
    pieces += [ol.edge_point(tooth.nodes[edges[int(kt)]], np.linspace(-1.0, xt, per_edge))]
    ring = np.concatenate(pieces)
    x, y = ring.T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


__all__ = ["ChippedTooth", "chip_area", "chip_cut", "chipped_tooth"]
