"""A root crack growing through a gear's tooth or rim (docs/fracture.md, sections 8 and 9):
the kinked crack's mesh and seam, K at the tip of the loaded cracked sector, the growth
loop and its verdict, Paris's life, and ``spurdyn crack``'s refusals."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from spurdyn.cli.main import main
from spurdyn.errors import InputError
from spurdyn.fracture.direction import driving_k, equivalent_k, growth_angle
from spurdyn.fracture.growth import (JUNCTION_SHARE, JUNCTION_TIPS, GrowthStopped, Region, TipState,
                                     cell_region, grow, junction_band, path_length)
from spurdyn.fracture.life import ParisLaw, paris_cycles
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.mesh.cracked import cracked_tooth
from spurdyn.mesh.polyline import piece_normals, side_of
from spurdyn.sector.crack_growth import initial_path, sector_region
from spurdyn.sector.crack_tip import cracked_sector, load_rolls, tip_loads
from spurdyn.sector.statics import driving_pair, position_displacements

PAIR = paper_pair()


@pytest.fixture(scope="module")
def sector():
    """The paper's pair on coarse sectors, the driver's tooth to be cracked, three loads."""
    return cracked_sector(PAIR, PAPER_TORQUE, "a", 4, 14, positions=2)


def _kinked(sector, turn_deg: float = 25.0):
    """A crack 0.4 mm long along the fillet's normal, then 0.3 mm turned by ``turn_deg``."""
    p = initial_path(sector, 0.4e-3, None)
    d = (p[1] - p[0]) / np.hypot(*(p[1] - p[0]))
    t = math.radians(turn_deg)
    d2 = np.array([math.cos(t) * d[0] - math.sin(t) * d[1], math.sin(t) * d[0] + math.cos(t) * d[1]])
    return np.vstack([p, p[1] + 0.3e-3 * d2])


# --- the kinked crack's mesh --------------------------------------------------------------

def test_side_of_a_kink():
    path = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    pts = np.array([[0.5, 0.2], [0.5, -0.2], [1.0, 0.1], [1.2, -0.3], [1.8, 1.0], [1.5, 0.2]])
    s = side_of(pts, path, 1.0)
    # above the first piece, below it, above the kink, beyond the kink's outer side (below
    # both pieces), above the second piece, below it
    assert np.sign(s).tolist() == [1, -1, 1, -1, 1, -1]
    assert s[0] == pytest.approx(0.2) and s[4] == pytest.approx(0.2 / math.sqrt(2.0))


def test_kinked_crack_seam(sector):
    path = _kinked(sector)
    mesh = cracked_tooth(sector.gear, sector.cell, path, tip_size=0.03e-3)
    nodes, seam = mesh.nodes, mesh.seam
    assert np.allclose(nodes[seam[:, 0]], nodes[seam[:, 1]], rtol=0, atol=1e-15)
    assert np.allclose(np.hypot(*mesh.normal.T), 1.0)
    # the kink is a twin; the tip is one node, not in the seam
    assert np.min(np.hypot(*(nodes[seam[:, 0]] - path[1]).T)) < 1e-12
    assert mesh.tip not in seam and np.hypot(*(nodes[mesh.tip] - path[-1])) < 1e-12
    # each face's elements lie on its side of the crack: face two on the normals' side
    sense = float(np.sign(mesh.normal[0] @ piece_normals(path, 1.0)[0]))
    for face, sign in ((0, -1.0), (1, 1.0)):
        touching = mesh.elements[np.any(np.isin(mesh.elements, seam[:, face]), axis=1)]
        off = np.setdiff1d(touching.ravel(), np.append(seam.ravel(), mesh.tip))
        off = off[(nodes[off] - path[-1]) @ (path[-1] - path[-2]) <= 0.0]   # not ahead of the tip
        assert off.size and np.all(sign * side_of(nodes[off], path, sense) > 0.0)
    # the twin faces share no element
    one = np.any(np.isin(mesh.elements, seam[:, 0]), axis=1)
    two = np.any(np.isin(mesh.elements, seam[:, 1]), axis=1)
    assert not np.any(one & two)


# --- K at the tip of the loaded sector ----------------------------------------------------

def test_zero_load_gives_zero_k():
    idle = cracked_sector(PAIR, 0.0, "a", 4, 14, positions=2)
    load, _, _ = tip_loads(idle, initial_path(idle, 0.3e-3, None), 0.02e-3)
    assert np.all(load.k_i == 0.0) and np.all(load.k_ii == 0.0) and np.all(load.k_eq == 0.0)


@pytest.fixture(scope="module")
def loaded(sector):
    """K at the tip of a first crack of 0.3 mm at every load position."""
    return tip_loads(sector, initial_path(sector, 0.3e-3, None), 0.02e-3)


def test_free_faces_are_the_contact_solution_where_the_crack_opens(sector, loaded):
    load, bodies, u = loaded
    assert np.all(load.closed_near_tip == 0) and np.all(load.closed == 0)
    rho = float(load.roll[load.worst])
    free = position_displacements(sector.law, rho, bodies=bodies, faces=False)[0]
    held = position_displacements(sector.law, rho, bodies=bodies)
    assert np.all(held[2] == 0.0)                           # no face carries a force
    assert np.all(bodies[0].openings(free) > 0.0)
    assert np.allclose(held[0], free, rtol=0, atol=1e-12 * np.max(np.abs(free)))
    assert np.allclose(u, free, rtol=0, atol=1e-12 * np.max(np.abs(free)))


def test_straight_polyline_is_the_straight_crack(sector):
    """A crack cut in two collinear pieces is meshed differently but is the same crack."""
    path = initial_path(sector, 0.6e-3, None)
    two = np.vstack([path[:1], 0.5 * (path[0] + path[1]), path[1:]])
    k = [tip_loads(sector, p, 0.03e-3, rolls=sector.rolls[-1:])[0] for p in (path, two)]
    assert k[1].k_i[0] == pytest.approx(k[0].k_i[0], rel=5e-3)
    assert abs(k[1].k_ii[0] - k[0].k_ii[0]) < 5e-3 * k[0].k_i[0]
    assert np.all(k[0].spread < 5e-3) and np.all(k[1].spread < 5e-3)


def test_worst_load_is_at_the_highest_point_of_single_contact(sector, loaded):
    load = loaded[0]
    dp = sector.pair
    hpstc = dp.start_roll_a + 2.0 * math.pi / dp.gear_a.teeth
    assert load.roll[load.worst] == pytest.approx(hpstc)
    assert load.force[load.worst] == pytest.approx(sector.law.load)


# --- the growth loop and its verdict ------------------------------------------------------

def _box(kind_left: str = "tooth") -> Region:
    """The square 0..10 x 0..10, its left side ``kind_left``, the others free."""
    sides = [np.linspace(p, q, 8, endpoint=False) for p, q in
             (([0, 0], [10, 0]), ([10, 0], [10, 10]), ([10, 10], [0, 10]), ([0, 10], [0, 0]))]
    kinds = ["tooth"] * 24 + [kind_left] * 8
    return Region(polygon=np.vstack(sides).astype(float), kind=np.array(kinds), inner_radius=0.0)


def test_mode_i_runs_straight_to_the_wall():
    path = np.array([[9.0, 5.0], [8.0, 5.0]])
    grown = grow(path, 0.5, lambda p: TipState(1.0, 0.0, 1.0, 0.0), _box("rim"))
    assert grown.verdict == "rim"
    assert grown.length == pytest.approx(9.0)
    assert np.allclose(grown.exit, [0.0, 5.0])
    assert np.allclose(grown.path[:, 1], 5.0)
    # decided once the wall is within 1.5 increments of the tip
    assert grown.steps[-1].length == pytest.approx(8.5)      # the wall 0.5 ahead; at 8.0, 1.0


def test_mixed_mode_turns_by_the_maximum_tangential_stress():
    path = np.array([[9.0, 5.0], [8.0, 5.0]])
    grown = grow(path, 0.5, lambda p: TipState(1.0, 0.2, 1.0, 0.0), _box(), max_steps=3)
    turns = np.diff(np.unwrap(np.arctan2(*np.diff(grown.path, axis=0).T[::-1])))
    assert np.allclose(turns, growth_angle(1.0, 0.2))
    assert grown.verdict is None and "3 increments" in grown.reason


@pytest.mark.parametrize("k_ii", [0.0, 0.01, 1.0, -1.0])
def test_shut_tip_stops_undecided(k_ii):
    """A tip closed in mode I (K_I < 0) drives no growth whatever its K_II: the state goes
    through the same rule as the sector's (driving_k), and the loop stops undecided."""
    path = np.array([[9.0, 5.0], [8.0, 5.0]])
    grown = grow(path, 0.5, lambda p: TipState(-1.0, k_ii, driving_k(-1.0, k_ii), 0.0), _box())
    assert grown.verdict is None and "closed" in grown.reason
    assert len(grown.steps) == 1 and np.array_equal(grown.path, path)


def test_driving_k_is_the_equivalent_factor_of_an_open_tip():
    assert driving_k(-1.0, 0.01) == 0.0 and driving_k(0.0, 1.0) == 0.0
    assert driving_k(2.0, 0.0) == 2.0
    assert driving_k(1.0, 0.5) == equivalent_k(1.0, 0.5) > 1.0


def test_a_tip_that_cannot_be_solved_ends_the_growth_with_the_path_so_far():
    path = np.array([[9.0, 5.0], [8.0, 5.0]])

    def evaluate(p):
        if p.shape[0] > 3:
            raise GrowthStopped("mesh refused")
        return TipState(1.0, 0.0, 1.0, 0.0)

    grown = grow(path, 0.5, evaluate, _box())
    assert grown.verdict is None and grown.reason == "mesh refused"
    assert grown.path.shape[0] == 3 and len(grown.steps) == 2
    with pytest.raises(GrowthStopped):                       # at the first tip: the caller's
        grow(path, 0.5, lambda p: (_ for _ in ()).throw(GrowthStopped("x")), _box())


def test_the_worst_positions_include_both_ends_of_single_contact():
    pair = paper_pair()
    dp = driving_pair(pair)
    p = 2.0 * math.pi / dp.gear_a.teeth
    for count in (1, 2, 7):
        rolls = load_rolls(pair, count)
        assert np.any(np.isclose(rolls, dp.start_roll_a + p, rtol=0, atol=1e-12))
        assert np.any(np.isclose(rolls, dp.end_roll_a - p, rtol=0, atol=1e-12))


def test_cell_region_labels_the_hub_and_the_cuts_rim(sector):
    region = sector_region(sector)
    r_root = sector.gear.root_radius
    down = region.ray(np.array([0.0, r_root - 1e-3]), np.array([0.0, -1.0]))
    assert down[1] == "rim" and down[0] == pytest.approx(r_root - 1e-3 - np.min(
        np.hypot(*sector.cell.nodes.T)), rel=1e-3)
    side = region.ray(np.array([0.0, r_root - 2e-3]), np.array([1.0, 0.0]))
    assert side[1] == "rim"                                 # the cut to the next cell
    across = region.ray(np.array([0.0, 0.5 * (r_root + sector.gear.tip_radius)]),
                        np.array([-1.0, 0.0]))
    assert across[1] == "tooth"                             # the other flank


def test_a_tip_below_a_web_s_junction_is_through_the_rim(sector):
    region = cell_region(sector.cell, math.pi / 28, 0.02, rim_radius=0.038)
    path = np.array([[0.0, 0.0399], [0.0, 0.03945]])
    grown = grow(path, 0.5e-3, lambda p: TipState(1.0, 0.0, 1.0, 0.0), region)
    # decided where the path crosses the junction's circle, not an increment past it
    assert grown.verdict == "rim" and grown.exit[1] == pytest.approx(0.038, rel=1e-12)
    assert grown.length == pytest.approx(0.0399 - 0.038, rel=1e-9)


def test_a_tip_running_just_above_a_web_s_junction_is_through_the_rim(sector):
    """A crack running across the tooth 0.1 mm above the junction (its ray never crosses the
    circle) is decided when its next tip comes within the band above it (10 tip sizes of
    0.024 mm): at the circle's point nearest that tip, a rim fracture; 0.3 mm above, or
    without the band, it runs on."""
    region = cell_region(sector.cell, math.pi / 28, 0.02, rim_radius=0.038)
    band = junction_band(0.024e-3, 0.04048 - 0.038)
    assert band == pytest.approx(JUNCTION_TIPS * 0.024e-3, rel=1e-12)
    path = np.array([[0.0015, 0.0381], [0.001, 0.0381]])
    grown = grow(path, 0.5e-3, lambda p: TipState(1.0, 0.0, 1.0, 0.0), region, band=band)
    nxt = np.array([0.0005, 0.0381])
    assert grown.verdict == "rim" and len(grown.steps) == 1
    assert np.allclose(grown.exit, nxt * 0.038 / np.hypot(*nxt), rtol=0, atol=1e-15)
    higher = grow(path + [0.0, 3e-4], 0.5e-3, lambda p: TipState(1.0, 0.0, 1.0, 0.0), region,
                  band=band)
    assert len(higher.steps) > 1
    assert len(grow(path, 0.5e-3, lambda p: TipState(1.0, 0.0, 1.0, 0.0), region).steps) > 1


def test_the_cracked_sector_keeps_the_domains_to_the_tip_s_width():
    """The paper's driver on a web of 1.6 mm at m_b = 0.3 (``examples/thin_rim.toml``), a
    crack whose tip is 0.127 mm (5 tip sizes) above the web's junction: the domains reach
    web elements; the tip's K is the integral's with ``widths=`` the mesh's widths, and far
    from the one without (the domains across the junction, docs/fracture.md 8.7)."""
    import dataclasses

    from spurdyn.fracture.integral import DEFAULT_RINGS, element_rings, stress_intensity
    from spurdyn.geometry.blank import Blank
    from spurdyn.sector.crack_tip import tip_node

    gear = dataclasses.replace(PAIR.gear_a, blank=Blank(0.0, 0.020, 0.0383365, 0.0016),
                               disk_inertia=None)
    webbed = cracked_sector(dataclasses.replace(PAIR, gear_a=gear), PAPER_TORQUE, "a", 4, 14,
                            positions=1)
    path = np.vstack([initial_path(webbed, 0.3e-3, None), [1.0e-3, 38.45e-3]])
    load, bodies, u = tip_loads(webbed, path, 0.024e-3, rolls=webbed.rolls[-1:])
    mesh = bodies[0].mesh
    tip = tip_node(bodies[0], path[-1])
    ring = element_rings(mesh.elements, tip, max(DEFAULT_RINGS) + 1)
    assert np.any(mesh.width[ring > 0] != gear.face_width)      # the domains cross the junction
    k = [stress_intensity(mesh.nodes, mesh.elements, u, gear.material, tip, path[-1] - path[-2],
                          DEFAULT_RINGS, widths=w) for w in (mesh.width, None)]
    assert load.k_i[0] == pytest.approx(np.mean(k[0].k_i), rel=1e-9)
    assert load.k_ii[0] == pytest.approx(np.mean(k[0].k_ii), rel=1e-9)
    scale = math.hypot(load.k_i[0], load.k_ii[0])
    across = max(abs(np.mean(k[1].k_i) - load.k_i[0]), abs(np.mean(k[1].k_ii) - load.k_ii[0]))
    assert across > 0.1 * scale and load.spread[0] < 0.01


def test_the_junction_s_band_is_capped_by_the_rim_s_thickness():
    """A large tip size (a long first crack) takes at most a quarter of a thin rim."""
    assert junction_band(0.16e-3, 0.5e-3) == pytest.approx(JUNCTION_SHARE * 0.5e-3, rel=1e-12)
    assert junction_band(0.01e-3, 0.5e-3) == pytest.approx(JUNCTION_TIPS * 0.01e-3, rel=1e-12)


# --- life ---------------------------------------------------------------------------------

def test_paris_cycles_match_the_closed_form():
    law = ParisLaw(1e-29, 3.0, 1e6)
    a = np.array([1e-3, 2e-3, 4e-3])
    dk = np.array([5e6, 8e6, 14e6])
    life = paris_cycles(a, dk, law)
    exact = [0.0]
    for i in range(2):
        s = (dk[i + 1] - dk[i]) / (a[i + 1] - a[i])
        exact.append(exact[-1] + (dk[i + 1] ** -2.0 - dk[i] ** -2.0) / (law.c * s * -2.0))
    assert np.allclose(life.cycles, exact, rtol=1e-9)
    assert life.arrested_at is None


def test_paris_threshold_arrests():
    law = ParisLaw(1e-29, 3.0, 6e6)
    life = paris_cycles([1e-3, 2e-3, 3e-3], [8e6, 4e6, 9e6], law)
    assert life.arrested_at == pytest.approx(1.5e-3)
    assert life.cycles[0] == 0.0 and np.all(np.isinf(life.cycles[1:]))
    assert paris_cycles([1e-3, 2e-3], [5e6, 9e6], law).arrested_at == 1e-3


@pytest.mark.parametrize("kwargs, key", [({"c": -1.0, "m": 3.0}, "crack.paris_c"),
                                         ({"c": 1e-29, "m": 0.0}, "crack.paris_m"),
                                         ({"c": 1e-29, "m": 3.0, "threshold": -1.0}, "crack.threshold")])
def test_paris_refusals(kwargs, key):
    with pytest.raises(InputError) as err:
        ParisLaw(**kwargs)
    assert err.value.field == key


# --- the command's refusals ---------------------------------------------------------------

@pytest.mark.parametrize("extra, flag", [
    (["--tooth", "28"], "--tooth"),
    (["--tooth", "-1"], "--tooth"),
    (["--gear", "c"], "--gear"),
    (["--increment", "0.02"], "--increment"),
    (["--increment", "-1e-4"], "--increment"),
    (["--length", "0"], "--length"),
    (["--start", "0.05"], "--start"),
    (["--paris-c", "1e-29"], "--paris-m"),
    (["--paris-m", "3"], "--paris-c"),
    (["--paris-c", "-1e-29", "--paris-m", "3"], "--paris-c"),
    (["--paris-c", "1e-29", "--paris-m", "3", "--threshold", "-2"], "--threshold"),
    (["--backup-ratio", "-0.5"], "--backup-ratio"),
    (["--backup-ratio", "30"], "--backup-ratio"),
    (["--positions", "0"], "--positions"),
    (["--max-increments", "0"], "--max-increments"),
    (["--torque", "-5"], "--torque"),
])
def test_crack_command_refusals(tmp_path, capsys, extra, flag):
    out = tmp_path / "crack"
    code = main(["crack", "paper", "--out", str(out)] + extra)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and flag in err[0]
    assert not out.exists() and list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("extra, flag", [(["--start", "0.05"], "--start"),
                                         (["--length", "0.02"], "--length")])
def test_start_and_length_are_refused_before_the_sectors_are_built(tmp_path, capsys, monkeypatch,
                                                                   extra, flag):
    """``--start`` off the fillet and ``--length`` leaving the cell are refused on the tooth's
    cell alone: the sectors (seconds of assembly) are never built."""
    import spurdyn.sector.crack_tip as crack_tip

    def built(*args, **kwargs):
        raise AssertionError("the sectors were built before --start and --length were checked")

    monkeypatch.setattr(crack_tip, "cracked_sector", built)
    out = tmp_path / "crack"
    code = main(["crack", "paper", "--out", str(out)] + extra)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and flag in err[0]
    assert not out.exists()


THIN_RIM = Path(__file__).resolve().parents[1] / "examples" / "thin_rim.toml"


def test_backup_ratio_on_a_web_moves_the_web_s_junction(tmp_path, capsys):
    """On a webbed blank ``--backup-ratio`` moves the rim's inner radius (the web's junction)
    to MB whole depths below the root circle, the hub and the web kept; a junction inside the
    hub is refused in one line naming the flag."""
    import argparse

    from spurdyn.cli.crack import add_crack_parser, crack_inputs, rim_support

    parser = argparse.ArgumentParser()
    add_crack_parser(parser.add_subparsers())
    args = parser.parse_args(["crack", str(THIN_RIM), "--backup-ratio", "0.5",
                              "--out", str(tmp_path / "crack")])
    spec = crack_inputs(args)
    gear = spec["case"].pair.gear_a
    depth = gear.tip_radius - gear.root_radius
    assert gear.blank.rim_radius == pytest.approx(gear.root_radius - 0.5 * depth, rel=1e-12)
    assert (gear.blank.hub_radius, gear.blank.web_width) == (0.020, 0.0016)
    assert spec["inner_radius"] is None
    assert rim_support(gear) == "web" and rim_support(PAIR.gear_a) == "held"
    code = main(["crack", str(THIN_RIM), "--backup-ratio", "3", "--out", str(tmp_path / "crack")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--backup-ratio" in err[0] and "hub" in err[0]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("case", ["paper", str(THIN_RIM)])
def test_a_backup_ratio_leaving_no_rim_is_refused_naming_the_flag(tmp_path, capsys, case):
    """A ratio whose rim is thinner than the sector mesh takes (on a web, or held) is refused
    in one line naming ``--backup-ratio``, not as the blank's or the model's radius."""
    out = tmp_path / "crack"
    code = main(["crack", case, "--backup-ratio", "1e-4", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--backup-ratio" in err[0] and "rim_radius" not in err[0]
    assert list(tmp_path.iterdir()) == []


def test_crack_command_refuses_an_out_that_is_not_its_own(tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    (tmp_path / "theirs").mkdir()
    (tmp_path / "theirs" / "notes.txt").write_text("x")
    for out in ("file", "theirs"):
        code = main(["crack", "paper", "--out", str(tmp_path / out)])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1 and "--out" in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "theirs"]
    assert [p.name for p in (tmp_path / "theirs").iterdir()] == ["notes.txt"]


def test_path_length():
    assert path_length(np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]])) == 6.0


# --- the whole command (slow: a crack grown to its verdict) ------------------------------

@pytest.mark.slow
def test_crack_command_grows_to_a_verdict_and_writes_its_folder(tmp_path, capsys):
    import csv
    import json

    out = tmp_path / "crack"
    code = main(["crack", "paper", "--increment", "1.5e-3", "--paris-c", "1e-29", "--paris-m", "3",
                 "--out", str(out), "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert sorted(p.name for p in out.iterdir()) == sorted(summary["files"])
    assert summary["verdict"]["breaks_through"] == "tooth"       # the paper's solid blank
    assert summary["rim_support"] == "held"
    rows = list(csv.DictReader(open(out / "path.csv")))
    assert len(rows) == summary["increments"] + 1
    length = [float(r["length_m"]) for r in rows]
    assert summary["verdict"]["length_m"] > length[-1]
    assert length[-1] == pytest.approx(summary["verdict"]["decided_at_m"], rel=1e-8)
    assert np.allclose(np.diff(length), 1.5e-3)
    cycles = [float(r["cycles"]) for r in rows]
    assert cycles[0] == 0.0 and np.all(np.diff(cycles) > 0.0)
    assert summary["life"]["cycles"] == pytest.approx(cycles[-1])
    assert summary["closed_faces_near_tip"] == 0


def test_driven_tooth_s_worst_load_is_its_highest_point_of_single_contact(loaded):
    """The paper's gears are alike: the driven gear's crack sees the driver's worst K at
    the driven tooth's highest point of single contact, the lower end of the zone."""
    driven = cracked_sector(PAIR, PAPER_TORQUE, "b", 4, 14, positions=2)
    load, _, _ = tip_loads(driven, initial_path(driven, 0.3e-3, None), 0.02e-3)
    dp = driven.pair
    assert load.roll[load.worst] == pytest.approx(dp.end_roll_a - 2.0 * math.pi / dp.gear_a.teeth)
    assert load.force[load.worst] == pytest.approx(driven.law.load)
    assert load.k_eq[load.worst] == pytest.approx(loaded[0].k_eq[loaded[0].worst], rel=0.01)


def test_growth_picture_without_pillow_is_a_strip_of_frames(tmp_path, monkeypatch):
    import importlib.util

    from spurdyn.sector.crack_plot import draw_growth

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "PIL" else real(name, *a))
    cell = np.array([[-5e-3, 20e-3], [5e-3, 20e-3], [5e-3, 48e-3], [-5e-3, 48e-3]])
    path = np.array([[3e-3, 41e-3], [2.7e-3, 40.8e-3], [2.2e-3, 40.5e-3], [1.7e-3, 40.3e-3]])
    kind = draw_growth(cell, cell, np.array([0.3e-3, 0.8e-3, 1.3e-3]), path,
                       np.array([1e6, 2e6, 3e6]), "probe", tmp_path / "crack_growth")
    assert kind == "png" and (tmp_path / "crack_growth.png").stat().st_size > 0
    assert not (tmp_path / "crack_growth.gif").exists()
