"""Cracked rectangles of the handbooks, meshed by gmsh with a seam of twin nodes, loaded on
their ends, solved: the checks of the interaction integral (docs/fracture.md, section 5).

Two meshes: a strip ``0 <= x <= W``, ``-h <= y <= h`` with an edge crack from ``(0, 0)`` to
``(a, 0)``; a plate ``|x| <= W / 2``, ``|y| <= H / 2`` with a centre crack of half-length
``a`` at an angle ``beta`` to the ``x`` axis. Both are refined toward the tips as the cracked
tooth is (:mod:`spurdyn.mesh.gmsh_quads`). The loads are tractions on the ends ``y = +-h``
(``+-H / 2``), self-equilibrated, and the supports statically determinate (three DOFs of two
corners), so the supports carry no force and the stress is the handbook's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_stiffness, jacobian_determinants
from spurdyn.fem.element import edge_dweights, edge_weights
from spurdyn.fem.factor import factor_spd
from spurdyn.fem.material import Material
from spurdyn.mesh.cracked import RETRY_SHARES, counter_clockwise, split_seam
from spurdyn.mesh.gmsh_quads import (
    GmshQuads, boundary_edges, element_edges, mesh_with_crack, mesh_with_inner_crack,
)

__all__ = ["CrackedPlate", "centre_crack_plate", "edge_crack_strip", "end_load", "solve"]

#: Points of each straight side gmsh draws (a spline through them is the straight line).
SIDE_POINTS = 3
#: The elements at a tip must lie within this many tip sizes of it. Their farthest node is
#: 1.5 to 8.5 tip sizes away in the meshes measured (docs/fracture.md, section 7), but
#: gmsh's quads at times ignore the size field at a tip (a centre crack along the x axis in
#: a 40 a square at size 2 a: 24 and 44 tip sizes), which the guard catches.
TIP_GUARD = 10.0


@dataclass(frozen=True)
class CrackedPlate:
    """A cracked rectangle's Q8 mesh.

    Attributes
    ----------
    nodes
        ``(N, 2)`` node coordinates (m).
    elements
        ``(E, 8)`` Q8 elements, counter-clockwise; all Jacobians > 0.
    seam
        ``(S, 2)`` twin nodes along the crack, tips excluded: the nodes of the faces on
        either side, the second on the side of :attr:`normal`.
    normal
        ``(2,)`` the crack's unit normal toward the second face's side.
    tips
        ``(T,)`` the tips' nodes (one for an edge crack, two for a centre crack).
    ahead
        ``(T, 2)`` each tip's unit direction of growth along the crack.
    width, height
        The rectangle's sides (m).
    """

    nodes: NDArray[np.float64]
    elements: NDArray[np.intp]
    seam: NDArray[np.intp]
    normal: NDArray[np.float64]
    tips: NDArray[np.intp]
    ahead: NDArray[np.float64]
    width: float
    height: float


def _sides(corners: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """The straight sides of a polygon as gmsh's curves (each from its corner to the next)."""
    return [np.linspace(p, q, SIDE_POINTS) for p, q in zip(corners, np.roll(corners, -1, axis=0))]


def _positive(key: str, value: float) -> float:
    """``value`` as a float, refused naming ``key`` unless a finite length above 0."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0.0 \
            or not math.isfinite(value):
        raise InputError(key, f"must be a positive length in m (got {value!r})")
    return float(value)


def _finish(quads: GmshQuads, inner: slice, ahead: NDArray[np.float64], width: float,
            height: float, tip_size: float) -> CrackedPlate:
    """The mesh counter-clockwise, the crack's nodes ``crack[inner]`` doubled; refused
    (``size``) for an element of Jacobian <= 0, a crack the elements do not follow, or a tip
    gmsh did not refine to (:data:`TIP_GUARD`)."""
    elements = counter_clockwise(quads.nodes, quads.elements)
    if not np.all(jacobian_determinants(quads.nodes, elements) > 0.0):
        raise InputError("size", "an element has a non-positive Jacobian; try another size")
    _check_conforms(elements, quads.crack)
    tips = np.delete(quads.crack, np.arange(quads.crack.size)[inner])
    for tip in tips:
        around = quads.nodes[elements[np.any(elements == tip, axis=1)]]
        if np.max(np.hypot(*(around - quads.nodes[tip]).transpose(2, 0, 1))) > \
                TIP_GUARD * tip_size:
            raise InputError("size", "gmsh did not refine the mesh toward the crack's tip; "
                             "try a slightly different size")
    d = ahead[-1]
    normal = np.array([-d[1], d[0]])
    try:
        nodes, elements, seam = split_seam(quads.nodes, elements, quads.crack[inner], normal,
                                           quads.nodes[quads.crack[[0, -1]]])
    except RuntimeError as error:
        raise InputError("size", "gmsh's elements do not follow the crack; try another "
                         "size") from error
    return CrackedPlate(nodes=nodes, elements=elements, seam=seam, normal=normal, tips=tips,
                        ahead=ahead, width=width, height=height)


def _check_conforms(elements: NDArray[np.intp], crack: NDArray[np.intp]) -> None:
    """Refuse a mesh whose element edges do not run along the whole crack, each piece of it
    an edge of two elements (gmsh has been seen to lose a piece of an embedded line)."""
    have = np.sort(element_edges(elements)[:, [0, 2]], axis=1)
    pieces = np.sort(np.stack([crack[:-2:2], crack[2::2]], axis=1), axis=1)
    count = [(have == piece).all(axis=1).sum() for piece in pieces]
    if crack.size % 2 == 0 or any(c != 2 for c in count):
        raise InputError("size", "gmsh's elements do not follow the crack; try another size")


def _retry(make: Callable[[float], CrackedPlate]) -> CrackedPlate:
    """``make(share)`` of the element size at the shares :data:`RETRY_SHARES` in turn until
    gmsh's mesh passes the checks; the last refusal is raised."""
    for share in RETRY_SHARES[:-1]:
        try:
            return make(share)
        except InputError:
            continue
    return make(RETRY_SHARES[-1])


def edge_crack_strip(width: float, half_height: float, depth: float, size: float,
                     tip_size: float) -> CrackedPlate:
    """A strip ``0 <= x <= width``, ``|y| <= half_height`` with an edge crack from ``(0, 0)``
    to ``(depth, 0)``, element size ``size`` refined to ``tip_size`` at the tip (m).

    Raises
    ------
    InputError
        ``width``, ``half_height``, ``depth``, ``size``, ``tip_size`` not positive, a crack
        not inside the strip (``depth``), or a mesh gmsh could not make (``size``).
    """
    w, h, a = (_positive(k, v) for k, v in (("width", width), ("half_height", half_height),
                                            ("depth", depth)))
    size, tip_size = _positive("size", size), _positive("tip_size", tip_size)
    if not a < w:
        raise InputError("depth", f"must be below the width {w:g} m (got {a:g})")
    corners = np.array([[0.0, -h], [w, -h], [w, h], [0.0, h], [0.0, 0.0]])

    def make(share: float) -> CrackedPlate:
        quads = mesh_with_crack(_sides(corners), 4, np.array([a, 0.0]), share * size,
                                min(tip_size, share * size))
        return _finish(quads, slice(0, -1), np.array([[1.0, 0.0]]), w, 2.0 * h, tip_size)

    return _retry(make)


def centre_crack_plate(width: float, height: float, half_length: float, angle: float,
                       size: float, tip_size: float) -> CrackedPlate:
    """A plate ``|x| <= width / 2``, ``|y| <= height / 2`` with a centre crack of half-length
    ``half_length`` at ``angle`` (rad) counter-clockwise from the ``x`` axis; tips: the end at
    ``+half_length (cos angle, sin angle)`` first.

    Raises
    ------
    InputError
        A length not positive, ``angle`` not finite, a crack not inside the plate
        (``half_length``) or a mesh gmsh could not make (``size``).
    """
    w, h, a = (_positive(k, v) for k, v in (("width", width), ("height", height),
                                            ("half_length", half_length)))
    size, tip_size = _positive("size", size), _positive("tip_size", tip_size)
    if not math.isfinite(angle):
        raise InputError("angle", f"must be finite (got {angle!r})")
    d = np.array([math.cos(angle), math.sin(angle)])
    if not np.all(a * np.abs(d) < 0.5 * np.array([w, h]) - size):
        raise InputError("half_length", "the crack must lie inside the plate, an element "
                         "size from its edges")
    corners = 0.5 * np.array([[-w, -h], [w, -h], [w, h], [-w, h]])
    tips_ahead = np.array([-d, d])              # the crack's nodes run from -a d to +a d

    def make(share: float) -> CrackedPlate:
        quads = mesh_with_inner_crack(_sides(corners), np.array([-a * d, a * d]), share * size,
                                      min(tip_size, share * size), "size")
        return _finish(quads, slice(1, -1), tips_ahead, w, h, tip_size)

    plate = _retry(make)
    return CrackedPlate(nodes=plate.nodes, elements=plate.elements, seam=plate.seam,
                        normal=plate.normal, tips=plate.tips[::-1], ahead=tips_ahead[::-1],
                        width=w, height=h)


def end_load(plate: CrackedPlate, stress: Callable[[NDArray[np.float64]], NDArray[np.float64]],
             thickness: float = 1.0) -> NDArray[np.float64]:
    """Nodal forces (N), interleaved, of a normal traction ``stress(x)`` (Pa) on the top end
    (pulling up where positive) and its mirror on the bottom end (pulling down), integrated
    on each Q8 edge by 3-point Gauss (exact for a traction linear in ``x``)."""
    edges = boundary_edges(plate.elements)
    y = plate.nodes[edges, 1]
    top = np.max(plate.nodes[:, 1])
    bottom = np.min(plate.nodes[:, 1])
    tol = 1e-9 * max(plate.width, plate.height)
    forces = np.zeros(plate.nodes.shape[0] * 2)
    eta, weight = np.polynomial.legendre.leggauss(3)
    for end, sense in ((top, 1.0), (bottom, -1.0)):
        chosen = edges[np.all(np.abs(y - end) < tol, axis=1)]
        xyz = plate.nodes[chosen]                                  # (B, 3, 2)
        for e, w in zip(eta, weight):
            n, dn = edge_weights(e), edge_dweights(e)
            x = np.einsum("i,bik->bk", n, xyz)
            length = np.hypot(*np.einsum("i,bik->bk", dn, xyz).T)
            np.add.at(forces, 2 * chosen + 1, sense * thickness * w * np.outer(
                stress(x) * length, n))
    return forces


def solve(plate: CrackedPlate, material: Material, forces: NDArray[np.float64],
          thickness: float = 1.0) -> NDArray[np.float64]:
    """Displacements (m), interleaved, under self-equilibrated ``forces``: the bottom left
    corner held in x and y, the bottom right in y (statically determinate)."""
    x, y = plate.nodes.T
    left = int(np.argmin(np.hypot(x - x.min(), y - y.min())))
    right = int(np.argmin(np.hypot(x - x.max(), y - y.min())))
    fixed = np.array([2 * left, 2 * left + 1, 2 * right + 1])
    free = np.setdiff1d(np.arange(forces.size), fixed)
    k = assemble_stiffness(plate.nodes, plate.elements, material, thickness)
    u = np.zeros(forces.size)
    u[free] = factor_spd(k[free][:, free]).solve(forces[free])
    return u
