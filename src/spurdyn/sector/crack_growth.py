"""A root crack grown through a gear's tooth or its rim under the tooth's worst load over a
mesh cycle (docs/fracture.md, section 8): :func:`spurdyn.fracture.growth.grow` on the
cracked sector of :mod:`spurdyn.sector.crack_tip`, the cell meshed again round each new tip.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fracture.growth import (Growth, GrowthStopped, Region, Step, TipState, cell_region, grow,
                                     junction_band, path_length)
from spurdyn.mesh import outline as ol
from spurdyn.mesh.cracked import crack_path
from spurdyn.sector.crack_tip import CrackedSector, TipLoad, tip_loads

__all__ = ["TIP_SHARE", "GrownCrack", "first_crack", "grow_crack", "initial_path", "sector_region"]

#: The element size at the tip, as a share of the increment (and of the first crack's
#: length, if shorter): the domains of 2 and 3 rings then lie within the last piece.
TIP_SHARE = 0.08


@dataclass(frozen=True)
class GrownCrack:
    """A grown crack and what was solved on the way: :attr:`growth`, each tip's K at every
    load position (:attr:`loads`), the last cracked sector and its worst displacements (for
    the pictures)."""

    growth: Growth
    loads: tuple[TipLoad, ...]
    bodies: Any
    displacement: NDArray[np.float64]
    tip_size: float
    increment: float


def sector_region(sector: CrackedSector) -> Region:
    """The cracked cell's region: the hub (or a web's junction) and the cuts to the
    neighbouring cells the rim's inner boundary."""
    gear = sector.gear
    blank = gear.blank
    inner = float(np.min(np.hypot(*sector.cell.nodes.T)))
    rim = blank.rim_radius if blank is not None and blank.webbed else None
    return cell_region(sector.cell, math.pi / gear.teeth, inner, rim)


def _fillet_normal(cell: Any, mouth: NDArray[np.float64]) -> float:
    """The angle (rad) below the line across the tooth of the fillet's inward normal at the
    mouth (the structured outline's quadratic edge there) of the tooth's ``cell``."""
    edges = ol.outline_edges(cell)
    k, xi, _ = ol.locate(cell.nodes, edges, mouth)
    xyz = cell.nodes[edges[k]]
    tangent = ol.edge_point(xyz, xi + 1e-6) - ol.edge_point(xyz, xi - 1e-6)
    inward = np.array([-tangent[1], tangent[0]])          # the outline runs counter-clockwise
    return math.atan2(-inward[1], -inward[0])


def first_crack(gear: Any, cell: Any, nx: int, ny: int, grading: float, length: float,
                start: float | None) -> NDArray[np.float64]:
    """The first crack in ``gear``'s tooth ``cell`` (:func:`spurdyn.sector.body.body_cell`):
    straight, ``length`` (m) from the right fillet's point of radius ``start`` (default ISO
    6336-3's 30 deg tangent point) along the fillet's inward normal. Needs the cell only,
    so the command checks ``--start`` and ``--length`` before building the sectors.

    Raises
    ------
    InputError
        ``--start`` off the fillet, ``--length`` leaving the cell.
    """
    from spurdyn.mesh.tooth import tooth_mesh

    tooth = tooth_mesh(gear, nx, ny, grading=grading)
    try:
        probe = crack_path(gear, tooth, "right", 1e-6, math.radians(45.0), start, region=cell)
        angle = _fillet_normal(cell, probe[0])
        return crack_path(gear, tooth, "right", length, angle, start, region=cell)
    except InputError as err:
        key = {"fault.start": "--start", "fault.depth": "--length"}.get(err.field, err.field)
        raise InputError(key, err.reason) from None


def initial_path(sector: CrackedSector, length: float, start: float | None) -> NDArray[np.float64]:
    """:func:`first_crack` in ``sector``'s cell."""
    return first_crack(sector.gear, sector.cell, sector.nx, sector.ny, sector.grading, length, start)


def grow_crack(sector: CrackedSector, length: float, increment: float, start: float | None = None,
               max_steps: int = 400, progress: Callable[[Step], None] | None = None) -> GrownCrack:
    """Grow the root crack of ``sector``'s gear from a straight ``length`` (m) by
    ``increment`` (m) until it breaks through the tooth or the rim."""
    path = initial_path(sector, length, start)
    tip_size = TIP_SHARE * min(increment, length)
    loads: list[TipLoad] = []
    last: list[Any] = [None, None]

    def evaluate(p: NDArray[np.float64]) -> TipState:
        try:
            load, bodies, u = tip_loads(sector, p, tip_size)
        except InputError as err:
            if loads:       # a later tip: the growth ends there, the path so far kept
                raise GrowthStopped(f"the tip at {path_length(p) * 1e3:.4g} mm could not be "
                                    f"solved ({err.field}: {err.reason})") from None
            raise InputError("--length", f"the first crack's tip cannot be solved ({err.field}: "
                             f"{err.reason}); give another --length or --mesh") from None
        loads.append(load)
        last[:] = [bodies, u]
        w = load.worst
        return TipState(float(load.k_i[w]), float(load.k_ii[w]), float(load.k_eq[w]),
                        float(load.roll[w]))

    region = sector_region(sector)
    band = junction_band(tip_size, sector.gear.root_radius - region.inner_radius)
    growth = grow(path, increment, evaluate, region, max_steps, progress, band)
    return GrownCrack(growth=growth, loads=tuple(loads), bodies=last[0], displacement=last[1],
                      tip_size=tip_size, increment=increment)
