"""A chipped tip (docs/faults.md, "A chipped tip"): the ``[[fault]]`` table's refusals, the
chipped cell's mesh, the static revolution (the chipped flank's contact ends at the cut, a
very small chip tends to the uncut cell) and the dynamic run (no force beyond the cut, the
compiled rows the NumPy ones)."""

from __future__ import annotations

import math
import signal
from pathlib import Path

import numpy as np
import pytest

from spurdyn.case.fault_tables import faults_from_dict, parse_fault_option
from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.fem.element import gauss_2d
from spurdyn.geometry.fault import Fault, active_rolls, chip_roll
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.mesh.chipped import chip_area, chip_cut, chipped_tooth
from spurdyn.sector.body import body_cell
from spurdyn.sector.faulty import chipped_mesh, faulty_revolution
from spurdyn.sector.statics import contact_law, driving_pair, sector_bodies, solve_position

# the coarse mesh and positions of tests/test_faults.py
NX, NY, POSITIONS = 2, 4, 9
PAIR = paper_pair()
CHIP_A = Fault("a", 5, "chip", depth=1.0e-3, width=0.5e-3)
CHIP_B = Fault("b", 15, "chip", depth=1.0e-3, width=0.5e-3)


def _area(nodes, elements) -> float:
    return float((jacobian_determinants(nodes, elements) * gauss_2d(3)[1]).sum())


def _exact_corner(gear, height: float, width: float, n: int = 4001) -> float:
    """The corner a chip takes from the exact tooth: the involute from the cut's radius to
    the tip, the tip circle's arc of ``width`` back toward the centre line, the cut (m^2)."""
    flank = np.array([gear.right_side_point(r) for r in np.linspace(gear.tip_radius - height, gear.tip_radius, n)])
    phi = math.atan2(flank[-1, 1], flank[-1, 0]) + np.linspace(0.0, width / gear.tip_radius, n)[1:]
    x, y = np.vstack([flank, gear.tip_radius * np.stack([np.cos(phi), np.sin(phi)], axis=1)]).T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def test_chip_tables_refused_by_the_key_written():
    g = PAIR.gear_a
    low = g.base_radius * math.hypot(1.0, active_rolls(PAIR, "a")[0])
    good = {"gear": "a", "tooth": 5, "kind": "chip", "height": 1e-3, "width": 5e-4}
    assert faults_from_dict({"fault": [good]}, PAIR) == (CHIP_A,)
    cases = [
        ({**good, "height": 1.01 * (g.tip_radius - low)}, "fault[0].height"),    # below the active flank
        ({**good, "height": 0.0}, "fault[0].height"),
        ({**good, "height": -1e-3}, "fault[0].height"),
        ({**good, "width": 1.01 * g.tip_thickness}, "fault[0].width"),          # wider than the top land
        ({**good, "width": 0.0}, "fault[0].width"),
        ({**good, "depth": 1e-5}, "fault[0].depth"),                             # a key a chip does not read
        ({**good, "spam": 1}, "fault[0].spam"),
        ({k: v for k, v in good.items() if k != "width"}, "fault[0].width"),
    ]
    for table, key in cases:
        with pytest.raises(InputError) as err:
            faults_from_dict({"fault": [table]}, PAIR)
        assert err.value.field == key, (table, err.value)
    with pytest.raises(InputError) as err:
        faults_from_dict({"fault": [{**good, "height": 0.0}]}, PAIR)
    assert "inf" not in err.value.reason
    # a spall on the chipped flank must end below the cut (beyond it the flank is gone)
    cut = math.degrees(chip_roll(g, CHIP_A))
    lo = math.degrees(active_rolls(PAIR, "a")[0])
    spall = {"gear": "a", "tooth": 5, "kind": "spall", "depth": 2e-5}
    for tables in ([good, {**spall, "roll_deg": [lo + 1.0, cut + 0.5]}],
                   [{**spall, "roll_deg": [cut + 0.2, cut + 0.5]}, good]):
        with pytest.raises(InputError) as err:
            faults_from_dict({"fault": tables}, PAIR)
        assert err.value.field == f"fault[{tables.index(good) ^ 1}].roll_deg", err.value
    assert len(faults_from_dict({"fault": [good, {**spall, "roll_deg": [lo + 1.0, cut - 0.5]}]}, PAIR)) == 2
    # just inside both limits is taken
    faults_from_dict({"fault": [{**good, "height": 0.99 * (g.tip_radius - low), "width": 0.99 * g.tip_thickness}]},
                     PAIR)
    crack = {"gear": "a", "tooth": 5, "kind": "crack", "depth": 1e-4}
    with pytest.raises(InputError) as err:
        faults_from_dict({"fault": [crack, good]}, PAIR)
    assert err.value.field == "fault[1].tooth"
    assert parse_fault_option("gear=a,tooth=5,kind=chip,height=1e-3,width=5e-4", PAIR) == CHIP_A
    with pytest.raises(InputError) as err:
        parse_fault_option("gear=a,tooth=5,kind=chip,height=1e-3", PAIR)
    assert err.value.field == "--fault" and "width" in err.value.reason
    # a sweep's size is the chip's height, each checked as the table's
    from types import SimpleNamespace

    from spurdyn.sweep.faults import _check_size, size_of

    assert size_of(CHIP_A) == CHIP_A.depth
    _check_size(SimpleNamespace(pair=PAIR), CHIP_A, 2e-3)
    with pytest.raises(InputError) as err:
        _check_size(SimpleNamespace(pair=PAIR), CHIP_A, 1.01 * (g.tip_radius - low))
    assert err.value.field == "--fault-size" and "height" in err.value.reason


def test_the_chipped_mesh_loses_the_corners_area_and_the_flank_above_the_cut():
    g = PAIR.gear_a
    cell = body_cell(g, NX, NY)
    cut = chip_cut(cell, g.tip_radius, CHIP_A.depth, CHIP_A.width)
    assert np.hypot(*cut[0]) == pytest.approx(g.tip_radius - CHIP_A.depth, rel=1e-12)
    chip = chipped_tooth(cell, cut)
    assert np.all(jacobian_determinants(chip.nodes, chip.elements) > 0.0)
    assert np.unique(chip.elements).size == chip.nodes.shape[0]
    # the mesh's outline is the structured one's below the cut and the cut: the area lost is
    # the corner's, measured on the outline's parabolas (a shoelace of 4000 points an edge)
    lost = _area(cell.nodes, cell.elements) - _area(chip.nodes, chip.elements)
    corner = chip_area(cell, cut)
    assert abs(lost / corner - 1.0) < 1e-7
    # ... and that corner is the exact tooth's (the involute above the cut, the tip circle's
    # arc of the width) within the coarse outline's interpolation error (2.8e-4 at 2 x 4,
    # 4e-6 at 4 x 14)
    assert abs(corner / _exact_corner(g, CHIP_A.depth, CHIP_A.width) - 1.0) < 1e-3
    right = cell.side("right")
    above = np.hypot(*cell.nodes[right].T) > g.tip_radius - CHIP_A.depth
    assert above.any() and np.all(chip.structured[right[above]] < 0)
    assert np.all(chip.structured[right[~above]] >= 0)
    # the cut's node stands in for the flank above the cut
    corner_node = chip.stand_in[right[above]]
    assert np.all(corner_node == corner_node[0])
    assert np.allclose(chip.nodes[corner_node[0]], cut[0], atol=1e-12 * g.tip_radius)
    # the split edge's nodes are held on the quadratic through their parents
    assert chip.ties.shape[0] > 0
    np.testing.assert_allclose(chip.tie_weights.sum(axis=1), 1.0, atol=1e-12)
    held = np.einsum("tk,tkd->td", chip.tie_weights, chip.nodes[chip.ties[:, 1:]])
    np.testing.assert_allclose(held, chip.nodes[chip.ties[:, 0]], atol=1e-9 * g.tip_radius)


def test_a_strip_reaching_past_the_cut_loads_the_cut_node_whole():
    """A strip just below the cut whose flank element the cut splits: its share beyond the
    cut goes to the cut's node, and the tooth's nodal forces add up to the unit normal
    force still (each copy of the standing-in node added, none overwritten)."""
    from spurdyn.sector.body import sector_body

    g = PAIR.gear_a
    mesh = chipped_mesh(g, CHIP_A, NX, NY, 1.0)
    body = sector_body(g, 3, NX, NY, first=-1, cracked={0: mesh})
    r = g.tip_radius - 1.05 * CHIP_A.depth
    f = body.load(0, r, 0.2e-3).reshape(-1, 2)
    normal = g.flank_normal(np.asarray(r))
    assert np.hypot(*f.sum(axis=0)) == pytest.approx(float(np.hypot(*normal)), rel=1e-12)
    corner = int(np.argmin(np.hypot(*(body.mesh.nodes - chip_cut(body_cell(g, NX, NY), g.tip_radius, CHIP_A.depth,
                                                                   CHIP_A.width)[0]).T)))
    assert np.hypot(*f[corner]) > 0.0


@pytest.fixture(scope="module")
def revolution():
    """The paper pair's revolution with a chip on the pinion's tooth 5 and the wheel's 15."""
    return faulty_revolution(PAIR, PAPER_TORQUE, (CHIP_A, CHIP_B), NX, NY, positions=POSITIONS)


@pytest.mark.slow
def test_the_chipped_flanks_contact_ends_at_the_cut(revolution):
    rev = revolution
    dp = driving_pair(PAIR)
    pitch, per = 2.0 * math.pi / dp.gear_a.teeth, POSITIONS - 1
    rolls = dp.start_roll_a + pitch * np.arange(POSITIONS) / per
    rb_a, rb_b, length = dp.gear_a.base_radius, dp.gear_b.base_radius, dp.line_of_centres_length
    spacing = pitch / per
    # the chipped gear's own roll of the cut, as the driver's roll of the contact point
    cut_a = chip_roll(dp.gear_a, CHIP_A)
    cut_b = (length - chip_roll(dp.gear_b, CHIP_B) * rb_b) / rb_a
    for fault, cut, beyond in ((CHIP_A, cut_a, np.greater), (CHIP_B, cut_b, np.less)):
        loaded, lost = [], []
        for c in range(dp.gear_a.teeth):
            j = c - fault.tooth                 # the chipped tooth is pair c - tooth of cycle c
            if not 0 <= j < rev.force.shape[1]:
                continue
            for i in range(per):
                rho = rolls[i] + j * pitch      # the pair's contact point as the driver's roll
                if dp.start_roll_a <= rho <= dp.end_roll_a:
                    (lost if beyond(rho, cut) else loaded).append((rho, rev.force[c * per + i, j]))
        loaded, lost = np.array(loaded), np.array(lost)
        # nothing beyond the cut; load on every position before it
        assert lost.size and np.all(lost[:, 1] == 0.0)
        assert np.all(loaded[:, 1] > 0.0)
        # the change from loaded to lost is at the cut, within a position's spacing
        edge = loaded[:, 0].max() if beyond is np.greater else loaded[:, 0].min()
        assert abs(edge - cut) <= spacing + 1e-12
    # the stiffness dips (below the uncut pair's least) and only in the cycles holding a chip
    summary = rev.summary()
    assert rev.faulty == (4, 5, 6, 7, 14, 15, 16, 17)
    assert summary["mesh_stiffness_min_N_per_m"] < summary["mesh_stiffness_healthy_min_N_per_m"]
    clean = ~np.isin(rev.cycle, rev.faulty)
    assert np.array_equal(rev.stiffness[clean], rev.healthy_stiffness[clean])


def test_a_very_small_chip_tends_to_the_uncut_cell():
    """At rolls where the chipped pair lies below every cut, the chip's effect on the
    approach falls with its size toward the cell meshed again uncut (the chip of no size)."""
    dp = driving_pair(PAIR)
    g, pitch = dp.gear_a, 2.0 * math.pi / dp.gear_a.teeth
    law = contact_law(dp, PAPER_TORQUE, sector_bodies(dp, 4, NX, NY))
    # pair 1 (body tooth 1) from entering to below the largest chip's cut
    rolls = dp.start_roll_a + pitch * np.linspace(0.0, 0.45, 4)
    assert rolls[-1] + pitch < chip_roll(g, Fault("a", 0, "chip", depth=0.4e-3))

    def approach(height: float) -> np.ndarray:
        mesh = chipped_mesh(g, Fault("a", 0, "chip", depth=height, width=height), NX, NY, 1.0)
        bodies = sector_bodies(dp, 4, NX, NY, cracked=({1: mesh}, {}))
        return np.array([solve_position(law, float(r), bodies=bodies)[2] for r in rolls])

    uncut = approach(0.0)
    effect = [float(np.max(np.abs(approach(h) / uncut - 1.0))) for h in (0.4e-3, 0.1e-3, 0.025e-3)]
    assert effect[0] > effect[1] > effect[2]
    assert effect[2] < 2e-3


@pytest.mark.slow
def test_a_dynamic_run_with_chips_loads_no_flank_beyond_the_cut_compiled_as_numpy():
    """Two mesh cycles of an 18-tooth pair (the paper's teeth; fewer of them, a cheaper
    eigen-solve) with chips on a tooth of each gear that meets the path in them: no force
    wherever a chipped flank lies beyond its cut, load before it, and the compiled loop's
    forces the NumPy loop's (over the first cycle and a half, both chips' changes in it)."""
    from dataclasses import replace

    from spurdyn.geometry.pair import GearPair
    from spurdyn.sector.model import SectorModel
    from spurdyn.settings import RPM
    from spurdyn.solvers.check import run_settings
    from spurdyn.solvers.sector.stepper import SectorRecord, make_stepper

    small = GearPair(gear_a=replace(PAIR.gear_a, teeth=18), gear_b=replace(PAIR.gear_b, teeth=18), driver="a")
    chips = (Fault("a", 0, "chip", depth=1e-3, width=5e-4), Fault("b", 1, "chip", depth=1e-3, width=5e-4))
    s = run_settings(small, 8000 * RPM, 22.25, model="sector", cycles=2, faults=chips, nx=NX, ny=NY)
    model = SectorModel.build(small, s)
    n, n_numpy = 2 * model.per_cycle, 3 * model.per_cycle // 2
    records = []
    for backend, steps in (("numba", n), ("numpy", n_numpy)):
        record = SectorRecord(model, model.per_cycle * model.cycles)
        assert make_stepper(model, record, "implicit", backend).steps(steps) == ""
        records.append(record)
    fast = records[0].force[:n + 1]
    slow = records[1].force[:n_numpy + 1]
    assert np.nanmax(np.abs(fast[:n_numpy + 1] - slow)) <= 1e-9 * np.nanmax(fast)
    theta = records[0].theta[:n + 1, :1]
    rolls = model.roll_0 + theta + model.c_teeth[None, :] * model.pitch
    rolls = np.where(model.c_side == 1, model.sigma - rolls, rolls)
    near = (rolls >= model.roll_0 - model.reach) & (rolls <= model.roll_1 + model.reach)
    lost = model.lost(model.c_teeth[None, :], model.c_side[None, :], rolls) & near
    # both chipped flanks come beyond their cuts near the path, within the NumPy steps too,
    # and carry nothing there
    chipped = np.flatnonzero(lost.any(axis=0))
    assert chipped.size == 2 and np.all(lost[:n_numpy + 1, chipped].any(axis=0))
    # the lost stretch is where the chipped gear's own roll of the contact lies beyond its
    # cut's, r_a - height on its flank (the driven gear's own roll from the driver's)
    from spurdyn.sector.statics import driving_pair

    dp = driving_pair(small)
    cut_a, cut_b = chip_roll(small.gear_a, chips[0]), chip_roll(small.gear_b, chips[1])
    own_b = (dp.line_of_centres_length - rolls * small.gear_a.base_radius) / small.gear_b.base_radius
    beyond = [(rolls > cut_a) & near, (own_b > cut_b) & near]
    owner = [next(g for g in (0, 1) if np.array_equal(lost[:, col], beyond[g][:, col])) for col in chipped]
    assert sorted(owner) == [0, 1]
    # at the cut itself the contact is kept (as the statics keep it), just beyond it lost
    col = chipped[owner.index(0)]
    at = model.lost(model.c_teeth[col], model.c_side[col], np.array([cut_a, np.nextafter(cut_a, 1.0)]))
    assert at.tolist() == [False, True]
    assert np.all(fast[lost] == 0.0)               # exact zeros, no NaN
    # each carries load on the path before its cut (the cut's node standing in near it)
    for col in chipped:
        on_path = (rolls[:, col] >= model.roll_0) & (rolls[:, col] <= model.roll_1) & ~lost[:, col]
        assert np.nanmax(fast[on_path, col]) > 0.0


def test_a_deep_chips_ritz_basis_stays_above_the_held_modes():
    """A 4 mm chip (three of the old flank radii above its cut): the static shapes' loads lie
    below the cut, and even a basis made dependent on purpose gives Ritz values no lower than
    the held body's lowest (Rayleigh-Ritz bounds from above) on M-orthonormal modes."""
    from spurdyn.sector import reduced
    from spurdyn.sector.model import KEEP_FREQUENCY
    from spurdyn.sector.system import gear_block

    gear = PAIR.gear_a
    height = 4.0e-3
    block = gear_block(gear, 1.0, -1, 3, NX, NY, 1.0,
                       cracked={0: chipped_mesh(gear, Fault("a", 0, "chip", depth=height, width=0.5e-3), NX, NY, 1.0)})
    cut = reduced._cut_radius(block, 0)
    assert cut == pytest.approx(gear.tip_radius - height, rel=1e-9)
    assert reduced._cut_radius(block, 1) is None
    assert np.all(reduced._radii(block, cut) < cut)
    target = (2.0 * math.pi * KEEP_FREQUENCY) ** 2
    lowest = reduced._held_modes(block, target)[0].min()
    loads = reduced._flank_loads(block)
    for basis_loads in (loads, np.column_stack([loads, loads[:, :2] + loads[:, 2:4]])):
        out = reduced._reduce(block, target, basis_loads)
        phi = out["phi"]
        assert out["omega2"].min() >= lowest * (1.0 - 1e-9)
        np.testing.assert_allclose(phi.T @ (block.mass[:, None] * phi), np.eye(phi.shape[1]), atol=1e-7)


@pytest.mark.parametrize("node, offset", [(-3, 0.0), (-3, 2e-6), (-3, -2e-6), (-3, 1e-10), (-2, -1e-11)])
def test_a_cut_on_or_by_a_node_ties_each_node_once(node, offset):
    """A cut ending on a structured flank corner node (the last below the tip, ``-3``) splits
    no edge; one a few um or less beside it, or 1e-11 m above a mid-side node (``-2``), is
    meshed (not refused): the tie map's rows sum to 1 (each tied node held once) and a rigid
    translation stores no strain energy."""
    from spurdyn.sector.body import sector_body

    gear = PAIR.gear_a
    cell = body_cell(gear, NX, NY)
    right = cell.side("right")
    height = gear.tip_radius - float(np.hypot(*cell.nodes[right[node]])) + offset
    mesh = chipped_mesh(gear, Fault("a", 0, "chip", depth=height, width=0.5e-3), NX, NY, 1.0)
    body = sector_body(gear, 3, NX, NY, first=-1, cracked={0: mesh})
    ties = body.ties.tocsr()
    sums = np.asarray(ties.sum(axis=1)).ravel()
    np.testing.assert_allclose(sums[sums != 0.0], 1.0, rtol=0.0, atol=1e-12)
    for axis in (0, 1):
        u = np.zeros(2 * body.mesh.nodes.shape[0])
        u[axis::2] = 1.0
        u = ties @ u
        k = body.stiffness
        assert abs(float(u @ (k @ u))) <= 1e-14 * float(k.diagonal().sum())


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads Linux's /proc")
def test_meshing_with_gmsh_leaves_broken_pipes_an_error_not_a_death():
    """gmsh's initialisation sets SIGPIPE to its default behind Python's back; after a mesh
    the process must still ignore it (a write to a closed pipe an error, not the end of the
    process: a run's writer process that died would otherwise take the run with it)."""
    def ignored() -> bool:
        line = next(l for l in Path("/proc/self/status").read_text().splitlines()
                    if l.startswith("SigIgn:"))
        return bool(int(line.split()[1], 16) >> (signal.SIGPIPE - 1) & 1)

    assert ignored()
    g = paper_pair().gear_a
    chipped_mesh(g, CHIP_A, NX, NY, 1.0)
    assert ignored()
