"""Structured Q8 mesh of a gear sector: K consecutive teeth on their elastic rim.

Each tooth keeps the single-tooth mesh of :mod:`spurdyn.mesh.tooth` (so its flanks, contact
rows and spline points are the paper model's, node for node), and the rim beneath it is
meshed in one *cell* per tooth: the region of the gear between the two radial lines half
an angular pitch either side of the tooth's centre line, from the hub radius ``r_in`` up to
the cell's *top curve*. The top curve runs, left to right, along the root circle (the land,
if the fillets leave one), up the left fillet to the cut point where the tooth mesh starts,
along the tooth mesh's bottom curve, and down the right fillet and land again. In polar
coordinates ``(chi, r)`` (``chi`` clockwise from the tooth's centre line) that curve is a
graph ``r_top(chi)``, so the cell is meshed by radial columns: every node of the top curve
has a column of nodes straight beneath it, at radii ``r_in + (r_top - r_in) tau_j`` with the
row parameters ``tau_j`` graded geometrically, fine under the teeth and coarser towards the
hub. Neighbouring cells share their radial edges, and ``K = z`` closes the ring.

The nodes on ``r = r_in`` are the hub's: the rigid disk (with its inertia) is attached
there. Everything is in the gear's own frame, tooth 0 along +y, tooth ``k`` turned by
``k 2 pi / z`` clockwise (the sense in which a driving gear's right flanks lead).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.geometry.gear import DEFAULT_FILLET_CUT_ANGLE, Gear
from spurdyn.mesh.cracked import outline_ties
from spurdyn.mesh.cracked_cell import cracked_cell
from spurdyn.mesh.tooth import DEFAULT_GRADING, DEFAULT_NX, DEFAULT_NY, ToothMesh, tooth_mesh

#: Largest turn of the fillet's tangent over one element of a tooth space (rad).
MAX_TURN = math.radians(15.0)
#: Growth of the rim's row heights from the root towards the hub.
RIM_GROWTH = 1.3
#: Default depth of the elastic rim below the root circle of a solid blank, in whole depths
#: of the tooth (docs/sector.md, "Rim depth": the mesh stiffness changes by less than 1 %
#: beyond it).
DEFAULT_RIM_DEPTHS = 3.0
#: Thinnest rim above a web's junction the mesh takes (m): below it the rim's rows vanish.
RIM_THICKNESS_MIN = 1e-6


@dataclass(frozen=True)
class SectorMesh:
    """A Q8 mesh of ``K`` teeth on their rim, in the gear's frame.

    Attributes
    ----------
    nodes, elements
        ``(N, 2)`` coordinates (m) and ``(E, 8)`` Q8 connectivity (corners counter-clockwise,
        then mid-sides).
    width
        ``(E,)`` axial width of each element (m): the face width, or a web's.
    hub_nodes
        Nodes on the hub radius, tied to the rigid disk.
    teeth
        ``(K,)`` tooth numbers ``k`` (0 the middle one), tooth ``k`` turned by ``k 2 pi / z``.
    tooth_nodes
        ``(K, n)``: sector node of each node of the single-tooth mesh, per tooth.
    tooth
        The single-tooth mesh every tooth is a turned copy of.
    inner_radius
        The hub radius ``r_in`` (m).
    pitch_angle
        ``2 pi / z`` (rad).
    seams, seam_normals
        ``(S, 2)`` the node pairs of the cracks' two faces (face one, face two) and the unit
        normal from face one into face two's side at each, in the gear's frame (none
        without a crack).
    ties, tie_weights
        ``(T, 4)`` a cracked cell's nodes on its edges with the neighbouring cells that the
        neighbours' quadratic edges do not have, each with that edge's three nodes, and
        ``(T, 3)`` the edge's shape functions there: the node moves with the edge
        (``u = sum w u_edge``), so the cells stay joined.
    """

    nodes: NDArray[np.float64]
    elements: NDArray[np.intp]
    width: NDArray[np.float64]
    hub_nodes: NDArray[np.intp]
    teeth: NDArray[np.intp]
    tooth_nodes: NDArray[np.intp]
    tooth: ToothMesh
    inner_radius: float
    pitch_angle: float
    seams: NDArray[np.intp] = field(default_factory=lambda: np.zeros((0, 2), dtype=np.intp))
    seam_normals: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    ties: NDArray[np.intp] = field(default_factory=lambda: np.zeros((0, 4), dtype=np.intp))
    tie_weights: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def n_dof(self) -> int:
        return 2 * self.n_nodes

    def tooth_angle(self, k: int) -> float:
        """Clockwise angle (rad) by which tooth ``k`` is turned from tooth 0."""
        return float(k) * self.pitch_angle

    def tooth_dofs(self, k: int) -> NDArray[np.intp]:
        """Sector DOFs of tooth ``k``'s DOFs, in the single-tooth mesh's order."""
        i = int(np.flatnonzero(self.teeth == k)[0])
        n = self.tooth_nodes[i]
        return np.column_stack([2 * n, 2 * n + 1]).ravel()


def turn(xy: NDArray[np.float64], angle: float) -> NDArray[np.float64]:
    """Points ``(..., 2)`` turned clockwise by ``angle`` (rad): ``(r, chi) -> (r, chi + angle)``."""
    c, s = math.cos(angle), math.sin(angle)
    x, y = xy[..., 0], xy[..., 1]
    return np.stack([x * c + y * s, -x * s + y * c], axis=-1)


def default_inner_radius(gear: Gear) -> float:
    """Hub radius of a gear without one given: :data:`DEFAULT_RIM_DEPTHS` whole depths below
    the root circle, not below the bore, and not below a fifth of the root radius."""
    depth = DEFAULT_RIM_DEPTHS * (gear.tip_radius - gear.root_radius)
    bore = gear.blank.bore_radius if getattr(gear, "blank", None) is not None else 0.0
    return max(gear.root_radius - depth, bore, 0.2 * gear.root_radius)


def _chi(xy: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.arctan2(xy[..., 0], xy[..., 1])


def _fillet_start(gear: Gear, half_pitch: float) -> float:
    """Normal angle (from the root circle) at which the right fillet leaves the cell: 0 when
    it reaches the root circle inside it, else where it crosses the cell's edge (the two
    fillets of a tooth space meet above the root circle)."""
    from scipy.optimize import brentq

    def over(a: float) -> float:
        return float(_chi(gear.fillet_points(np.asarray(a)))) - half_pitch

    if over(0.0) <= 0.0:
        return 0.0
    return float(brentq(over, 0.0, DEFAULT_FILLET_CUT_ANGLE, xtol=1e-14))


def _space_side(gear: Gear, cut_angle: float, h: float) -> NDArray[np.float64]:
    """Points ``(chi, r)`` (with mid-sides) of the right half of a tooth space, from the tooth
    mesh's cut point on the fillet down the fillet and along the root land to the cell's edge
    at half a pitch: elements of about ``h``, evenly spaced in arc length, each point exactly
    on the fillet or the root circle."""
    half = math.pi / gear.teeth
    a0 = _fillet_start(gear, half)
    a = np.linspace(cut_angle, a0, 801)
    fil = gear.fillet_points(a)
    s_fil = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(fil, axis=0).T))])
    chi0 = float(_chi(fil[-1]))
    land = max(half - chi0, 0.0) * gear.root_radius
    # the fillet's elements at most h long and turning at most MAX_TURN each (the fillet
    # turns by cut_angle - a0); the land's at most h, or a short land joins the last one
    m_fil = max(math.ceil(s_fil[-1] / h - 0.25), math.ceil((cut_angle - a0) / MAX_TURN - 1e-9), 1)
    step = s_fil[-1] / m_fil
    m_land = max(1, math.ceil(land / h - 0.25)) if land > 0.5 * step else 0
    s = np.linspace(0.0, s_fil[-1], 2 * m_fil + 1)
    if m_land:
        s = np.concatenate([s, s_fil[-1] + np.linspace(0.0, land, 2 * m_land + 1)[1:]])
    else:
        s[-1] += land
    out = np.empty((s.size, 2))
    on_fillet = s <= s_fil[-1]
    pts = gear.fillet_points(np.interp(s[on_fillet], s_fil, a))
    out[on_fillet] = np.column_stack([_chi(pts), np.hypot(pts[:, 0], pts[:, 1])])
    out[~on_fillet, 0] = chi0 + (s[~on_fillet] - s_fil[-1]) / gear.root_radius
    out[~on_fillet, 1] = gear.root_radius
    out[-1, 0] = half                       # the cell's edge, whatever the round-off
    return out


def _top_curve(gear: Gear, tooth: ToothMesh, cut_angle: float, h: float) -> tuple[NDArray[np.float64], int]:
    """The cell's top curve as ``(2 m + 1, 2)`` points ``(chi, r)`` with mid-side points, left
    to right, and the index of its first node on the tooth's bottom curve."""
    right = _space_side(gear, cut_angle, h)          # cut point -> edge
    left = right[::-1] * np.array([-1.0, 1.0])       # edge -> cut point
    bottom = tooth.nodes[tooth.root_nodes]
    mid = np.column_stack([_chi(bottom), np.hypot(bottom[:, 0], bottom[:, 1])])
    return np.vstack([left[:-1], mid, right[1:]]), left.shape[0] - 1


def _rim_rows(depth: float, h: float) -> NDArray[np.float64]:
    """Row parameters ``tau`` (with mid-rows) from the hub (0) to the top curve (1): heights
    growing by :data:`RIM_GROWTH` from ``h`` at the top, scaled to fill ``depth``."""
    n = 1
    while h * (RIM_GROWTH**n - 1.0) / (RIM_GROWTH - 1.0) < depth:
        n += 1
    heights = RIM_GROWTH ** np.arange(n)
    corners = np.concatenate([[0.0], np.cumsum(heights)]) / heights.sum()   # from the top
    tau_c = (1.0 - corners)[::-1]                                         # hub -> top
    tau_c[0], tau_c[-1] = 0.0, 1.0
    tau = np.empty(2 * n + 1)
    tau[::2] = tau_c
    tau[1::2] = 0.5 * (tau_c[:-1] + tau_c[1:])
    return tau


@dataclass(frozen=True)
class _Cell:
    """What every cell of a gear is made of: its tooth, its rim's grid (node ``(i, j)``, i
    across left to right, j from the hub up) with coordinates and elements, which rim
    elements are web, the rim's top nodes under the tooth (``top_b``) and the hub radius."""

    tooth: ToothMesh
    index: NDArray[np.intp]
    rim_xy: NDArray[np.float64]
    rim_el: NDArray[np.intp]
    rim_is_web: NDArray[np.bool_]
    top_b: NDArray[np.intp]
    first_b: int
    r_in: float
    web_radius: float

    @property
    def hub_local(self) -> NDArray[np.intp]:
        return self.index[:, 0][self.index[:, 0] >= 0]


def _cell(gear: Gear, nx: int, ny: int, inner_radius: float | None, grading: float, cut_angle: float,
          web: tuple[float, float] | None) -> _Cell:
    """One cell's tooth and rim (:func:`sector_mesh`'s arguments)."""
    r_in = default_inner_radius(gear) if inner_radius is None else float(inner_radius)
    if not 0.0 < r_in < gear.root_radius - RIM_THICKNESS_MIN:
        raise InputError("model.rim_inner_radius", f"must lie between 0 and the root radius "
                         f"{gear.root_radius * 1e3:.4g} mm (got {r_in * 1e3:.4g} mm)")
    tooth = tooth_mesh(gear, nx, ny, cut_angle, grading)
    bottom = tooth.nodes[tooth.root_nodes]
    h = float(np.sum(np.hypot(*np.diff(bottom, axis=0).T))) / nx
    top, first_b = _top_curve(gear, tooth, cut_angle, h)
    if not np.all(np.diff(top[:, 0]) > 0.0):
        raise InputError("model", "the fillets turn back over themselves (an undercut tooth): "
                         "the sector model cannot mesh this gear's rim")
    # the rim's first row about as tall as the tooth's rows, so that the element size runs
    # on across the bottom curve
    h_row = (gear.tip_radius - gear.root_radius) / ny
    r, n_web = _rim_radii(gear, top[:, 1][:, None], r_in, h_row, web)
    index, rim_xy, rim_el, ncol = _rim_cell(top, r)
    rim_is_web = np.zeros(rim_el.shape[0], dtype=bool)
    rim_is_web[:n_web * ncol] = True
    # the rim's top nodes under the tooth are the tooth's bottom nodes
    top_b = index[first_b:first_b + 2 * nx + 1, -1]
    return _Cell(tooth, index, rim_xy, rim_el, rim_is_web, top_b, first_b, r_in,
                 float(web[0]) if web is not None else 0.0)


def _joined(cell: _Cell) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]:
    """The cell's tooth and rim as one mesh: ``(nodes, elements, each tooth node's number,
    each rim node's number)``, the rim's top under the tooth the tooth's bottom."""
    tooth = cell.tooth
    rmap = tooth.n_nodes + np.arange(cell.rim_xy.shape[0])
    rmap[cell.top_b] = tooth.root_nodes
    xy = np.vstack([tooth.nodes, cell.rim_xy])
    elements = np.vstack([tooth.elements, rmap[cell.rim_el]])
    used = np.unique(elements)
    new = -np.ones(xy.shape[0], dtype=np.intp)
    new[used] = np.arange(used.size)
    return xy[used], new[elements], new[np.arange(tooth.n_nodes)], new[rmap]


def cell_mesh(gear: Gear, nx: int = DEFAULT_NX, ny: int = DEFAULT_NY, inner_radius: float | None = None,
              grading: float = DEFAULT_GRADING, cut_angle: float = DEFAULT_FILLET_CUT_ANGLE,
              web: tuple[float, float] | None = None) -> ToothMesh:
    """Tooth 0's cell of :func:`sector_mesh` (its tooth on its stretch of rim, down to the
    hub) as one structured mesh in a :class:`ToothMesh`'s shape: ``root_nodes`` the hub's,
    each side the cell's radial edge from the hub, the rim's top curve to the tooth and the
    tooth's outline to the tip. The region a root crack may run in
    (:func:`spurdyn.mesh.cracked.crack_path`), and what a cracked cell is meshed from."""
    return _cell_tooth(_cell(gear, nx, ny, inner_radius, grading, cut_angle, web))


def sector_mesh(gear: Gear, teeth: int, nx: int = DEFAULT_NX, ny: int = DEFAULT_NY,
                inner_radius: float | None = None, grading: float = DEFAULT_GRADING,
                cut_angle: float = DEFAULT_FILLET_CUT_ANGLE, first: int | None = None,
                full_rim: bool = True, web: tuple[float, float] | None = None,
                missing: frozenset[int] = frozenset(), cracked: Mapping[int, Any] | None = None) -> SectorMesh:
    """Mesh ``teeth`` consecutive teeth of ``gear``, numbered from ``first`` (default: the
    middle one is 0), and their rim down to ``inner_radius`` (default
    :func:`default_inner_radius`). With ``full_rim`` the rim goes all the way round (the
    cells without a tooth end at the teeth's bottom curve, a free surface), so the sector has
    no cut ends; without it the rim stops half a pitch beyond the first and last teeth, at
    free radial faces. ``web = (rim_radius, web_width)`` makes the elements below
    ``rim_radius`` a web of that axial width (:attr:`SectorMesh.width`). All ``z`` teeth
    close the ring. The teeth of ``missing`` (body numbers) are broken off at their root
    section: their cells keep the rim, whose top under the tooth becomes free surface, and
    their rows of :attr:`SectorMesh.tooth_nodes` hold -1 for the nodes that went with them.
    ``cracked`` maps body teeth to their cracked meshes
    (:class:`spurdyn.mesh.cracked.CrackedTooth`), which take the structured tooth's place on
    its bottom row; their rows of ``tooth_nodes`` hold the structured nodes' places (-1 for
    those the cracked mesh has not), and their cracks' faces become :attr:`SectorMesh.seams`.

    Raises
    ------
    InputError
        If ``teeth`` is not from 1 to ``z``, the hub radius is not below the root circle,
        or an element would have a non-positive Jacobian.
    """
    z = gear.teeth
    if isinstance(teeth, bool) or not isinstance(teeth, (int, np.integer)) or not 1 <= teeth <= z:
        raise InputError("model.teeth", f"must be a whole number from 1 to the gear's {z} teeth "
                         f"(got {teeth!r})")
    cell = _cell(gear, nx, ny, inner_radius, grading, cut_angle, web)
    ks = np.arange(teeth) + (-((teeth - 1) // 2) if first is None else int(first))
    pitch = 2.0 * math.pi / z
    cells = ks if not full_rim or teeth == z else np.arange(int(ks[0]), int(ks[0]) + z)
    placed = _place_cells(cell, ks, cells, pitch, missing, cracked or {})
    xy, elements, hub, raw_teeth, is_web, seams, normals, ties, weights = placed
    # the cracks' faces lie on each other: kept apart
    nodes, elements, renum = _merge_nodes(xy, elements, 1e-9 * gear.tip_radius, seams.ravel())
    det = jacobian_determinants(nodes, elements)
    if not np.all(det > 0.0):
        bad = int(np.argmin(det.min(axis=1)))
        raise InputError("mesh", f"sector element {bad} has a non-positive Jacobian; "
                         "use a different nx x ny")
    width = np.where(is_web, float(web[1]) if web is not None else gear.face_width, gear.face_width)
    return SectorMesh(nodes=nodes, elements=elements, width=width, hub_nodes=np.unique(renum[hub]),
                      teeth=ks.astype(np.intp), tooth_nodes=np.where(raw_teeth >= 0, renum[raw_teeth], -1),
                      tooth=cell.tooth, inner_radius=cell.r_in, pitch_angle=pitch,
                      seams=renum[seams].reshape(-1, 2), seam_normals=normals,
                      ties=renum[ties].reshape(-1, 4), tie_weights=weights)


def _rim_radii(gear: Gear, r_top: NDArray[np.float64], r_in: float, h_row: float,
               web: tuple[float, float] | None) -> tuple[NDArray[np.float64], int]:
    """The radii of one cell's rim nodes, column ``i`` from its top radius ``r_top[i]`` down
    to the hub ``r_in`` (with a ``web``, the rim down to its radius, then the web), and the
    number of web rows."""
    if web is None:
        tau = _rim_rows(gear.root_radius - r_in, h_row)
        return r_in + (r_top - r_in) * tau[None, :], 0
    # the rim from the top curve down to the circle r_w, then the web to the hub
    r_w = float(web[0])
    if not r_in < r_w < gear.root_radius - RIM_THICKNESS_MIN:
        raise InputError("blank.rim_radius", f"must lie between the hub radius "
                         f"{r_in * 1e3:.4g} mm and the root radius {gear.root_radius * 1e3:.4g} mm")
    tau = _rim_rows(gear.root_radius - r_w, h_row)
    tau_web = _rim_rows(r_w - r_in, (gear.root_radius - r_w) * (tau[2] - tau[0]))
    r = np.hstack([np.broadcast_to(r_in + (r_w - r_in) * tau_web[None, :-1], (r_top.shape[0], tau_web.size - 1)),
                   r_w + (r_top - r_w) * tau[None, :]])
    return r, (tau_web.size - 1) // 2


def _rim_cell(top: NDArray[np.float64], r: NDArray[np.float64]) -> tuple[
        NDArray[np.intp], NDArray[np.float64], NDArray[np.intp], int]:
    """One cell's rim: the node number of grid point ``(i, j)`` (``-1`` at an element's
    middle), the nodes' coordinates, the Q8 elements and the elements a row."""
    ncol, nrow = (top.shape[0] - 1) // 2, (r.shape[1] - 1) // 2
    # rim grid of one cell: node (i, j), i across (left to right), j up (hub to top)
    chi = np.broadcast_to(top[:, 0][:, None], r.shape)
    index = -np.ones(chi.shape, dtype=np.intp)
    keep = ~((np.arange(chi.shape[0])[:, None] % 2 == 1) & (np.arange(r.shape[1])[None, :] % 2 == 1))
    index[keep] = np.arange(int(keep.sum()))
    rim_xy = np.stack([r[keep] * np.sin(chi[keep]), r[keep] * np.cos(chi[keep])], axis=-1)
    rim_el = np.empty((ncol * nrow, 8), dtype=np.intp)
    for ey in range(nrow):
        for ex in range(ncol):
            i, j = 2 * ex, 2 * ey
            rim_el[ey * ncol + ex] = [index[i, j], index[i + 2, j], index[i + 2, j + 2], index[i, j + 2],
                                      index[i + 1, j], index[i + 2, j + 1], index[i + 1, j + 2], index[i, j + 1]]
    return index, rim_xy, rim_el, ncol


def _place_cells(cell: _Cell, ks: NDArray[np.int64], cells: NDArray[np.int64], pitch: float,
                 missing: frozenset[int] = frozenset(), cracked: Mapping[int, Any] | None = None) -> tuple[
        NDArray[np.float64], NDArray[np.intp], NDArray[np.intp], NDArray[np.intp], NDArray[np.bool_],
        NDArray[np.intp], NDArray[np.float64], NDArray[np.intp], NDArray[np.float64]]:
    """Every cell turned to its place, a tooth on those of ``ks`` (its elements left out on
    those of ``missing``, a cracked cell's mesh on those of ``cracked``): ``(nodes,
    elements, hub nodes, each tooth's nodes (-1: none), web elements, seams, their
    normals, ties, their weights)``, the coincident nodes not yet merged."""
    parts: list[list[Any]] = [[], [], [], [], []]        # nodes, elements, hub, tooth, web
    seam_parts, normal_parts = [np.zeros((0, 2), dtype=np.intp)], [np.zeros((0, 2))]
    tie_parts, weight_parts = [np.zeros((0, 4), dtype=np.intp)], [np.zeros((0, 3))]
    count = 0
    for k in cells:
        ang = float(k) * pitch
        body = (cracked or {}).get(int(k)) if k in ks else None
        if body is not None:
            xy, el, hub, teeth, web = cracked_cell(body, _joined(cell)[2], cell.r_in, cell.web_radius, count)
            seam_parts.append(count + np.asarray(body.seam))
            normal_parts.append(turn(np.asarray(body.normal, dtype=float), ang))
            tied, parents, weights = outline_ties(_cell_tooth(cell), body)
            tie_parts.append(count + np.column_stack([tied, parents]))
            weight_parts.append(weights)
            if getattr(body, "ties", None) is not None:      # a chipped cell's split flank edge
                tie_parts.append(count + np.asarray(body.ties))
                weight_parts.append(np.asarray(body.tie_weights))
        else:
            xy, el, hub, teeth, web = _plain_cell(cell, count, k in ks, int(k) in missing)
        for part, item in zip(parts, (turn(xy, ang), el, hub, teeth, web)):
            if item is not None:
                part.append(item)
        count += xy.shape[0]
    return (np.vstack(parts[0]), np.vstack(parts[1]), np.concatenate(parts[2]), np.vstack(parts[3]),
            np.concatenate(parts[4]), np.vstack(seam_parts), np.vstack(normal_parts),
            np.vstack(tie_parts), np.vstack(weight_parts))


def _plain_cell(cell: _Cell, count: int, toothed: bool, missing: bool) -> tuple[Any, ...]:
    """A cell's nodes (in tooth 0's place), elements, hub nodes, tooth nodes (``None``
    without a tooth) and web flags, numbered from ``count``: tooth nodes first, then the
    rim's, its top-under-tooth nodes mapped onto the tooth's bottom."""
    tooth, n_rim = cell.tooth, cell.rim_xy.shape[0]
    if not toothed:
        rmap = count + np.arange(n_rim)
        return cell.rim_xy, rmap[cell.rim_el], rmap[cell.hub_local], None, cell.rim_is_web
    tmap = count + np.arange(tooth.n_nodes)
    rmap = count + tooth.n_nodes + np.arange(n_rim)
    rmap[cell.top_b] = tmap[tooth.root_nodes]
    xy = np.vstack([tooth.nodes, cell.rim_xy])
    if missing:
        return xy, rmap[cell.rim_el], rmap[cell.hub_local], tmap, cell.rim_is_web
    return (xy, np.vstack([tmap[tooth.elements], rmap[cell.rim_el]]), rmap[cell.hub_local], tmap,
            np.concatenate([np.zeros(tooth.n_elements, dtype=bool), cell.rim_is_web]))


def _cell_tooth(cell: _Cell) -> ToothMesh:
    """The structured cell as one mesh in a :class:`ToothMesh`'s shape (:func:`cell_mesh`)."""
    nodes, elements, t_in, r_in = _joined(cell)
    tooth, top, b = cell.tooth, cell.index[:, -1], cell.first_b
    right = np.concatenate([r_in[cell.index[-1, :]], r_in[top[-2:b + 2 * tooth.nx:-1]], t_in[tooth.right_side]])
    left = np.concatenate([r_in[cell.index[0, :]], r_in[top[1:b]], t_in[tooth.left_side]])
    return ToothMesh(nodes=nodes, elements=elements, root_nodes=r_in[cell.index[:, 0]], right_side=right,
                     left_side=left, tip_nodes=t_in[tooth.tip_nodes], nx=tooth.nx, ny=tooth.ny,
                     grading=tooth.grading)


def _merge_nodes(xy: NDArray[np.float64], elements: NDArray[np.intp], tol: float,
                 apart: NDArray[np.intp] | None = None) -> tuple[NDArray[np.float64], NDArray[np.intp],
                                                                 NDArray[np.intp]]:
    """Merge the nodes closer than ``tol`` (the duplicated tooth-bottom rows and the shared
    radial edges), those of ``apart`` (a crack's faces) excepted: ``(nodes, elements, new
    number of each old node)``."""
    used = np.unique(elements)
    if apart is not None and apart.size:
        used = np.setdiff1d(used, apart)
    tree = cKDTree(xy[used])
    rep = np.arange(xy.shape[0])
    for a, b in sorted(tree.query_pairs(tol)):
        ia, ib = used[a], used[b]
        lo, hi = min(rep[ia], rep[ib]), max(rep[ia], rep[ib])
        rep[rep == hi] = lo
    keep_nodes = np.unique(rep[np.unique(elements)])
    new = -np.ones(xy.shape[0], dtype=np.intp)
    new[keep_nodes] = np.arange(keep_nodes.size)
    renum = new[rep]
    return xy[keep_nodes], renum[elements], renum


__all__ = ["DEFAULT_RIM_DEPTHS", "RIM_GROWTH", "RIM_THICKNESS_MIN", "SectorMesh", "cell_mesh", "default_inner_radius", "sector_mesh",
           "turn"]
