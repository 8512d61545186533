"""Structured Q8 mesh of one gear tooth, from the root to the tip.

The tooth is the region bounded by the two tooth outlines (involute over trochoidal
fillet), the tip circle, and at the bottom a curve that follows the root circle under
the tooth and rises to meet the fillets where their generating normal is ``cut_angle``
away from the root circle's (measured in the rack cutter's frame; 45 deg puts the cut of
the paper's gear at 40.99 mm, where the fillet climbs at 50 deg to the circle).
``docs/geometry.md`` explains why the fillets are cut: a fillet meets the root circle
tangentially, which would leave a degenerate 180-degree element corner.
The crescent beneath that curve belongs to the rigid disk.

Nodes are placed by transfinite (Coons) interpolation of the four boundary curves on a
``(2 nx + 1) x (2 ny + 1)`` grid, so every boundary node lies exactly on its curve. Rows
along the tooth are spaced evenly in radius on the outline (on a tip-relieved flank, in
the radius of the unmodified involute point the relieved one is taken from). Columns
across the tooth are even, or graded toward both outlines (:func:`thickness_spacing`),
so that the elements under a contact strip or along a fillet are thin.

Rows can be graded too (``mesh.row_grading`` G, :func:`row_radii`): with G above 1 the
outline is split at the form radius into two stretches, the fillet (cut point to form
radius, length ``L_f`` in radius) and the active flank (form radius to the tip, ``L_a``),
each with rows even in radius; the fillet gets ``n_f = round(ny L_f / (L_f + G L_a))`` of
the ``ny`` rows (at least 1, at most ``ny - 1``) and the flank the rest, so a fillet row is
about G times as tall as a flank row. Why: the Hertzian strip (``contact = "hertz"``) is
resolved once the elements under it are about as small as its half-width, along the flank
as well as across it; column grading thins them across, and only shorter rows where the
contact runs shorten them along, without adding rows. G = 1 (the default) is the even mesh
above, bit for bit. The flank coordinate stays linear in radius over the flank's rows, which
is all the contact search reads: :func:`spurdyn.model.flank.make_flank` continues that law
down to a virtual ``r0``. docs/geometry.md, section 6.3, has the rule and its measurements.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.geometry.gear import DEFAULT_FILLET_CUT_ANGLE, Gear

#: Default density: elements across and along the tooth. Stable under RK4 at the
#: paper's step of 3e-8 s (see ``spurdyn info paper``); finer meshes need smaller steps.
DEFAULT_NX, DEFAULT_NY = 4, 14
#: Default grading across the tooth: even columns (the paper's mesh).
DEFAULT_GRADING = 1.0
#: Largest grading: the surface elements ``MAX_GRADING`` times thinner than the middle ones.
MAX_GRADING = 50.0
#: Default row grading: rows even in radius from the cut to the tip (the paper's mesh).
DEFAULT_ROW_GRADING = 1.0
#: Largest row grading (the fillet gets at least one row whatever it is).
MAX_ROW_GRADING = 1000.0


@dataclass(frozen=True)
class ToothMesh:
    """A Q8 mesh of one tooth in the gear's own frame (tooth centre line along +y).

    Attributes
    ----------
    nodes
        ``(N, 2)`` node coordinates (m).
    elements
        ``(E, 8)`` node indices, corners counter-clockwise then mid-sides.
    root_nodes
        Nodes on the bottom curve, tied to the rigid disk, left to right.
    right_side, left_side
        Nodes on each outline (fillet then involute), ordered root to tip. The right
        outline lies at ``x > 0``.
    tip_nodes
        Nodes on the tip circle, left to right.
    nx, ny
        Elements across and along the tooth.
    grading
        Ratio of the middle columns' width to the outline columns' (1: even), see
        :func:`thickness_spacing`.
    row_grading, fillet_rows
        Ratio of a fillet row's height (in radius) to a flank row's, and the rows below
        the form radius (0: rows even in radius over the whole outline), see
        :func:`row_radii`.
    """

    nodes: NDArray[np.float64]
    elements: NDArray[np.intp]
    root_nodes: NDArray[np.intp]
    right_side: NDArray[np.intp]
    left_side: NDArray[np.intp]
    tip_nodes: NDArray[np.intp]
    nx: int
    ny: int
    grading: float = DEFAULT_GRADING
    row_grading: float = DEFAULT_ROW_GRADING
    fillet_rows: int = 0

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.elements.shape[0])

    @property
    def n_dof(self) -> int:
        return 2 * self.n_nodes

    def side(self, which: str) -> NDArray[np.intp]:
        """Outline nodes root to tip; ``which`` is ``"right"`` or ``"left"``."""
        return self.right_side if which == "right" else self.left_side

    def side_elements(self, which: str) -> NDArray[np.intp]:
        """Elements along an outline, root to tip (one per row of the mesh)."""
        col = self.nx - 1 if which == "right" else 0
        return np.arange(self.ny) * self.nx + col


def _grid_index(nx: int, ny: int) -> NDArray[np.intp]:
    """Node number of each grid point ``(i, j)``; -1 at element centres (no node)."""
    ni, nj = 2 * nx + 1, 2 * ny + 1
    index = -np.ones((ni, nj), dtype=np.intp)
    count = 0
    for j in range(nj):
        for i in range(ni):
            if i % 2 == 1 and j % 2 == 1:
                continue
            index[i, j] = count
            count += 1
    return index


def thickness_spacing(nx: int, grading: float = DEFAULT_GRADING) -> NDArray[np.float64]:
    """Parameters ``0 = s_0 < ... < s_2nx = 1`` of the grid's columns across the tooth.

    The corners sit at ``s = xi - a sin(2 pi xi) / (2 pi)`` for ``xi = k / nx``, with
    ``a = (G - 1) / (G + 1)``: the map's slope is ``1 - a`` at both outlines and ``1 + a``
    in the middle, so the middle columns are ``G`` (``grading``) times as wide as those
    at the outlines (in the limit of many columns; for ``G = 1`` the columns are even).
    The map is symmetric, so both flanks are graded alike. Each mid-side node sits at the
    mean parameter of its corners, which keeps it in the middle of its edge.
    """
    if grading == DEFAULT_GRADING:
        return np.linspace(0.0, 1.0, 2 * nx + 1)    # the even grid, bit for bit as before
    a = (grading - 1.0) / (grading + 1.0)
    xi = np.linspace(0.0, 1.0, nx + 1)
    corners = xi - a * np.sin(2.0 * np.pi * xi) / (2.0 * np.pi)
    corners[0], corners[-1] = 0.0, 1.0      # exact ends whatever the round-off
    s = np.empty(2 * nx + 1)
    s[::2] = corners
    s[1::2] = 0.5 * (corners[:-1] + corners[1:])
    return s


def row_radii(r_cut: float, r_form: float, r_end: float, ny: int,
              row_grading: float = DEFAULT_ROW_GRADING) -> tuple[NDArray[np.float64], int]:
    """Radii of the ``2 ny + 1`` outline grid points, root to tip, and the fillet's rows.

    For ``row_grading`` 1 the rows are even in radius from ``r_cut`` to ``r_end`` (the
    paper's mesh, bit for bit) and the fillet row count returned is 0. Otherwise the fillet
    ``[r_cut, r_form]`` gets ``n_f = round(ny L_f / (L_f + G L_a))`` rows (at least 1, at
    most ``ny - 1``), ``L_f = r_form - r_cut``, ``L_a = r_end - r_form``, ``G`` the row
    grading, and the flank ``[r_form, r_end]`` the other ``ny - n_f``; each stretch's rows
    are even in radius (so a fillet row is about ``G`` times as tall as a flank row), and
    each mid-side point sits at the mean radius of its corners.
    """
    if row_grading == DEFAULT_ROW_GRADING or ny < 2 or not r_cut < r_form < r_end:
        return r_cut + np.linspace(0.0, 1.0, 2 * ny + 1) * (r_end - r_cut), 0
    l_f, l_a = r_form - r_cut, r_end - r_form
    n_f = int(min(max(round(ny * l_f / (l_f + row_grading * l_a)), 1), ny - 1))
    corners = np.concatenate([np.linspace(r_cut, r_form, n_f + 1)[:-1],
                              np.linspace(r_form, r_end, ny - n_f + 1)])
    r = np.empty(2 * ny + 1)
    r[::2] = corners
    r[1::2] = 0.5 * (corners[:-1] + corners[1:])
    return r, n_f


def _polar(r: NDArray[np.float64], chi: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.stack([r * np.sin(chi), r * np.cos(chi)], axis=-1)


def _check_mesh_args(gear: Gear, nx: int, ny: int, cut_angle: float, grading: float,
                     row_grading: float) -> None:
    """Refuse a mesh density, grading or fillet cut angle out of range, naming its key.

    Parameters
    ----------
    gear
        The gear meshed (its fillet end angle bounds ``cut_angle``).
    nx, ny, cut_angle, grading, row_grading
        As :func:`tooth_mesh` takes them.

    Raises
    ------
    InputError
        For the first value out of range, in the order of the parameters.
    """
    for name, n, lo, hi in (("mesh.nx", nx, 1, 64), ("mesh.ny", ny, 2, 256)):
        if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or not lo <= n <= hi:
            raise InputError(name, f"must be a whole number from {lo} to {hi} (got {n!r})")
    if (isinstance(grading, bool) or not isinstance(grading, (int, float, np.floating))
            or not DEFAULT_GRADING <= grading <= MAX_GRADING):
        raise InputError("mesh.grading", f"must be a number from 1 (even) to {MAX_GRADING:g} "
                         f"(got {grading!r})")
    if (isinstance(row_grading, bool) or not isinstance(row_grading, (int, float, np.floating))
            or not DEFAULT_ROW_GRADING <= row_grading <= MAX_ROW_GRADING):
        raise InputError("mesh.row_grading", f"must be a number from 1 (even rows) to "
                         f"{MAX_ROW_GRADING:g} (got {row_grading!r})")
    if not 0.0 < cut_angle < gear.fillet_end_angle:
        raise InputError("mesh.fillet_cut_angle", "must lie between 0 and 90 deg - pressure angle")


def _side_outlines(gear: Gear, ny: int, cut_angle: float, row_grading: float
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]:
    """The right and left outlines' grid points, root to tip, and the rows' blend parameter.

    Right outline, from the cut point on the fillet to the tip corner. With a tip relief
    the rows are evenly spaced in the radius of the unmodified involute point, up to the
    one whose relieved point lies on the tip circle (``flank_end_radius``).

    Parameters
    ----------
    gear
        The gear meshed.
    ny, cut_angle, row_grading
        As :func:`tooth_mesh` takes them (checked).

    Returns
    -------
    right, left
        The ``2 ny + 1`` points of each outline, shape ``(2 ny + 1, 2)``.
    t
        The rows' blend parameter, 0 at the cut point to 1 at the tip corner.
    fillet_rows
        The fillet's rows (:func:`row_radii`; 0 for even rows).
    """
    cut = gear.fillet_points(np.asarray(cut_angle))
    r_cut = float(np.hypot(*cut))
    radii, fillet_rows = row_radii(r_cut, float(gear.form_radius), float(gear.flank_end_radius),
                                   ny, float(row_grading))
    t = (radii - r_cut) / (gear.flank_end_radius - r_cut)   # the rows' blend parameter
    if not fillet_rows:
        t = np.linspace(0.0, 1.0, 2 * ny + 1)               # the even grid, bit for bit
    right = np.array([cut] + [gear.right_side_point(r) for r in radii[1:]])
    left = right * np.array([-1.0, 1.0])
    return right, left, t, fillet_rows


def _end_outlines(gear: Gear, s: NDArray[np.float64], right: NDArray[np.float64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The bottom and top curves' grid points, left to right.

    Parameters
    ----------
    gear
        The gear meshed.
    s
        The columns' spacing across the tooth (:func:`thickness_spacing`).
    right
        The right outline (:func:`_side_outlines`): its first point is the cut point, its
        last the tip corner.

    Returns
    -------
    bottom, top
        The bottom curve, from the root circle under the tooth up to the cut points, and
        the tip circle's arc; shape ``(2 nx + 1, 2)`` each.
    """
    cut = right[0]
    r_cut = float(np.hypot(*cut))
    chi_cut = float(np.arctan2(cut[0], cut[1]))
    u = 2.0 * s - 1.0
    bottom = _polar(gear.root_radius + (r_cut - gear.root_radius) * u**2, chi_cut * u)
    chi_tip = float(np.arctan2(right[-1, 0], right[-1, 1]))
    top = _polar(np.full_like(u, gear.tip_radius), chi_tip * u)
    return bottom, top


def _coons_grid(bottom: NDArray[np.float64], top: NDArray[np.float64], left: NDArray[np.float64],
                right: NDArray[np.float64], s: NDArray[np.float64], t: NDArray[np.float64]
                ) -> NDArray[np.float64]:
    """The Coons patch of the four curves: blend them, remove the doubly counted corners.

    Parameters
    ----------
    bottom, top
        The end curves, ``(2 nx + 1, 2)`` each (:func:`_end_outlines`).
    left, right
        The outlines, ``(2 ny + 1, 2)`` each (:func:`_side_outlines`).
    s, t
        The blend parameters across and along the tooth.

    Returns
    -------
    NDArray
        The grid's points, shape ``(2 nx + 1, 2 ny + 1, 2)``.
    """
    S, T = s[:, None, None], t[None, :, None]
    return ((1 - T) * bottom[:, None, :] + T * top[:, None, :]
            + (1 - S) * left[None, :, :] + S * right[None, :, :]
            - ((1 - S) * (1 - T) * left[0] + S * (1 - T) * right[0]
               + (1 - S) * T * left[-1] + S * T * right[-1]))


def _q8_elements(index: NDArray[np.intp], nx: int, ny: int) -> NDArray[np.intp]:
    """The ``nx ny`` Q8 elements' node numbers, row by row from the root.

    Parameters
    ----------
    index
        The node number of each grid point, -1 for the elements' centres (:func:`_grid_index`).
    nx, ny
        Elements across and along the tooth.

    Returns
    -------
    NDArray
        Shape ``(nx ny, 8)``: the four corners counter-clockwise from the bottom left, then
        the four mid-side nodes from the bottom one.
    """
    elements = np.empty((nx * ny, 8), dtype=np.intp)
    for ey in range(ny):
        for ex in range(nx):
            i, j = 2 * ex, 2 * ey
            elements[ey * nx + ex] = [
                index[i, j], index[i + 2, j], index[i + 2, j + 2], index[i, j + 2],
                index[i + 1, j], index[i + 2, j + 1], index[i + 1, j + 2], index[i, j + 1],
            ]
    return elements


def tooth_mesh(
    gear: Gear,
    nx: int = DEFAULT_NX,
    ny: int = DEFAULT_NY,
    cut_angle: float = DEFAULT_FILLET_CUT_ANGLE,
    grading: float = DEFAULT_GRADING,
    row_grading: float = DEFAULT_ROW_GRADING,
) -> ToothMesh:
    """Mesh one tooth of ``gear`` with ``nx`` x ``ny`` Q8 elements, graded across the tooth
    by ``grading`` (:func:`thickness_spacing`) and along it by ``row_grading``
    (:func:`row_radii`).

    Raises
    ------
    InputError
        If the density is not a pair of whole numbers in range, or the mesh would hold
        an element with a non-positive Jacobian.
    """
    _check_mesh_args(gear, nx, ny, cut_angle, grading, row_grading)
    right, left, t, fillet_rows = _side_outlines(gear, ny, cut_angle, row_grading)
    s = thickness_spacing(nx, float(grading))
    bottom, top = _end_outlines(gear, s, right)
    grid = _coons_grid(bottom, top, left, right, s, t)

    index = _grid_index(nx, ny)
    keep = index >= 0
    nodes = np.empty((int(keep.sum()), 2))
    nodes[index[keep]] = grid[keep]
    elements = _q8_elements(index, nx, ny)

    det = jacobian_determinants(nodes, elements)
    if not np.all(det > 0.0):
        bad = int(np.argmin(det.min(axis=1)))
        raise InputError("mesh", f"element {bad} has a non-positive Jacobian; "
                         "use a different nx x ny")

    return ToothMesh(
        nodes=nodes,
        elements=elements,
        root_nodes=index[:, 0].copy(),
        right_side=index[-1, :].copy(),
        left_side=index[0, :].copy(),
        tip_nodes=index[:, -1].copy(),
        nx=int(nx),
        ny=int(ny),
        grading=float(grading),
        row_grading=float(row_grading),
        fillet_rows=fillet_rows,
    )
