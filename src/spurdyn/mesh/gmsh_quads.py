"""gmsh's 8-node quadrilaterals in a polygon with an embedded straight line (a crack).

gmsh (the Python API of the package on the package index) meshes the polygon with the crack
embedded, refining toward the crack's tip by a distance threshold; quads come from the
Frontal-Delaunay for quads algorithm and the Blossom full-quad recombination (a mesh at twice
the size, recombined, then split, so no triangle is left), made second order and incomplete
(8 nodes). gmsh keeps global state and is not thread-safe: one mesh at a time.
"""

from __future__ import annotations

from dataclasses import dataclass

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
        For each polygon side ``i`` (from point ``i`` to point ``i + 1``), the nodes gmsh put
        inside it and their parameters ``u`` in ``(0, 1)`` along it.
    crack
        The crack line's nodes from the mouth to the tip, both ends included.
    """

    nodes: NDArray[np.float64]
    elements: NDArray[np.intp]
    sides: tuple[tuple[NDArray[np.intp], NDArray[np.float64]], ...]
    crack: NDArray[np.intp]


def _set_options(gmsh: object) -> None:
    """Quads only, second order incomplete (8 nodes), sizes from the field alone."""
    for name, value in (("General.Terminal", 0), ("Mesh.MeshSizeExtendFromBoundary", 0),
                        ("Mesh.MeshSizeFromPoints", 0), ("Mesh.MeshSizeFromCurvature", 0),
                        ("Mesh.Algorithm", 8), ("Mesh.RecombineAll", 1),
                        # Blossom's recombination, then every element split into quads: the
                        # full-quad Blossom (3) refuses a polygon whose sides it cannot halve,
                        # as a tooth's whole cell down to the hub
                        ("Mesh.RecombinationAlgorithm", 1), ("Mesh.ElementOrder", 2),
                        ("Mesh.SecondOrderIncomplete", 1), ("Mesh.SubdivisionAlgorithm", 1)):
        gmsh.option.setNumber(name, value)


def _geometry(gmsh: object, points: NDArray[np.float64], mouth: int, tip: NDArray[np.float64]
              ) -> tuple[list[int], int, int]:
    """The polygon's surface with the crack embedded; its sides', crack's and tip's tags."""
    geo = gmsh.model.geo
    tags = [geo.addPoint(float(x), float(y), 0.0) for x, y in points]
    sides = [geo.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
    surface = geo.addPlaneSurface([geo.addCurveLoop(sides)])
    tip_tag = geo.addPoint(float(tip[0]), float(tip[1]), 0.0)
    crack = geo.addLine(tags[mouth], tip_tag)
    geo.synchronize()
    gmsh.model.mesh.embed(1, [crack], 2, surface)
    return sides, crack, tip_tag


def _size_field(gmsh: object, tip_tag: int, size: float, tip_size: float) -> None:
    """Element size ``tip_size`` at the tip, growing linearly to ``size``."""
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", [tip_tag])
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", tip_size)
    field.setNumber(threshold, "SizeMax", size)
    field.setNumber(threshold, "DistMin", 0.0)
    field.setNumber(threshold, "DistMax", GROWTH_DISTANCE * size)
    field.setAsBackgroundMesh(threshold)


def _read(gmsh: object, points: NDArray[np.float64], sides: list[int], crack: int,
          scale: float, origin: NDArray[np.float64]) -> GmshQuads:
    """The mesh gmsh made, nodes renumbered from 0, back in the caller's units."""
    mesh = gmsh.model.mesh
    types = set(mesh.getElementTypes(2))
    if types != {GMSH_QUAD8}:
        names = sorted(mesh.getElementProperties(t)[0] for t in types)
        raise InputError("fault.size", f"gmsh left elements other than 8-node quads "
                         f"({', '.join(names)}); try another element size")
    tags, xyz, _ = mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.intp)
    index[tags.astype(np.intp)] = np.arange(tags.size)
    nodes = xyz.reshape(-1, 3)[:, :2] / scale + origin
    _, connectivity = mesh.getElementsByType(GMSH_QUAD8)
    elements = index[connectivity.astype(np.intp)].reshape(-1, 8)
    out = []
    for i, side in enumerate(sides):
        on, _, _ = mesh.getNodes(1, side, includeBoundary=False)
        a, b = points[i], points[(i + 1) % len(points)]
        idx = index[on.astype(np.intp)]
        u = (nodes[idx] - a) @ (b - a) / float((b - a) @ (b - a))
        out.append((idx, u))
    on, _, _ = mesh.getNodes(1, crack, includeBoundary=True)
    return GmshQuads(nodes=nodes, elements=elements, sides=tuple(out),
                     crack=np.unique(index[on.astype(np.intp)]))


def mesh_with_crack(points: NDArray[np.float64], mouth: int, tip: NDArray[np.float64],
                    size: float, tip_size: float) -> GmshQuads:
    """Mesh the polygon ``points`` (counter-clockwise) with the crack from point ``mouth`` to
    ``tip`` embedded, element size ``size`` refined to ``tip_size`` at the tip.

    gmsh works in coordinates scaled to the element size's order (its tolerances are
    absolute); the nodes come back in the caller's units. gmsh is started and always
    finalized here.

    Raises
    ------
    InputError
        ``fault.size`` if gmsh fails (its full-quad recombination refuses a curve it cannot
        halve when the size is large beside the polygon's sides) or leaves an element other
        than an 8-node quad.
    """
    import gmsh      # imported when used: loading gmsh's library takes a moment

    origin = points.mean(axis=0)
    scale = 1.0 / size
    gmsh.initialize(readConfigFiles=False)
    try:
        _set_options(gmsh)
        gmsh.model.add("cracked tooth")
        sides, crack, tip_tag = _geometry(gmsh, (points - origin) * scale, mouth,
                                          (tip - origin) * scale)
        _size_field(gmsh, tip_tag, 1.0, tip_size * scale)
        try:
            gmsh.model.mesh.generate(2)
        except Exception as error:      # gmsh raises a bare Exception with its last message
            raise InputError("fault.size", f"gmsh could not mesh the cracked tooth ({error}); "
                             "try a smaller element size") from error
        quads = _read(gmsh, points, sides, crack, scale, origin)
    finally:
        gmsh.finalize()
    order = np.argsort(np.hypot(*(quads.nodes[quads.crack] - points[mouth]).T))
    return GmshQuads(nodes=quads.nodes, elements=quads.elements, sides=quads.sides,
                     crack=quads.crack[order])
