"""gmsh's 8-node quadrilaterals in a region bounded by splines, with an embedded straight line
(a crack).

gmsh (the Python API of the package on the package index) meshes the region with the crack
embedded, refining toward the crack's tip by a distance threshold (the interior; the curves
get even segment counts from the same sizes, :func:`_segments`); quads come from the
Frontal-Delaunay for quads algorithm and the Blossom full-quad recombination (a mesh at twice
the size, recombined, then split, so no triangle is left), made second order and incomplete
(8 nodes). gmsh keeps global state and is not thread-safe: one mesh at a time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError

#: gmsh's element type of the 8-node quadrilateral; its node order is spurdyn's Q8 order
#: (corners, then the mid-side after each corner).
GMSH_QUAD8 = 16
#: Growth of the element size away from the tip: it reaches the size elsewhere this many
#: element sizes from the tip.
GROWTH_DISTANCE = 3.0


@dataclass(frozen=True)
class GmshQuads:
    """What gmsh made, in the caller's units.

    Attributes
    ----------
    nodes
        ``(N, 2)`` node coordinates.
    elements
        ``(E, 8)`` node indices in gmsh's 8-node order (orientation not checked).
    sides
        For each side of the outline, the nodes gmsh put inside it (ends left out).
    crack
        The crack's nodes from the mouth to the tip, both ends included (a polyline's kinks
        once).
    """

    nodes: NDArray[np.float64]
    elements: NDArray[np.intp]
    sides: tuple[NDArray[np.intp], ...]
    crack: NDArray[np.intp]


def _set_options(gmsh: object) -> None:
    """Quads only, second order incomplete (8 nodes), sizes from the field and the curves'
    segment counts only (none from points, curvature or the boundary)."""
    for name, value in (("General.Terminal", 0), ("Mesh.MeshSizeExtendFromBoundary", 0),
                        ("Mesh.MeshSizeFromPoints", 0), ("Mesh.MeshSizeFromCurvature", 0),
                        ("Mesh.Algorithm", 8), ("Mesh.RecombineAll", 1),
                        ("Mesh.RecombinationAlgorithm", 3), ("Mesh.ElementOrder", 2),
                        ("Mesh.SecondOrderIncomplete", 1)):
        gmsh.option.setNumber(name, value)


def _geometry(gmsh: object, curves: list[NDArray[np.float64]], mouth: int,
              path: NDArray[np.float64], size: float, tip_size: float) -> tuple[list[int], list[int], int]:
    """The polygon's surface with the crack embedded; its sides', crack's and tip's tags.
    The crack runs from side ``mouth``'s first point through ``path`` ``(k, 2)`` (its kinks,
    then its tip), one line a piece. Every line gets an even number of segments
    (:func:`_segments`); the crack's shrink geometrically toward the tip."""
    geo = gmsh.model.geo
    tags, surface, sides = _outline(gmsh, curves)
    ends = [tags[mouth]] + [geo.addPoint(float(x), float(y), 0.0) for x, y in path]
    lines = [geo.addLine(a, b) for a, b in zip(ends[:-1], ends[1:])]
    geo.synchronize()
    tip = path[-1]
    _count_sides(gmsh, curves, sides, tip[None], size, tip_size)
    points = np.vstack([curves[mouth][0][None], path])
    for line, p, q in zip(lines, points[:-1], points[1:]):
        _grade(gmsh, line, p, q, tip[None], size, tip_size)
    gmsh.model.mesh.embed(1, lines, 2, surface)
    return sides, lines, ends[-1]


def _grade(gmsh: object, line: int, p: NDArray[np.float64], q: NDArray[np.float64],
           tips: NDArray[np.float64], size: float, tip_size: float) -> None:
    """An even number of segments on the line ``p q`` shrinking geometrically toward ``q``."""
    n, h_p, h_q = _segments(p, q, tips, size, tip_size)
    ratio = (h_q / h_p) ** (1.0 / max(n - 1, 1))
    gmsh.model.mesh.setTransfiniteCurve(line, n + 1, "Progression", ratio)


def _outline(gmsh: object, curves: list[NDArray[np.float64]]) -> tuple[list[int], int, list[int]]:
    """The region inside ``curves`` (splines): its corners' tags, its surface's and its
    sides'."""
    geo = gmsh.model.geo
    tags = [geo.addPoint(float(c[0, 0]), float(c[0, 1]), 0.0) for c in curves]
    sides = []
    for i, c in enumerate(curves):
        inner = [geo.addPoint(float(x), float(y), 0.0) for x, y in c[1:-1]]
        sides.append(geo.addSpline([tags[i]] + inner + [tags[(i + 1) % len(tags)]]))
    surface = geo.addPlaneSurface([geo.addCurveLoop(sides)])
    return tags, surface, sides


def _count_sides(gmsh: object, curves: list[NDArray[np.float64]], sides: list[int],
                 tips: NDArray[np.float64], size: float, tip_size: float) -> None:
    """Every side's even segment count; after the last ``synchronize``, which would reset
    it."""
    for c, side in zip(curves, sides):
        n, _, _ = _segments(c[0], c[-1], tips, size, tip_size)
        gmsh.model.mesh.setTransfiniteCurve(side, n + 1)


def _inner_geometry(gmsh: object, curves: list[NDArray[np.float64]], ends: NDArray[np.float64],
                    size: float, tip_size: float) -> list[int]:
    """The region with a crack whose two ends lie inside it embedded, as two lines from its
    middle, each graded toward its end; returns the ends' tags."""
    geo = gmsh.model.geo
    _, surface, sides = _outline(gmsh, curves)
    middle = 0.5 * (ends[0] + ends[1])
    m = geo.addPoint(float(middle[0]), float(middle[1]), 0.0)
    tips = [geo.addPoint(float(x), float(y), 0.0) for x, y in ends]
    lines = [geo.addLine(m, t) for t in tips]
    geo.synchronize()
    _count_sides(gmsh, curves, sides, ends, size, tip_size)
    for line, end in zip(lines, ends):
        _grade(gmsh, line, middle, end, ends, size, tip_size)
    gmsh.model.mesh.embed(1, lines, 2, surface)
    return tips


def _size_at(distance: NDArray[np.float64], size: float, tip_size: float) -> NDArray[np.float64]:
    """The element size the threshold field asks at ``distance`` from the tip."""
    return np.clip(tip_size + (size - tip_size) * distance / (GROWTH_DISTANCE * size),
                   tip_size, size)


def _segments(p: NDArray[np.float64], q: NDArray[np.float64], tip: NDArray[np.float64],
              size: float, tip_size: float) -> tuple[int, float, float]:
    """An even number of segments for the line ``p q`` (about ``int ds / h``), and the sizes
    the field asks at its ends; ``tip`` is one tip ``(2,)`` or several ``(k, 2)``, the size
    set by the nearest.

    Even because gmsh's full-quad recombination meshes the surface on every other node of
    each curve's 1D mesh, then splits the quads: an odd count stops it ("1D mesh cannot be
    divided by 2").
    """
    s = np.linspace(0.0, 1.0, 65)
    pts = p + s[:, None] * (q - p)
    tips = np.atleast_2d(tip)
    h = _size_at(np.min(np.hypot(*(pts[None] - tips[:, None]).transpose(2, 0, 1)), axis=0),
                 size, tip_size)
    count = float(np.hypot(*(q - p)) * np.mean(1.0 / h))
    return 2 * max(1, int(np.ceil(0.5 * count))), float(h[0]), float(h[-1])


def _size_field(gmsh: object, tip_tags: list[int], size: float, tip_size: float) -> None:
    """Element size ``tip_size`` at the tips, growing linearly to ``size``."""
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", tip_tags)
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", tip_size)
    field.setNumber(threshold, "SizeMax", size)
    field.setNumber(threshold, "DistMin", 0.0)
    field.setNumber(threshold, "DistMax", GROWTH_DISTANCE * size)
    field.setAsBackgroundMesh(threshold)


def element_edges(elements: NDArray[np.intp]) -> NDArray[np.intp]:
    """Every element's four edges, ``(4 E, 3)``: corner, mid-side, corner, in the element's
    order (each inner edge twice, once from either element)."""
    return np.concatenate([elements[:, [0, 4, 1]], elements[:, [1, 5, 2]],
                           elements[:, [2, 6, 3]], elements[:, [3, 7, 0]]])


def boundary_edges(elements: NDArray[np.intp]) -> NDArray[np.intp]:
    """The element edges that belong to one element only (the outline, a crack's faces),
    ``(B, 3)``: corner, mid-side, corner, counter-clockwise around their element."""
    trips = element_edges(elements)
    key = np.sort(trips[:, [0, 2]], axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return trips[counts[inverse.ravel()] == 1]


def boundary_nodes(elements: NDArray[np.intp]) -> NDArray[np.intp]:
    """The nodes of the element edges that belong to one element only (the outline)."""
    return np.unique(boundary_edges(elements))


def _side_nodes(nodes: NDArray[np.float64], elements: NDArray[np.intp],
                curves: list[NDArray[np.float64]]) -> tuple[NDArray[np.intp], ...]:
    """For each side, the outline nodes inside it (its end points left out).

    Taken from the elements (edges of one element), each node given to the side whose
    points pass nearest, rather than from gmsh's classification of nodes on curves, which
    after the full-quad split can put an interior edge's mid-side node on a curve.
    """
    on = boundary_nodes(elements)
    ends = np.array([c[0] for c in curves])
    span = float(np.ptp(ends, axis=0).max())
    at_end = np.min(np.hypot(*(nodes[on][:, None, :] - ends[None]).transpose(2, 0, 1)), axis=1)
    on = on[at_end > 1e-9 * span]
    dense = [np.linspace(c[:-1], c[1:], 9, axis=1).reshape(-1, 2) for c in curves]
    dist = np.stack([np.min(np.hypot(*(nodes[on][:, None, :] - d[None]).transpose(2, 0, 1)),
                            axis=1) for d in dense], axis=1)
    which = np.argmin(dist, axis=1)
    return tuple(on[which == i] for i in range(len(curves)))


def _crack_nodes(nodes: NDArray[np.float64], path: NDArray[np.float64]) -> NDArray[np.intp]:
    """The nodes on the crack ``path`` ``(k, 2)`` (mouth, kinks, tip), mouth to tip: those on
    its pieces (the mesh conforms to the embedded lines, so no element edge crosses them),
    each kink once."""
    found: list[NDArray[np.intp]] = []
    for i, (mouth, tip) in enumerate(zip(path[:-1], path[1:])):
        d = tip - mouth
        u = (nodes - mouth) @ d / float(d @ d)
        off = np.abs((nodes - mouth) @ np.array([-d[1], d[0]])) / float(d @ d)
        on = np.flatnonzero((off < 1e-9) & (u > -1e-9) & (u < 1.0 + 1e-9))
        on = on[np.argsort(u[on])]
        found.append(on if i == 0 else on[1:])
    return np.concatenate(found)


def _read(gmsh: object, curves: list[NDArray[np.float64]], scale: float,
          origin: NDArray[np.float64], key: str) -> GmshQuads:
    """The mesh gmsh made, nodes renumbered from 0, back in the caller's units."""
    mesh = gmsh.model.mesh
    types = set(mesh.getElementTypes(2))
    if types != {GMSH_QUAD8}:
        names = sorted(mesh.getElementProperties(t)[0] for t in types)
        raise InputError(key, f"gmsh left elements other than 8-node quads "
                         f"({', '.join(names)}); try another element size")
    tags, xyz, _ = mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.intp)
    index[tags.astype(np.intp)] = np.arange(tags.size)
    nodes = xyz.reshape(-1, 3)[:, :2] / scale + origin
    _, connectivity = mesh.getElementsByType(GMSH_QUAD8)
    elements = index[connectivity.astype(np.intp)].reshape(-1, 8)
    used = np.unique(elements)            # the splines' control points are nodes of no element
    renumber = np.full(nodes.shape[0], -1, dtype=np.intp)
    renumber[used] = np.arange(used.size)
    nodes, elements = nodes[used], renumber[elements]
    return GmshQuads(nodes=nodes, elements=elements, sides=_side_nodes(nodes, elements, curves),
                     crack=np.zeros(0, dtype=np.intp))


def mesh_with_crack(curves: list[NDArray[np.float64]], mouth: int, tip: NDArray[np.float64],
                    size: float, tip_size: float) -> GmshQuads:
    """Mesh the region inside ``curves`` (the outline's sides counter-clockwise, each
    ``(k, 2)`` points from its first point to the next side's) with the crack from side
    ``mouth``'s first point to ``tip`` embedded, element size ``size`` refined to
    ``tip_size`` at the tip. ``tip`` is the tip ``(2,)`` of a straight crack, or ``(k, 2)``
    the kinks of a polyline crack then its tip.

    gmsh is started and always finalized here (:func:`_generate`).

    Raises
    ------
    InputError
        ``fault.size`` if gmsh fails (its full-quad recombination refuses a curve it cannot
        halve when the size is large beside the polygon's sides) or leaves an element other
        than an 8-node quad.
    """
    points = np.array([c[0] for c in curves])
    path = np.atleast_2d(np.asarray(tip, dtype=float))

    def build(gmsh: object, scaled: list[NDArray[np.float64]], at: Callable,
              h_tip: float) -> list[int]:
        _, _, tip_tag = _geometry(gmsh, scaled, mouth, at(path), 1.0, h_tip)
        return [tip_tag]

    quads = _generate(curves, build, size, tip_size, "fault.size", "the cracked tooth")
    return GmshQuads(nodes=quads.nodes, elements=quads.elements, sides=quads.sides,
                     crack=_crack_nodes(quads.nodes, np.vstack([points[mouth][None], path])))


def mesh_region(curves: list[NDArray[np.float64]], size: float, key: str) -> GmshQuads:
    """Mesh the region inside ``curves`` (as :func:`mesh_with_crack`) with nothing embedded,
    the element size ``size`` throughout (a chipped tooth, :mod:`spurdyn.mesh.chipped`).

    Raises
    ------
    InputError
        ``key`` if gmsh fails or leaves an element other than an 8-node quad.
    """
    def build(gmsh: object, scaled: list[NDArray[np.float64]], at: Callable,
              h_tip: float) -> list[int]:
        tags, _, sides = _outline(gmsh, scaled)
        gmsh.model.geo.synchronize()
        _count_sides(gmsh, scaled, sides, scaled[0][0][None], 1.0, 1.0)
        return tags[:1]

    return _generate(curves, build, size, size, key, "the region")


def mesh_with_inner_crack(curves: list[NDArray[np.float64]], ends: NDArray[np.float64],
                          size: float, tip_size: float, key: str) -> GmshQuads:
    """Mesh the region inside ``curves`` (as :func:`mesh_with_crack`) with a crack whose two
    ends ``ends`` ``(2, 2)`` both lie inside it, refined to ``tip_size`` at both; the crack's
    nodes run from ``ends[0]`` to ``ends[1]``.

    Raises
    ------
    InputError
        ``key`` if gmsh fails or leaves an element other than an 8-node quad.
    """
    ends = np.asarray(ends, dtype=float)

    def build(gmsh: object, scaled: list[NDArray[np.float64]], at: Callable,
              h_tip: float) -> list[int]:
        return _inner_geometry(gmsh, scaled, at(ends), 1.0, h_tip)

    quads = _generate(curves, build, size, tip_size, key, "the region")
    return GmshQuads(nodes=quads.nodes, elements=quads.elements, sides=quads.sides,
                     crack=_crack_nodes(quads.nodes, ends))


def _restore_sigpipe() -> None:
    """Give SIGPIPE back the disposition Python keeps for it (ignored: a write to a closed
    pipe raises ``BrokenPipeError``). gmsh's initialisation sets it to the default behind
    Python's back, after which such a write ends the whole process without a word (a run's
    writer process gone, a reader of the output closed). Outside the main thread a signal
    cannot be set: left as it is there."""
    import signal

    if hasattr(signal, "SIGPIPE"):
        try:
            signal.signal(signal.SIGPIPE, signal.getsignal(signal.SIGPIPE))
        except ValueError:
            pass


def _generate(curves: list[NDArray[np.float64]], build: Callable, size: float, tip_size: float,
              key: str, what: str) -> GmshQuads:
    """Start gmsh, let ``build(gmsh, scaled curves, to scaled, scaled tip size)`` draw the
    geometry and return the tips' tags, refine to them, mesh, read, and always finalize gmsh.

    gmsh works in coordinates scaled to the element size's order (its tolerances are
    absolute); the nodes come back in the caller's units.
    """
    import gmsh      # imported when used: loading gmsh's library takes a moment

    points = np.array([c[0] for c in curves])
    origin = points.mean(axis=0)
    scale = 1.0 / size
    # not interruptible: gmsh would install a SIGINT handler, which only the main thread may
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    _restore_sigpipe()
    try:
        _set_options(gmsh)
        gmsh.model.add(what)
        tips = build(gmsh, [(c - origin) * scale for c in curves],
                     lambda x: (np.asarray(x) - origin) * scale, tip_size * scale)
        _size_field(gmsh, tips, 1.0, tip_size * scale)
        try:
            gmsh.model.mesh.generate(2)
        except Exception as error:      # gmsh raises a bare Exception with its last message
            raise InputError(key, f"gmsh could not mesh {what} ({error}); "
                             "try a smaller element size") from error
        return _read(gmsh, curves, scale, origin, key)
    finally:
        gmsh.finalize()
