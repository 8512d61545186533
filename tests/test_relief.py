"""Tip relief: the depth formula, the relieved flank, its mesh, and its refusals."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from spurdyn.case import gear_from_table, gear_to_dict, load_pair
from spurdyn.cli.main import main
from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.geometry import (
    NASA_LIKE_TIP_RELIEF,
    GearPair,
    nasa_like_relief,
    paper_gear,
    paper_pair,
    relief_depth,
    relief_params,
)
from spurdyn.geometry import involute as ivl
from spurdyn.mesh.tooth import tooth_mesh

PAPER = (Path(__file__).resolve().parents[1] / "examples" / "paper_pair.toml").read_text()
C_A = 20e-6


def relieved(shape: str = "linear", amount: float = C_A, start_deg: float = 23.0):
    return dataclasses.replace(paper_gear(), tip_relief=amount,
                               tip_relief_start_roll=math.radians(start_deg),
                               tip_relief_shape=shape)


def compiled_style_depth(params, r, rb):
    """The depth as the solver evaluates it from relief_params, one scalar at a time."""
    amount, start, exponent, tip = params
    xi = math.sqrt(r * r - rb * rb) / rb
    return amount * max(0.0, (xi - start) / (tip - start)) ** exponent if amount > 0 else 0.0


# -- the depth formula -------------------------------------------------------------------

@pytest.mark.parametrize("shape, k", [("linear", 1), ("parabolic", 2)])
def test_depth_zero_below_start_and_amount_at_tip(shape, k):
    g = relieved(shape)
    xi_s, xi_a = g.tip_relief_start_roll, float(g.roll_angle_at(g.tip_radius))
    r_s = float(g.radius_at_roll_angle(xi_s))
    below = np.linspace(g.base_radius, r_s * (1 - 1e-12), 50)
    assert np.all(g.relief_depth(below) == 0.0)
    assert float(g.relief_depth(g.tip_radius)) == pytest.approx(C_A, rel=1e-14)
    # Halfway in roll angle: C_a / 2 (linear) or C_a / 4 (parabolic).
    r_mid = float(g.radius_at_roll_angle(0.5 * (xi_s + xi_a)))
    assert float(g.relief_depth(r_mid)) == pytest.approx(C_A * 0.5**k, rel=1e-10)
    # Monotone and continuous at the start: the depth just above it is tiny.
    r = np.linspace(r_s, g.tip_radius, 401)
    d = g.relief_depth(r)
    assert np.all(np.diff(d) >= 0.0)
    assert float(g.relief_depth(r_s * (1 + 1e-9))) < 1e-9 * C_A * 1e3


def test_parabolic_lies_below_linear_and_both_agree_at_the_ends():
    lin, par = relieved("linear"), relieved("parabolic")
    r_s = float(lin.radius_at_roll_angle(lin.tip_relief_start_roll))
    r = np.linspace(r_s, lin.tip_radius, 101)
    d_lin, d_par = lin.relief_depth(r), par.relief_depth(r)
    assert np.all(d_par[1:-1] < d_lin[1:-1])
    assert d_lin[0] < 1e-18 and d_par[0] < 1e-30 and d_lin[-1] == pytest.approx(d_par[-1], rel=1e-14)
    # Parabolic = linear^2 / C_a.
    assert np.allclose(d_par, d_lin**2 / C_A, rtol=1e-12, atol=1e-30)


def test_relief_params_give_the_same_depth_as_the_gear():
    for g in (relieved("linear"), relieved("parabolic"), paper_gear()):
        params = relief_params(g)
        assert all(isinstance(v, float) for v in params)
        r = np.linspace(g.form_radius, g.tip_radius, 37)
        mine = np.array([compiled_style_depth(params, float(x), g.base_radius) for x in r])
        assert np.allclose(g.relief_depth(r), mine, rtol=1e-13, atol=1e-20)
        assert np.array_equal(g.relief_depth(r),
                              relief_depth(g.roll_angle_at(r), params[0], params[1],
                                           params[3], params[2]))
    amount, start, exponent, tip = relief_params(paper_gear())
    assert amount == 0.0 and exponent == 1.0
    assert tip == pytest.approx(math.radians(31.38), abs=1e-4)
    amount, start, exponent, tip = relief_params(relieved("parabolic"))
    assert (amount, exponent) == (C_A, 2.0) and start == pytest.approx(math.radians(23.0))


# -- the relieved flank ------------------------------------------------------------------

def test_modified_flank_point_is_moved_inwards_along_the_normal():
    g = relieved()
    r = np.linspace(g.form_radius, g.tip_radius, 25)
    q = g.modified_flank_point(r)
    p, n = g.flank_point(r), g.flank_normal(r)
    assert np.allclose((p - q) @ np.eye(2), g.relief_depth(r)[:, None] * n, atol=1e-18)
    assert np.allclose(np.linalg.norm(p - q, axis=1), g.relief_depth(r), atol=1e-18)
    # Inwards: the relieved point lies closer to the tooth centre line.
    assert np.all(q[:, 0] <= p[:, 0])
    # The outline above the form radius is the relieved flank; the fillet is untouched.
    for x in (g.form_radius, 0.5 * (g.form_radius + g.tip_radius), g.tip_radius):
        assert np.array_equal(g.right_side_point(x), g.modified_flank_point(np.asarray(x)))
    below = 0.5 * (g.root_radius + g.form_radius)
    assert np.array_equal(g.right_side_point(below), paper_gear().right_side_point(below))


def test_unmodified_gear_is_unchanged_bit_for_bit():
    g = paper_gear()
    assert (g.tip_relief, g.tip_relief_start_roll, g.tip_relief_shape) == (0.0, None, "linear")
    assert not g.has_tip_relief
    r = np.linspace(g.form_radius, g.tip_radius, 30)
    assert np.array_equal(g.modified_flank_point(r), g.flank_point(r))
    for x in r:
        assert np.array_equal(g.right_side_point(float(x)),
                              ivl.right_flank_point(float(x), g.base_radius, g.half_angle_base))
    assert g.flank_end_radius == g.tip_radius
    assert g.tip_thickness == float(g.thickness_at(g.tip_radius))
    # An explicit zero relief (with a start, as in a sweep over C_a) is the same tooth.
    z = dataclasses.replace(g, tip_relief=0.0, tip_relief_start_roll=math.radians(25.0))
    assert np.array_equal(tooth_mesh(z).nodes, tooth_mesh(g).nodes)


def test_relieved_flank_meets_the_tip_circle_just_above_the_involute_tip():
    g = relieved()
    corner = g.modified_flank_point(np.asarray(g.flank_end_radius))
    assert float(np.hypot(*corner)) == pytest.approx(g.tip_radius, abs=1e-14)
    # The relief moves the tip point in by about C_a sin(alpha_a): the flank reaches
    # the tip circle that much further up the involute.
    alpha_a = float(ivl.pressure_angle_at(g.tip_radius, g.base_radius))
    extra = g.flank_end_radius - g.tip_radius
    assert extra == pytest.approx(C_A * math.sin(alpha_a), rel=0.02)
    # There the depth is C_a continued by the same formula (under 1 % more).
    assert C_A < float(g.relief_depth(g.flank_end_radius)) < 1.01 * C_A


def test_tip_land_is_that_of_the_relieved_tooth():
    g0, g = paper_gear(), relieved()
    alpha_a = float(ivl.pressure_angle_at(g.tip_radius, g.base_radius))
    narrower = g0.tip_thickness - g.tip_thickness
    assert narrower == pytest.approx(2 * C_A / math.cos(alpha_a), rel=0.02)
    mesh = tooth_mesh(g)
    tip = mesh.nodes[mesh.tip_nodes]
    span = math.atan2(tip[-1, 0], tip[-1, 1]) - math.atan2(tip[0, 0], tip[0, 1])
    assert g.tip_radius * span == pytest.approx(g.tip_thickness, rel=1e-12)


# -- the mesh ------------------------------------------------------------------------------

def on_relieved_flank_distance(g, x: np.ndarray) -> float:
    """Distance of ``x`` from the relieved flank, found without the mesh's own radii.

    A relieved point lies on the involute's normal line at its parameter ``r``, i.e. on
    the base-circle tangent, at the distance ``L(r) - depth(r)`` from the tangent point.
    """
    length = math.sqrt(float(x @ x) - g.base_radius**2)

    def gap(r: float) -> float:
        return float(ivl.roll_length(r, g.base_radius) - g.relief_depth(r)) - length

    r = brentq(gap, g.form_radius * (1 - 1e-3), g.tip_radius * (1 + 1e-3), xtol=1e-16)
    return float(np.linalg.norm(x - g.modified_flank_point(np.asarray(r))))


@pytest.mark.parametrize("shape", ["linear", "parabolic"])
@pytest.mark.parametrize("nx, ny", [(1, 2), (4, 14), (8, 28)])
def test_outline_nodes_lie_on_the_relieved_flank_and_jacobians_stay_positive(shape, nx, ny):
    g = relieved(shape)
    mesh = tooth_mesh(g, nx, ny)
    xy = mesh.nodes
    r = np.hypot(xy[:, 0], xy[:, 1])
    side = mesh.right_side
    above = side[r[side] >= g.form_radius]
    assert len(above) >= 2
    for node in above:
        assert on_relieved_flank_distance(g, xy[node]) < 1e-12
    # Nodes in the relieved zone are off the unmodified involute by the depth.
    r_s = float(g.radius_at_roll_angle(g.tip_relief_start_roll))
    top = xy[side[-1]]
    assert on_relieved_flank_distance(g, top) < 1e-12
    assert np.hypot(*top) == pytest.approx(g.tip_radius, abs=1e-14)
    assert np.allclose(r[mesh.tip_nodes], g.tip_radius, rtol=1e-12)
    assert np.allclose(xy[mesh.left_side], xy[side] * [-1, 1], atol=1e-15)
    low = side[(r[side] >= g.form_radius) & (r[side] < r_s)]
    if len(low):
        assert np.allclose(xy[low], g.flank_point(r[low]), atol=1e-12)
    det = jacobian_determinants(xy, mesh.elements)
    assert np.all(det > 0.0)
    assert np.all(det.max(axis=1) / det.min(axis=1) < 3.0)


@pytest.mark.parametrize("shape, amount, start_deg", [
    ("parabolic", 0.1 * 0.003175, 14.0),  # the cap, 317.5 um, far beyond any real relief
    ("linear", 250e-6, 15.0),             # tilt 0.08 rad, near the limit of 0.1
    ("linear", 30e-6, 30.0),              # short and steep
])
def test_largest_allowed_reliefs_still_mesh(shape, amount, start_deg):
    g = dataclasses.replace(paper_gear(), tip_relief=amount,
                            tip_relief_start_roll=math.radians(start_deg), tip_relief_shape=shape)
    for nx, ny in ((1, 2), (4, 14), (8, 28)):
        mesh = tooth_mesh(g, nx, ny)
        det = jacobian_determinants(mesh.nodes, mesh.elements)
        assert np.all(det > 0.0)
        assert np.all(det.max(axis=1) / det.min(axis=1) < 3.0)
        r = np.hypot(*mesh.nodes[mesh.right_side].T)
        assert np.all(np.diff(r) > 0.0)  # the outline still climbs from root to tip


# -- the preset ---------------------------------------------------------------------------

def test_nasa_like_relief_starts_at_the_highest_point_of_single_contact():
    p = paper_pair()
    g = nasa_like_relief(p.gear_a)
    assert g.tip_relief == NASA_LIKE_TIP_RELIEF == 20e-6 and g.tip_relief_shape == "linear"
    assert g.tip_relief_start_roll == pytest.approx(p.single_contact_roll_a[1], rel=1e-14)
    assert round(math.degrees(g.tip_relief_start_roll), 2) == 23.18
    assert round(float(g.radius_at_roll_angle(g.tip_relief_start_roll)) * 1e3, 2) == 45.06
    # Everything but the relief is the paper's gear.
    assert dataclasses.replace(g, tip_relief=0.0, tip_relief_start_roll=None) == p.gear_a
    # With another mate the start moves with that pair's HPSTC.
    big = dataclasses.replace(p.gear_a, teeth=56)
    g2 = nasa_like_relief(p.gear_a, big)
    assert g2.tip_relief_start_roll == pytest.approx(
        GearPair(gear_a=p.gear_a, gear_b=big).single_contact_roll_a[1], rel=1e-14)


def test_pitch_point_stiffness_unchanged_by_a_relief_above_the_pitch_point():
    from spurdyn.model import build_tooth, pitch_point_stiffness

    p = paper_pair()
    g = nasa_like_relief(p.gear_a)
    assert g.tip_relief_start_roll > p.pitch_roll_a
    assert float(g.relief_depth(g.pitch_radius)) == 0.0
    assert np.array_equal(g.right_side_point(g.pitch_radius), p.gear_a.right_side_point(g.pitch_radius))
    k0 = pitch_point_stiffness(p, build_tooth(p.gear_a), build_tooth(p.gear_a))
    relieved_pair = GearPair(gear_a=g, gear_b=g)
    t = build_tooth(g)
    k1 = pitch_point_stiffness(relieved_pair, t, t)
    # Only the mesh rows move (they follow the relieved outline up to the tip circle):
    # 0.05 % for the paper's pair.
    assert k1 == pytest.approx(k0, rel=2e-3)


# -- refusals ---------------------------------------------------------------------------------

@pytest.mark.parametrize("changes, field, words", [
    ({"tip_relief": -1e-6, "tip_relief_start_roll": 0.4}, "tip_relief", "positive"),
    ({"tip_relief": float("nan"), "tip_relief_start_roll": 0.4}, "tip_relief", "positive"),
    ({"tip_relief": True, "tip_relief_start_roll": 0.4}, "tip_relief", "number"),
    ({"tip_relief": 4e-4, "tip_relief_start_roll": 0.3}, "tip_relief", "too large"),
    ({"tip_relief": 2e-5}, "tip_relief_start_roll", "missing"),
    ({"tip_relief": 2e-5, "tip_relief_start_roll": 0.05}, "tip_relief_start_roll", "form radius"),
    ({"tip_relief": 2e-5, "tip_relief_start_roll": 0.6}, "tip_relief_start_roll", "tip"),
    ({"tip_relief": 2e-5, "tip_relief_start_roll": float("inf")}, "tip_relief_start_roll", "finite"),
    ({"tip_relief": 2e-5, "tip_relief_start_roll": 0.4, "tip_relief_shape": "cubic"},
     "tip_relief_shape", "linear, parabolic"),
    ({"tip_relief": 3e-4, "tip_relief_start_roll": 0.545}, "tip_relief_start_roll", "too close"),
])
def test_gear_refuses_bad_relief(changes, field, words):
    with pytest.raises(InputError) as err:
        dataclasses.replace(paper_gear(), **changes)
    assert err.value.field == field
    assert words in err.value.reason


def with_relief(lines: str) -> str:
    return PAPER.replace("disk_inertia = 2.965e-4\n", f"disk_inertia = 2.965e-4\n{lines}\n", 1)


@pytest.mark.parametrize("lines, field, words", [
    ("tip_relief = -2e-5\ntip_relief_start_roll_deg = 23.0", "gear_a.tip_relief", "positive"),
    ('tip_relief = "small"\ntip_relief_start_roll_deg = 23.0', "gear_a.tip_relief", "number"),
    ("tip_relief = 1e-3\ntip_relief_start_roll_deg = 23.0", "gear_a.tip_relief", "too large"),
    ("tip_relief = 2e-5", "gear_a.tip_relief_start_roll_deg", "is missing"),
    ("tip_relief = 2e-5\ntip_relief_start_roll_deg = 5.0",
     "gear_a.tip_relief_start_roll_deg", "must lie on the involute"),
    ("tip_relief = 2e-5\ntip_relief_start_roll_deg = 32.0",
     "gear_a.tip_relief_start_roll_deg", "must lie on the involute"),
    ("tip_relief = 2e-5\ntip_relief_start_radius = 0.0420",
     "gear_a.tip_relief_start_radius", "must lie on the involute"),
    ("tip_relief = 2e-5\ntip_relief_start_radius = 0.0410",
     "gear_a.tip_relief_start_radius", "base radius"),
    ("tip_relief = 2e-5\ntip_relief_start_radius = 0.048",
     "gear_a.tip_relief_start_radius", "must lie on the involute"),
    ("tip_relief = 2e-5\ntip_relief_start_roll_deg = 23.0\ntip_relief_start_radius = 0.045",
     "gear_a.tip_relief_start_radius", "not both"),
    ("tip_relief_start_roll_deg = 23.0", "gear_a.tip_relief_start_roll_deg", "needs tip_relief"),
    ('tip_relief_shape = "parabolic"', "gear_a.tip_relief_shape", "needs tip_relief"),
    ('tip_relief = 2e-5\ntip_relief_start_roll_deg = 23.0\ntip_relief_shape = "cubic"',
     "gear_a.tip_relief_shape", "must be one of"),
    ("tip_relief = 2e-5\ntip_relief_start_roll_deg = 23.0\ntip_relief_shape = 2",
     "gear_a.tip_relief_shape", "must be"),
    ("tip_relief = 2e-5\ntip_relief_start_roll = 0.4", "gear_a.tip_relief_start_roll",
     "unknown key"),
])
def test_bad_relief_keys_refused_in_one_line(tmp_path, capsys, lines, field, words):
    path = tmp_path / "bad.toml"
    path.write_text(with_relief(lines))
    code = main(["info", str(path)])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err.endswith("\n") and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"spurdyn: error: {field}: "), err
    assert words in err, err


def test_relief_keys_accepted_and_written_back(tmp_path, capsys):
    path = tmp_path / "relieved.toml"
    path.write_text(with_relief('tip_relief = 2e-5\ntip_relief_start_radius = 0.04506\n'
                                'tip_relief_shape = "parabolic"'))
    assert main(["info", str(path)]) == 0
    assert capsys.readouterr().err == ""
    g = load_pair(path).pair.gear_a
    assert g.tip_relief == 2e-5 and g.tip_relief_shape == "parabolic"
    assert float(g.radius_at_roll_angle(g.tip_relief_start_roll)) == pytest.approx(0.04506, rel=1e-13)
    # Gear B copies A, relief included.
    assert load_pair(path).pair.gear_b == g
    # The TOML form written back reads as the same gear.
    table = gear_to_dict(g)
    assert set(table) >= {"tip_relief", "tip_relief_start_roll_deg", "tip_relief_shape"}
    again = gear_from_table(table, "gear_a")
    assert again.tip_relief == g.tip_relief and again.tip_relief_shape == g.tip_relief_shape
    assert again.tip_relief_start_roll == pytest.approx(g.tip_relief_start_roll, rel=1e-14)
    # An unmodified gear writes no relief keys (stored case files stay as they were).
    assert not any(k.startswith("tip_relief") for k in gear_to_dict(paper_gear()))


def test_start_roll_and_start_radius_give_the_same_gear(tmp_path):
    a, b = tmp_path / "a.toml", tmp_path / "b.toml"
    g = paper_gear()
    r_s = float(g.radius_at_roll_angle(math.radians(23.0)))
    a.write_text(with_relief("tip_relief = 2e-5\ntip_relief_start_roll_deg = 23.0"))
    b.write_text(with_relief(f"tip_relief = 2e-5\ntip_relief_start_radius = {r_s!r}"))
    ga, gb = load_pair(a).pair.gear_a, load_pair(b).pair.gear_a
    assert ga.tip_relief_start_roll == pytest.approx(gb.tip_relief_start_roll, rel=1e-13)
    assert ga.tip_relief_shape == "linear"
