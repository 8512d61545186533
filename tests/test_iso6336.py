"""ISO 6336 module against the hand-worked examples of docs/iso6336.md, and its properties.

The reference numbers below were derived by hand (a ``bc -l`` calculator session, no
spurdyn code; the steps are in docs/iso6336.md, section 6) and are quoted there to 7
significant figures; they are asserted to that precision (relative 1e-6).
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from spurdyn.geometry import involute as ivl
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.iso6336 import contact, dynamics, root, safety
from spurdyn.iso6336.__main__ import RPM, example_pair
from spurdyn.iso6336.rating import dynamic_factor_at, iso_pair, rate
from spurdyn.model.stiffness import iso_6336_stiffness

HAND = 1e-6  # 7 significant figures, as quoted in the doc


@pytest.fixture(scope="module")
def paper():
    return rate(iso_pair(paper_pair()), PAPER_TORQUE)


@pytest.fixture(scope="module")
def second():
    return rate(example_pair(), 100.0)


# -- worked example (i): the paper's pair --------------------------------------------
def test_paper_contact_figures_match_hand(paper):
    assert paper.tangential_force == pytest.approx(500.5624, rel=HAND)
    assert paper.eps_alpha == pytest.approx(1.638004, rel=HAND)
    assert paper.z_h == pytest.approx(2.494573, rel=HAND)
    assert paper.z_e == pytest.approx(191.6457e3, rel=HAND)
    assert paper.z_eps == pytest.approx(0.8873173, rel=HAND)
    assert paper.sigma_h0 == pytest.approx(564.9117e6, rel=HAND)
    assert paper.z_b == pytest.approx(1.006285, rel=HAND)
    assert paper.z_d == paper.z_b


def test_paper_root_figures_match_hand(paper):
    s = paper.sections[0]
    assert math.degrees(s.theta) == pytest.approx(49.64244, rel=HAND)
    assert s.s_fn == pytest.approx(6.501977e-3, rel=HAND)
    assert s.rho_f == pytest.approx(1.757529e-3, rel=HAND)
    assert s.d_en == pytest.approx(90.11689e-3, rel=HAND)
    assert math.degrees(s.alpha_fen) == pytest.approx(19.11283, rel=HAND)
    assert s.h_fe == pytest.approx(3.217535e-3, rel=HAND)
    assert paper.y_f[0] == pytest.approx(1.457861, rel=HAND)
    assert paper.y_s[0] == pytest.approx(1.900685, rel=HAND)
    assert paper.sigma_f0[0] == pytest.approx(68.79661e6, rel=HAND)
    # Identical gears: identical figures.
    assert paper.sigma_f0[1] == paper.sigma_f0[0]


def test_paper_dynamics_match_hand(paper):
    assert paper.single_pair == pytest.approx(11.85281e9, rel=HAND)
    assert paper.mesh == pytest.approx(17.52442e9, rel=HAND)
    assert paper.reduced_mass == pytest.approx(0.08497272, rel=HAND)
    assert paper.resonance_speed / RPM == pytest.approx(12341.91, rel=HAND)
    assert dynamic_factor_at(paper, 4000 * RPM) == pytest.approx(1.074543, rel=HAND)
    assert dynamic_factor_at(paper, 20000 * RPM) == pytest.approx(0.7615651, rel=HAND)


# -- worked example (ii): 23/47, m = 2 mm, 25 deg -----------------------------------
def test_second_pair_matches_hand(second):
    assert second.tangential_force == pytest.approx(4347.826, rel=HAND)
    assert second.eps_alpha == pytest.approx(1.481584, rel=HAND)
    assert second.z_h == pytest.approx(2.285088, rel=HAND)
    assert second.z_eps == pytest.approx(0.9162271, rel=HAND)
    assert second.sigma_h0 == pytest.approx(1064.504e6, rel=HAND)
    assert second.z_b == pytest.approx(1.053054, rel=HAND)
    assert second.z_d == 1.0  # M_2 = 0.9708033 < 1
    hand = ((47.28235, 4.367837e-3, 1.122112e-3, 47.19417e-3, 24.76725, 2.183424e-3,
             1.375957, 1.936094, 289.5632e6),
            (53.23473, 4.721826e-3, 1.032280e-3, 95.40833e-3, 25.25496, 2.258993e-3,
             1.213305, 2.105416, 277.6642e6))
    for i, (theta, s_fn, rho_f, d_en, a_fen, h_fe, y_f, y_s, s_f0) in enumerate(hand):
        s = second.sections[i]
        assert math.degrees(s.theta) == pytest.approx(theta, rel=HAND)
        assert s.s_fn == pytest.approx(s_fn, rel=HAND)
        assert s.rho_f == pytest.approx(rho_f, rel=HAND)
        assert s.d_en == pytest.approx(d_en, rel=HAND)
        assert math.degrees(s.alpha_fen) == pytest.approx(a_fen, rel=HAND)
        assert s.h_fe == pytest.approx(h_fe, rel=HAND)
        assert second.y_f[i] == pytest.approx(y_f, rel=HAND)
        assert second.y_s[i] == pytest.approx(y_s, rel=HAND)
        assert second.sigma_f0[i] == pytest.approx(s_f0, rel=HAND)
    # Above 100 N/mm: no low-load correction of c'.
    assert second.single_pair == pytest.approx(14.42532e9, rel=HAND)
    assert second.mesh == pytest.approx(19.63557e9, rel=HAND)
    assert second.reduced_mass / 20e-3 == pytest.approx(6.120072, rel=HAND)  # kg/m
    assert second.resonance_speed / RPM == pytest.approx(23517.28, rel=HAND)
    assert dynamic_factor_at(second, 3000 * RPM) == pytest.approx(1.029340, rel=HAND)


# -- published figures ---------------------------------------------------------------
def test_stiffness_and_z_e_reproduce_published_reference():
    """ISO/TR 6336-30 example 1 as tabulated in gfsReboucas/Drivetrain (ISO_6336.m):
    z = 17/103, x1 = 0.145, beta = 15.8 deg, rack D (h_fP = 1.4 m): c'_th = 17.85584,
    c' = 12.37047 N/(mm um); steel E = 206 GPa: Z_E = 189.8117 sqrt(N/mm^2)."""
    beta, alpha = math.radians(15.8), math.radians(20.0)
    beta_b = math.asin(math.sin(beta) * math.cos(alpha))
    zn = [z / (math.cos(beta_b) ** 2 * math.cos(beta)) for z in (17, 103)]
    c_th = dynamics.single_pair_stiffness(zn[0], zn[1], alpha, 1.2, 0.145, 0.0, c_m=1.0)
    assert c_th / 1e9 == pytest.approx(17.85584, rel=5e-7)
    c1 = dynamics.single_pair_stiffness(zn[0], zn[1], alpha, 1.4, 0.145, 0.0) * math.cos(beta)
    assert c1 / 1e9 == pytest.approx(12.37047, rel=5e-7)
    assert contact.elasticity_factor(206e9, 0.3, 206e9, 0.3) / 1e3 == pytest.approx(189.8117, rel=5e-7)


# -- the old stiffness function --------------------------------------------------------
def _pair(z_a: int, z_b: int, module: float, deg: float, ded: float) -> GearPair:
    def gear(z: int) -> Gear:
        return Gear(teeth=z, module=module, pressure_angle=math.radians(deg), face_width=10 * module,
                    addendum=module, dedendum=ded * module, cutter_tip_radius=0.25 * module,
                    disk_inertia=1e-3)
    return GearPair(gear_a=gear(z_a), gear_b=gear(z_b))


@pytest.mark.parametrize("pair", [paper_pair(), _pair(23, 47, 2e-3, 25.0, 1.25),
                                  _pair(40, 31, 4e-3, 20.0, 1.3)])
def test_single_pair_stiffness_matches_model_function(pair):
    """The model's ``iso_6336_stiffness`` (now a wrapper of ``single_pair_stiffness``) gives
    what its earlier body computed for unshifted gears, written out here: ``c' = C_M C_B / q'``
    with ``q' = 0.04723 + 0.15551/z1 + 0.25791/z2`` in N/(mm um)."""
    wrapped = iso_6336_stiffness(pair)
    ga, gb = pair.gear_a, pair.gear_b
    q = 0.04723 + 0.15551 / ga.teeth + 0.25791 / gb.teeth
    alpha_deg = math.degrees(ga.pressure_angle)
    c_b = (1.0 + 0.5 * (1.2 - ga.dedendum / ga.module)) * (1.0 - 0.02 * (20.0 - alpha_deg))
    written_out = 0.8 * c_b / q
    assert wrapped.single_pair == pytest.approx(written_out, rel=1e-14)
    assert wrapped.mesh == pytest.approx(written_out * (0.75 * pair.contact_ratio + 0.25), rel=1e-14)
    new = dynamics.single_pair_stiffness(ga.teeth, gb.teeth, ga.pressure_angle, ga.dedendum / ga.module)
    assert new == pytest.approx(written_out * 1e9, rel=1e-14)


@pytest.mark.parametrize("pair", [paper_pair(), _pair(23, 47, 2e-3, 25.0, 1.25),
                                  _pair(40, 31, 4e-3, 20.0, 1.3)])
def test_single_pair_contact_factors_are_the_curvature_ratio(pair):
    """Z_B^2 = (rho_1 rho_2 at the pitch point) / (rho_1 rho_2 at the start of single contact),
    with the points from spurdyn.geometry; Z_D likewise at its end (the wheel's inner point)."""
    ga, gb = pair.gear_a, pair.gear_b
    eps = contact.transverse_contact_ratio(ga.teeth, gb.teeth, ga.module, ga.pressure_angle,
                                           ga.tip_radius, gb.tip_radius)
    z_b, z_d = contact.single_pair_contact_factors(ga.teeth, gb.teeth, ga.module, ga.pressure_angle,
                                                   ga.tip_radius, gb.tip_radius, eps)

    def curvature_product(roll_a):
        return ga.base_radius * roll_a * gb.base_radius * float(pair.roll_b_from_roll_a(roll_a))

    pitch = curvature_product(pair.pitch_roll_a)
    inner_a, inner_b = pair.single_contact_roll_a
    assert z_b == pytest.approx(max(1.0, math.sqrt(pitch / curvature_product(inner_a))), rel=1e-13)
    assert z_d == pytest.approx(max(1.0, math.sqrt(pitch / curvature_product(inner_b))), rel=1e-13)


# -- the 30 deg tangent ------------------------------------------------------------------
def _tangent_point(z, module, alpha, ded, rho):
    """Independent construction: the trochoid of spurdyn.geometry where its tangent is 30 deg
    off the tooth's centre line, and its curvature radius there (finite differences)."""
    rp = module * z / 2
    centre = ivl.cutter_tip_centre(module, alpha, ded, rho)

    def normal_angle(phi):
        # The fillet's normal is the rounding circle's normal at the enveloping point,
        # turned with the gear (rotate by phi, as fillet_point does).
        dx, dy = centre[0] + rp * phi, centre[1]
        n = ivl.rotate(np.array([dx, dy]), phi)
        return math.atan2(abs(n[1]), abs(n[0]))  # off the x axis = tangent off the y axis

    lo = float(ivl.fillet_phi_at_normal_angle(1e-9, rp, centre))
    hi = float(ivl.fillet_phi_at_normal_angle(math.pi / 2 - alpha - 1e-9, rp, centre))
    phi = brentq(lambda p: normal_angle(p) - math.pi / 6, lo, hi, xtol=1e-16, rtol=1e-15)
    point = ivl.fillet_point(phi, rp, centre, rho)
    h = 1e-5
    pm, pp = (ivl.fillet_point(phi + s, rp, centre, rho) for s in (-h, h))
    d1, d2 = (pp - pm) / (2 * h), (pp - 2 * point + pm) / h**2
    radius = np.linalg.norm(d1) ** 3 / abs(d1[0] * d2[1] - d1[1] * d2[0])
    return point, radius


@pytest.mark.parametrize("z, alpha_deg, rho_ratio", [(28, 20.0, 0.38), (23, 25.0, 0.38),
                                                     (47, 25.0, 0.38), (60, 20.0, 0.25)])
def test_tangent_point_solves_its_equation_and_is_the_30_degree_point(z, alpha_deg, rho_ratio):
    m, alpha = 2e-3, math.radians(alpha_deg)
    ded, rho = 1.25 * m, rho_ratio * m
    _, g, h = root.rack_auxiliaries(z, m, alpha, ded, rho)
    theta = root.tangent_angle(z, g, h)
    assert abs(theta - (2 * g / z * math.tan(theta) - h)) < 1e-12
    eps = contact.transverse_contact_ratio(z, 50, m, alpha, m * z / 2 + m, 26 * m)
    sec = root.root_section(z, m, alpha, ded, rho, m * z / 2 + m, eps)
    point, radius = _tangent_point(z, m, alpha, ded, rho)
    assert sec.s_fn == pytest.approx(2 * point[0], rel=1e-11)
    # rho_F against a finite-difference curvature (step 1e-5: truncation ~1e-6).
    assert sec.rho_f == pytest.approx(radius, rel=1e-5)
    # h_Fe: the load line at d_en along the flank normal meets the centre line h_Fe
    # above the chord of the tangent points; alpha_Fen is its angle off the chord.
    rb, half = m * z / 2 * math.cos(alpha), math.pi / (2 * z) + float(ivl.inv(alpha))
    q = ivl.right_flank_point(sec.d_en / 2, rb, half)
    n = ivl.right_flank_normal(sec.d_en / 2, rb, half)
    y_axis = q[1] - q[0] / n[0] * n[1]
    assert sec.h_fe == pytest.approx(y_axis - point[1], rel=1e-11)
    assert sec.alpha_fen == pytest.approx(math.atan2(abs(n[1]), abs(n[0])), rel=1e-12)


def test_tangent_angle_refuses_a_root_off_the_fillet():
    # Absurd auxiliaries whose Newton root lies at negative theta.
    with pytest.raises(ArithmeticError):
        root.tangent_angle(1, 5.0, -1.0)
    with pytest.raises(ArithmeticError):
        root.tangent_angle(1, -50.0, 3.0)


# -- properties ------------------------------------------------------------------------
def test_form_factor_falls_with_tooth_count():
    m, alpha = 2e-3, math.radians(20.0)
    y_f = []
    for z in (17, 20, 25, 30, 40, 60, 100, 200):
        eps = contact.transverse_contact_ratio(z, 60, m, alpha, m * z / 2 + m, 31 * m)
        sec = root.root_section(z, m, alpha, 1.25 * m, 0.38 * m, m * z / 2 + m, eps)
        y_f.append(root.form_factor(sec, m, alpha))
    assert all(a > b for a, b in zip(y_f, y_f[1:]))


def test_contact_ratio_factor_tends_to_one():
    assert contact.contact_ratio_factor(1.0) == 1.0
    assert contact.contact_ratio_factor(1.0 + 1e-9) == pytest.approx(1.0, abs=1e-9)
    assert contact.contact_ratio_factor(1.6) < contact.contact_ratio_factor(1.2) < 1.0


def test_contact_stress_scales_as_root_of_force():
    args = (0.05, 0.02, 2.0, 2.49, 1.9e5, 0.89)
    s1 = contact.nominal_contact_stress(1000.0, *args)
    assert contact.nominal_contact_stress(4000.0, *args) == pytest.approx(2 * s1, rel=1e-15)
    assert contact.nominal_contact_stress(9000.0, *args) == pytest.approx(3 * s1, rel=1e-15)


def test_zone_factor_standard_form():
    a = math.radians(20.0)
    assert contact.zone_factor(a) == pytest.approx(math.sqrt(4 / math.sin(2 * a)), rel=1e-15)
    # A larger working angle (spread centres) lowers Z_H.
    assert contact.zone_factor(a, math.radians(22.0)) < contact.zone_factor(a)


def test_dynamic_factor_tends_to_one_far_below_resonance():
    c1, w = 14e9, 2e5
    for dev in (0.0, 10e-6):
        assert dynamics.dynamic_factor(1e-6, c1, w, 1.6, dev, dev) == pytest.approx(1.0, abs=1e-5)
    assert dynamics.dynamic_factor(0.0, c1, w, 1.6, 10e-6, 5e-6, 8e-6) == 1.0


def test_dynamic_factor_ranges_join():
    c1, w, eps = 14e9, 2e5, 1.6
    args = (c1, w, eps, 12e-6, 8e-6, 5e-6)
    main = dynamics.dynamic_factor(1.0, *args)
    superc = dynamics.dynamic_factor(2.0, *args)
    assert dynamics.dynamic_factor(1.15, *args) == main
    assert dynamics.dynamic_factor(1.15 + 1e-12, *args) == pytest.approx(main, rel=1e-10)
    assert dynamics.dynamic_factor(1.5 - 1e-12, *args) == pytest.approx(superc, rel=1e-10)
    mid = dynamics.dynamic_factor(1.325, *args)
    assert mid == pytest.approx(0.5 * (main + superc), rel=1e-12)
    # Pitch deviation raises K_v in every range.
    for n in (0.5, 1.0, 1.3, 2.0):
        assert dynamics.dynamic_factor(n, c1, w, eps, 20e-6) > dynamics.dynamic_factor(n, c1, w, eps, 0.0)


def test_dynamic_coefficients_continuous_in_contact_ratio():
    for edge in (1.5, 2.5):
        lo, hi = dynamics.dynamic_coefficients(edge - 1e-9), dynamics.dynamic_coefficients(edge + 1e-9)
        assert lo[6] == pytest.approx(hi[6], abs=1e-8)


def test_modulus_ratio_scales_stiffness():
    alpha = math.radians(20)
    steel = dynamics.single_pair_stiffness(30, 60, alpha, 1.25)
    half = dynamics.single_pair_stiffness(30, 60, alpha, 1.25, modulus_ratio=0.5)
    assert half == pytest.approx(0.5 * steel, rel=1e-15)


def test_low_load_bound_and_stiffness_correction():
    assert dynamics.lower_resonance_bound(1e5) == 0.85
    assert dynamics.lower_resonance_bound(1e5 * (1 - 1e-12)) == pytest.approx(0.85, rel=1e-10)
    full = dynamics.single_pair_stiffness(28, 28, math.radians(20), 1.25)
    assert dynamics.single_pair_stiffness(28, 28, math.radians(20), 1.25, line_load=1e5) == full
    quarter = dynamics.single_pair_stiffness(28, 28, math.radians(20), 1.25, line_load=6.25e3)
    assert quarter == pytest.approx(0.5 * full, rel=1e-15)  # (1/16)^(1/4)


def test_resonance_speed_is_iso_formula_in_its_units():
    c_iso, m_iso, z = 17.5, 0.0061, 23  # N/(mm um), kg/mm
    n_iso = 30000 / (math.pi * z) * math.sqrt(c_iso / m_iso)  # min^-1
    omega = dynamics.resonance_speed(z, c_iso * 1e9, m_iso * 1e3)
    assert omega / RPM == pytest.approx(n_iso, rel=1e-14)


def test_reduced_mass_of_solid_discs_is_iso_closed_form():
    """ISO's m_red = pi rho u^2 d_m1^4 / (8 (u^2 + 1) d_b1^2) when d_m and d_b scale with u."""
    rho, d_m1, d_b1, u = 7800.0, 0.05, 0.045, 2.5
    j1 = dynamics.solid_disk_inertia_per_width(d_m1, rho)
    j2 = dynamics.solid_disk_inertia_per_width(u * d_m1, rho)
    m_red = dynamics.reduced_mass(j1, j2, d_b1 / 2, u * d_b1 / 2)
    assert m_red == pytest.approx(math.pi * rho * u**2 * d_m1**4 / (8 * (u**2 + 1) * d_b1**2), rel=1e-14)


def test_running_in_tip_relief():
    assert dynamics.running_in_tip_relief(97 * 18.45e6) == pytest.approx(1.5e-6, rel=1e-12)


def test_safety_factors(paper):
    k_v = dynamic_factor_at(paper, 4000 * RPM)
    sigma_f = safety.root_stress(paper.sigma_f0[0], k_a=1.25, k_v=k_v)
    assert sigma_f == pytest.approx(paper.sigma_f0[0] * 1.25 * k_v, rel=1e-15)
    s_f = safety.root_safety(sigma_f, safety.root_limit(430e6))
    assert s_f == pytest.approx(2 * 430e6 / sigma_f, rel=1e-15)
    # A simulated peak equal to ISO's sigma_F0 K_v gives ISO's S_F.
    peak = paper.sigma_f0[0] * k_v
    assert safety.root_stress_from_peak(peak, k_a=1.25) == pytest.approx(sigma_f, rel=1e-15)
    sigma_h = safety.contact_stress(paper.sigma_h0, k_a=1.25, k_v=k_v)
    assert sigma_h == pytest.approx(paper.sigma_h0 * math.sqrt(1.25 * k_v), rel=1e-15)
    peak_h = paper.sigma_h0 * math.sqrt(k_v)
    assert safety.contact_stress_from_peak(peak_h, k_a=1.25) == pytest.approx(sigma_h, rel=1e-15)
    assert safety.contact_safety(sigma_h, safety.contact_limit(1500e6)) == pytest.approx(1500e6 / sigma_h)


def test_iso_pair_reads_the_model_pair():
    p = paper_pair()
    ip = iso_pair(p)
    assert ip.gear1.inertia == p.gear_a.disk_inertia
    assert ip.gear1.rack_tip_radius == p.gear_a.cutter_tip_radius
    assert ip.gear1.young == p.gear_a.material.young
    spread = dataclasses.replace(p, centre_distance=p.centre_distance + 1e-4)
    with pytest.raises(ValueError):
        iso_pair(spread)


def test_softer_material_lowers_elasticity_factor():
    steel = contact.elasticity_factor(210e9, 0.3, 210e9, 0.3)
    assert contact.elasticity_factor(105e9, 0.3, 105e9, 0.3) == pytest.approx(steel / math.sqrt(2), rel=1e-15)
