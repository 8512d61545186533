"""A Q8 mesh of one tooth with a straight root crack: gmsh's quads around a seam of twin nodes.

The structured tooth mesh (:mod:`spurdyn.mesh.tooth`) cannot follow a crack, so the tooth is
meshed again, unstructured, inside the same outline: the structured outline's quadratic
edges (:mod:`spurdyn.mesh.outline`) with every outline node kept where it was, the crack a
line embedded in the surface, the elements refined toward its tip. The crack's nodes other
than the tip are then doubled: the elements on one side of the crack take the copies, so the
two faces can part. docs/faults.md, "Root crack: the cracked tooth's mesh", has the method,
the defaults and the measured figures.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.fem.element import edge_weights
from spurdyn.geometry.gear import Gear
from spurdyn.mesh import outline as ol
from spurdyn.mesh.gmsh_quads import GmshQuads, mesh_with_crack
from spurdyn.mesh.tooth import ToothMesh

#: Angle between the fillet's tangent and the tooth's centre line at the default crack
#: mouth (rad): ISO 6336-3's critical section of the tooth root, where tooth-root cracks
#: start (the 30 deg tangent points of method B).
DEFAULT_MOUTH_TANGENT = math.radians(30.0)
#: Least share of the fillet part (from the mesh's cut under the tooth to the form radius)
#: the default mouth lies above the cut.
DEFAULT_MOUTH_MARGIN = 0.05
#: Default angle of the crack below the line across the tooth (perpendicular to the centre
#: line), running down and in toward the centre line (rad): the straight cracks of the
#: literature (Tian 2004's 45 deg to the centre line, the same line at 45 deg): a convention
#: of those models, not a measured path.
DEFAULT_CRACK_ANGLE = math.radians(45.0)
#: Default element size near the tip, as a share of the smaller of the crack's length and
#: the element size elsewhere.
TIP_SIZE_SHARE = 0.1
#: Least distance of the crack's tip from the outline, as a share of the crack's length:
#: room for a few elements of the default tip size between the tip and the outline.
TIP_CLEARANCE = 0.2
#: Shares of the element size tried in turn when gmsh refuses one (:func:`_mesh`).
RETRY_SHARES = (1.0, 0.9, 0.8, 0.7)
#: Points of a structured edge's parabola through which gmsh draws a side of the outline.
CURVE_POINTS = 9
#: Two nodes closer than this share of the tip radius are at the same place.
SAME_PLACE = 1e-12


@dataclass(frozen=True)
class CrackedTooth:
    """A Q8 mesh of one tooth with a root crack, in the structured mesh's frame.

    Attributes
    ----------
    nodes
        ``(N, 2)`` node coordinates (m), the frame of :attr:`ToothMesh.nodes`.
    elements
        ``(E, 8)`` Q8 elements, corners counter-clockwise then mid-sides; all Jacobians > 0.
    structured
        ``(n,)`` for every node of the structured mesh, the node of this mesh at the same
        place (to ``SAME_PLACE`` of the tip radius), -1 if none (or two: a seam's twins).
        Every structured outline node maps, except the mid-side node of the fillet edge the
        crack's mouth splits.
    seam
        ``(S, 2)`` twin nodes (face one, face two) along the crack, mouth first, tip excluded;
        mid-side nodes included.
    normal
        ``(S, 2)`` unit normal of the crack at each twin, pointing from face one into face
        two's side (opening ``(u_two - u_one) . normal > 0``); face two is the side toward the
        tip circle (the normal's y component is positive).
    tip
        The crack tip's node (one node, shared by both faces).
    """

    nodes: NDArray[np.float64]
    elements: NDArray[np.intp]
    structured: NDArray[np.intp]
    seam: NDArray[np.intp]
    normal: NDArray[np.float64]
    tip: int


def mouth_radius(gear: Gear, tangent: float = DEFAULT_MOUTH_TANGENT) -> float:
    """Radius of the right fillet's point whose tangent makes ``tangent`` with the tooth's
    centre line (m); raises :class:`InputError` (``fault.start``) if the fillet has none."""
    from scipy.optimize import brentq      # imported when used: scipy.optimize is slow to load

    def excess(a: float) -> float:
        h = 1e-7
        t = gear.fillet_points(np.asarray(a + h)) - gear.fillet_points(np.asarray(a - h))
        return math.atan2(abs(t[0]), abs(t[1])) - tangent

    a = np.linspace(1e-4, gear.fillet_end_angle - 1e-4, 64)
    f = np.array([excess(float(x)) for x in a])
    turns = np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))
    if not turns.size:
        raise InputError("fault.start", f"the fillet has no point whose tangent makes "
                         f"{math.degrees(tangent):g} deg with the centre line; give the radius")
    root = brentq(excess, a[turns[0]], a[turns[0] + 1], xtol=1e-14)
    return float(np.hypot(*gear.fillet_points(np.asarray(root))))


def _point_at_radius(tooth: ToothMesh, side: str, r: float) -> NDArray[np.float64]:
    """The point of the structured ``side`` outline's quadratic edges at radius ``r``."""
    from scipy.optimize import brentq

    nodes, line = tooth.nodes, tooth.side(side)
    radii = np.hypot(*nodes[line[::2]].T)
    k = int(np.clip(np.searchsorted(radii, r) - 1, 0, radii.size - 2))
    xyz = nodes[line[2 * k: 2 * k + 3]]
    xi = brentq(lambda s: float(np.hypot(*ol.edge_point(xyz, s))) - r, -1.0, 1.0, xtol=1e-15)
    return ol.edge_point(xyz, xi)


def _check_number(key: str, value: object, low: float = 0.0) -> float:
    """``value`` as a float if it is a finite number above ``low``, else :class:`InputError`."""
    if (isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer))
            or not math.isfinite(value) or not value > low):
        raise InputError(key, f"must be a number above {low:g} (got {value!r})")
    return float(value)


def _check_inside(tooth: ToothMesh, mouth: NDArray[np.float64], tip: NDArray[np.float64]) -> None:
    """Refuse (``fault.depth``) a crack that leaves the structured tooth's outline; ``tip``
    is the tip ``(2,)`` or a polyline's kinks and tip ``(k, 2)``, and the tip must lie
    :data:`TIP_CLEARANCE` of the last piece's length from the outline."""
    poly = ol.polygon(tooth.nodes, ol.outline_edges(tooth))
    points = np.vstack([mouth[None], np.atleast_2d(tip)])
    start = mouth + 1e-6 * (points[1] - mouth)   # just inside: the mouth lies on the outline
    pieces = [(start, points[1])] + list(zip(points[1:-1], points[2:]))
    clear = ol.distance(poly, points[-1]) >= TIP_CLEARANCE * float(np.hypot(*(points[-1] - points[-2])))
    if not ol.inside(poly, np.vstack([start[None], points[1:]])).all() or \
            any(ol.crosses(poly, p, q) for p, q in pieces) or not clear:
        raise InputError("fault.depth", "the crack would leave the tooth's mesh, or its tip "
                         f"come closer than {TIP_CLEARANCE:g} of its length to the outline "
                         "(the curve under the tooth, below which the rim begins, or the other "
                         "outline); give a shorter crack or a shallower angle")


def crack_path(gear: Gear, tooth: ToothMesh, side: str, depth: float, angle: float | None = None,
               start: float | None = None, region: ToothMesh | None = None) -> NDArray[np.float64]:
    """A straight root crack: its mouth on the fillet of one outline, its tip inside the tooth.

    Parameters
    ----------
    gear
        The gear the tooth mesh belongs to.
    tooth
        The structured tooth mesh (its outline's quadratic edges carry the mouth).
    side
        ``"right"`` (the outline at ``x > 0``) or ``"left"``.
    depth
        The crack's length (m), above 0.
    angle
        The crack's angle below the line across the tooth, running down and in toward the
        centre line (rad, in (0, 90 deg)); default ``DEFAULT_CRACK_ANGLE``.
    start
        The mouth's radius (m) on the fillet part of the structured outline (between the
        fillet's cut under the tooth and the form radius); default the radius of ISO
        6336-3's 30 deg tangent point (:func:`mouth_radius`), or where that lies at or below
        the cut (gears of few teeth) :data:`DEFAULT_MOUTH_MARGIN` of the fillet part above it.
    region
        The structured mesh whose outline the crack must stay inside (default ``tooth``; the
        sector model gives the tooth's whole cell, :func:`spurdyn.mesh.sector.cell_mesh`,
        so that a crack may run on into the rim).

    Returns
    -------
    NDArray
        ``(2, 2)``: the mouth and the tip.

    Raises
    ------
    InputError
        ``fault.side``, ``fault.depth``, ``fault.angle`` or ``fault.start`` out of range, or
        ``fault.depth`` for a crack that would leave the tooth's mesh.
    """
    if side not in ("right", "left"):
        raise InputError("fault.side", f"must be 'right' or 'left' (got {side!r})")
    depth = _check_number("fault.depth", depth)
    angle = DEFAULT_CRACK_ANGLE if angle is None else _check_number("fault.angle", angle)
    if not angle < math.pi / 2.0:
        raise InputError("fault.angle", f"must lie below 90 deg (got {math.degrees(angle):g})")
    r_cut = float(np.hypot(*tooth.nodes[tooth.right_side[0]]))
    if start is None:
        # ISO's point, raised into the fillet part where the mesh's cut lies above it (on an
        # 18-tooth gear of the paper's rack by 3.4 um): a default the mesher takes
        r = max(mouth_radius(gear), r_cut + DEFAULT_MOUTH_MARGIN * (gear.form_radius - r_cut))
    else:
        r = _check_number("fault.start", start)
    if not r_cut < r < gear.form_radius:
        raise InputError("fault.start", f"the mouth's radius {r * 1e3:.4g} mm is off the "
                         f"fillet part of the tooth's mesh: give one between "
                         f"{r_cut * 1e3:.4g} and {gear.form_radius * 1e3:.4g} mm")
    sense = 1.0 if side == "right" else -1.0
    mouth = _point_at_radius(tooth, side, r)
    tip = mouth + depth * np.array([-sense * math.cos(angle), -math.sin(angle)])
    _check_inside(tooth if region is None else region, mouth, tip)
    return np.array([mouth, tip])


def _polygon(tooth: ToothMesh, path: NDArray[np.float64]
             ) -> tuple[NDArray[np.float64], NDArray[np.float64], int, int]:
    """The polygon gmsh meshes: every structured outline node, the mouth in place of the
    mid-side node of the edge it splits.

    Returns
    -------
    points
        ``(P, 2)`` the polygon's points counter-clockwise (the mouth on its quadratic edge).
    sides
        ``(P, 3)`` each side's structured edge (row of :func:`outline.outline_edges`) and the
        edge parameters of its ends.
    mouth
        The mouth's row in ``points``.
    split
        The structured edge the mouth splits.
    """
    nodes, edges = tooth.nodes, ol.outline_edges(tooth)
    k, xi_m, dist = ol.locate(nodes, edges, path[0])
    fillet = np.concatenate([tooth.right_side[:-1], tooth.left_side[:-1]])
    r_tip = float(np.max(np.hypot(*nodes.T)))
    if dist > 1e-9 * r_tip or abs(xi_m) > 1.0 - 1e-6 or edges[k, 1] not in fillet:
        raise InputError("fault.path", "the crack's mouth must lie inside an edge of a "
                         "side of the tooth's outline (crack_path puts it there)")
    points, sides = [], []
    for e, (a, m, _) in enumerate(edges):
        mid = xi_m if e == k else 0.0
        points += [nodes[a], ol.edge_point(nodes[edges[e]], mid)]
        sides += [(e, -1.0, mid), (e, mid, 1.0)]
    return np.array(points), np.array(sides), 2 * k + 1, k


def _curves(tooth: ToothMesh, sides: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Each polygon side drawn as ``CURVE_POINTS`` points of its structured edge's parabola."""
    edges = ol.outline_edges(tooth)
    return [ol.edge_point(tooth.nodes[edges[int(e)]], np.linspace(x0, x1, CURVE_POINTS))
            for e, x0, x1 in sides]


def _onto_outline(quads: GmshQuads, tooth: ToothMesh, points: NDArray[np.float64],
                  sides: NDArray[np.float64]) -> NDArray[np.float64]:
    """gmsh's nodes with those on the outline put exactly on the structured quadratic edges.

    Along a side ``(edge, xi_0, xi_1)`` the nodes alternate corner, mid-side, corner (the
    side's ends are the polygon's points, kept exactly). A corner goes to the nearest point
    of the edge's parabola (gmsh's spline through the parabola's points is within a fraction
    of a micrometre of it); a mid-side node to the parabola's point at the mean parameter of
    its corners, so each element edge is a piece of the structured edge (module docstring of
    :mod:`spurdyn.mesh.outline`).
    """
    nodes = quads.nodes.copy()
    edges = ol.outline_edges(tooth)
    for idx, (e, x0, x1) in zip(quads.sides, sides):
        xyz = tooth.nodes[edges[int(e)]]
        guess = np.linspace(x0, x1, 65)
        pts = ol.edge_point(xyz, guess)
        xi = np.array([ol.project(xyz, nodes[n], float(guess[np.argmin(np.hypot(
            *(pts - nodes[n]).T))])) for n in idx])
        order = np.argsort(xi) if x1 > x0 else np.argsort(-xi)
        xi = np.concatenate([[x0], xi[order], [x1]])
        xi[1::2] = 0.5 * (xi[:-1:2] + xi[2::2])
        nodes[idx[order]] = ol.edge_point(xyz, xi[1:-1])
    from scipy.spatial import cKDTree

    dist, near = cKDTree(nodes).query(points)
    if np.any(dist > 1e-6 * np.ptp(points, axis=0).max()):
        raise RuntimeError("gmsh moved a point of the outline")
    nodes[near] = points
    return nodes


def counter_clockwise(nodes: NDArray[np.float64], elements: NDArray[np.intp]) -> NDArray[np.intp]:
    """The elements with their nodes counter-clockwise (clockwise ones renumbered)."""
    c = nodes[elements[:, :4]]
    area = 0.5 * np.sum(c[:, :, 0] * np.roll(c[:, :, 1], -1, axis=1)
                        - np.roll(c[:, :, 0], -1, axis=1) * c[:, :, 1], axis=1)
    flipped = elements[:, [0, 3, 2, 1, 7, 6, 5, 4]]
    return np.where((area < 0.0)[:, None], flipped, elements)


def split_seam(nodes: NDArray[np.float64], elements: NDArray[np.intp], seam: NDArray[np.intp],
               normal: NDArray[np.float64], ends: NDArray[np.float64] | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.intp]]:
    """Double the nodes ``seam`` of a straight crack (its nodes but the tips, in order): the
    elements on the side ``normal`` points to take the twins.

    An element touching the crack with nodes on both sides of its line is refused, unless
    ``ends`` (the crack's ``(2, 2)`` ends) is given and its nodes alongside the crack (between
    the ends) lie on one side: an element at the last node before a tip may reach across the
    line's extension ahead of the tip.

    Returns the nodes with the twins appended, the elements, and the ``(S, 2)`` seam.
    Raises ``RuntimeError`` if an element touching the crack lies on both of its sides.
    """
    twin = np.full(nodes.shape[0], -1, dtype=np.intp)
    twin[seam] = nodes.shape[0] + np.arange(seam.size)
    side = (nodes - nodes[seam[0]]) @ normal               # signed distance from the crack
    touching = np.flatnonzero(np.any(twin[elements] >= 0, axis=1))
    tol = 1e-9 * np.ptp(nodes, axis=0).max()
    s = side[elements[touching]]
    both = (s.max(axis=1) > tol) & (s.min(axis=1) < -tol)
    if ends is not None and np.any(both):
        along = (nodes - ends[0]) @ (ends[1] - ends[0]) / float(np.sum((ends[1] - ends[0]) ** 2))
        beside = (along > -1e-9) & (along < 1.0 + 1e-9)
        s[both] = np.where(beside[elements[touching[both]]], s[both], 0.0)
        both = (s.max(axis=1) > tol) & (s.min(axis=1) < -tol)
    if np.any(both):
        raise RuntimeError("an element straddles the crack")
    two = s.max(axis=1) > tol
    out = elements.copy()
    rows = out[touching[two]]
    out[touching[two]] = np.where(twin[rows] >= 0, twin[rows], rows)
    return np.concatenate([nodes, nodes[seam]]), out, np.stack([seam, twin[seam]], axis=1)


def _structured_map(tooth: ToothMesh, nodes: NDArray[np.float64], split: int) -> NDArray[np.intp]:
    """For each structured node the node at the same place, -1 if none (or two: the seam);
    checks that every structured outline node maps but the split edge's mid-side node."""
    from scipy.spatial import cKDTree

    tol = SAME_PLACE * float(np.max(np.hypot(*tooth.nodes.T)))
    dist, near = cKDTree(nodes).query(tooth.nodes, k=2)
    out = np.where((dist[:, 0] <= tol) & (dist[:, 1] > tol), near[:, 0], -1).astype(np.intp)
    edges = ol.outline_edges(tooth)
    need = np.setdiff1d(edges.ravel(), [edges[split, 1]])
    if np.any(out[need] < 0):
        raise RuntimeError("an outline node of the structured mesh was lost")
    return out


def default_size(tooth: ToothMesh) -> float:
    """The default element size (m): half the structured outline's median edge, corner to
    corner, so about one element per side of the polygon gmsh meshes."""
    edges = ol.outline_edges(tooth)
    chords = np.hypot(*(tooth.nodes[edges[:, 2]] - tooth.nodes[edges[:, 0]]).T)
    return 0.5 * float(np.median(chords))


def _sizes(tooth: ToothMesh, path: NDArray[np.float64], tip_size: float | None,
           size: float | None) -> tuple[float, float]:
    """The element sizes: ``size`` by default :func:`default_size`, ``tip_size`` by default ``TIP_SIZE_SHARE`` of the smaller of ``size`` and the
    crack's length."""
    size = default_size(tooth) if size is None else _check_number("fault.size", size)
    depth = float(np.hypot(*(path[-1] - path[-2])))          # the last piece's
    tip = TIP_SIZE_SHARE * min(size, depth) if tip_size is None else \
        _check_number("fault.tip_size", tip_size)
    if tip > size:
        raise InputError("fault.tip_size", f"must not exceed the element size {size:g} m "
                         f"(got {tip:g})")
    return size, tip


def _mesh(curves: list[NDArray[np.float64]], mouth: int, tip: NDArray[np.float64], size: float,
          tip_size: float) -> GmshQuads:
    """gmsh's mesh at ``size``, or at a slightly smaller size if gmsh's full-quad
    recombination refuses it (it must halve every curve's 1D mesh, which some sizes beside
    the polygon's sides do not allow); the last refusal is raised."""
    for share in RETRY_SHARES[:-1]:
        try:
            return mesh_with_crack(curves, mouth, tip, share * size, min(tip_size, share * size))
        except InputError:
            continue
    share = RETRY_SHARES[-1]
    return mesh_with_crack(curves, mouth, tip, share * size, min(tip_size, share * size))


def outline_ties(tooth: ToothMesh, cracked: CrackedTooth
                 ) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.float64]]:
    """The cracked mesh's outline nodes that the structured mesh does not have, each as the
    structured edge's quadratic interpolation of its three nodes.

    gmsh's full-quad meshes split every structured outline edge into two or more element
    edges, all on the structured edge's parabola. Tying each extra node's displacement to
    ``sum_i N_i(xi) u_i`` over the structured edge's nodes ``(a, m, b)`` (their cracked-mesh
    twins, ``structured``) makes the cracked tooth's trace on that edge the structured Q8
    edge's, so the tooth joins a rim meshed for the structured tooth without a gap.

    Returns
    -------
    nodes
        ``(T,)`` the extra nodes of the cracked mesh.
    parents
        ``(T, 3)`` the cracked mesh's nodes at the structured edge's ``a``, ``m``, ``b``.
        The fillet edge the mouth splits has no ``m``: its nodes are left out (a flank is
        free surface; only the curve under the tooth must meet the rim).
    weights
        ``(T, 3)`` the edge's shape functions at the node.
    """
    edges = ol.outline_edges(tooth)
    mapped = cracked.structured[edges]
    r_tip = float(np.max(np.hypot(*tooth.nodes.T)))
    own = np.setdiff1d(np.arange(cracked.nodes.shape[0]), cracked.structured)
    from scipy.spatial import cKDTree

    # the outline sampled finely enough that a node on it is within 1e-3 r_tip of a sample
    dense = ol.polygon(tooth.nodes, edges)
    gap = float(np.max(np.hypot(*np.diff(dense, axis=0).T)))
    near = own[cKDTree(dense).query(cracked.nodes[own])[0] < 1e-3 * r_tip + gap]
    out = []
    for node, (k, xi, dist) in zip(near, ol.locate_many(tooth.nodes, edges, cracked.nodes[near])):
        if dist <= 1e-9 * r_tip and np.all(mapped[k] >= 0):
            out.append((node, k, xi))
    nodes = np.array([o[0] for o in out], dtype=np.intp)
    parents = mapped[np.array([o[1] for o in out], dtype=np.intp)].reshape(-1, 3)
    weights = np.array([edge_weights(o[2]) for o in out]).reshape(-1, 3)
    return nodes, parents, weights


def cracked_tooth(gear: Gear, tooth: ToothMesh, path: NDArray[np.float64],
                  tip_size: float | None = None, size: float | None = None) -> CrackedTooth:
    """Mesh ``tooth``'s outline again with the crack ``path`` (:func:`crack_path`) in it.

    Parameters
    ----------
    gear
        The gear (unused by the mesh itself; kept so the signature matches :func:`crack_path`).
    tooth
        The structured tooth mesh whose outline (and outline nodes) the cracked mesh keeps.
    path
        ``(k, 2)`` the crack's mouth, on a side's fillet edge, then its kinks (a crack that
        has grown, :mod:`spurdyn.mesh.polyline`) and its tip, inside the tooth.
    tip_size, size
        Element sizes at the tip and elsewhere (m); defaults in :func:`_sizes`.

    Returns
    -------
    CrackedTooth

    Raises
    ------
    InputError
        ``fault.path`` for a mouth off the outline's sides, ``fault.depth`` for a crack
        leaving the tooth, ``fault.size``/``fault.tip_size`` for sizes out of range or a mesh
        gmsh could not make of quads with positive Jacobians.
    """
    del gear
    path = np.asarray(path, dtype=float)
    if path.ndim != 2 or path.shape[0] < 2 or path.shape[1] != 2 or not np.all(np.isfinite(path)):
        raise InputError("fault.path", f"must be a (k, 2) array, k >= 2: mouth, kinks, tip "
                         f"(got {path!r})")
    points, sides, mouth, split = _polygon(tooth, path)
    _check_inside(tooth, points[mouth], path[1:])
    size, tip_size = _sizes(tooth, path, tip_size, size)
    quads = _mesh(_curves(tooth, sides), mouth, path[1:], size, tip_size)
    nodes = _onto_outline(quads, tooth, points, sides)
    elements = counter_clockwise(nodes, quads.elements)
    if not np.all(jacobian_determinants(nodes, elements) > 0.0):
        raise InputError("fault.size", "an element of the cracked mesh has a non-positive "
                         "Jacobian; try another element size")
    d = (path[1] - points[mouth]) / np.hypot(*(path[1] - points[mouth]))
    n = np.array([-d[1], d[0]])
    sense = -1.0 if n[1] < 0.0 else 1.0                             # toward the tip circle
    if path.shape[0] > 2:
        from spurdyn.mesh.polyline import split_polyline_seam

        full = np.vstack([points[mouth][None], path[1:]])
        try:
            nodes, elements, seam, normal = split_polyline_seam(nodes, elements, quads.crack[:-1],
                                                                full, sense)
        except RuntimeError as error:
            raise InputError("fault.size", "gmsh's elements do not follow the crack; try "
                             "another element size") from error
    else:
        nodes, elements, seam = split_seam(nodes, elements, quads.crack[:-1], sense * n)
        normal = np.tile(sense * n, (seam.shape[0], 1))
    return CrackedTooth(nodes=nodes, elements=elements,
                        structured=_structured_map(tooth, nodes, split), seam=seam,
                        normal=normal, tip=int(quads.crack[-1]))
