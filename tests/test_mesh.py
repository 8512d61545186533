"""The structured Q8 tooth mesh."""

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.fem import jacobian_determinants
from spurdyn.geometry import paper_gear, paper_pair
from spurdyn.geometry.placement import line_of_action_point, mesh_angles, to_world_a, to_world_b
from spurdyn.mesh import DEFAULT_NX, DEFAULT_NY, tooth_mesh


@pytest.mark.parametrize("nx, ny", [(1, 2), (3, 10), (4, 14), (6, 20), (8, 28)])
def test_jacobian_positive_and_elements_well_shaped(nx, ny):
    mesh = tooth_mesh(paper_gear(), nx, ny)
    det = jacobian_determinants(mesh.nodes, mesh.elements)
    assert np.all(det > 0)
    # Well shaped: the Jacobian varies by less than a factor 3 inside any element.
    assert np.all(det.min(axis=1) / det.max(axis=1) > 1 / 3)
    assert mesh.n_nodes == (2 * nx + 1) * (2 * ny + 1) - nx * ny
    assert mesh.n_elements == nx * ny


def test_boundary_sets_lie_on_their_curves():
    g = paper_gear()
    mesh = tooth_mesh(g)
    xy = mesh.nodes
    r = lambda idx: np.hypot(xy[idx, 0], xy[idx, 1])  # noqa: E731
    # Tip nodes on the tip circle.
    assert np.allclose(r(mesh.tip_nodes), g.tip_radius, rtol=1e-12)
    # Right side: ordered root to tip, on the involute above the form radius.
    rs = r(mesh.right_side)
    assert np.all(np.diff(rs) > 0)
    above = rs >= g.form_radius
    assert np.allclose(xy[mesh.right_side[above]], g.flank_point(rs[above]), atol=1e-12)
    # Left side mirrors the right.
    assert np.allclose(xy[mesh.left_side], xy[mesh.right_side] * [-1, 1], atol=1e-15)
    # Root nodes: the middle one on the root circle, none below it, none above the cut.
    rr = r(mesh.root_nodes)
    assert rr.min() == pytest.approx(g.root_radius, rel=1e-12)
    assert np.all(rr >= g.root_radius * (1 - 1e-12))
    assert rr.max() < g.form_radius
    assert len(mesh.root_nodes) == 2 * DEFAULT_NX + 1 and len(mesh.right_side) == 2 * DEFAULT_NY + 1


def test_mesh_area_matches_outline_area():
    g = paper_gear()
    coarse, fine = tooth_mesh(g, 2, 6), tooth_mesh(g, 8, 28)

    def area(mesh):
        from spurdyn.fem import ElementQuadS2, gauss_2d
        pts, w = gauss_2d(3)
        dn = ElementQuadS2().dshape(pts[:, 0], pts[:, 1])
        total = 0.0
        for e in mesh.elements:
            j = np.einsum("ni,gnj->gij", mesh.nodes[e], dn)
            total += float(np.sum(w * np.linalg.det(j)))
        return total

    # Shoelace area of the finely sampled boundary polygon, independent of the elements.
    m = fine
    loop = np.concatenate([m.root_nodes, m.right_side[1:], m.tip_nodes[::-1][1:], m.left_side[::-1][1:-1]])
    x, y = m.nodes[loop].T
    poly = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert area(fine) == pytest.approx(poly, rel=2e-4)
    assert area(coarse) == pytest.approx(area(fine), rel=2e-3)


def test_bad_density_is_refused():
    with pytest.raises(InputError, match="mesh.nx"):
        tooth_mesh(paper_gear(), 0, 10)
    with pytest.raises(InputError, match="mesh.ny"):
        tooth_mesh(paper_gear(), 4, 2.5)


def test_teeth_touch_in_mesh_position_without_overlap():
    p = paper_pair()
    g = p.gear_a
    for roll in np.linspace(p.start_roll_a, p.end_roll_a, 5):
        ta, tb = mesh_angles(p, roll)
        q = line_of_action_point(p, roll)
        ra = float(np.hypot(*q))
        rb = float(np.hypot(*(q - [0, p.centre_distance])))
        pa = to_world_a(g.flank_point(ra), ta)
        pb = to_world_b(g.flank_point(rb), tb, p.centre_distance)
        assert np.allclose(pa, q, atol=1e-12) and np.allclose(pb, q, atol=1e-12)
        # Both normals lie along the line of action, opposed.
        na = to_world_a(g.flank_normal(ra), ta)
        nb = to_world_b(g.flank_normal(rb), tb, 0.0)
        assert float(na @ nb) == pytest.approx(-1.0, abs=1e-12)
    # Rotation from start to end of contact is the angle of action.
    t0, _ = mesh_angles(p, p.start_roll_a)
    t1, _ = mesh_angles(p, p.end_roll_a)
    assert t1 - t0 == pytest.approx(p.theta_s, rel=1e-12)


def test_default_density_is_the_finest_of_the_table_stable_at_the_paper_step():
    """docs/stiffness.md: RK4 at 3e-8 s is stable for 4x14 but not for 6x20."""
    from spurdyn.model import build_tooth
    g = paper_gear()
    assert (DEFAULT_NX, DEFAULT_NY) == (4, 14)
    assert build_tooth(g, 4, 14).stable_step().dt_rk4 >= 3e-8
    assert build_tooth(g, 6, 20).stable_step().dt_rk4 < 3e-8
