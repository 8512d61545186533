"""A cracked cell in the sector mesh (docs/faults.md): a cell meshed again with its crack
(:func:`spurdyn.mesh.cracked.cracked_tooth` of :func:`spurdyn.mesh.sector.cell_mesh`) put in
the structured cell's place, its outline held to the structured quadratic edges' motion."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.mesh.outline import edge_point, outline_edges
from spurdyn.mesh.tooth import ToothMesh


def cracked_cell(body: Any, t_in: NDArray[np.intp], r_in: NDArray[np.intp], index: NDArray[np.intp],
                 hub_radius: float, web_radius: float, count: int) -> tuple[Any, ...]:
    """A cracked cell's nodes, elements, hub nodes, tooth nodes (the structured tooth's nodes'
    places, -1 where none) and web flags, numbered from ``count``; ``t_in``/``r_in`` the
    structured tooth's and rim's nodes in the structured cell, ``index`` the rim's grid."""
    where = np.asarray(body.structured)
    nodes = np.asarray(body.nodes, dtype=float)
    el = np.asarray(body.elements)
    teeth = where[t_in]
    centroid = np.hypot(*nodes[el[:, :4]].mean(axis=1).T)
    # every node on the hub circle is held, the mesher's between the structured ones too
    hub = np.flatnonzero(np.abs(np.hypot(*nodes.T) - hub_radius) <= 1e-9 * hub_radius)
    return (nodes, count + el, count + hub, np.where(teeth >= 0, count + np.maximum(teeth, 0), -1),
            centroid < web_radius)


def edge_ties(body: Any, structured: ToothMesh, scale: float) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """A cracked cell's nodes inside the ``structured`` cell's outline edges, each with its
    edge's nodes and the edge's shape functions there, in the cracked mesh's numbering: the
    outline keeps the structured quadratic edges' motion (the radial sides stay joined to the
    neighbouring cells, a flank takes its contact's load as the structured flank does), but
    for the edge the crack's mouth splits and its neighbours, which move freely. ``scale``:
    a length of the cell, for the tolerance."""
    where = np.asarray(body.structured)
    nodes = np.asarray(body.nodes, dtype=float)
    edges = where[outline_edges(structured)]
    split = np.flatnonzero(edges[:, 1] < 0)
    free = set() if not split.size else {(int(split[0]) + d) % edges.shape[0] for d in (-1, 0, 1)}
    ties, weights = [np.zeros((0, 4), dtype=np.intp)], [np.zeros((0, 3))]
    tol = 1e-9 * scale
    for e, (a, m, b) in enumerate(edges):
        if e in free:
            continue
        xyz = nodes[[a, m, b]]
        d = xyz[2] - xyz[0]
        near = np.flatnonzero(np.hypot(*(nodes - 0.5 * (xyz[0] + xyz[2])).T) < 0.75 * np.hypot(*d) + tol)
        near = near[(near != a) & (near != m) & (near != b)]
        xi = edge_parameter(xyz, nodes[near])
        on = (np.abs(xi) < 1.0) & (np.hypot(*(edge_point(xyz, xi) - nodes[near]).T) <= tol)
        x = xi[on]
        ties.append(np.column_stack([near[on], np.tile([a, m, b], (x.size, 1))]))
        weights.append(np.column_stack([0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)]))
    return np.vstack(ties).astype(np.intp), np.vstack(weights)


def edge_parameter(xyz: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The parameter ``xi`` of the quadratic edge ``xyz`` (corner, mid-side, corner at -1, 0,
    1) nearest each point: Newton's steps from the chord's projection."""
    d = xyz[2] - xyz[0]
    xi = 2.0 * ((points - xyz[0]) @ d) / (d @ d) - 1.0
    for _ in range(8):
        x = edge_point(xyz, xi)
        dx = (xi - 0.5)[:, None] * xyz[0] - 2.0 * xi[:, None] * xyz[1] + (xi + 0.5)[:, None] * xyz[2]
        xi = xi - np.sum((x - points) * dx, axis=1) / np.maximum(np.sum(dx * dx, axis=1), 1e-300)
    return xi


__all__ = ["cracked_cell", "edge_parameter", "edge_ties"]
