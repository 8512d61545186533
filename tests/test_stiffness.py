"""Static single-pair stiffness of the paper's pair."""

import numpy as np
import pytest

from spurdyn.geometry import paper_pair
from spurdyn.model import ToothCompliance, build_tooth, iso_6336_stiffness, pair_stiffness, pitch_point_stiffness


@pytest.fixture(scope="module")
def pair_and_tooth():
    p = paper_pair()
    return p, build_tooth(p.gear_a)


def test_iso_reference_figures(pair_and_tooth):
    p, _ = pair_and_tooth
    iso = iso_6336_stiffness(p)
    assert iso.single_pair == pytest.approx(12.6, abs=0.05)
    assert iso.mesh == pytest.approx(18.6, abs=0.05)


def test_pitch_point_stiffness_between_one_and_three_times_iso(pair_and_tooth):
    p, tooth = pair_and_tooth
    k = pitch_point_stiffness(p, tooth, tooth)
    c_b, _ = iso_6336_stiffness(p).per_face_width(p.gear_a.face_width)
    assert 1.0 * c_b < k < 3.0 * c_b


def test_stiffness_falls_slowly_with_refinement():
    p = paper_pair()
    ks = [pitch_point_stiffness(p, t, t) for t in (build_tooth(p.gear_a, nx, ny)
                                                   for nx, ny in ((3, 10), (4, 14), (6, 20), (8, 28)))]
    assert all(a > b for a, b in zip(ks, ks[1:]))
    # A few percent per refinement, not a collapse: the point-load compliance grows
    # logarithmically with resolution.
    steps = np.array(ks[:-1]) / np.array(ks[1:]) - 1
    assert np.all(steps < 0.12)


def test_stiffness_curve_symmetric_for_identical_gears_and_lowest_at_ends(pair_and_tooth):
    p, tooth = pair_and_tooth
    rolls = np.linspace(p.start_roll_a, p.end_roll_a, 9)
    k = pair_stiffness(p, tooth, tooth, rolls).stiffness
    assert np.allclose(k, k[::-1], rtol=1e-9)
    assert k.argmax() == 4 and k[0] < 0.7 * k[4]


def test_compliance_is_the_work_of_a_unit_load(pair_and_tooth):
    """Compliance equals f.K^-1 f, and doubling the modulus halves it (linearity)."""
    p, tooth = pair_and_tooth
    c = ToothCompliance(tooth)
    r = p.gear_a.pitch_radius
    f = c.load_vector(r)
    # Unit load: the nodal forces add up to the unit normal (shape functions sum to 1).
    assert np.hypot(f[0::2].sum(), f[1::2].sum()) == pytest.approx(1.0, rel=1e-12)
    from dataclasses import replace
    from spurdyn.fem import Material
    stiff_gear = replace(p.gear_a, material=Material(2 * 210e9, 0.3, 7800.0))
    assert ToothCompliance(build_tooth(stiff_gear))(r) == pytest.approx(c(r) / 2, rel=1e-10)


def test_refinement_adds_the_point_load_log_compliance_of_two_half_planes():
    """Why the stiffness keeps falling with refinement (docs/stiffness.md).

    A point force F on a plane-stress half-plane of thickness b has a surface
    displacement ``(2 F / (pi E b)) ln(1/r)``: each halving of the element size near the
    load lets the loaded point sink by ``(2 / (pi E b)) ln 2`` more per unit force, per
    tooth. Halving the mesh (4x14 -> 8x28, 6x20 -> 12x40) must add about twice that to
    the pair compliance, and the pitch stiffness must fall at every step from 4x14 on.
    """
    p = paper_pair()
    g = p.gear_a
    densities = [(4, 14), (6, 20), (8, 28), (12, 40)]
    comp = {d: 1.0 / pitch_point_stiffness(p, t, t)
            for d, t in ((d, build_tooth(g, *d)) for d in densities)}
    ks = [1.0 / comp[d] for d in densities]
    assert all(a > b for a, b in zip(ks, ks[1:]))
    half_planes = 2 * 2.0 / (np.pi * g.material.young * g.face_width) * np.log(2.0)
    for coarse, fine in (((4, 14), (8, 28)), ((6, 20), (12, 40))):
        added = comp[fine] - comp[coarse]
        assert 0.8 * half_planes < added < 1.25 * half_planes
