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


# --- grading across the tooth -------------------------------------------------------

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from spurdyn.mesh.tooth import MAX_GRADING, thickness_spacing  # noqa: E402


@settings(max_examples=60, deadline=None)
@given(nx=st.integers(1, 64), grading=st.floats(1.0, MAX_GRADING))
def test_thickness_spacing_is_an_increasing_symmetric_map_of_the_unit_interval(nx, grading):
    s = thickness_spacing(nx, grading)
    assert s.shape == (2 * nx + 1,) and s[0] == 0.0 and s[-1] == 1.0
    assert np.all(np.diff(s) > 0)
    assert np.allclose(s + s[::-1], 1.0, atol=1e-14)                   # both flanks alike
    assert np.allclose(s[1::2], 0.5 * (s[:-1:2] + s[2::2]), atol=1e-15)  # mid-sides centred


def test_even_grading_is_the_paper_grid_bit_for_bit():
    for nx in (1, 4, 12):
        assert np.array_equal(thickness_spacing(nx, 1.0), np.linspace(0.0, 1.0, 2 * nx + 1))
    g = paper_gear()
    assert np.array_equal(tooth_mesh(g, 4, 14).nodes, tooth_mesh(g, 4, 14, grading=1.0).nodes)


@pytest.mark.parametrize("grading", [2.0, 6.0, 20.0])
def test_grading_is_the_limit_of_the_middle_to_outline_width_ratio(grading):
    def ratio(nx):
        widths = np.diff(thickness_spacing(nx, grading)[::2])
        return widths[nx // 2] / widths[0]
    # finite columns: widths h (1 -+ a) +- a (2 pi h)^2 h / 6 at the outline and the middle,
    # so the ratio falls short of G by eps a (1/(1 + a) + 1/(1 - a)), eps = (2 pi h)^2 / 6
    a = (grading - 1.0) / (grading + 1.0)
    for nx in (64, 256):
        eps = (2.0 * np.pi / nx) ** 2 / 6.0
        expected = -eps * a * (1.0 / (1.0 + a) + 1.0 / (1.0 - a))
        assert ratio(nx) / grading - 1.0 == pytest.approx(expected, rel=0.05)


@pytest.mark.parametrize("nx, ny, grading", [(4, 14, 6.0), (12, 40, 6.0), (16, 56, 20.0), (3, 10, 50.0)])
def test_graded_mesh_is_valid_and_keeps_the_outline(nx, ny, grading):
    g = paper_gear()
    even, graded = tooth_mesh(g, nx, ny), tooth_mesh(g, nx, ny, grading=grading)
    assert np.all(jacobian_determinants(graded.nodes, graded.elements) > 0)
    for side in ("right_side", "left_side"):   # the same flank nodes; tip and root graded
        np.testing.assert_allclose(graded.nodes[getattr(graded, side)],
                                   even.nodes[getattr(even, side)], atol=1e-15)
    np.testing.assert_allclose(np.hypot(*graded.nodes[graded.tip_nodes].T), g.tip_radius, rtol=1e-12)
    assert graded.grading == grading
    # the outline column is thinner than the even one, the middle one wider
    corner = even.right_side[ny]            # a corner half-way up
    first = lambda m: m.elements[np.flatnonzero(m.elements[:, 1] == corner)[0]]  # noqa: E731
    width = lambda m: float(np.hypot(*(m.nodes[first(m)[1]] - m.nodes[first(m)[0]])))  # noqa: E731
    assert width(graded) < width(even)


@pytest.mark.parametrize("bad", [0.5, 0.0, -2.0, 51.0, float("nan"), True, "6"])
def test_bad_grading_is_refused(bad):
    with pytest.raises(InputError, match="mesh.grading"):
        tooth_mesh(paper_gear(), 4, 14, grading=bad)
