"""Profile shift, basic racks, backlash and blanks (docs/geometry.md, sections 8 and 9)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.geometry import ISO_53, Blank, Gear, GearPair, default_rack, paper_pair
from spurdyn.geometry import involute as ivl
from spurdyn.geometry.rack import full_round_radius
from spurdyn.geometry.working import inv_inverse

M = 0.002
ALPHA = math.radians(20.0)


def gear(z: int, x: float = 0.0, deg: float = 20.0, **kw) -> Gear:
    return Gear.standard(z, M, deg, 0.01, profile_shift=x, **kw)


@pytest.mark.parametrize("y", [1e-6, 0.0149, 0.05, 0.3, 2.0])
def test_inv_inverse_inverts_the_involute_function(y):
    assert float(ivl.inv(inv_inverse(y))) == pytest.approx(y, rel=1e-13)


@pytest.mark.parametrize("z1, z2, x1, x2", [(12, 40, 0.4, 0.0), (23, 47, 0.3, -0.1),
                                            (18, 30, 0.5, 0.5), (25, 25, -0.2, -0.1)])
def test_default_centre_distance_obeys_the_involute_function_relation(z1, z2, x1, x2):
    pair = GearPair(gear(z1, x1), gear(z2, x2))
    aw = pair.working_pressure_angle
    expected = 2.0 * math.tan(ALPHA) * (x1 + x2) / (z1 + z2) + float(ivl.inv(ALPHA))
    assert float(ivl.inv(aw)) == pytest.approx(expected, rel=1e-12)
    assert pair.centre_distance == pytest.approx(M * (z1 + z2) / 2 * math.cos(ALPHA) / math.cos(aw),
                                                 rel=1e-14)
    # No backlash: the teeth fill the working pitch exactly, measured on the outlines.
    rw1, rw2 = pair.working_pitch_radii
    s1 = float(pair.gear_a.thickness_at(rw1))
    s2 = float(pair.gear_b.thickness_at(rw2))
    assert s1 + s2 == pytest.approx(2.0 * math.pi * rw1 / z1, rel=1e-12)
    assert abs(pair.backlash_normal) < 1e-15


def test_shifted_radii_and_thickness_follow_the_rack():
    g = gear(30, 0.4, thickness_allowance=30e-6)
    r_p = M * 15
    assert g.tip_radius == pytest.approx(r_p + M * (1.0 + 0.4), rel=1e-15)
    # The allowance is cut by feeding the rack in: the root drops by A / (2 tan alpha).
    assert g.root_radius == pytest.approx(r_p - M * (1.25 - 0.4) - 30e-6 / (2 * math.tan(ALPHA)),
                                          rel=1e-14)
    s = float(g.thickness_at(r_p))
    assert s == pytest.approx(M * (math.pi / 2 + 2 * 0.4 * math.tan(ALPHA)) - 30e-6, rel=1e-13)


@pytest.mark.parametrize("x, allowance", [(0.5, 0.0), (-0.3, 0.0), (0.4, 40e-6)])
def test_the_shifted_rack_fillet_meets_the_shifted_involute(x, allowance):
    # The rack's rounding and its straight flank cut one outline: the fillet must end on
    # the involute (a fillet from a rack shifted differently from the flank would not).
    g = gear(30, x, thickness_allowance=allowance)
    p = g.fillet_points(np.asarray(g.fillet_end_angle))
    assert float(np.hypot(*p)) == pytest.approx(g.form_radius, abs=1e-14)
    np.testing.assert_allclose(p, g.flank_point(np.asarray(np.hypot(*p))), atol=1e-14)


def test_a_shifted_12_tooth_pinion_that_would_undercut_unshifted():
    with pytest.raises(InputError, match="profile shift of at least") as err:
        gear(12)
    assert err.value.field == "teeth"
    # Classical limit: x_min = (h_fP - rho_fP (1 - sin alpha)) / m - z sin^2(alpha) / 2.
    a = ISO_53["A"]
    x_min = a.dedendum - a.fillet_radius * (1 - math.sin(ALPHA)) - 12 * math.sin(ALPHA) ** 2 / 2
    assert f"{math.ceil(x_min * 1000) / 1000:.3f}" in err.value.reason
    with pytest.raises(InputError, match="undercut"):
        gear(12, x_min - 0.01)
    g = gear(12, x_min + 1e-6)
    assert not g.undercut and g.form_radius >= g.base_radius
    pair = GearPair(g, gear(40))
    assert pair.contact_ratio > 1.0 and pair.centre_distance > M * 26


def test_tip_pointing_accounts_for_the_shift():
    gear(12, 0.6)
    with pytest.raises(InputError, match="come to a point") as err:
        gear(12, 0.86)
    assert err.value.field == "profile_shift"


def test_backlash_from_centre_distance_and_allowances():
    g1, g2 = gear(20), gear(37)
    tight = GearPair(g1, g2)
    assert tight.centre_distance == g1.pitch_radius + g2.pitch_radius   # exactly, unshifted
    da = 1e-6
    loose = GearPair(g1, g2, centre_distance=tight.centre_distance + da)
    # To first order the play opens by 2 da sin(alpha_w) along the line of action.
    assert loose.backlash_normal == pytest.approx(2 * da * math.sin(ALPHA), rel=1e-4)
    assert loose.tight_centre_distance == pytest.approx(tight.centre_distance, abs=1e-15)
    # Thinner teeth on the standard centre distance: the allowances on the pitch circle.
    thin = GearPair(gear(20, thickness_allowance=20e-6), gear(37, thickness_allowance=30e-6))
    assert thin.backlash_circumferential == pytest.approx(50e-6, rel=1e-9)
    assert thin.backlash_normal == pytest.approx(50e-6 * math.cos(ALPHA), rel=1e-9)
    with pytest.raises(InputError, match="overlap") as err:
        GearPair(g1, g2, centre_distance=tight.centre_distance - da)
    assert err.value.field == "centre_distance"


def test_iso_53_racks_and_the_default_for_the_pressure_angle():
    assert [(r.addendum, r.dedendum, r.fillet_radius) for r in ISO_53.values()] == \
        [(1.0, 1.25, 0.38), (1.0, 1.25, 0.30), (1.0, 1.25, 0.25), (1.0, 1.40, 0.39)]
    assert default_rack(ALPHA) is ISO_53["A"]
    for deg in (14.5, 17.5, 20.0, 22.5, 25.0, 28.0, 30.0):
        rack = default_rack(math.radians(deg))
        assert rack.fillet_radius <= full_round_radius(math.radians(deg), rack.dedendum)
        g = Gear.standard(40, M, deg, 0.01)             # a standard gear is never refused
        assert g.cutter_tip_radius == pytest.approx(rack.fillet_radius * M, rel=1e-15)
    assert default_rack(math.radians(25.0)).fillet_radius == 0.31
    # An ISO 53 rack named for a 25 deg gear is too round for it: refused, saying so.
    with pytest.raises(InputError, match="too large for the cutter tooth") as err:
        Gear.standard(40, M, 25.0, 0.01, basic_rack=ISO_53["A"])
    assert err.value.field == "cutter_tip_radius"


def test_the_paper_gear_keeps_its_geometry():
    g = paper_pair().gear_a
    assert g.cutter_tip_radius == 0.38 * g.module and g.profile_shift == 0.0
    assert g.half_angle_base == math.pi / 56 + float(ivl.inv(math.radians(20.0)))
    assert g.disk_inertia == 2.965e-4 and g.blank is None


def _polygon_polar_moment(points: np.ndarray) -> float:
    """Polar second moment of area of a closed polygon (counter-clockwise), about 0."""
    x, y = points[:, 0], points[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    return float(np.sum(cross * (x * x + x * xn + xn * xn + y * y + y * yn + yn * yn)) / 12.0)


def test_tooth_polar_inertia_matches_its_outline_polygon():
    g = gear(23, 0.2, deg=25.0)
    # Right outline root to tip, tip arc, mirrored left outline, root arc: a dense polygon.
    r = np.concatenate([np.linspace(g.root_radius, g.form_radius, 400)[1:],
                        np.linspace(g.form_radius, g.tip_radius, 400)[1:]])
    right = np.array([g.right_side_point(float(ri)) for ri in r])
    chi_tip = math.atan2(*right[-1])
    chi_root = math.atan2(*right[0])
    tip = g.tip_radius * np.column_stack([np.sin(np.linspace(chi_tip, -chi_tip, 200)),
                                          np.cos(np.linspace(chi_tip, -chi_tip, 200))])
    left = right[::-1] * np.array([-1.0, 1.0])
    root = g.root_radius * np.column_stack([np.sin(np.linspace(-chi_root, chi_root, 200)),
                                            np.cos(np.linspace(-chi_root, chi_root, 200))])
    outline = np.concatenate([right, tip, left, root])   # counter-clockwise
    polygon = g.material.density * g.face_width * _polygon_polar_moment(outline)
    assert g.tooth_polar_inertia() == pytest.approx(polygon, rel=2e-4)


def test_blank_inertia_counts_the_disk_and_the_rigid_teeth():
    g = gear(23)
    rho, b, rf = g.material.density, g.face_width, g.root_radius
    disk = rho * b * math.pi * rf**4 / 2
    assert g.disk_inertia == pytest.approx(disk + 22 * g.tooth_polar_inertia(), rel=1e-14)
    assert "solid disk" in g.inertia_source
    bored = gear(23, blank=Blank(bore_radius=0.01))
    assert bored.disk_inertia == pytest.approx(g.disk_inertia - rho * b * math.pi * 0.01**4 / 2,
                                               rel=1e-14)
    webbed = gear(23, blank=Blank(0.005, 0.01, 0.018, 0.004))
    web_cut = rho * (b - 0.004) * math.pi * (0.018**4 - 0.01**4) / 2
    assert webbed.disk_inertia == pytest.approx(g.disk_inertia - rho * b * math.pi * 0.005**4 / 2
                                                - web_cut, rel=1e-13)
    with pytest.raises(InputError) as err:
        gear(23, blank=Blank(0.005, 0.01, 0.03, 0.004))
    assert err.value.field == "blank.rim_radius"
    with pytest.raises(InputError, match="not both"):
        gear(23, disk_inertia=1e-4, blank=Blank())


@pytest.mark.parametrize("x1, x2, allowance, extra", [(0.4, -0.1, 0.0, 0.0), (0.3, 0.2, 30e-6, 50e-6)])
def test_shifted_backlashed_teeth_touch_where_they_are_placed(x1, x2, allowance, extra):
    from spurdyn.geometry.placement import line_of_action_point, mesh_angles, to_world_a, to_world_b

    tight = GearPair(gear(14, x1, thickness_allowance=allowance), gear(31, x2))
    pair = GearPair(tight.gear_a, tight.gear_b, centre_distance=tight.centre_distance + extra)
    assert pair.backlash_normal >= -1e-15
    for roll in np.linspace(pair.start_roll_a, pair.end_roll_a, 5):
        q = line_of_action_point(pair, float(roll))
        ta, tb = mesh_angles(pair, float(roll))
        pa = to_world_a(pair.gear_a.flank_point(np.asarray(np.hypot(*q))), ta)
        rb = float(np.hypot(q[0], q[1] - pair.centre_distance))
        pb = to_world_b(pair.gear_b.flank_point(np.asarray(rb)), tb, pair.centre_distance)
        np.testing.assert_allclose(pa, q, atol=1e-13)
        np.testing.assert_allclose(pb, q, atol=1e-13)
