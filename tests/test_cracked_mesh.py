"""The cracked tooth's mesh (spurdyn.mesh.cracked): gmsh's quads inside the structured
tooth's outline, a seam of twin nodes along a straight root crack (docs/faults.md, "Root
crack: the cracked tooth's mesh")."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.fem.element import gauss_2d
from spurdyn.geometry.presets import paper_gear
from spurdyn.mesh import outline as ol
from spurdyn.mesh.cracked import (
    CrackedTooth, crack_path, cracked_tooth, default_size, mouth_radius, outline_ties,
)
from spurdyn.mesh.tooth import tooth_mesh

_SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "cracked_tooth_mesh.py"
_spec = importlib.util.spec_from_file_location("cracked_tooth_mesh", _SCRIPT)
figures = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(figures)

GEAR = paper_gear()
TOL = 1e-12 * GEAR.tip_radius


@pytest.fixture(scope="module")
def tooth():
    return tooth_mesh(GEAR)


@pytest.fixture(scope="module", params=["right", "left"])
def cracked(request, tooth):
    path = crack_path(GEAR, tooth, request.param, 0.15e-3)
    return path, cracked_tooth(GEAR, tooth, path)


def _area(nodes, elements) -> float:
    return float((jacobian_determinants(nodes, elements) * gauss_2d(3)[1]).sum())


def test_elements_are_q8_with_positive_jacobians(cracked):
    _, c = cracked
    assert isinstance(c, CrackedTooth)
    assert c.elements.shape[1] == 8 and c.elements.shape[0] > 100
    assert np.all(jacobian_determinants(c.nodes, c.elements) > 0.0)
    # every node is used: no orphan (a spline's control point) left in
    assert np.unique(c.elements).size == c.nodes.shape[0]


def test_area_is_the_structured_tooth_s(cracked, tooth):
    """The outline's element edges are pieces of the structured quadratic edges: the same
    curve, so the Gauss quadrature of det J gives the same area (the crack encloses none)."""
    _, c = cracked
    a0 = _area(tooth.nodes, tooth.elements)
    assert abs(_area(c.nodes, c.elements) / a0 - 1.0) < 1e-9


def test_structured_nodes_map_to_the_same_places(cracked, tooth):
    path, c = cracked
    assert c.structured.shape == (tooth.n_nodes,)
    hit = c.structured >= 0
    assert np.all(np.abs(c.nodes[c.structured[hit]] - tooth.nodes[hit]) <= TOL)
    edges = ol.outline_edges(tooth)
    k, xi, _ = ol.locate(tooth.nodes, edges, path[0])
    lost = [n for n in np.unique(edges) if c.structured[n] < 0]
    assert lost == [edges[k, 1]]        # only the mid-side node of the edge the mouth splits
    assert abs(xi) < 1.0


def test_seam_twins_coincide_and_faces_are_disjoint(cracked):
    path, c = cracked
    one, two = c.seam.T
    assert np.all(one != two) and c.tip not in c.seam
    assert np.all(np.abs(c.nodes[one] - c.nodes[two]) == 0.0)
    assert np.allclose(c.nodes[one[0]], path[0], atol=TOL)          # mouth first
    d = (path[1] - path[0]) / np.hypot(*(path[1] - path[0]))
    along = (c.nodes[one] - path[0]) @ d
    assert np.all(np.diff(along) > 0) and along[-1] < np.hypot(*(path[1] - path[0]))
    assert np.allclose(c.nodes[c.tip], path[1], atol=TOL)
    assert np.allclose(np.abs((c.nodes[one] - path[0]) @ c.normal[0]), 0.0, atol=TOL)
    assert np.allclose(np.hypot(*c.normal.T), 1.0) and np.allclose(c.normal @ d, 0.0)
    on_one = np.any(np.isin(c.elements, one), axis=1)
    on_two = np.any(np.isin(c.elements, two), axis=1)
    assert on_one.any() and on_two.any() and not np.any(on_one & on_two)
    # no element straddles the crack: face one's below the line, face two's above it
    side = (c.nodes - path[0]) @ c.normal[0]
    tol = 1e-9 * GEAR.tip_radius
    assert np.all(side[c.elements[on_one]] <= tol) and np.all(side[c.elements[on_two]] >= -tol)


def test_mouth_is_iso_s_30_degree_tangent_point(tooth):
    """The default mouth: the fillet's tangent makes 30 deg with the centre line there."""
    r = mouth_radius(GEAR)
    h = 1e-9
    t = GEAR.right_side_point(r + h) - GEAR.right_side_point(r - h)
    assert math.degrees(math.atan2(abs(t[0]), abs(t[1]))) == pytest.approx(30.0, abs=1e-4)
    path = crack_path(GEAR, tooth, "right", 0.1e-3)
    assert np.hypot(*path[0]) == pytest.approx(r, abs=TOL)
    left = crack_path(GEAR, tooth, "left", 0.1e-3)
    assert np.allclose(left * [-1.0, 1.0], path, atol=TOL)
    d = path[1] - path[0]      # 45 deg below the line across the tooth, toward the centre line
    assert d[0] < 0 and math.degrees(math.atan2(-d[1], -d[0])) == pytest.approx(45.0)


def test_ties_reproduce_the_structured_edges(cracked, tooth):
    """An outline node the structured mesh lacks lies on its edge's parabola: the quadratic
    interpolation of the edge's nodes puts it where it is, and so ties it to the rim."""
    _, c = cracked
    nodes, parents, weights = outline_ties(tooth, c)
    assert nodes.size > 0 and np.all(parents >= 0)
    assert np.allclose(weights.sum(axis=1), 1.0)
    assert np.all(np.abs(np.einsum("ti,tij->tj", weights, c.nodes[parents])
                         - c.nodes[nodes]) <= 1e-9 * GEAR.tip_radius)
    bottom = figures.bottom_nodes(tooth, c)
    assert np.unique(bottom).size > tooth.root_nodes.size


@pytest.fixture(scope="module")
def compliances():
    """The table of docs/faults.md at two of its sizes: fillet cut 20 deg, crack 0.5 mm."""
    tooth = tooth_mesh(GEAR, cut_angle=math.radians(20.0))
    size = default_size(tooth)
    rows = [figures.row(GEAR, tooth, 0.5e-3, share, size) for share in (1.0, 0.5)]
    structured = figures.compliance(tooth.nodes, tooth.elements, tooth.root_nodes, GEAR)
    return rows, structured


def test_crack_softens_the_tooth_and_converges(compliances):
    rows, structured = compliances
    coarse, fine = rows
    for r in rows:
        assert r["cracked"] > 1.02 * r["tied"]           # a 0.5 mm root crack: about +3.3 %
        assert r["cracked"] > 1.02 * structured
    # displacement elements are too stiff: refining softens, by far less than the crack does
    assert fine["cracked"] >= coarse["cracked"]
    assert (fine["cracked"] - coarse["cracked"]) < 0.05 * (fine["cracked"] - fine["tied"])
    assert fine["elements"] > 2 * coarse["elements"]


def test_tied_faces_give_back_the_structured_tooth(compliances):
    """Faces tied again: the structured tooth, but for the two meshes' difference."""
    rows, structured = compliances
    for r in rows:
        assert r["tied"] == pytest.approx(structured, rel=0.01)
        assert r["tied"] >= structured                   # the finer mesh is the softer


def test_crack_opens_on_the_tension_side(tooth):
    """The tip pushed toward -x bends the right fillet open: the faces part along the normal."""
    import scipy.sparse.linalg as spla
    from spurdyn.fem.assembly import assemble_stiffness

    path = crack_path(GEAR, tooth, "right", 0.15e-3)
    c = cracked_tooth(GEAR, tooth, path)
    n = 2 * c.nodes.shape[0]
    fx, _ = figures.tip_load(c.nodes, figures.tip_edges(c.nodes, c.elements, GEAR.tip_radius))
    f = np.zeros(n)
    f[0::2] = fx
    fixed = figures.bottom_nodes(tooth, c)
    free = np.setdiff1d(np.arange(n), np.concatenate([2 * fixed, 2 * fixed + 1]))
    k = assemble_stiffness(c.nodes, c.elements, GEAR.material, GEAR.face_width).tocsr()
    u = np.zeros(n)
    u[free] = spla.spsolve(k[free][:, free].tocsc(), f[free])
    d = u.reshape(-1, 2)
    opening = np.sum((d[c.seam[:, 1]] - d[c.seam[:, 0]]) * c.normal, axis=1)
    assert np.all(opening > 0.0) and opening[0] > opening[-1]


@pytest.mark.parametrize("kwargs, key", [
    ({"side": "top"}, "fault.side"),
    ({"depth": 0.0}, "fault.depth"),
    ({"depth": -1e-4}, "fault.depth"),
    ({"depth": 2e-3}, "fault.depth"),          # through the curve under the tooth
    ({"depth": 0.1e-3, "angle": math.radians(90.0)}, "fault.angle"),
    ({"start": 40.0e-3}, "fault.start"),       # below the fillet's cut
    ({"start": 43.0e-3}, "fault.start"),       # above the form radius: the involute
])
def test_crack_path_refusals(tooth, kwargs, key):
    args = {"side": "right", "depth": 0.1e-3} | kwargs
    with pytest.raises(InputError) as err:
        crack_path(GEAR, tooth, **args)
    assert err.value.field == key


@pytest.mark.parametrize("kwargs, key", [
    ({"size": -1.0}, "fault.size"),
    ({"size": 0.1e-3, "tip_size": 0.2e-3}, "fault.tip_size"),
])
def test_cracked_tooth_refusals(tooth, kwargs, key):
    path = crack_path(GEAR, tooth, "right", 0.1e-3)
    with pytest.raises(InputError) as err:
        cracked_tooth(GEAR, tooth, path, **kwargs)
    assert err.value.field == key


def test_mouth_off_the_outline_is_refused(tooth):
    path = crack_path(GEAR, tooth, "right", 0.1e-3)
    with pytest.raises(InputError) as err:
        cracked_tooth(GEAR, tooth, path + [[-1e-4, 0.0], [-1e-4, 0.0]])
    assert err.value.field == "fault.path"
