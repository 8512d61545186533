"""The sector model's body and its quasi-static mesh cycle (issue 15; docs/sector.md): the
mesh against the gear's own outline, rigid motions, the hub, a web's twist against the
annulus formula, the cut ends, the load balance and complementarity, the load share
against the model's own single-pair solutions, and ``spurdyn stiffness``."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.fem.element import gauss_2d
from spurdyn.geometry.blank import Blank
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, nasa_like_relief, paper_pair
from spurdyn.mesh.sector import sector_mesh
from spurdyn.sector.body import sector_body
from spurdyn.sector.statics import _active_set, mesh_cycle, pair_forces_at

PAIR = paper_pair()
GEAR = PAIR.gear_a


def _mesh_area(nodes, elements) -> float:
    _, w = gauss_2d(3)
    return float((jacobian_determinants(nodes, elements) * w[None, :]).sum())


def _cell_outline_area(gear, r_in: float) -> float:
    """Area of one tooth's cell (half a pitch either side of its centre line, down to
    ``r_in``) from the gear's outline alone: the shoelace formula over a dense polygon of
    the root land, the fillet and flank (``right_side_point``), the tip arc and the hub arc."""
    half = math.pi / gear.teeth
    rr = np.linspace(gear.root_radius * (1 + 1e-12), gear.tip_radius, 4001)
    right = np.array([gear.right_side_point(float(r)) for r in rr])        # root -> tip
    chi_root = math.atan2(*right[0])
    land = gear.root_radius * np.stack([np.sin(np.linspace(half, chi_root, 200)),
                                        np.cos(np.linspace(half, chi_root, 200))], axis=-1)
    chi_tip = math.atan2(*right[-1])
    tip = gear.tip_radius * np.stack([np.sin(np.linspace(chi_tip, -chi_tip, 200)),
                                      np.cos(np.linspace(chi_tip, -chi_tip, 200))], axis=-1)
    left = (right * [-1.0, 1.0])[::-1]
    land_l = (land * [-1.0, 1.0])[::-1]
    hub = r_in * np.stack([np.sin(np.linspace(-half, half, 400)),
                           np.cos(np.linspace(-half, half, 400))], axis=-1)
    # counter-clockwise: hub left to right, up the right edge, land, right outline up, tip
    # right to left, left outline down, left land, down the left edge
    poly = np.vstack([hub, land, right, tip, left, land_l])
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def test_the_whole_gear_mesh_covers_the_gear_outline():
    """All ``z`` teeth on the ring: the elements' area equals ``z`` cells of the outline's
    own polygon (to the quadratic edges' approximation of the curves)."""
    m = sector_mesh(GEAR, GEAR.teeth)
    area = _mesh_area(m.nodes, m.elements)
    assert area == pytest.approx(GEAR.teeth * _cell_outline_area(GEAR, m.inner_radius), rel=2e-6)
    r = np.hypot(*m.nodes.T)
    assert np.allclose(r[m.hub_nodes], m.inner_radius, rtol=1e-12)
    assert r.min() == pytest.approx(m.inner_radius, rel=1e-12)
    # every node is used and no two nodes coincide
    assert np.array_equal(np.unique(m.elements), np.arange(m.n_nodes))
    from scipy.spatial import cKDTree
    assert not cKDTree(m.nodes).query_pairs(1e-9 * GEAR.tip_radius)


def test_a_sector_is_its_teeth_and_the_whole_rim():
    """A sector of K teeth on the full rim: the teeth are the single-tooth mesh turned by
    ``k 2 pi / z`` node for node, and the area is the whole gear's less the missing teeth
    above their bottom curves."""
    whole = sector_mesh(GEAR, GEAR.teeth)
    m = sector_mesh(GEAR, 4, first=-1)
    assert list(m.teeth) == [-1, 0, 1, 2]
    t = m.tooth
    for i, k in enumerate(m.teeth):
        a = k * 2 * math.pi / GEAR.teeth
        c, s = math.cos(a), math.sin(a)
        turned = np.column_stack([t.nodes[:, 0] * c + t.nodes[:, 1] * s, -t.nodes[:, 0] * s + t.nodes[:, 1] * c])
        assert np.allclose(m.nodes[m.tooth_nodes[i]], turned, atol=1e-15)
    tooth_area = _mesh_area(t.nodes, t.elements)
    assert _mesh_area(m.nodes, m.elements) == pytest.approx(
        _mesh_area(whole.nodes, whole.elements) - (GEAR.teeth - 4) * tooth_area, rel=1e-12)


def test_rigid_motions_cost_no_strain_energy():
    body = sector_body(GEAR, 4, 4, 14)
    xy = body.mesh.nodes
    k = body.stiffness
    for u in (np.tile([1.0, 0.0], xy.shape[0]), np.tile([0.0, 1.0], xy.shape[0]),
              np.column_stack([xy[:, 1], -xy[:, 0]]).ravel() / GEAR.tip_radius):
        assert np.abs(k @ u).max() <= 1e-9 * abs(k).max() * np.abs(u).max()


def test_a_web_twists_as_the_annulus_formula_says():
    """A webbed blank: a torque ``T`` on the web's outer circle turns the web's circle of
    radius ``r`` by ``T / (4 pi G b_w) (1/r_h^2 - 1/r^2)``, the exact twist of a plane annulus
    (measured on a circle of nodes inside the web, away from the nodal forces)."""
    rh, rw, ww = 0.015, 0.033, 0.6e-3
    gear = dataclasses.replace(GEAR, blank=Blank(hub_radius=rh, rim_radius=rw, web_width=ww),
                               disk_inertia=None)
    # what is left is the web rows' quadratic fields against the annulus' 1/r (rows up to
    # a quarter of their radius tall): 1.3e-4 on this mesh
    assert _web_twist_error(gear, rh, rw, ww, 14) < 3e-4


def _web_twist_error(gear, rh, rw, ww, ny):
    body = sector_body(gear, 4, 4, ny)
    xy = body.mesh.nodes
    r = np.hypot(*xy.T)
    ring = np.flatnonzero(np.abs(r - rw) < 1e-9)
    assert ring.size > 100 and body.mesh.inner_radius == rh
    t = np.column_stack([xy[ring, 1], -xy[ring, 0]]) / r[ring, None]    # clockwise tangent
    f = np.zeros(body.mesh.n_dof)
    f[2 * ring], f[2 * ring + 1] = t[:, 0], t[:, 1]
    u = body.solve(f)
    radii = np.unique(np.round(r[(r > rh) & (r < rw)], 12))
    rm = radii[np.argmin(np.abs(radii - math.sqrt(rh * rw)))]
    mid = np.flatnonzero(np.abs(r - rm) < 1e-9)
    tm = np.column_stack([xy[mid, 1], -xy[mid, 0]]) / r[mid, None]
    turn = (u[2 * mid] * tm[:, 0] + u[2 * mid + 1] * tm[:, 1]) / r[mid]
    g = gear.material.young / (2 * (1 + gear.material.poisson))
    expected = r[ring].sum() / (4 * math.pi * g * ww) * (1 / rh**2 - 1 / rm**2)
    assert np.ptp(turn) < 2e-5 * expected          # nearly the same turn all round
    return float(np.abs(turn / expected - 1).max())


@pytest.fixture(scope="module")
def cycle():
    return mesh_cycle(PAIR, PAPER_TORQUE, 4, 14, positions=21)


@pytest.mark.slow
def test_the_cut_ends_change_the_mesh_stiffness_by_less_than_one_percent(cycle):
    wider = mesh_cycle(PAIR, PAPER_TORQUE, 4, 14, teeth=cycle.teeth + 2, positions=21)
    assert wider.stiffness_mean == pytest.approx(cycle.stiffness_mean, rel=1e-2)
    assert np.abs(wider.stiffness / cycle.stiffness - 1).max() < 1e-2


@pytest.mark.slow
def test_the_pairs_carry_the_load_and_only_push(cycle):
    assert np.abs(cycle.force.sum(axis=1) / cycle.load - 1).max() < 1e-12
    assert (cycle.force >= 0).all()
    two = (cycle.force > 0).sum(axis=1)
    assert set(two) == {1, 2}               # the paper's pair: contact ratio 1.64
    # in the single-contact zone the mesh stiffness is the lone pair's
    one = two == 1
    lone = np.nanmax(np.where(cycle.force[one] > 0, cycle.single_pair[one], np.nan), axis=1)
    assert cycle.stiffness[one] == pytest.approx(lone, rel=1e-12)
    # the static transmission error is the load over the mesh stiffness (no relief: no gap)
    assert cycle.transmission_error == pytest.approx(cycle.load / cycle.stiffness, rel=1e-6)


@pytest.mark.slow
def test_the_load_share_follows_the_single_pair_solutions():
    """Two pairs in contact: with each pair loaded alone, ``c_ij`` is the approach of pair
    ``i`` per newton at pair ``j`` (both sectors and the strips), and equal approaches give
    ``F_0 / W = (c_11 - c_10) / (c_00 + c_11 - c_01 - c_10)``."""
    from spurdyn.contact.hertz import effective_modulus, half_width, involute_curvature_radius, strip_compliance
    from spurdyn.model.loading import static_force

    ga, gb = PAIR.gear_a, PAIR.gear_b
    body_a = sector_body(ga, 4, 4, 14, first=-1)
    body_b = sector_body(gb, 4, 4, 14, first=-2)
    pitch = 2 * math.pi / ga.teeth
    rho = PAIR.start_roll_a + 0.3 * (PAIR.end_roll_a - pitch - PAIR.start_roll_a)
    rolls = np.array([rho, rho + pitch])
    ra = ga.radius_at_roll_angle(rolls)
    rb = gb.radius_at_roll_angle(np.asarray(PAIR.roll_b_from_roll_a(rolls)))
    estar = effective_modulus(ga.material.young, ga.material.poisson, gb.material.young, gb.material.poisson)
    w = static_force(PAIR, PAPER_TORQUE)
    f = np.array([w / 2, w / 2])
    for _ in range(30):
        b = half_width(f, [involute_curvature_radius(float(r), ga.base_radius) for r in ra],
                       [involute_curvature_radius(float(r), gb.base_radius) for r in rb], estar, ga.face_width)
        c = np.zeros((2, 2))
        for j in range(2):
            ua = body_a.solve(body_a.load(j, float(ra[j]), float(b[j])))
            ub = body_b.solve(body_b.load(-j, float(rb[j]), float(b[j])))
            for i in range(2):
                c[i, j] = (body_a.load(i, float(ra[i]), float(b[i])) @ ua
                           + body_b.load(-i, float(rb[i]), float(b[i])) @ ub)
        c += strip_compliance(estar, ga.face_width) * np.eye(2)
        share = (c[1, 1] - c[1, 0]) / (c[0, 0] + c[1, 1] - c[0, 1] - c[1, 0])
        f = w * np.array([share, 1 - share])
    assert pair_forces_at(PAIR, PAPER_TORQUE, rho, (body_a, body_b)) == pytest.approx(f, rel=1e-9)
    assert 0.3 < share < 0.7 and c[0, 1] > 0      # the rim couples the pairs


def test_the_active_set_opens_a_pair_whose_gap_the_load_does_not_close():
    c = np.array([[2.0, 0.5], [0.5, 2.0]]) * 1e-8
    f, e, active = _active_set(c, np.array([0.0, 1e-5]), 100.0)
    assert list(active) == [True, False] and f[1] == 0.0 and f[0] == pytest.approx(100.0)
    assert c[1] @ f + 1e-5 >= e
    f, e, active = _active_set(c, np.array([0.0, 1e-7]), 100.0)
    assert active.all() and f.sum() == pytest.approx(100.0)
    assert (c @ f + [0.0, 1e-7]) == pytest.approx([e, e], rel=1e-12)


@pytest.mark.slow
def test_tip_relief_cuts_the_transmission_error_near_its_design_load_only():
    """The NASA-like relief (20 um from the HPSTC): at 60 N m the static transmission
    error's peak-to-peak falls below the unmodified pair's; at a light 5 N m the relief
    itself is the transmission error and it is far larger."""
    relieved = GearPair(nasa_like_relief(PAIR.gear_a, PAIR.gear_b), nasa_like_relief(PAIR.gear_b, PAIR.gear_a))
    pp = {}
    for tq in (5.0, 60.0):
        pp[tq] = (mesh_cycle(PAIR, tq, 4, 14, positions=21).transmission_error_pp,
                  mesh_cycle(relieved, tq, 4, 14, positions=21).transmission_error_pp)
    assert pp[60.0][1] < pp[60.0][0]
    assert pp[5.0][1] > 5 * pp[5.0][0]


@pytest.mark.slow
def test_spurdyn_stiffness_prints_the_cycle_and_refuses_bad_input(tmp_path, capsys):
    from spurdyn.cli.main import main

    assert main(["stiffness", "paper", "--positions", "9", "--json",
                 "--png", str(tmp_path / "k.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["mesh_stiffness_mean_N_per_m"] > 5e7 and (tmp_path / "k.png").stat().st_size > 0
    row = out["torques"][0]
    assert len(row["mesh_stiffness_N_per_m"]) == 9 and row["torque_Nm"] == PAPER_TORQUE
    assert row["iso6336_mesh_N_per_m"] > 0
    for argv in (["stiffness", "paper", "--torque", "-3"],
                 ["stiffness", "paper", "--torque", "x"],
                 ["stiffness", "paper", "--teeth", "1"],
                 ["stiffness", "paper", "--positions", "2"]):
        assert main(argv + ["--png", str(tmp_path / "bad.png")]) == 2
        err = capsys.readouterr().err
        assert err.startswith("spurdyn: error: --") and err.count("\n") == 1
    assert not (tmp_path / "bad.png").exists()


def test_the_sector_refuses_what_it_cannot_mesh():
    with pytest.raises(InputError, match="model.teeth"):
        sector_mesh(GEAR, 0)
    with pytest.raises(InputError, match="model.rim_inner_radius"):
        sector_mesh(GEAR, 3, inner_radius=GEAR.root_radius)
