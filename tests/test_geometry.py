"""Geometry of involute gears: the paper's pair, fillets, and refusals."""

import math

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.geometry import Gear, GearPair, paper_gear, paper_pair
from spurdyn.geometry import involute as ivl


def sig3(x: float) -> float:
    return float(f"{x:.3g}")


def test_paper_pair_derived_figures():
    p = paper_pair()
    assert sig3(p.contact_ratio) == 1.64  # 1.638 to 3 s.f.
    assert round(p.contact_ratio, 3) == 1.638
    assert round(math.degrees(p.theta_s), 2) == 21.06
    assert round(math.degrees(p.theta_2), 2) == 8.20
    assert round(p.gear_a.base_radius * 1e3, 2) == 41.77
    assert round(p.gear_a.base_pitch * 1e3, 3) == 9.373
    assert round(p.path_of_contact * 1e3, 3) == 15.353
    assert round(math.degrees(p.single_contact_angle), 2) == 4.65


def test_paper_pair_roll_angles_and_radii():
    p = paper_pair()
    g = p.gear_a
    assert round(math.degrees(p.start_roll_a), 2) == 10.32
    assert round(math.degrees(p.pitch_roll_a), 2) == 20.85
    assert round(math.degrees(p.end_roll_a), 2) == 31.38
    assert round(float(g.radius_at_roll_angle(p.start_roll_a)) * 1e3, 2) == 42.44
    assert round(math.degrees(g.half_angle_base), 3) == 4.068
    assert round(g.tip_thickness * 1e3, 2) == 2.32
    # The angle of action is the rotation between the two roll angles.
    assert p.end_roll_a - p.start_roll_a == pytest.approx(p.theta_s, rel=1e-12)


def test_thickness_at_pitch_circle_is_half_the_circular_pitch():
    g = paper_gear()
    assert float(g.thickness_at(g.pitch_radius)) == pytest.approx(math.pi * g.module / 2, rel=1e-12)


def test_involute_normal_is_perpendicular_to_flank_and_tangent_to_base_circle():
    g = paper_gear()
    r = np.linspace(g.base_radius * 1.001, g.tip_radius, 9)
    h = 1e-7
    tangent = (g.flank_point(r + h) - g.flank_point(r - h)) / (2 * h)
    n = g.flank_normal(r)
    assert np.allclose(np.einsum("ij,ij->i", tangent, n) / np.linalg.norm(tangent, axis=1), 0, atol=1e-7)
    # Distance of the normal line from the centre equals the base radius.
    p = g.flank_point(r)
    dist = np.abs(p[:, 0] * n[:, 1] - p[:, 1] * n[:, 0])
    assert np.allclose(dist, g.base_radius, rtol=1e-10)
    # Outward: pointing away from the tooth centre line at the right flank.
    assert np.all(n[:, 0] > 0)


def test_fillet_meets_involute_tangentially_below_active_profile():
    p = paper_pair()
    g = p.gear_a
    a_end = g.fillet_end_angle
    junction = g.fillet_points(np.asarray(a_end))
    assert np.allclose(junction, g.flank_point(g.form_radius), atol=1e-12)
    # Tangent directions of fillet (end) and involute (start) agree.
    h = 1e-6
    t_fillet = g.fillet_points(np.asarray(a_end)) - g.fillet_points(np.asarray(a_end - h))
    t_flank = g.flank_point(g.form_radius + h) - g.flank_point(g.form_radius)
    t_fillet /= np.linalg.norm(t_fillet)
    t_flank /= np.linalg.norm(t_flank)
    assert float(t_fillet @ t_flank) > 1 - 1e-8
    # Below the start of the active profile (42.44 mm), as the reference gives (42.1-42.2).
    assert 42.1e-3 < g.form_radius < 42.2e-3
    assert g.form_radius < float(g.radius_at_roll_angle(p.start_roll_a))


def test_fillet_reaches_root_circle_tangentially():
    g = paper_gear()
    root = g.fillet_points(np.asarray(0.0))
    assert float(np.hypot(*root)) == pytest.approx(g.root_radius, rel=1e-12)
    near = g.fillet_points(np.asarray(1e-4))
    # Radial direction at the root point is normal to the fillet there.
    t = near - root
    assert abs(float(t @ root)) / (np.linalg.norm(t) * np.linalg.norm(root)) < 1e-3
    # Fillet radius falls monotonically from the involute to the root.
    pts = g.fillet_points(np.linspace(0, g.fillet_end_angle, 200))
    assert np.all(np.diff(np.hypot(pts[:, 0], pts[:, 1])) > 0)



def _gears_with_fillets():
    m = 0.003
    return {
        "paper": paper_gear(),
        "z20": Gear(teeth=20, module=m, pressure_angle=math.radians(20), face_width=0.01,
                    addendum=m, dedendum=1.25 * m, cutter_tip_radius=0.38 * m, disk_inertia=1e-4),
        "z40": Gear(teeth=40, module=m, pressure_angle=math.radians(20), face_width=0.01,
                    addendum=m, dedendum=1.25 * m, cutter_tip_radius=0.38 * m, disk_inertia=1e-3),
        "z30-25deg": Gear(teeth=30, module=m, pressure_angle=math.radians(25), face_width=0.01,
                          addendum=m, dedendum=1.25 * m, cutter_tip_radius=0.25 * m,
                          disk_inertia=1e-3),
    }


@pytest.mark.parametrize("name", ["paper", "z20", "z40", "z30-25deg"])
def test_fillet_tangent_equals_involute_tangent_at_form_radius(name):
    """Central differences of both curves at the junction give the same direction.

    Central differences are O(h^2): at h = 1e-5 (rad of normal angle on the fillet,
    1e-8 m of radius on the involute) the two unit tangents of the paper's gear differ
    by 4e-10 rad; a kink of even 1e-6 rad would fail the test.
    """
    g = _gears_with_fillets()[name]
    a, r, h = g.fillet_end_angle, g.form_radius, 1e-5
    junction = g.fillet_points(np.asarray(a))
    assert np.allclose(junction, g.flank_point(r), rtol=0, atol=1e-13)
    t_fillet = g.fillet_points(np.asarray(a + h)) - g.fillet_points(np.asarray(a - h))
    t_flank = g.flank_point(r + h * 1e-3) - g.flank_point(r - h * 1e-3)
    t_fillet /= np.linalg.norm(t_fillet)
    t_flank /= np.linalg.norm(t_flank)
    angle = math.atan2(t_fillet[0] * t_flank[1] - t_fillet[1] * t_flank[0], float(t_fillet @ t_flank))
    assert abs(angle) < 1e-8
    # The involute's analytic normal is also the fillet's normal at the junction.
    n = g.flank_normal(np.asarray(r))
    assert abs(float(t_fillet @ n)) < 1e-8


@pytest.mark.parametrize("name", ["paper", "z20", "z40", "z30-25deg"])
def test_fillet_spans_root_circle_to_form_radius(name):
    """Sampled densely, the fillet's smallest radius is the root radius and its largest
    the form radius: it reaches the root circle and stops at the involute."""
    g = _gears_with_fillets()[name]
    pts = g.fillet_points(np.linspace(0.0, g.fillet_end_angle, 4001))
    radii = np.hypot(pts[:, 0], pts[:, 1])
    assert radii.min() == pytest.approx(g.root_radius, rel=1e-12)
    assert radii.max() == pytest.approx(g.form_radius, rel=1e-12)
    assert g.root_radius < g.form_radius
    # The form radius lies above the base circle (no undercut) ...
    assert g.form_radius > g.base_radius
    # ... and right_side_point follows the fillet below it and the involute above it.
    for r in np.linspace(g.root_radius, g.tip_radius, 13):
        assert float(np.hypot(*g.right_side_point(float(r)))) == pytest.approx(r, rel=1e-12)


def test_paper_form_radius_and_margin_below_active_profile():
    p = paper_pair()
    g = p.gear_a
    assert round(g.form_radius * 1e3, 2) == 42.19
    start = float(g.radius_at_roll_angle(p.start_roll_a))
    # Contact never reaches the fillet: a quarter of a millimetre of involute to spare.
    assert 0.2e-3 < start - g.form_radius < 0.3e-3
    assert g.min_teeth_without_undercut == 18


def test_no_undercut_for_28_teeth_and_clear_error_below_limit():
    g = paper_gear()
    assert not g.undercut
    assert g.min_teeth_without_undercut <= 18
    with pytest.raises(InputError, match="teeth.*undercut"):
        Gear(teeth=12, module=g.module, pressure_angle=g.pressure_angle, face_width=g.face_width,
             addendum=g.module, dedendum=1.25 * g.module, cutter_tip_radius=0.38 * g.module,
             disk_inertia=1e-4)


def test_rack_tooth_coming_to_a_point_is_refused_naming_the_dedendum():
    # 35 deg with a 1.25 m dedendum: the rack tooth's flanks meet above its tip line.
    with pytest.raises(InputError) as err:
        Gear(teeth=30, module=0.003, pressure_angle=math.radians(35), face_width=0.01,
             addendum=0.003, dedendum=0.00375, cutter_tip_radius=0.0003, disk_inertia=1e-4)
    assert err.value.field == "dedendum" and "comes to a point" in err.value.reason


def test_gears_too_far_apart_to_touch_are_refused():
    g = paper_gear()
    with pytest.raises(InputError) as err:
        GearPair(g, g, centre_distance=2 * g.tip_radius + 1e-4)
    assert err.value.field == "centre_distance" and "never touch" in err.value.reason
    # Touching, but less than one pair in mesh at all times.
    with pytest.raises(InputError, match="contact ratio 0.*below 1") as err:
        GearPair(g, g, centre_distance=2 * g.pitch_radius + 3e-3)
    assert err.value.field == "centre_distance"


def test_interference_is_refused():
    # Long addenda on a small pinion: the mating tip would reach into the fillet.
    big = Gear(teeth=100, module=0.003, pressure_angle=math.radians(20), face_width=0.01,
               addendum=0.0036, dedendum=0.00375, cutter_tip_radius=0.38 * 0.003, disk_inertia=1e-3)
    small = Gear(teeth=18, module=0.003, pressure_angle=math.radians(20), face_width=0.01,
                 addendum=0.003, dedendum=0.00375, cutter_tip_radius=0.38 * 0.003, disk_inertia=1e-4)
    with pytest.raises(InputError, match="interference"):
        GearPair(gear_a=small, gear_b=big)


def test_different_gears_pair():
    g20 = Gear(teeth=20, module=0.003, pressure_angle=math.radians(20), face_width=0.01,
               addendum=0.003, dedendum=0.00375, cutter_tip_radius=0.00114, disk_inertia=1e-4)
    g40 = Gear(teeth=40, module=0.003, pressure_angle=math.radians(20), face_width=0.01,
               addendum=0.003, dedendum=0.00375, cutter_tip_radius=0.00114, disk_inertia=1e-3)
    p = GearPair(g20, g40)
    assert p.centre_distance == pytest.approx(0.09)
    # Textbook contact ratio for 20/40, 20 deg, standard addenda.
    rb1, rb2 = g20.base_radius, g40.base_radius
    expected = (math.sqrt(0.033**2 - rb1**2) + math.sqrt(0.063**2 - rb2**2) - 0.09 * math.sin(math.radians(20))) \
        / (math.pi * 0.003 * math.cos(math.radians(20)))
    assert p.contact_ratio == pytest.approx(expected, rel=1e-12)
    # Roll angles of the contact point on both gears add up along the line of action.
    roll_b_end = float(p.roll_b_from_roll_a(p.end_roll_a))
    assert roll_b_end == pytest.approx(p.start_roll_b, rel=1e-12)


@pytest.mark.parametrize("field, kwargs, pattern", [
    ("teeth", {"teeth": 5}, "teeth"),
    ("teeth", {"teeth": 28.0}, "teeth"),
    ("module", {"module": -0.003}, "module"),
    ("face_width", {"face_width": 0.0}, "face_width"),
    ("pressure_angle", {"pressure_angle": math.radians(50)}, "pressure_angle"),
    ("pressure_angle", {"pressure_angle": math.radians(5)}, "pressure_angle"),
    ("disk_inertia", {"disk_inertia": float("nan")}, "disk_inertia"),
    ("addendum", {"addendum": 0.009}, "addendum"),
    ("cutter_tip_radius", {"cutter_tip_radius": 0.003}, "cutter_tip_radius"),
])
def test_bad_gear_is_refused_naming_the_field(field, kwargs, pattern):
    base = dict(teeth=28, module=0.003175, pressure_angle=math.radians(20), face_width=0.00635,
                addendum=0.003175, dedendum=0.00397, cutter_tip_radius=0.0012, disk_inertia=2.965e-4)
    base.update(kwargs)
    with pytest.raises(InputError) as err:
        Gear(**base)
    assert err.value.field == field
    assert "\n" not in str(err.value)


def test_tip_not_above_root_is_refused():
    with pytest.raises(InputError, match="tip_radius"):
        Gear.from_radii(teeth=28, pitch_radius=0.04445, tip_radius=0.040, root_radius=0.04048,
                        pressure_angle=math.radians(20), face_width=0.00635, disk_inertia=1e-4)


def test_involute_function_matches_definition():
    a = np.linspace(0.1, 0.6, 7)
    assert np.allclose(ivl.inv(a), np.tan(a) - a)
