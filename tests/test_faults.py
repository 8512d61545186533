"""Faults on the sector model's teeth (docs/faults.md): the ``[[fault]]`` tables, a
missing tooth's mesh, and the quasi-static mesh over the faulty gear's revolution."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from cli_helpers import run

from spurdyn.case.fault_tables import faults_from_dict, parse_fault_option
from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault, active_rolls
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.mesh.sector import sector_mesh
from spurdyn.sector.faulty import faulty_revolution

# a coarse mesh and few positions: the tests check the bookkeeping and the limits, the
# mesh study is the page's
NX, NY, POSITIONS = 2, 4, 9


@pytest.fixture(scope="module")
def pair():
    return paper_pair()


def _spall(pair, depth: float, fraction: float) -> Fault:
    lo, hi = active_rolls(pair, "a")
    return Fault("a", 5, "spall", roll=(lo + 0.25 * (hi - lo), lo + 0.6 * (hi - lo)), depth=depth,
                 width_fraction=fraction)


def _run(pair, *faults: Fault):
    return faulty_revolution(pair, PAPER_TORQUE, faults, NX, NY, positions=POSITIONS)


def test_missing_tooth_mesh_drops_its_elements_and_nodes(pair):
    whole = sector_mesh(pair.gear_a, 4, NX, NY)
    broken = sector_mesh(pair.gear_a, 4, NX, NY, missing=frozenset({1}))
    assert broken.elements.shape[0] == whole.elements.shape[0] - whole.tooth.n_elements
    # no node is left without an element (the stiffness stays non-singular)
    assert np.array_equal(np.unique(broken.elements), np.arange(broken.n_nodes))
    row = list(broken.teeth).index(1)
    gone = broken.tooth_nodes[row] < 0
    # the tooth's root row stays: it is the rim's top under the tooth
    assert gone.sum() == whole.tooth.n_nodes - whole.tooth.root_nodes.size


@pytest.fixture(scope="module")
def healthy(pair):
    return _run(pair)


def test_spall_of_no_depth_is_the_healthy_pair(pair, healthy):
    # the pair split into the intact face and a pit of no depth: two contacts in parallel
    rev = _run(pair, _spall(pair, 0.0, 0.5))
    assert rev.faulty
    np.testing.assert_allclose(rev.stiffness, healthy.stiffness, rtol=1e-12)
    np.testing.assert_allclose(rev.transmission_error, healthy.transmission_error, rtol=1e-11)


def test_no_fault_repeats_the_healthy_cycle(pair, healthy):
    rev = healthy
    assert rev.faulty == ()
    per = POSITIONS - 1
    k = rev.stiffness[:-1].reshape(pair.gear_a.teeth, per)
    assert np.array_equal(k, np.broadcast_to(k[0], k.shape))
    assert np.array_equal(rev.stiffness, rev.healthy_stiffness)


def test_deep_full_width_spall_carries_nothing_on_the_pit(pair):
    fault = _spall(pair, 1e-4, 1.0)           # deeper than any deflection here
    rev = _run(pair, fault)
    per, pitch = POSITIONS - 1, 2 * math.pi / pair.gear_a.teeth
    rolls = pair.start_roll_a + pitch * np.arange(POSITIONS) / (POSITIONS - 1)
    hits = 0
    for c in rev.faulty:
        for i in range(per):
            j = c - fault.tooth                # the faulty tooth is pair c - 5 of cycle c
            on_path = np.sum(rolls[i] + np.arange(rev.force.shape[1]) * pitch <= pair.end_roll_a + 1e-12)
            if 0 <= j < rev.force.shape[1] and fault.covers(rolls[i] + j * pitch):
                # where another pair is on the path it takes the load; where the pitted
                # pair is alone, the load reaches the pit's bottom
                te = rev.transmission_error[c * per + i]
                assert (rev.force[c * per + i, j] == 0.0) if on_path > 1 else (te > fault.depth)
                hits += on_path > 1
    assert hits > 0
    # and half the face spalled carries where the full face would not
    half = _run(pair, _spall(pair, 1e-4, 0.5))
    assert half.stiffness.min() > rev.stiffness.min()
    assert half.stiffness.min() < half.healthy_stiffness.min()


def test_missing_tooth_loses_the_load_over_its_single_contact(pair):
    rev = _run(pair, Fault("a", 5, "missing"))
    z, eps = pair.gear_a.teeth, pair.contact_ratio
    # no pair on the path where the missing tooth would carry alone: 2 - eps of a pitch
    lost = (2.0 - eps) / z
    assert abs(rev.summary()["contact_lost_fraction"] - lost) <= 1.0 / (z * (POSITIONS - 1))
    assert rev.summary()["mesh_stiffness_dip"] == 1.0
    assert np.all(rev.stiffness[np.isnan(rev.transmission_error)] == 0.0)
    # the cycles without the fault in their sectors are the healthy ones, to the bit
    healthy = ~np.isin(rev.cycle, rev.faulty)
    assert np.array_equal(rev.stiffness[healthy], rev.healthy_stiffness[healthy])


def test_tables_refused_by_the_key_written(pair):
    good = {"gear": "a", "tooth": 5, "kind": "missing"}
    assert faults_from_dict({"fault": [good]}, pair) == (Fault("a", 5, "missing"),)
    cases = [
        ({"gear": "c", "tooth": 5, "kind": "missing"}, "fault[0].gear"),
        ({"gear": "a", "tooth": 28, "kind": "missing"}, "fault[0].tooth"),
        ({"gear": "a", "tooth": 5, "kind": "dent"}, "fault[0].kind"),
        ({"gear": "a", "tooth": 5, "kind": "missing", "depth": 1e-5}, "fault[0].depth"),
        ({"gear": "a", "tooth": 5, "kind": "spall", "roll_deg": [0, 5], "depth": 1e-5}, "fault[0].roll_deg"),
        ({"gear": "a", "tooth": 5, "kind": "spall", "roll_deg": [20, 25], "depth": -1.0}, "fault[0].depth"),
        ({"gear": "a", "tooth": 5, "kind": "spall", "roll_deg": [20, 25], "depth": 1e-5,
          "width_fraction": 1.5}, "fault[0].width_fraction"),
    ]
    for table, key in cases:
        with pytest.raises(InputError) as err:
            faults_from_dict({"fault": [table]}, pair)
        assert err.value.field == key
    with pytest.raises(InputError) as err:
        faults_from_dict({"fault": [good, good]}, pair)
    assert err.value.field == "fault[1].tooth"
    with pytest.raises(InputError) as err:
        parse_fault_option("gear=a,tooth=five,kind=missing", pair)
    assert err.value.field == "--fault"
    f = parse_fault_option("gear=a,tooth=5,kind=spall,roll_deg=20:24,depth=2e-5", pair)
    assert f.roll == pytest.approx((math.radians(20), math.radians(24)))


def test_commands_refuse_faults_where_not_read_show_them_and_write_the_table(tmp_path, capsys):
    case = tmp_path / "broken.toml"
    case.write_text('[gear_a]\nteeth = 28\nmodule = 3.175e-3\nface_width = 6.35e-3\n\n'
                    '[run]\ntorque = 22.25\n\n[[fault]]\ngear = "a"\ntooth = 5\nkind = "missing"\n')
    for command in (["run", str(case), "--model", "fe", "--speed-a", "1000", "--out", str(tmp_path / "out")], ["mesh", str(case), "--png", str(tmp_path / "m.png")],
                    ["sweep", str(case), "--model", "lumped", "--rpm", "1000:2000/2", "--out", str(tmp_path / "out")],
                    ["report", str(case), "--out", str(tmp_path / "out")]):
        code, out, err = run(capsys, *command)
        assert code == 2 and err.strip().count("\n") == 0 and "fault" in err
    assert not (tmp_path / "out").exists() and not (tmp_path / "m.png").exists()
    code, out, err = run(capsys, "info", str(case))
    assert code == 0 and "gear A tooth 5: missing" in out
    table = tmp_path / "k.csv"
    code, out, err = run(capsys, "stiffness", str(case), "--mesh", f"{NX}x{NY}", "--positions",
                             str(POSITIONS), "--csv", str(table), "--json")
    assert code == 0, err
    report = json.loads(out)
    rows = table.read_text().splitlines()
    assert rows[0].split(",")[:3] == ["torque_Nm", "angle_deg", "mesh_stiffness_N_per_m"]
    assert len(rows) - 1 == len(report["torques"][0]["angle_deg"])
    assert report["torques"][0]["mesh_stiffness_min_N_per_m"] == 0.0


def _crack_position(pair, depth: float, bond: bool = False):
    """The pitch point's solve with the pinion's tooth 0 cracked from its loaded fillet at the
    base circle, 45 deg to the centre line (its faces joined again with ``bond``)."""
    from dataclasses import replace as dc_replace

    from spurdyn.mesh.cracked import crack_path, cracked_tooth
    from spurdyn.mesh.tooth import tooth_mesh
    from spurdyn.sector.body import body_cell
    from spurdyn.sector.statics import contact_law, driving_pair, sector_bodies, solve_position

    dp = driving_pair(pair)
    g = dp.gear_a
    cell = body_cell(g, NX, NY)
    path = crack_path(g, tooth_mesh(g, NX, NY), "right", depth, math.radians(45.0), g.base_radius,
                      region=cell)
    ct = cracked_tooth(g, cell, path)
    if bond:
        back = np.arange(ct.nodes.shape[0])
        back[ct.seam[:, 1]] = ct.seam[:, 0]
        ct = dc_replace(ct, elements=back[ct.elements], seam=np.zeros((0, 2), dtype=np.intp),
                        normal=np.zeros((0, 2)))
    law = contact_law(dp, PAPER_TORQUE, sector_bodies(dp, 4, NX, NY))
    bodies = sector_bodies(dp, 4, NX, NY, cracked=({0: ct}, {}))
    return solve_position(law, dp.pitch_roll_a, bodies=bodies), law


def test_a_root_crack_softens_the_tooth_and_opens(pair):
    """The cracked cell's own mesh, the crack's faces bonded, is the structured cell within
    its mesh difference; cracked, the tooth is softer the deeper the crack, and the faces,
    on the tension side, open."""
    from spurdyn.sector.statics import solve_position

    (js, f, e_bond, c, active), law = _crack_position(pair, 1.0e-3, bond=True)
    e_struct = solve_position(law, pair.pitch_roll_a)[2]
    assert abs(e_bond / e_struct - 1.0) < 0.05
    approach = []
    for depth in (0.5e-3, 1.0e-3):
        (js, f, e, c, active), _ = _crack_position(pair, depth)
        assert c.shape[0] > len(js) and not active[len(js):].any()     # faces open
        approach.append(e)
    assert e_bond < approach[0] < approach[1]


def test_crack_tables_refused_by_the_key_written(pair):
    good = {"gear": "a", "tooth": 3, "kind": "crack", "depth": 1.0e-3, "start_radius": pair.gear_a.base_radius}
    (fault,) = faults_from_dict({"fault": [good]}, pair)
    assert fault.kind == "crack" and fault.depth == 1.0e-3 and fault.angle is None
    for change, key in (({"depth": 0.05}, "fault[0].depth"), ({"angle_deg": 95.0}, "fault[0].angle_deg"),
                        ({"start_radius": 0.05}, "fault[0].start_radius"), ({"roll_deg": [20, 24]}, "fault[0].roll_deg")):
        with pytest.raises(InputError) as err:
            faults_from_dict({"fault": [{**good, **change}]}, pair)
        assert err.value.field == key


@pytest.mark.slow
def test_a_cracked_tooth_over_the_revolution(pair):
    # the mouth at the base circle splits the first flank edge, which at 2 x 4 reaches the
    # lowest contact (refused, below): a finer mesh along the tooth
    crack = Fault("a", 5, "crack", depth=1.0e-3, start=pair.gear_a.base_radius)
    with pytest.raises(InputError) as err:
        _run(pair, crack)
    assert err.value.field == "fault" and "finer mesh" in err.value.reason
    healthy = faulty_revolution(pair, PAPER_TORQUE, (), NX, 8, positions=POSITIONS)
    rev = faulty_revolution(pair, PAPER_TORQUE, (crack,), NX, 8, positions=POSITIONS)
    assert rev.faulty
    outside = ~np.isin(rev.cycle, rev.faulty)
    assert np.array_equal(rev.stiffness[outside], healthy.stiffness[outside])
    assert 0.0 < rev.summary()["mesh_stiffness_dip"] < 0.5
    assert rev.stiffness.min() < healthy.stiffness.min()


def test_a_revolution_too_long_is_refused_before_any_work(pair):
    """Faults on both gears of 28 and 29 teeth follow them over 812 mesh cycles, 212 of
    them with a fault in the sectors: at 101 positions a cycle refused by its count of
    positions, naming the faults, before a sector is meshed."""
    from dataclasses import replace as dc_replace

    from spurdyn.sector.faulty import MAX_FAULTY_POSITIONS

    unequal = dc_replace(pair, gear_b=dc_replace(pair.gear_b, teeth=29), centre_distance=None)
    faults = (Fault("a", 1, "missing"), Fault("b", 2, "missing"))
    with pytest.raises(InputError) as err:
        faulty_revolution(unequal, PAPER_TORQUE, faults, NX, NY, positions=101)
    assert err.value.field == "fault" and f"{MAX_FAULTY_POSITIONS:,}" in err.value.reason


def test_run_takes_a_fault_option_beside_the_tables(tmp_path, capsys):
    case = tmp_path / "pair.toml"
    case.write_text('[gear_a]\nteeth = 28\nmodule = 3.175e-3\nface_width = 6.35e-3\n\n[run]\ntorque = 22.25\n'
                    'speed_a_rpm = 1000\n')
    for extra, words in ((["--model", "fe", "--fault", "gear=a,tooth=5,kind=missing"], "sector model carries"),
                         (["--fault", "gear=a,tooth=28,kind=missing"], "0 to 27"),
                         (["--fault", "gear=a,tooth=5"], "kind"),
                         (["--fault", "gear=a,tooth=5,kind=missing", "--fault", "gear=a,tooth=5,kind=missing"],
                          "takes no other fault")):
        code, out, err = run(capsys, "run", str(case), "--out", str(tmp_path / "out"), *extra)
        assert code == 2 and err.count("\n") == 1 and "--fault" in err and words in err, err
    assert not (tmp_path / "out").exists()
