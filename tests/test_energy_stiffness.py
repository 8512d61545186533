"""The potential-energy mesh stiffness (spurdyn.energy, docs/faults_energy.md): the
integrals against an independent parametrisation of the flank and a closed form, their
convergence, the crack's limits and monotony, the mean's identity, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair
from spurdyn.energy import Crack, mean_mesh_stiffness, mesh_cycle, pair_compliance, tooth_compliance
from spurdyn.energy.foundation import centre_line_crossing, foundation_compliance, root_half_angle
from spurdyn.energy.section import half_height, load_angle, radial_position, tip_alpha
from spurdyn.energy.tooth import SHEAR_FACTOR, root_segment_integrals

PAIR = paper_pair()
GEAR = PAIR.gear_a
BORE = 0.01905
ROLLS = np.linspace(PAIR.start_roll_a, PAIR.end_roll_a, 9)


def deepest(angle: float = math.radians(45.0)) -> float:
    """The deepest crack the published limiting line leaves a tip to (m)."""
    h_b = GEAR.base_radius * math.sin(GEAR.half_angle_base)
    h_tip = float(half_height(tip_alpha(GEAR), GEAR.base_radius, GEAR.half_angle_base))
    return (h_b + h_tip) / math.sin(angle)


def flank_beam(roll: float) -> tuple[float, float, float]:
    """Bending, shear, axial compliances of the healthy tooth from the flank as
    :mod:`spurdyn.geometry` draws it (points and normals by radius), integrated by
    ``quad`` over the radius: independent of the ``alpha`` parametrisation."""
    rb, width = GEAR.base_radius, GEAR.face_width
    young = GEAR.material.young
    shear_modulus = young / (2.0 * (1.0 + GEAR.material.poisson))
    r_c = float(GEAR.radius_at_roll_angle(roll))
    x_c, y_c = GEAR.flank_point(np.asarray(r_c))
    n_x, n_y = GEAR.flank_normal(np.asarray(r_c))

    def section(r: float) -> tuple[float, float, float]:
        x, y = GEAR.flank_point(np.asarray(r))
        step = 1e-7 * r
        dy = (GEAR.flank_point(np.asarray(r + step))[1]
              - GEAR.flank_point(np.asarray(r - step))[1]) / (2 * step)
        return float(x), float(y), float(dy)

    def bending(r: float) -> float:
        x, y, dy = section(r)
        moment = x_c * n_y - (y_c - y) * n_x          # the force -n at (x_c, y_c) about (0, y)
        return moment**2 / (young * width * (2 * x) ** 3 / 12) * dy

    def shear(r: float) -> float:
        x, _, dy = section(r)
        return SHEAR_FACTOR * n_x**2 / (shear_modulus * width * 2 * x) * dy

    def axial(r: float) -> float:
        x, _, dy = section(r)
        return n_y**2 / (young * width * 2 * x) * dy

    lo = rb * (1 + 1e-12)
    return tuple(quad(f, lo, r_c, epsabs=0.0, epsrel=1e-9, limit=200)[0]
                 for f in (bending, shear, axial))


@pytest.mark.parametrize("roll", [PAIR.start_roll_a, PAIR.pitch_roll_a, PAIR.end_roll_a])
def test_alpha_integrals_match_the_flank_of_the_geometry_package(roll):
    t = tooth_compliance(GEAR, [roll])
    reference = flank_beam(roll)
    for got, want in zip((t.bending[0], t.shear[0], t.axial[0]), reference):
        assert got == pytest.approx(want, rel=1e-6)


def test_root_segment_is_the_uniform_cantilever_closed_form():
    a1 = load_angle(GEAR, ROLLS)
    rb, a2, width = GEAR.base_radius, GEAR.half_angle_base, GEAR.face_width
    bending, shear, axial = root_segment_integrals(GEAR, a1, width)
    young = GEAR.material.young
    g = young / (2.0 * (1.0 + GEAR.material.poisson))
    height = 2.0 * rb * math.sin(a2)
    inertia, area = width * height**3 / 12.0, width * height
    y_b = float(radial_position(a2, rb, a2))
    d = y_b - GEAR.root_radius
    # M(y) = cos(a1) (y_c - y) - sin(a1) h_c is linear in y:
    # int M^2 dy = (M_0^3 - M_1^3) / (3 cos a1)
    m_root = np.cos(a1) * (radial_position(-a1, rb, a2) - GEAR.root_radius) \
        - np.sin(a1) * half_height(-a1, rb, a2)
    m_base = m_root - np.cos(a1) * d
    closed = (m_root**3 - m_base**3) / (3 * np.cos(a1) * young * inertia)
    np.testing.assert_allclose(bending, closed, rtol=1e-12)
    np.testing.assert_allclose(shear, SHEAR_FACTOR * np.cos(a1) ** 2 * d / (g * area), rtol=1e-12)
    np.testing.assert_allclose(axial, np.sin(a1) ** 2 * d / (young * area), rtol=1e-12)


@pytest.mark.parametrize("crack", [None, Crack(1.5e-3), Crack(4.5e-3, math.radians(60.0))])
def test_quadrature_converges(crack):
    fine = tooth_compliance(GEAR, ROLLS, crack, BORE, points=512).total
    for points in (48, 96):
        coarse = tooth_compliance(GEAR, ROLLS, crack, BORE, points=points).total
        np.testing.assert_allclose(coarse, fine, rtol=1e-11)


def test_zero_crack_is_the_healthy_tooth_to_round_off():
    healthy = pair_compliance(PAIR, ROLLS, bore_radii=(BORE, BORE))
    zero = pair_compliance(PAIR, ROLLS, Crack(0.0), Crack(0.0), bore_radii=(BORE, BORE))
    np.testing.assert_allclose(zero.total, healthy.total, rtol=1e-14, atol=0.0)


def test_vanishing_crack_cuts_only_the_bulge_above_the_base_circle():
    """As ``q -> 0+`` the published limiting line stands at ``h_b``, and the flank's bulge
    above the base circle (``h`` up to ``r_b a2``) carries nothing: a jump no larger than
    the section's ``(2 h_max / (h_max + h_b))^3``."""
    healthy = tooth_compliance(GEAR, ROLLS)
    tiny = tooth_compliance(GEAR, ROLLS, Crack(1e-12))
    h_b = GEAR.base_radius * math.sin(GEAR.half_angle_base)
    h_max = GEAR.base_radius * GEAR.half_angle_base
    bound = (2 * h_max / (h_max + h_b)) ** 3 - 1
    jump = tiny.bending / healthy.bending - 1
    assert np.all(jump > 0) and np.all(jump < bound)


def test_stiffness_falls_monotonically_with_depth():
    depths = np.linspace(0.0, 0.98 * deepest(), 14)
    k = np.array([pair_compliance(PAIR, ROLLS, Crack(q), bore_radii=(BORE, BORE)).stiffness
                  for q in depths])
    assert np.all(np.diff(k, axis=0) <= 1e-12 * k[0])
    assert np.all(np.diff(k[:, 0]) < 0)        # the lowest contact: every section is cut
    means = [mean_mesh_stiffness(PAIR, Crack(q), bore_radii=(BORE, BORE)) for q in depths]
    assert np.all(np.diff(means) < 0)


def test_crack_on_either_gear_of_an_identical_pair_mirrors():
    crack = Crack(2e-3)
    mirrored = PAIR.line_of_centres_length / GEAR.base_radius - ROLLS
    on_a = pair_compliance(PAIR, ROLLS, crack_a=crack, bore_radii=(BORE, BORE)).total
    on_b = pair_compliance(PAIR, mirrored, crack_b=crack, bore_radii=(BORE, BORE)).total
    np.testing.assert_allclose(on_a, on_b, rtol=1e-12)


def test_mean_is_the_cycle_average():
    """``(1/p) int k_pair`` over the path is the mesh stiffness's mean over a cycle."""
    pitch = 2 * math.pi / GEAR.teeth
    n = 4000
    xi = PAIR.start_roll_a + (np.arange(n) + 0.5) * pitch / n
    cycle = mesh_cycle(PAIR, xi, bore_radii=(BORE, BORE))
    assert set(np.unique(cycle.pairs)) == {1, 2}
    assert np.mean(cycle.mesh) == pytest.approx(mean_mesh_stiffness(PAIR, bore_radii=(BORE, BORE)),
                                                rel=1e-3)


def test_foundation_geometry_and_bore():
    """``u_f`` from the line of action as the geometry package draws it; ``theta_f`` on the
    root circle; the body's compliance grows as its bore shrinks (more body under the tooth)."""
    for roll in ROLLS:
        r_c = float(GEAR.radius_at_roll_angle(roll))
        (x, y), (n_x, n_y) = GEAR.flank_point(np.asarray(r_c)), GEAR.flank_normal(np.asarray(r_c))
        assert centre_line_crossing(GEAR, roll) == pytest.approx(y - x / n_x * n_y, rel=1e-13)
    angle = root_half_angle(GEAR)
    corner = GEAR.root_radius * np.array([math.sin(angle), math.cos(angle)])
    np.testing.assert_allclose(GEAR.fillet_points(np.asarray(0.0)), corner, rtol=1e-12)
    bores = np.linspace(0.3, 0.9, 7) * GEAR.root_radius
    c = np.array([foundation_compliance(GEAR, ROLLS, bore) for bore in bores])
    assert np.all(c > 0) and np.all(np.diff(c, axis=0) < 0)


@pytest.mark.parametrize("make, key", [
    (lambda: Crack(-1e-3), "depth"),
    (lambda: Crack(1e-3, 0.0), "angle"),
    (lambda: Crack(float("nan")), "depth"),
    (lambda: tooth_compliance(GEAR, ROLLS, Crack(1.01 * deepest())), "depth"),
    (lambda: tooth_compliance(GEAR, ROLLS, bore_radius=GEAR.root_radius), "bore_radius"),
])
def test_bad_input_is_refused_by_its_key(make, key):
    with pytest.raises(InputError) as err:
        make()
    assert err.value.field == key
