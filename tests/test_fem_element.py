"""Single-element checks of the Q8 shape functions, quadrature and matrices."""

from __future__ import annotations

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.fem import (
    STEEL,
    ElementQuadS2,
    Material,
    element_mass,
    element_stiffness,
    gauss_2d,
    hrz_lump,
    plane_stress_matrix,
)

ELEMENT = ElementQuadS2()
RNG = np.random.default_rng(20240601)

# A distorted, non-parallelogram quad with straight sides (midsides at midpoints).
CORNERS = np.array([[0.0, 0.0], [2.0, -0.3], [2.4, 1.6], [0.3, 1.1]])


def straight_sided(corners: np.ndarray) -> np.ndarray:
    """Q8 nodal coordinates with midside nodes at edge midpoints."""
    mids = 0.5 * (corners + np.roll(corners, -1, axis=0))
    return np.vstack([corners, mids])


def shoelace(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def integrate_one(xy: np.ndarray, n: int = 3) -> float:
    """Area from the isoparametric map, integrating det J with an n x n rule."""
    pts, wts = gauss_2d(n)
    dn = ELEMENT.dshape(pts[:, 0], pts[:, 1])
    jac = np.einsum("gia,ib->gab", dn, xy)
    return float(np.dot(wts, np.linalg.det(jac)))


# --------------------------------------------------------------------------
# Shape functions
# --------------------------------------------------------------------------


def test_partition_of_unity_at_random_points() -> None:
    xi, eta = RNG.uniform(-1, 1, size=(2, 200))
    n = ELEMENT.shape(xi, eta)
    assert n.shape == (200, 8)
    np.testing.assert_allclose(n.sum(axis=-1), 1.0, atol=1e-14)
    # Derivatives of a partition of unity must sum to zero.
    np.testing.assert_allclose(ELEMENT.dshape(xi, eta).sum(axis=-2), 0.0, atol=1e-13)


def test_nodality() -> None:
    r = ELEMENT.ref_nodes
    np.testing.assert_allclose(ELEMENT.shape(r[:, 0], r[:, 1]), np.eye(8), atol=1e-15)


def test_reference_node_order() -> None:
    expected = [(-1, -1), (1, -1), (1, 1), (-1, 1), (0, -1), (1, 0), (0, 1), (-1, 0)]
    np.testing.assert_array_equal(ELEMENT.ref_nodes, np.array(expected, float))
    with pytest.raises(ValueError):
        ELEMENT.ref_nodes[0, 0] = 5.0  # shared table must be read-only


def test_shape_reproduces_quadratic_serendipity_space() -> None:
    # Any field in span{1, x, y, x^2, xy, y^2, x^2 y, x y^2} is interpolated exactly.
    xi, eta = RNG.uniform(-1, 1, size=(2, 50))
    r = ELEMENT.ref_nodes

    def f(x, y):
        quadratic = 0.3 - x + 2 * y + 0.7 * x**2 - 1.1 * x * y + 0.4 * y**2
        return quadratic + 0.9 * x**2 * y - 0.5 * x * y**2

    np.testing.assert_allclose(ELEMENT.shape(xi, eta) @ f(r[:, 0], r[:, 1]), f(xi, eta), atol=1e-13)


def test_dshape_matches_central_differences() -> None:
    xi, eta = RNG.uniform(-0.95, 0.95, size=(2, 40))
    h = 1e-6
    fd_xi = (ELEMENT.shape(xi + h, eta) - ELEMENT.shape(xi - h, eta)) / (2 * h)
    fd_eta = (ELEMENT.shape(xi, eta + h) - ELEMENT.shape(xi, eta - h)) / (2 * h)
    d = ELEMENT.dshape(xi, eta)
    assert d.shape == (40, 8, 2)
    np.testing.assert_allclose(d[..., 0], fd_xi, atol=1e-8)
    np.testing.assert_allclose(d[..., 1], fd_eta, atol=1e-8)


def test_shape_broadcasts() -> None:
    n = ELEMENT.shape(np.zeros((3, 1)), np.zeros((1, 4)))
    assert n.shape == (3, 4, 8)
    assert ELEMENT.dshape(0.2, -0.1).shape == (8, 2)


# --------------------------------------------------------------------------
# Quadrature and geometry
# --------------------------------------------------------------------------


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_gauss_rule_integrates_its_degree(n: int) -> None:
    pts, wts = gauss_2d(n)
    assert pts.shape == (n * n, 2) and wts.shape == (n * n,)
    np.testing.assert_allclose(wts.sum(), 4.0, rtol=1e-14)

    def integral(p: int, q: int) -> float:
        return float(np.dot(wts, pts[:, 0] ** p * pts[:, 1] ** q))

    # Degree 2n-2 (even, non-trivial) per variable is exact ...
    m = 2 * n - 2
    assert integral(m, m) == pytest.approx((2.0 / (m + 1)) ** 2, rel=1e-13)
    # ... and degree 2n is not: the rule really is n-point.
    assert integral(2 * n, 0) != pytest.approx(2.0 * 2.0 / (2 * n + 1), rel=1e-6)


def test_gauss_rule_order_xi_fastest() -> None:
    pts, _ = gauss_2d(3)
    assert pts[0, 1] == pts[1, 1] == pts[2, 1]
    assert pts[0, 0] < pts[1, 0] < pts[2, 0]


def test_gauss_rejects_bad_n() -> None:
    with pytest.raises(ValueError):
        gauss_2d(0)


def test_area_of_distorted_straight_element() -> None:
    xy = straight_sided(CORNERS)
    assert integrate_one(xy) == pytest.approx(shoelace(CORNERS), rel=1e-13)


def test_area_of_element_with_curved_midsides() -> None:
    # Push two midside nodes off their chords; each curved edge is a parabola
    # and adds/removes (2/3) * chord * (perpendicular offset) to the polygon.
    xy = straight_sided(CORNERS)
    expected = shoelace(CORNERS)
    for node, offset in ((5, 0.25), (6, -0.15)):  # edges 1-2 and 2-3
        a, b = CORNERS[node - 4], CORNERS[(node - 3) % 4]
        chord = b - a
        outward = np.array([chord[1], -chord[0]]) / np.linalg.norm(chord)  # CCW polygon
        xy[node] += offset * outward
        expected += 2.0 / 3.0 * np.linalg.norm(chord) * offset
    # det J is cubic per variable here, so 2x2 and 3x3 Gauss are both exact.
    assert integrate_one(xy, 3) == pytest.approx(expected, rel=1e-13)
    assert integrate_one(xy, 2) == pytest.approx(expected, rel=1e-13)
    assert abs(expected - shoelace(CORNERS)) > 0.1  # the curvature really matters


# --------------------------------------------------------------------------
# Element stiffness
# --------------------------------------------------------------------------


def curved_element() -> np.ndarray:
    xy = straight_sided(CORNERS)
    xy[5] += [0.2, 0.05]
    xy[7] += [-0.1, 0.08]
    return xy


def test_stiffness_has_exactly_three_rigid_modes() -> None:
    ke = element_stiffness(curved_element(), plane_stress_matrix(STEEL), 0.01)
    np.testing.assert_allclose(ke, ke.T, rtol=0, atol=1e-12 * np.abs(ke).max())
    w = np.linalg.eigvalsh(ke)
    rel = w / w[-1]
    assert np.all(np.abs(rel[:3]) < 1e-12)
    # Full 3x3 integration: no hourglass (spurious zero-energy) modes.
    assert rel[3] > 1e-4


def test_stiffness_annihilates_rigid_motions() -> None:
    xy = curved_element()
    ke = element_stiffness(xy, plane_stress_matrix(STEEL), 0.01)
    scale = np.abs(ke).max()
    tx = np.tile([1.0, 0.0], 8)
    ty = np.tile([0.0, 1.0], 8)
    rot = np.column_stack([-xy[:, 1], xy[:, 0]]).ravel()
    for mode in (tx, ty, rot):
        assert np.abs(ke @ mode).max() < 1e-12 * scale


def test_stiffness_scales_with_thickness_and_modulus() -> None:
    xy = curved_element()
    d = plane_stress_matrix(STEEL)
    k1 = element_stiffness(xy, d, 0.01)
    np.testing.assert_allclose(element_stiffness(xy, 2 * d, 0.03), 6 * k1, rtol=1e-13)


def test_stiffness_rejects_inverted_element() -> None:
    xy = straight_sided(CORNERS[::-1])  # clockwise corners -> det J < 0
    with pytest.raises(ValueError, match="Jacobian"):
        element_stiffness(xy, plane_stress_matrix(STEEL), 0.01)


def test_stiffness_rejects_folded_midside() -> None:
    xy = straight_sided(CORNERS)
    xy[4] = xy[1] + [0.3, 0.0]  # midside beyond its corner folds the map
    with pytest.raises(ValueError, match="Jacobian"):
        element_stiffness(xy, plane_stress_matrix(STEEL), 0.01)


# --------------------------------------------------------------------------
# Mass
# --------------------------------------------------------------------------


@pytest.mark.parametrize("xy_factory", [lambda: straight_sided(CORNERS), curved_element])
def test_consistent_and_hrz_mass_conserve_element_mass(xy_factory) -> None:
    xy = xy_factory()
    rho, t = 7800.0, 0.02
    total = rho * t * integrate_one(xy, 4)
    me = element_mass(xy, rho, t)
    np.testing.assert_allclose(me, me.T, atol=1e-14 * total)
    assert me[0::2, 0::2].sum() == pytest.approx(total, rel=1e-13)
    assert me[1::2, 1::2].sum() == pytest.approx(total, rel=1e-13)
    assert np.abs(me[0::2, 1::2]).max() == 0.0  # directions uncoupled
    assert np.linalg.eigvalsh(me).min() > 0  # consistent mass is positive definite
    ml = hrz_lump(me)
    assert ml.shape == (16,)
    assert ml[0::2].sum() == pytest.approx(total, rel=1e-13)
    assert ml[1::2].sum() == pytest.approx(total, rel=1e-13)
    assert np.all(ml > 0)


def test_hrz_rectangle_ratios_and_row_sum_contrast() -> None:
    # On a rectangle HRZ gives corner : midside = 3 : 16 (3/76 and 16/76 of
    # the mass), while row-sum lumping gives negative corner masses (-1/12).
    xy = straight_sided(np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 2.0], [0.0, 2.0]]))
    me = element_mass(xy, 1.0, 1.0)
    total = 6.0
    ml = hrz_lump(me)[0::2]
    np.testing.assert_allclose(ml[:4], 3 / 76 * total, rtol=1e-13)
    np.testing.assert_allclose(ml[4:], 16 / 76 * total, rtol=1e-13)
    row_sum = me[0::2, 0::2].sum(axis=1)
    np.testing.assert_allclose(row_sum[:4], -total / 12, rtol=1e-12)


def test_hrz_lump_shape_check() -> None:
    with pytest.raises(ValueError):
        hrz_lump(np.eye(8))


# --------------------------------------------------------------------------
# Material
# --------------------------------------------------------------------------


def test_material_validation_messages() -> None:
    # InputError (a ValueError) naming the bare field, so a reader can prefix it with
    # where the material came from (e.g. ``gear_a.material.young``).
    with pytest.raises(InputError, match=r"^young: must be > 0 \(got -1\)$") as err:
        Material(-1, 0.3, 7800.0)
    assert err.value.field == "young" and isinstance(err.value, ValueError)
    with pytest.raises(InputError, match=r"^density: must be > 0"):
        Material(1e9, 0.3, 0.0)
    with pytest.raises(InputError, match=r"^density: must be > 0"):
        Material(1e9, 0.3, float("nan"))
    with pytest.raises(InputError, match=r"^young: must be finite"):
        Material(float("inf"), 0.3, 1.0)
    for nu in (0.5, -1.0, 0.7, float("nan")):
        with pytest.raises(InputError, match=r"^poisson: must be in \(-1, 0.5\)"):
            Material(1e9, nu, 1.0)
    for bad in ("steel", True, None):
        with pytest.raises(InputError, match=r"^young: must be a number"):
            Material(bad, 0.3, 1.0)  # type: ignore[arg-type]


def test_plane_stress_matrix() -> None:
    d = plane_stress_matrix(Material(100.0, 0.25, 1.0))
    # Uniaxial stress sxx = E exx with eyy = -nu exx must give syy = 0.
    sig = d @ np.array([1.0, -0.25, 0.0])
    np.testing.assert_allclose(sig, [100.0, 0.0, 0.0], atol=1e-12)
    # Shear modulus G = E / (2 (1 + nu)).
    assert d[2, 2] == pytest.approx(100.0 / 2.5)
    assert STEEL.young == 210e9 and STEEL.poisson == 0.3 and STEEL.density == 7800.0
