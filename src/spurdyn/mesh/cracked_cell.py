"""A cracked cell in the sector mesh (docs/faults.md): a cell meshed again with its crack
(:func:`spurdyn.mesh.cracked.cracked_tooth` of :func:`spurdyn.mesh.sector.cell_mesh`) put in
the structured cell's place, its outline held to the structured quadratic edges' motion
(:func:`spurdyn.mesh.cracked.outline_ties`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray



def cracked_cell(body: Any, t_in: NDArray[np.intp], hub_radius: float, web_radius: float,
                 count: int) -> tuple[Any, ...]:
    """A cracked cell's nodes, elements, hub nodes, tooth nodes (the structured tooth's nodes'
    places, -1 where none) and web flags, numbered from ``count``; ``t_in`` the structured
    tooth's nodes in the structured cell."""
    # a chipped cell's flank nodes above its cut have the cut's node standing in for them
    where = np.asarray(getattr(body, "stand_in", body.structured))
    nodes = np.asarray(body.nodes, dtype=float)
    el = np.asarray(body.elements)
    teeth = where[t_in]
    centroid = np.hypot(*nodes[el[:, :4]].mean(axis=1).T)
    # every node on the hub circle is held, the mesher's between the structured ones too
    hub = np.flatnonzero(np.abs(np.hypot(*nodes.T) - hub_radius) <= 1e-9 * hub_radius)
    return (nodes, count + el, count + hub, np.where(teeth >= 0, count + np.maximum(teeth, 0), -1),
            centroid < web_radius)


__all__ = ["cracked_cell"]
