"""The figures of docs/faults.md, "Root crack: the cracked tooth's mesh": the cracked tooth's
meshes and their compliance under a load on the tip, against the structured tooth's.

Usage::

    python scripts/cracked_tooth_mesh.py          # print the page's tables (markdown)

The tooth is clamped along the whole curve under it (where the rim would hold it) and loaded
by a uniform tangential traction along its tip circle, toward -x (the crack on the right
fillet is then on the tension side). The compliance is the work-conjugate one, ``f . u / F^2``
(m/N): a displacement finite element model is too stiff, so it grows toward the exact
figure as the mesh is refined (a point load's own displacement would grow without bound).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_stiffness
from spurdyn.fem.element import edge_dweights, edge_weights
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.presets import paper_gear
from spurdyn.mesh.cracked import (
    CrackedTooth, crack_path, cracked_tooth, default_size, outline_ties,
)
from spurdyn.mesh.tooth import ToothMesh, tooth_mesh

#: The element edges of the Q8 order: (corner, mid-side, corner).
EDGES = ((0, 4, 1), (1, 5, 2), (2, 6, 3), (3, 7, 0))
#: Gauss points and weights on an edge (3 points: exact for the quadratic edge's load).
GAUSS = np.polynomial.legendre.leggauss(3)
#: The cut angles, crack depths (mm) and shares of the default element size of the table.
CASES = ((45.0, 0.15), (20.0, 0.5))
SHARES = (1.0, 0.5, 0.25)


def tip_edges(nodes: NDArray[np.float64], elements: NDArray[np.intp], r_tip: float
              ) -> NDArray[np.intp]:
    """The element edges ``(k, 3)`` whose three nodes lie on the tip circle."""
    on = np.abs(np.hypot(*nodes.T) - r_tip) < 1e-9 * r_tip
    rows = [elements[:, list(e)] for e in EDGES]
    cand = np.concatenate(rows)
    return cand[on[cand].all(axis=1)]


def tip_load(nodes: NDArray[np.float64], edges: NDArray[np.intp]) -> tuple[NDArray[np.float64], float]:
    """Nodal forces (x components, ``(N,)``) of a unit traction toward -x along ``edges``,
    and the total force (N per unit traction)."""
    f = np.zeros(nodes.shape[0])
    for eta, w in zip(*GAUSS):
        xy = nodes[edges]                                            # (k, 3, 2)
        ds = np.hypot(*np.einsum("i,kij->kj", edge_dweights(eta), xy).T)
        np.add.at(f, edges, -w * ds[:, None] * edge_weights(eta)[None, :])
    return f, float(-f.sum())


def compliance(nodes: NDArray[np.float64], elements: NDArray[np.intp], clamped: NDArray[np.intp],
               gear: Gear) -> float:
    """The work-conjugate compliance ``f . u / F^2`` (m/N) of the module docstring."""
    n = 2 * nodes.shape[0]
    fx, total = tip_load(nodes, tip_edges(nodes, elements, gear.tip_radius))
    f = np.zeros(n)
    f[0::2] = fx
    k = assemble_stiffness(nodes, elements, gear.material, gear.face_width).tocsr()
    free = np.setdiff1d(np.arange(n), np.concatenate([2 * clamped, 2 * clamped + 1]))
    u = np.zeros(n)
    u[free] = spla.spsolve(k[free][:, free].tocsc(), f[free])
    return float(f @ u) / total**2


def bottom_nodes(tooth: ToothMesh, cracked: CrackedTooth) -> NDArray[np.intp]:
    """The cracked mesh's nodes on the curve under the tooth (structured and tied ones)."""
    ties, parents, _ = outline_ties(tooth, cracked)
    root = cracked.structured[tooth.root_nodes]
    on_root = np.isin(parents, root).all(axis=1)
    return np.concatenate([root, ties[on_root]])


def tied(cracked: CrackedTooth) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """The cracked mesh with its faces tied again: the twins merged into face one's nodes."""
    n0 = cracked.nodes.shape[0] - cracked.seam.shape[0]
    merge = np.arange(cracked.nodes.shape[0])
    merge[cracked.seam[:, 1]] = cracked.seam[:, 0]
    return cracked.nodes[:n0], merge[cracked.elements]


def row(gear: Gear, tooth: ToothMesh, depth: float, share: float, size: float) -> dict:
    """One line of the table: the cracked mesh at ``share`` of ``size`` and its figures."""
    c = cracked_tooth(gear, tooth, crack_path(gear, tooth, "right", depth), size=share * size)
    clamped = bottom_nodes(tooth, c)
    return {"elements": c.elements.shape[0], "nodes": c.nodes.shape[0],
            "cracked": compliance(c.nodes, c.elements, clamped, gear),
            "tied": compliance(*tied(c), clamped, gear)}


def deepest(gear: Gear, tooth: ToothMesh, angle: float) -> float:
    """The longest crack from the default mouth at ``angle`` that crack_path accepts (m),
    by bisection to a nanometre."""
    lo, hi = 0.0, 10e-3
    while hi - lo > 1e-9:
        mid = 0.5 * (lo + hi)
        try:
            crack_path(gear, tooth, "right", mid, angle)
            lo = mid
        except InputError:
            hi = mid
    return lo


def main() -> None:
    gear = paper_gear()
    print("| fillet cut (deg) | cut radius (mm) | deepest at 45 deg (mm) | at 30 deg | at 15 deg |")
    print("|---|---|---|---|---|")
    for cut in (45.0, 30.0, 20.0, 10.0):
        tooth = tooth_mesh(gear, cut_angle=math.radians(cut))
        r_cut = float(np.hypot(*tooth.nodes[tooth.right_side[0]]))
        d = [deepest(gear, tooth, math.radians(a)) * 1e3 for a in (45.0, 30.0, 15.0)]
        print(f"| {cut:g} | {r_cut * 1e3:.3f} | {d[0]:.3f} | {d[1]:.3f} | {d[2]:.3f} |")
    print()
    print("| cut (deg) | crack (mm) | size (mm) | elements | nodes | cracked (m/GN) | "
          "tied (m/GN) | cracked / tied |")
    print("|---|---|---|---|---|---|---|---|")
    for cut, depth in CASES:
        tooth = tooth_mesh(gear, cut_angle=math.radians(cut))
        size = default_size(tooth)
        for share in SHARES:
            r = row(gear, tooth, depth * 1e-3, share, size)
            print(f"| {cut:g} | {depth:g} | {share * size * 1e3:.3f} | {r['elements']} | "
                  f"{r['nodes']} | {r['cracked'] * 1e9:.5f} | {r['tied'] * 1e9:.5f} | "
                  f"{r['cracked'] / r['tied']:.5f} |")
        for nx, ny in ((4, 14), (8, 28), (16, 56)):
            t = tooth_mesh(gear, nx, ny, cut_angle=math.radians(cut))
            print(f"| {cut:g} | structured {nx} x {ny} | | {t.n_elements} | {t.n_nodes} | | "
                  f"{compliance(t.nodes, t.elements, t.root_nodes, gear) * 1e9:.5f} | |")


if __name__ == "__main__":
    main()
