"""A root crack's tip in the loaded sector: K_I and K_II over the positions of a mesh cycle
(docs/fracture.md, section 8).

The crack sits on body tooth 0 of one gear of the sector statics (:mod:`spurdyn.sector.statics`:
pair 0 is that tooth at the driver's roll ``rho`` of the cycle), in its cell meshed again
with the crack (:func:`spurdyn.mesh.cracked.cracked_tooth` of the cell,
:func:`spurdyn.sector.body.body_cell`), the crack's faces in unilateral contact. At each
position the contact problem of both sectors is solved (the pairs' forces and the faces'),
the cracked body's displacements follow (:func:`~spurdyn.sector.statics.position_displacements`),
and the interaction integral reads K at the tip (:func:`spurdyn.fracture.stress_intensity`).
The other gear's body is healthy and built once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fracture.direction import driving_k
from spurdyn.fracture.integral import DEFAULT_RINGS, stress_intensity
from spurdyn.geometry.pair import GearPair
from spurdyn.mesh.cracked import RETRY_SHARES, CrackedTooth, cracked_tooth, default_size
from spurdyn.mesh.tooth import ToothMesh
from spurdyn.sector.body import SectorBody, body_cell, sector_body
from spurdyn.sector.statics import (
    ContactLaw, contact_law, default_teeth, driving_pair, position_displacements, sector_bodies,
    sector_firsts,
)

__all__ = ["CrackedSector", "TipLoad", "cracked_sector", "load_rolls", "tip_loads"]

#: Positions of pair 0's stretch of the path the load is put at, evenly (the single
#: contact zone's two ends are added: the highest and lowest points of single contact).
DEFAULT_LOAD_POSITIONS = 7


@dataclass(frozen=True)
class CrackedSector:
    """What every crack of one gear's tooth shares: the pair, the healthy other body, the
    cell the crack runs in, the load.

    Attributes
    ----------
    pair
        The driving pair (driver as gear A).
    g
        The cracked gear in ``pair``: 0 the driver, 1 the driven gear.
    law
        The contact law on the healthy sectors (load, strips).
    healthy
        The two healthy sectors; the cracked gear's is replaced at each crack.
    cell
        Body tooth 0's cell (:func:`~spurdyn.sector.body.body_cell`): the region the crack
        may run in, in the gear's frame.
    teeth, nx, ny, grading
        The sectors' teeth per gear and tooth mesh.
    size
        The cracked cell's element size away from the tip (m).
    rolls
        The load positions: the driver's roll of pair 0 (rad).
    inner_radius
        The cracked gear's hub radius where one was asked (m; ``None``: the sector's default).
    """

    pair: GearPair
    g: int
    law: ContactLaw
    healthy: tuple[SectorBody, SectorBody]
    cell: ToothMesh
    teeth: int
    nx: int
    ny: int
    grading: float
    size: float
    rolls: NDArray[np.float64] = field(repr=False)
    inner_radius: float | None = None

    @property
    def gear(self) -> Any:
        return self.pair.gear_a if self.g == 0 else self.pair.gear_b


@dataclass(frozen=True)
class TipLoad:
    """K at the crack's tip at each load position.

    Attributes
    ----------
    roll
        ``(n,)`` the positions (driver's roll of pair 0, rad).
    k_i, k_ii
        ``(n,)`` K_I, K_II (Pa sqrt(m)): the mean of the domains of :data:`DEFAULT_RINGS`.
    k_eq
        ``(n,)`` the maximum tangential stress's equivalent factor (Pa sqrt(m)); 0 where the
        tip is pressed shut (K_I <= 0 and K_II = 0).
    force
        ``(n,)`` the normal force on the cracked tooth's flank (N).
    spread
        ``(n,)`` the largest difference between the domains' K_I or K_II over the mean
        ``|K|`` (the domains' agreement).
    closed_near_tip
        ``(n,)`` the face pairs carrying a contact force within the largest domain (the
        domain form leaves their traction out: 0 where it is exact).
    closed
        ``(n,)`` the face pairs carrying a contact force anywhere along the crack.
    radius
        The largest domain's radius (m).
    nodes
        The cracked sector's node count.
    """

    roll: NDArray[np.float64]
    k_i: NDArray[np.float64]
    k_ii: NDArray[np.float64]
    k_eq: NDArray[np.float64]
    force: NDArray[np.float64]
    spread: NDArray[np.float64]
    closed_near_tip: NDArray[np.intp]
    closed: NDArray[np.intp]
    radius: float
    nodes: int

    @property
    def worst(self) -> int:
        """The position of the largest K_eq."""
        return int(np.argmax(self.k_eq))


#: Just inside the single contact zone from its lower end ``end - p``, as a share of the
#: pitch: the driven tooth's highest point of single contact carries the whole load only
#: once the pair ahead has left the path.
INSIDE = 1e-6


def load_rolls(pair: GearPair, count: int = DEFAULT_LOAD_POSITIONS) -> NDArray[np.float64]:
    """Pair 0's stretch of the path, ``count`` even positions and the ends of the single
    contact zone ``[end - p, start + p]`` (driver's roll, rad), its lower end both as the
    last position of double contact and just inside (:data:`INSIDE`), sorted."""
    dp = driving_pair(pair)
    p = 2.0 * math.pi / dp.gear_a.teeth
    start, end = dp.start_roll_a, dp.end_roll_a
    rolls = np.concatenate([start + p * np.linspace(0.0, 1.0, count),
                            [end - p, end - p + INSIDE * p, start + p]])
    return np.unique(rolls[(rolls >= start - 1e-12) & (rolls <= start + p + 1e-12)])


def cracked_sector(pair: GearPair, torque: float, gear: str, nx: int, ny: int,
                   grading: float = 1.0, teeth: int | None = None,
                   positions: int = DEFAULT_LOAD_POSITIONS,
                   inner_radius: float | None = None) -> CrackedSector:
    """The sectors of ``pair`` under the driver's ``torque`` (N m) with a crack to come on
    ``gear``'s (``"a"`` or ``"b"``, the case's names) body tooth 0, its hub at
    ``inner_radius`` (m; default the sector's: :func:`spurdyn.sector.body.sector_body`)."""
    dp = driving_pair(pair)
    g = 0 if gear == pair.driver else 1
    k = default_teeth(dp) if teeth is None else int(teeth)
    radii = (inner_radius, None) if g == 0 else (None, inner_radius)
    healthy = sector_bodies(dp, k, nx, ny, inner_radius=radii, grading=grading)
    gear_ = dp.gear_a if g == 0 else dp.gear_b
    cell = body_cell(gear_, nx, ny, grading, inner_radius)
    return CrackedSector(pair=dp, g=g, law=contact_law(pair, torque, healthy), healthy=healthy,
                         cell=cell, teeth=k, nx=nx, ny=ny, grading=grading,
                         size=default_size(cell), rolls=load_rolls(pair, positions),
                         inner_radius=inner_radius)


def cracked_bodies(sector: CrackedSector, mesh: CrackedTooth) -> tuple[SectorBody, SectorBody]:
    """The two sectors with the cracked gear's body tooth 0 on ``mesh``."""
    first = sector_firsts(sector.pair, sector.teeth)[sector.g]
    body = sector_body(sector.gear, sector.teeth, sector.nx, sector.ny, first=first,
                       inner_radius=sector.inner_radius, grading=sector.grading, cracked={0: mesh})
    return (body, sector.healthy[1]) if sector.g == 0 else (sector.healthy[0], body)


def tip_node(body: SectorBody, tip: NDArray[np.float64]) -> int:
    """The sector's node at the crack's tip (body tooth 0 is unturned: the cell's frame)."""
    d = np.hypot(*(body.mesh.nodes - tip).T)
    node = int(np.argmin(d))
    if d[node] > 1e-9 * sector_radius(body):
        raise RuntimeError("the crack's tip is not a node of the sector")   # pragma: no cover
    return node


def sector_radius(body: SectorBody) -> float:
    return float(np.max(np.hypot(*body.mesh.nodes.T)))


def tip_loads(sector: CrackedSector, path: NDArray[np.float64], tip_size: float,
              rolls: NDArray[np.float64] | None = None) -> tuple[TipLoad, tuple[SectorBody, SectorBody], Any]:
    """K at the tip of the crack ``path`` (``(k, 2)``: mouth on the right fillet, kinks, tip;
    the gear's frame) at each load position; also the cracked sectors and the worst
    position's displacements of the cracked body.

    Raises
    ------
    InputError
        ``fault.size`` or ``fault.depth`` from the mesher (:func:`cracked_tooth`), ``rings``
        if the domains reach the outline (a tip too near it for the tip size).
    """
    mesh = _cracked_cell(sector, path, tip_size)
    bodies = cracked_bodies(sector, mesh)
    body = bodies[sector.g]
    tip = tip_node(body, path[-1])
    ahead = path[-1] - path[-2]
    rolls = sector.rolls if rolls is None else rolls
    rows, fields = [], []
    for rho in rolls:
        u_a, u_b, faces, js, pair_f = _solved(sector, float(rho), bodies)
        u = u_a if sector.g == 0 else u_b
        # the domains kept to the tip's width (a web's junction: docs/fracture.md, 8.7)
        tf = stress_intensity(body.mesh.nodes, body.mesh.elements, u, sector.gear.material, tip,
                              ahead, DEFAULT_RINGS, widths=body.mesh.width)
        lam = faces if faces.size else np.zeros(body.mesh.seams.shape[0])
        near = np.hypot(*(body.mesh.nodes[body.mesh.seams[:, 0]] - path[-1]).T) <= tf.radius[-1]
        k_i, k_ii = float(np.mean(tf.k_i)), float(np.mean(tf.k_ii))
        scale = max(math.hypot(k_i, k_ii), 1e-300)
        spread = max(float(np.ptp(tf.k_i)), float(np.ptp(tf.k_ii))) / scale
        k_eq = driving_k(k_i, k_ii)
        rows.append((float(rho), k_i, k_ii, k_eq, float(pair_f[0]) if js and js[0] == 0 else 0.0,
                     spread, int(np.count_nonzero(lam[near] > 0.0)), float(tf.radius[-1]),
                     int(np.count_nonzero(lam > 0.0))))
        fields.append(u)
    r = np.array(rows)
    load = TipLoad(roll=r[:, 0], k_i=r[:, 1], k_ii=r[:, 2], k_eq=r[:, 3], force=r[:, 4],
                   spread=r[:, 5], closed_near_tip=r[:, 6].astype(np.intp),
                   closed=r[:, 8].astype(np.intp), radius=float(r[0, 7]),
                   nodes=body.mesh.n_nodes)
    return load, bodies, fields[load.worst]


def _cracked_cell(sector: CrackedSector, path: NDArray[np.float64], tip_size: float) -> CrackedTooth:
    """The cell meshed with the crack ``path``, at the cell's size or, if the mesh is refused
    (``fault.size``: gmsh failed, or its elements do not follow the kinked crack), at
    :data:`~spurdyn.mesh.cracked.RETRY_SHARES` of it in turn; the last refusal raised."""
    for share in RETRY_SHARES:
        try:
            return cracked_tooth(sector.gear, sector.cell, path, tip_size=tip_size,
                                 size=max(share * sector.size, tip_size))
        except InputError as err:
            if err.field != "fault.size" or share == RETRY_SHARES[-1]:
                raise
    raise AssertionError("unreachable")                      # pragma: no cover


def _solved(sector: CrackedSector, rho: float, bodies: tuple[SectorBody, SectorBody]) -> tuple[Any, ...]:
    """:func:`position_displacements` at ``rho``: first with the crack's faces free, and
    again with their contact only if a face then passes through the other (an opening
    below 0); the face forces are the cracked body's (none when free)."""
    u_a, u_b, faces, js, pair_f = position_displacements(sector.law, rho, bodies=bodies, faces=False)
    u = u_a if sector.g == 0 else u_b
    if np.all(bodies[sector.g].openings(u) >= -1e-12 * max(float(np.max(np.abs(u))), 1e-300)):
        return u_a, u_b, np.zeros(0), js, pair_f
    u_a, u_b, faces, js, pair_f = position_displacements(sector.law, rho, bodies=bodies)
    # the healthy body has no faces: the face forces are the cracked body's
    return u_a, u_b, faces, js, pair_f


def check_gear(gear: str) -> str:
    """``gear`` if ``"a"`` or ``"b"``, else refused naming ``--gear``."""
    if gear not in ("a", "b"):
        raise InputError("--gear", f"must be a or b (got {gear!r})")
    return gear
