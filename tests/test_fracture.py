"""Stress intensity factors by the interaction integral (docs/fracture.md): the auxiliary
fields, an exact field recovered, the handbook's strips and plates within 2 %, the domain's
independence, the growth direction's limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_stiffness
from spurdyn.fem.factor import factor_spd
from spurdyn.fem.material import STEEL, plane_stress_matrix
from spurdyn.fracture import (
    centre_crack_plate, edge_crack_strip, end_load, equivalent_k, growth_angle, solve,
    stress_intensity, tangential_stress,
)
from spurdyn.fracture import handbook as hb
from spurdyn.fracture.correlation import displacement_correlation, quarter_points
from spurdyn.fracture.williams import williams_fields
from spurdyn.geometry.presets import paper_gear
from spurdyn.mesh.cracked import crack_path, cracked_tooth
from spurdyn.mesh.tooth import tooth_mesh

WIDTH = 0.01
STRESS = 100e6
#: The strips' element size and the tip's share of the smaller of it and the crack's depth
#: (docs/fracture.md, section 5: the finest meshes of the study move F by under 0.5 %).
SIZE, TIP_SHARE = 0.1 * WIDTH, 0.05
TOLERANCE = 0.02


def _uniform(x: np.ndarray) -> np.ndarray:
    return np.full(len(x), STRESS)


def _bending(x: np.ndarray) -> np.ndarray:
    return STRESS * (1.0 - 2.0 * x[:, 0] / WIDTH)


@pytest.fixture(scope="module")
def strips() -> dict:
    return {}


def _strip(strips: dict, ratio: float):
    if ratio not in strips:
        depth = ratio * WIDTH
        strips[ratio] = edge_crack_strip(WIDTH, 2.0 * WIDTH, depth, SIZE,
                                         TIP_SHARE * min(depth, SIZE))
    return strips[ratio]


def test_williams_fields_are_consistent():
    """The gradient is the displacement's (central differences), the stress D times its strain,
    the crack's faces free of traction, and the stress ahead the unit K's."""
    rng = np.random.default_rng(3)
    x = rng.uniform(-1.0, 1.0, (30, 2)) * 1e-3
    d = plane_stress_matrix(STEEL)
    for mode in ("I", "II"):
        u, grad, stress = williams_fields(x, mode, STEEL)
        h = 1e-9
        fd = np.stack([(williams_fields(x + h * e, mode, STEEL)[0]
                        - williams_fields(x - h * e, mode, STEEL)[0]) / (2 * h)
                       for e in np.eye(2)], axis=-1)
        assert np.abs(fd - grad).max() < 1e-6 * np.abs(grad).max()
        strain = np.stack([grad[:, 0, 0], grad[:, 1, 1], grad[:, 0, 1] + grad[:, 1, 0]], -1)
        assert np.allclose(strain @ d.T, stress, rtol=0, atol=1e-12 * np.abs(stress).max())
        faces = np.array([[-1e-3, 0.0], [-1e-3, -0.0]])
        _, _, on_faces = williams_fields(faces, mode, STEEL)
        assert np.abs(on_faces[:, 1:]).max() < 1e-12 * np.abs(on_faces).max()
        r = 2e-4
        _, _, ahead = williams_fields(np.array([[r, 0.0]]), mode, STEEL)
        assert ahead[0, 1 if mode == "I" else 2] == pytest.approx(1.0 / math.sqrt(2 * math.pi * r))


def test_exact_near_tip_field_recovered(strips):
    """Nodal values of K_I u_I + K_II u_II on a cracked strip give back K_I and K_II (the
    interpolation's error only) in the domains a few rings out (in the first, 1 and 3 %:
    docs/fracture.md, section 5)."""
    plate = _strip(strips, 0.5)
    tip = plate.nodes[plate.tips[0]]
    x = plate.nodes - tip
    x[plate.seam[:, 0], 1] = -0.0               # the lower face: theta = -pi
    x[plate.tips[0]] = (1.0, 0.0)                # off the tip (its displacement is 0)
    k_i, k_ii = 3.0e6, -1.2e6
    u = k_i * williams_fields(x, "I", STEEL)[0] + k_ii * williams_fields(x, "II", STEEL)[0]
    u[plate.tips[0]] = 0.0
    k = stress_intensity(plate.nodes, plate.elements, u.ravel(), STEEL, int(plate.tips[0]),
                         plate.ahead[0], rings=(3, 4, 5))
    assert np.allclose(k.k_i, k_i, rtol=3e-3)
    assert np.allclose(k.k_ii, k_ii, rtol=3e-3)


@pytest.mark.parametrize("ratio", [0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
def test_edge_crack_in_a_strip(strips, ratio):
    """Tension: Tada, Paris & Irwin's F; bending: Brown & Srawley's; within 2 %, K_II nil."""
    plate = _strip(strips, ratio)
    k0 = STRESS * math.sqrt(math.pi * ratio * WIDTH)
    for load, handbook in ((_uniform, hb.tension_tada), (_bending, hb.bending_brown_srawley)):
        u = solve(plate, STEEL, end_load(plate, load))
        k = stress_intensity(plate.nodes, plate.elements, u, STEEL, int(plate.tips[0]),
                             plate.ahead[0])
        assert np.all(np.abs(k.k_i / (k0 * handbook(ratio)) - 1.0) < TOLERANCE)
        assert np.all(np.abs(k.k_ii) < 0.01 * k.k_i)


@pytest.mark.parametrize("degrees", [0.0, 30.0, 45.0, 60.0])
def test_inclined_centre_crack(degrees):
    """Both tips of a centre crack at beta in a square of 40 half-lengths: the infinite plate's
    K_I and K_II within 2 % of sigma sqrt(pi a) (the square's own effect some 0.2 %)."""
    a, beta = 1e-3, math.radians(degrees)
    plate = centre_crack_plate(40 * a, 40 * a, a, beta, 2 * a, 0.05 * a)
    u = solve(plate, STEEL, end_load(plate, _uniform))
    k_i, k_ii = hb.centre_crack(STRESS, a, beta)
    k0 = STRESS * math.sqrt(math.pi * a)
    for tip, ahead in zip(plate.tips, plate.ahead):
        k = stress_intensity(plate.nodes, plate.elements, u, STEEL, int(tip), ahead)
        assert np.all(np.abs(k.k_i - k_i) < TOLERANCE * k0)
        assert np.all(np.abs(k.k_ii - k_ii) < TOLERANCE * k0)


def test_domains_agree_and_supports_idle(strips):
    """Rings 1 to 5 of a strip in tension give one K to 0.5 %; the statically determinate
    supports carry no force (the loads are self-equilibrated)."""
    plate = _strip(strips, 0.4)
    forces = end_load(plate, _uniform)
    assert forces[1::2].sum() == pytest.approx(0.0, abs=1e-9 * STRESS * WIDTH)
    top = plate.nodes[:, 1] > 0.0
    assert forces[1::2][top].sum() == pytest.approx(STRESS * WIDTH)
    u = solve(plate, STEEL, forces)
    residual = assemble_stiffness(plate.nodes, plate.elements, STEEL, 1.0) @ u - forces
    assert np.abs(residual).max() < 1e-8 * np.abs(forces).max()
    k = stress_intensity(plate.nodes, plate.elements, u, STEEL, int(plate.tips[0]),
                         plate.ahead[0], rings=(1, 2, 3, 4, 5))
    assert np.ptp(k.k_i) < 0.005 * k.k_i.mean()
    assert np.all(np.diff(k.radius) > 0.0)


def test_domains_kept_to_the_tip_s_width_agree_across_a_change_of_width(strips):
    """A strip whose elements beyond 1.5 times the 2-ring domain's radius from the tip are a
    quarter as wide (a web's junction, docs/fracture.md 8.7): the domains reaching across the
    change disagree (the domain form assumes one width), those kept to the tip's width agree
    with the domains inside it to 0.5 %; with one width everywhere ``widths`` changes nothing."""
    plate = _strip(strips, 0.4)
    nd, el, tip = plate.nodes, plate.elements, int(plate.tips[0])
    forces = end_load(plate, _uniform)
    rings = (1, 2, 3, 4, 5, 6)
    u = solve(plate, STEEL, forces)
    same = stress_intensity(nd, el, u, STEEL, tip, plate.ahead[0], rings)
    kept = stress_intensity(nd, el, u, STEEL, tip, plate.ahead[0], rings, widths=np.ones(len(el)))
    assert np.array_equal(same.k_i, kept.k_i) and np.array_equal(same.k_ii, kept.k_ii)
    far = np.hypot(*(nd[el].mean(axis=1) - nd[tip]).T) > 1.5 * same.radius[1]
    widths = np.where(far, 0.25, 1.0)
    k = sum(assemble_stiffness(nd, el[widths == w], STEEL, w) for w in (0.25, 1.0)).tocsr()
    x, y = nd.T
    held = [int(np.argmin(np.hypot(x - x.min(), y - y.min()))),
            int(np.argmin(np.hypot(x - x.max(), y - y.min())))]
    free = np.setdiff1d(np.arange(forces.size), [2 * held[0], 2 * held[0] + 1, 2 * held[1] + 1])
    u = np.zeros(forces.size)
    u[free] = factor_spd(k[free][:, free]).solve(forces[free])
    across = stress_intensity(nd, el, u, STEEL, tip, plate.ahead[0], rings)
    kept = stress_intensity(nd, el, u, STEEL, tip, plate.ahead[0], rings, widths=widths)
    assert np.ptp(across.k_i) > 0.1 * across.k_i[1]
    assert np.all(np.abs(kept.k_i / kept.k_i[1] - 1.0) < 0.005)
    assert kept.k_i[1] == across.k_i[1]          # the 2-ring domain lies inside: unchanged


def test_refusals(strips):
    plate = _strip(strips, 0.3)
    u = np.zeros(plate.nodes.size)
    args = (plate.nodes, plate.elements, u, STEEL, int(plate.tips[0]))
    with pytest.raises(InputError, match="rings"):
        stress_intensity(*args, plate.ahead[0], rings=(2, 40))
    with pytest.raises(InputError, match="rings"):
        stress_intensity(*args, plate.ahead[0], rings=(0,))
    with pytest.raises(InputError, match="ahead"):
        stress_intensity(*args, np.zeros(2))
    with pytest.raises(InputError, match="depth"):
        edge_crack_strip(WIDTH, WIDTH, WIDTH, SIZE, SIZE)
    with pytest.raises(InputError, match="half_length"):
        centre_crack_plate(WIDTH, WIDTH, WIDTH, 0.0, SIZE, SIZE)
    with pytest.raises(InputError, match="k_i"):
        growth_angle(-1.0, 0.0)
    with pytest.raises(InputError, match="k_ii"):
        growth_angle(1.0, math.nan)


def test_growth_direction_limits():
    """Erdogan & Sih: pure mode I runs straight on; pure mode II turns by -acos(1/3) = -70.53
    deg with K_eq = 2 K_II / sqrt(3); the angle is the brief's form, odd in K_II, where the
    shear stress vanishes, and the tangential stress is largest there."""
    assert growth_angle(1.0e6, 0.0) == 0.0
    assert equivalent_k(1.0e6, 0.0) == pytest.approx(1.0e6)
    assert growth_angle(0.0, 1.0e6) == pytest.approx(-math.acos(1.0 / 3.0))
    assert math.degrees(growth_angle(0.0, 1.0e6)) == pytest.approx(-70.53, abs=0.01)
    assert equivalent_k(0.0, 1.0e6) == pytest.approx(2.0e6 / math.sqrt(3.0))
    for k_i, k_ii in ((1.0, 0.3), (0.5, -2.0), (-0.4, 1.0), (2.0, 5.0)):
        theta = growth_angle(k_i, k_ii)
        brief = 2.0 * math.atan((k_i - math.sqrt(k_i ** 2 + 8.0 * k_ii ** 2)) / (4.0 * k_ii))
        assert theta == pytest.approx(brief)
        assert growth_angle(k_i, -k_ii) == pytest.approx(-theta)
        assert k_i * math.sin(theta) + k_ii * (3.0 * math.cos(theta) - 1.0) == \
            pytest.approx(0.0, abs=1e-12 * (abs(k_i) + abs(k_ii)))
        grid = np.linspace(-math.pi + 1e-3, math.pi - 1e-3, 2001)
        assert equivalent_k(k_i, k_ii) >= max(tangential_stress(k_i, k_ii, t) for t in grid)


def test_displacement_correlation_on_the_exact_field(strips):
    """On quarter-point edges the faces' opening of an exact near-tip field is the element's
    sqrt(r) term, so the correlation gives K_I and K_II back to round-off: its formula's
    check (its error on a solved strip is the mesh's, docs/fracture.md, section 5)."""
    plate = _strip(strips, 0.3)
    tip = int(plate.tips[0])
    nodes = quarter_points(plate.nodes, plate.elements, tip)
    x = nodes - nodes[tip]
    x[plate.seam[:, 0], 1] = -0.0               # the lower face: theta = -pi
    x[tip] = (1.0, 0.0)
    k_i, k_ii = 2.0e6, 0.7e6
    u = k_i * williams_fields(x, "I", STEEL)[0] + k_ii * williams_fields(x, "II", STEEL)[0]
    u[tip] = 0.0
    found = displacement_correlation(nodes, u.ravel(), STEEL, tip, plate.ahead[0], plate.seam,
                                     plate.normal)
    assert found == pytest.approx((k_i, k_ii), rel=1e-9)
    with pytest.raises(InputError, match="seam"):
        displacement_correlation(plate.nodes, u.ravel(), STEEL, tip, plate.ahead[0],
                                 plate.seam, plate.normal)


def test_exact_field_on_the_cracked_tooth():
    """The exact field's test on the cracked tooth of the sector's faults (mesh/cracked.py),
    in the same domains: its tip, the crack's direction from its path and its seam's sides
    are what stress_intensity and the faces' angles read."""
    gear = paper_gear()
    tooth = tooth_mesh(gear)
    path = crack_path(gear, tooth, "right", 0.1e-3)
    cracked = cracked_tooth(gear, tooth, path, tip_size=0.005e-3)
    ahead = (path[1] - path[0]) / np.hypot(*(path[1] - path[0]))
    rot = np.array([[ahead[0], ahead[1]], [-ahead[1], ahead[0]]])
    x = (cracked.nodes - cracked.nodes[cracked.tip]) @ rot.T
    lower = 0 if cracked.normal[0] @ rot[1] > 0.0 else 1
    x[cracked.seam[:, lower], 1] = -0.0          # theta = -pi; round-off off the line set
    x[cracked.seam[:, 1 - lower], 1] = 0.0       # to +pi on the other face
    x[cracked.tip] = (1.0, 0.0)
    k_i, k_ii = 2.0e6, -1.0e6
    local = k_i * williams_fields(x, "I", gear.material)[0] \
        + k_ii * williams_fields(x, "II", gear.material)[0]
    local[cracked.tip] = 0.0
    k = stress_intensity(cracked.nodes, cracked.elements, (local @ rot).ravel(), gear.material,
                         cracked.tip, ahead, rings=(3, 4))
    assert np.allclose(k.k_i, k_i, rtol=3e-3)
    assert np.allclose(k.k_ii, k_ii, rtol=3e-3)
