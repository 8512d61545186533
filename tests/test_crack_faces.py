"""A crack's faces in the sector model's statics (docs/faults.md, "Root crack"): a seam of
duplicated nodes whose faces are a unilateral contact of their own.

The crack here runs along a row line of the structured tooth mesh (its element edges), from
one outline into the tooth: a crack the structured mesh can follow, so that the faces'
contact is tested apart from the cracked tooth's own mesher."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.mesh.sector import cell_mesh, sector_mesh
from spurdyn.mesh.tooth import tooth_mesh
from spurdyn.sector.statics import (contact_law, driving_pair, healthy_contacts, sector_bodies,
                                    solve_position)

NX, NY, TEETH = 4, 8, 4


@dataclass(frozen=True)
class RowCrack:
    """A cracked tooth in :class:`spurdyn.mesh.cracked.CrackedTooth`'s shape, its crack on
    the corner row ``2 * row`` from the ``side`` outline, ``depth`` elements deep."""

    nodes: np.ndarray
    elements: np.ndarray
    structured: np.ndarray
    seam: np.ndarray
    normal: np.ndarray
    tip: int


def row_crack(gear, row: int, depth: int, side: str) -> RowCrack:
    """The crack in tooth 0's cell (:func:`spurdyn.mesh.sector.cell_mesh`), as the sector
    mesh takes a cracked cell."""
    from scipy.spatial import cKDTree

    tooth, cell = tooth_mesh(gear, NX, NY), cell_mesh(gear, NX, NY)
    t_in = cKDTree(cell.nodes).query(tooth.nodes)[1]        # the tooth's nodes in the cell
    index = _index(tooth)
    j = 2 * row
    span = range(2 * tooth.nx, 2 * (tooth.nx - depth), -1) if side == "right" else range(0, 2 * depth)
    line = np.array([index[i, j] for i in span])
    tip = int(index[2 * (tooth.nx - depth), j] if side == "right" else index[2 * depth, j])
    copies = cell.n_nodes + np.arange(line.size)
    nodes = np.vstack([cell.nodes, tooth.nodes[line]])
    elements = cell.elements.copy()         # the tooth's elements first (in the tooth's order)
    cols = range(tooth.nx - depth, tooth.nx) if side == "right" else range(depth)
    lookup = dict(zip(t_in[line].tolist(), copies.tolist()))
    for e in [ey * tooth.nx + ex for ey in range(row, tooth.ny) for ex in cols]:
        elements[e] = [lookup.get(int(n), int(n)) for n in elements[e]]
    ends = tooth.nodes[np.array([index[i, j] for i in span] + [tip])]
    tangent = np.gradient(ends, axis=0)[:-1]
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    normal *= np.sign(normal[:, 1])[:, None]          # from below (face one) into above (two)
    return RowCrack(nodes, elements, np.arange(cell.n_nodes), np.column_stack([t_in[line], copies]),
                    normal, int(t_in[tip]))


def _index(tooth) -> np.ndarray:
    """The structured grid's node numbers ``[i across, j along]`` (-1 at element centres)."""
    out = -np.ones((2 * tooth.nx + 1, 2 * tooth.ny + 1), dtype=np.intp)
    for e, el in enumerate(tooth.elements):
        ey, ex = divmod(e, tooth.nx)
        corners = [(2 * ex, 2 * ey), (2 * ex + 2, 2 * ey), (2 * ex + 2, 2 * ey + 2), (2 * ex, 2 * ey + 2),
                   (2 * ex + 1, 2 * ey), (2 * ex + 2, 2 * ey + 1), (2 * ex + 1, 2 * ey + 2), (2 * ex, 2 * ey + 1)]
        for (i, j), n in zip(corners, el):
            out[i, j] = n
    return out


@pytest.fixture(scope="module")
def pair():
    return driving_pair(paper_pair())


def test_the_grid_is_read_back(pair):
    tooth = tooth_mesh(pair.gear_a, NX, NY)
    index = _index(tooth)
    assert np.array_equal(index[-1, :], tooth.right_side)
    assert np.array_equal(index[:, 0], tooth.root_nodes)


def test_a_cracked_cell_keeps_its_faces_apart(pair):
    crack = row_crack(pair.gear_a, 2, 2, "right")
    whole = sector_mesh(pair.gear_a, TEETH, NX, NY)
    mesh = sector_mesh(pair.gear_a, TEETH, NX, NY, cracked={0: crack})
    assert mesh.n_nodes == whole.n_nodes + crack.seam.shape[0]
    assert mesh.seams.shape == crack.seam.shape
    assert np.allclose(mesh.nodes[mesh.seams[:, 0]], mesh.nodes[mesh.seams[:, 1]], rtol=0, atol=1e-12)
    assert np.all(mesh.seams[:, 0] != mesh.seams[:, 1])
    np.testing.assert_allclose(np.linalg.norm(mesh.seam_normals, axis=1), 1.0)


def _position(pair, cracked, rho):
    """One position's solve with the cracked bodies, and all its forces again (pairs, then
    the faces) from its compliance and active set: the paper's pair has no relief, so the
    pairs' gaps are 0 and the faces' too."""
    from spurdyn.sector.statics import _active_set

    healthy = sector_bodies(pair, TEETH, NX, NY)
    law = contact_law(pair, PAPER_TORQUE, healthy)
    bodies = sector_bodies(pair, TEETH, NX, NY, cracked=cracked)
    js, f, e, c, active = solve_position(law, rho, healthy_contacts, bodies)
    f_all, e_all, _ = _active_set(c, np.zeros(c.shape[0]), law.load, np.arange(c.shape[0]) < len(js))
    assert e_all == pytest.approx(e, rel=1e-12)
    return js, f, e, c, f_all, law


@pytest.mark.parametrize("side, closes", [("right", False), ("left", True)])
def test_faces_open_in_tension_and_close_in_compression(pair, side, closes):
    """The driver's right flank carries the load: its right fillet is in tension, the left
    in compression. A crack on the tension side opens and carries nothing; one on the
    compression side closes, carries compression, and its faces do not pass through each
    other."""
    crack = row_crack(pair.gear_a, 1, 2, side)
    rho = 0.5 * (pair.start_roll_a + pair.end_roll_a)      # one pair near the pitch point
    js, f, e, c, f_all, law = _position(pair, ({0: crack}, {}), rho)
    n = len(js)
    faces = f_all[n:]
    opening = (c @ f_all)[n:]
    assert math.isclose(f.sum(), law.load, rel_tol=1e-12)
    assert np.all(faces >= 0.0)
    assert np.all(opening >= -1e-9 * abs(e))
    assert np.all(faces * opening <= 1e-9 * abs(e) * law.load)
    assert (faces.max() > 1e-3 * law.load) == closes
    healthy = solve_position(law, rho)
    # a crack makes the tooth more compliant: a larger approach for the same load
    assert e > healthy[2]
    if closes:
        # closed, it carries the compression: the tooth nearly as stiff as a whole one
        assert e - healthy[2] < 0.05 * healthy[2]
