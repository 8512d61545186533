"""The sector model's back flanks (docs/sector.md, 6.7): where they face each other across the
backlash, their loads and rows against the rotation field and the matrices written out, and
a light load at the resonance with a little backlash, which separates the drive flanks and
throws the back flanks together: both loops alike, the hubs' momenta their torques' impulse,
and the files saying so."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import xarray as xr

from spurdyn.geometry.corner import _tangent_points
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.statics import driving_pair
from spurdyn.sector.system import (
    back_roll_sum,
    gear_block,
    rigid_gap,
    teeth_for,
)
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.run import back_flanks_on, simulate_sector

PAIR = paper_pair()
MESH = dict(nx=2, ny=8)
#: 0.5 um beyond the tight centre distance: 0.34 um of normal backlash, which a light load
#: at the main resonance closes.
LOOSE = dataclasses.replace(PAIR, centre_distance=PAIR.centre_distance + 0.5e-6)


def _left_flank(gear, centre, phi0, rho, n=20000):
    """Points of the left flank of the tooth whose right flank is at roll ``rho`` in the frame
    of :mod:`spurdyn.geometry.corner`: the right flank's mirror image across the tooth's
    centre line (polar angle ``phi0 - rho + psi_b / 2``)."""
    rb = gear.base_radius
    s = np.linspace(0.0, math.sqrt(gear.tip_radius**2 - rb * rb) / rb, n)
    pts = np.column_stack(_tangent_points(s, rho, (float(centre[0]), float(centre[1])), rb, phi0)) - centre
    c = phi0 - rho + gear.half_angle_base
    ang, rad = 2 * c - np.arctan2(pts[:, 1], pts[:, 0]), np.hypot(pts[:, 0], pts[:, 1])
    return centre + np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])


@pytest.mark.slow
@pytest.mark.parametrize("more", [0.0, 0.2e-3])
def test_the_back_flanks_face_each_other_across_the_backlash(more):
    """Drawn from the outlines (the corner module's frame: the drive line of action the x
    axis), the driver's tooth ``k``'s left flank and the driven gear's tooth ``-k + 1``'s cross
    the back line of action (the drive line's mirror image across the line of centres) at the
    driver's back roll ``Sigma - rho`` and ``j_n`` apart, for the tight pair and one 0.2 mm
    further apart."""
    pair = driving_pair(dataclasses.replace(PAIR, centre_distance=PAIR.centre_distance + more))
    ga, gb = pair.gear_a, pair.gear_b
    ra, rb, length = ga.base_radius, gb.base_radius, pair.line_of_centres_length
    o_a, o_b = np.array([0.0, -ra]), np.array([length, rb])
    u = (o_b - o_a) / np.linalg.norm(o_b - o_a)

    def mirror(p):
        d = p - o_a
        return o_a + 2 * (d @ u) * u - d

    t_a, t_b = mirror(np.zeros(2)), mirror(np.array([length, 0.0]))
    e = (t_b - t_a) / np.linalg.norm(t_b - t_a)
    normal = np.array([-e[1], e[0]])

    def crossing(pts):
        h = (pts - t_a) @ normal
        i = int(np.flatnonzero(np.sign(h[:-1]) != np.sign(h[1:]))[0])
        p = pts[i] + h[i] / (h[i] - h[i + 1]) * (pts[i + 1] - pts[i])
        return float((p - t_a) @ e)

    pitch = 2 * math.pi / ga.teeth
    checked = 0
    for theta in (0.013, 0.11, 0.2):
        rho0 = pair.start_roll_a + theta
        for k in range(-2, 4):
            back = back_roll_sum(pair) - (rho0 + k * pitch)
            if not pair.start_roll_a + 0.01 < back < pair.end_roll_a - 0.01:
                continue
            x_a = crossing(_left_flank(ga, o_a, math.pi / 2, rho0 + k * pitch))
            rho_b = (length - ra * (rho0 + (k - 1) * pitch)) / rb        # tooth -(k - 1)
            x_b = crossing(_left_flank(gb, o_b, -math.pi / 2, rho_b))
            assert x_a / ra == pytest.approx(back, abs=1e-8)
            assert x_b - x_a == pytest.approx(pair.backlash_normal, abs=1e-10)
            checked += 1
    assert checked >= 4
    assert more == 0.0 or pair.backlash_normal > 1e-4


def test_a_back_flanks_load_is_the_mirror_image_and_its_row_the_rotation_fields_work():
    """The left flank's nodes are the right flank's mirror images, its unit strip load
    presses into the tooth from the other side, and a turn of the driver's body moves it by
    ``+r_bA`` per radian (the driven gear's ``-r_bB``), as a back row's hub entries say on the
    path (to the quadratic edges' approximation of the involute)."""
    dp = driving_pair(PAIR)
    for g, (gear, sense, expect) in enumerate(((dp.gear_a, 1.0, dp.gear_a.base_radius),
                                               (dp.gear_b, -1.0, -dp.gear_b.base_radius))):
        blk = gear_block(gear, sense, -2, 5, 4, 14, 1.0)
        tooth = blk.body.mesh.tooth.nodes
        left, right = tooth[blk._left], tooth[blk.body.flank.side_nodes]
        np.testing.assert_allclose(left, right * [-1.0, 1.0], rtol=0, atol=1e-12)
        for rho in (dp.start_roll_a + 0.02, dp.pitch_roll_a, dp.end_roll_a - 0.02):
            r = rigid_gap(dp, rho)[2 + g]
            for k in (0, 2):
                back = blk.flank_load(k, r, 50e-6, side=1)
                drive = blk.flank_load(k, r, 50e-6)
                assert float(back @ blk.rot[blk.flank_dofs(k, 1)]) == pytest.approx(expect, rel=2e-3)
                assert float(drive @ blk.rot[blk.flank_dofs(k)]) == pytest.approx(-expect, rel=2e-3)


@pytest.mark.slow
def test_a_back_flanks_rows_and_columns_are_their_matrices():
    """Rows on drive and back flanks together, on whole and modal bodies, against the
    matrices written out: ``E x``, ``S^-1 E^T``, and the modal bodies' residual compliance
    ``b_i^T (K^-1 - Phi Omega^-2 Phi^T) b_j`` flank by flank, round the ring too."""
    from spurdyn.sector.bodies import FullBody, ModalBody
    from spurdyn.sector.reduced import reduce_gear

    (fa, ca), _ = teeth_for(PAIR, 40.0)
    blk = gear_block(PAIR.gear_a, 1.0, fa, ca, **MESH, grading=1.0)
    red = reduce_gear(blk, 60e3)
    ks = np.array([3, 3, -7, 10 + blk.count, 4])
    sides = np.array([0, 1, 1, 1, 0])
    r = np.linspace(blk.body.flank.r0 + 1e-4, PAIR.gear_a.tip_radius - 1e-4, ks.size)
    b = np.array([90e-6, 30e-6, 120e-6, 60e-6, 0.0])
    loads = blk.flank_loads(r, b)
    turned = [blk.flank_load(int(k), float(ri), float(bi), int(s)) for k, ri, bi, s in zip(ks, r, b, sides)]
    rng = np.random.default_rng(7)
    for body in (FullBody(blk, 1e-6, 1e-12, (0.0, 0.0)), ModalBody(red, 1e-6, 1e-12, (0.0, 0.0), sides=2)):
        rows = body.rows(ks, loads, sides)
        x = rng.standard_normal(body.n)
        e = np.zeros((ks.size, body.n))
        for i, (k, s) in enumerate(zip(ks, sides)):
            if isinstance(body, FullBody):
                e[i, blk.flank_dofs(int(k), int(s)) + 1] = turned[i]
            else:
                e[i, 1:] = red.modes_at(int(k), int(s)).T @ turned[i]
        np.testing.assert_allclose(body.elastic(rows, x), e @ x, rtol=1e-12, atol=0)
        want = body.solve(e.T)
        np.testing.assert_allclose(body.columns(rows), want, rtol=0, atol=1e-9 * np.abs(want).max())
        if isinstance(body, ModalBody):
            flex = np.zeros((ks.size, ks.size))
            for i, (ki, si) in enumerate(zip(ks, sides)):
                for j, (kj, sj) in enumerate(zip(ks, sides)):
                    block = (red.static_response(int(kj), int(sj))[blk.flank_dofs(int(ki), int(si))]
                             - (red.modes_at(int(ki), int(si)) / red.omega2) @ red.modes_at(int(kj), int(sj)).T)
                    flex[i, j] = turned[i] @ block @ turned[j]
            np.testing.assert_allclose(body.residual(rows), flex, rtol=0, atol=1e-9 * np.abs(flex).max())
            assert abs(flex[1, 0]) > 1e-3 * abs(flex[0, 0])     # a tooth's two flanks do couple


def test_the_back_flanks_are_contacts_where_the_pair_has_backlash():
    s = run_settings(PAIR, 4000 * RPM, 22.25, model="sector", cycles=1, **MESH)
    assert not back_flanks_on(PAIR, s) and back_flanks_on(LOOSE, s)
    assert back_flanks_on(PAIR, s.with_(back_flanks=True)) and not back_flanks_on(LOOSE, s.with_(back_flanks=False))
    # the bodies hold every tooth a back pair needs: the driver's k and the driven gear's -k + 1
    (fa, ca), (fb, cb) = teeth_for(LOOSE, 1.0, back=True)
    assert ca < LOOSE.gear_a.teeth
    from spurdyn.sector.system import REACH, back_teeth

    lo, hi = back_teeth(LOOSE, 1.0, REACH * 2 * math.pi / LOOSE.gear_a.teeth)
    assert fa <= lo and hi <= fa + ca - 1 and fb <= -hi + 1 and -lo + 1 <= fb + cb - 1


@pytest.fixture(scope="module")
def rattle():
    """2 N m at 11,000 rpm (the main resonance) on 0.34 um of backlash, undamped, six
    cycles: the pair's ring grows until the drive flanks separate and the back flanks meet."""
    s = run_settings(LOOSE, 11000 * RPM, 2.0, model="sector", cycles=6, max_cycles=6, rho_inf=1.0, **MESH,
                     rayleigh_mass=0.0, rayleigh_stiffness=0.0, damping_ratio=0.0)
    return s, simulate_sector(LOOSE, s), simulate_sector(LOOSE, s.with_(backend="numpy"), energy=True)


@pytest.mark.slow
def test_a_light_load_rattles_across_a_little_backlash(rattle):
    """Drive-flank separation, then back-flank impact: the first step with a back-flank force
    comes after steps with no drive-flank force, with the driver's hub behind the rigid
    kinematics (the transmission error negative; the back gap ``j_n`` plus it and the teeth's
    own free vibration at the back flanks, some 0.1 um here, closes); the compiled loop is the
    NumPy loop's twin through the impacts."""
    _, fast, ref = rattle
    assert fast.status == ref.status == "complete" and fast.info["back_flanks"]
    back, drive = ref.back_force.sum(axis=1), np.nansum(ref.pair_force, axis=1)
    hit = int(np.flatnonzero(back > 0)[0])
    assert back.max() > 0.5 * ref.info["static_force"]
    assert (drive[hit - 3:hit] == 0).all() and (drive[:hit] > 0).sum() > 100
    assert ref.transmission_error[hit] < 0.0 < ref.transmission_error[0]
    np.testing.assert_allclose(fast.back_force, ref.back_force, rtol=0, atol=1e-8 * back.max())
    np.testing.assert_allclose(np.nan_to_num(fast.pair_force), np.nan_to_num(ref.pair_force), rtol=0,
                               atol=1e-8 * drive.max())
    np.testing.assert_allclose(fast.transmission_error, ref.transmission_error, rtol=0,
                               atol=1e-8 * np.abs(ref.transmission_error).max())


@pytest.mark.slow
def test_each_hubs_momentum_is_its_torques_impulse_through_back_impacts(rattle):
    """With rho_inf = 1 a hub's momentum changes by the trapezoidal impulse of its torque and
    of the contacts' forces through their rows' hub entries, the back flanks' with the
    opposite sign, to round-off through the impacts."""
    _, _, run = rattle
    p = np.array(run.info["momentum"]["hub_momentum"])
    q = np.array(run.info["momentum"]["contact_torque"]) + run.torque[0]
    impulse = np.concatenate([np.zeros((1, 2)), np.cumsum(0.5 * np.diff(run.time)[:, None] * (q[1:] + q[:-1]), axis=0)])
    np.testing.assert_allclose(p - p[0], impulse, rtol=0, atol=1e-9 * np.abs(p[0]).max())


@pytest.mark.slow
def test_spurdyn_run_writes_both_flanks_forces(tmp_path, capsys):
    """``spurdyn run`` of a case with backlash: ``result.nc`` has the back flanks' forces by
    the driver's tooth, the summary their peak and steps, the command's line says so; the
    flag turns them off, and a bad value of the key is refused in one line naming it."""
    from spurdyn.cli.main import main

    case = tmp_path / "loose.toml"
    case.write_text(
        "[gear_a]\nteeth = 28\npitch_radius = 0.04445\ntip_radius = 0.047625\nroot_radius = 0.04048\n"
        "pressure_angle_deg = 20.0\nface_width = 0.00635\ndisk_inertia = 2.965e-4\n"
        "[gear_a.material]\nyoung = 210e9\npoisson = 0.3\ndensity = 7800.0\n"
        f"[pair]\ncentre_distance = {LOOSE.centre_distance!r}\n[mesh]\nnx = 2\nny = 8\n"
        "[run]\nspeed_a_rpm = 11000\nspeed_b_rpm = 11000\ntorque = 2.0\ncycles = 6\nmax_cycles = 6\n"
        "damping_ratio = 0.0\n"
        "[model]\nkind = \"sector\"\n")
    assert main(["run", str(case), "--out", str(tmp_path / "on")]) == 0
    line = capsys.readouterr().out
    assert "back flanks" in line
    summary = json.loads((tmp_path / "on" / "summary.json").read_text())
    assert summary["back_flanks"]["contacts"] and summary["back_flanks"]["steps_in_contact"] > 0
    assert summary["back_flanks"]["backlash_normal_m"] == pytest.approx(LOOSE.backlash_normal)
    ds = xr.open_dataset(tmp_path / "on" / "result.nc")
    assert ds["back_pair_force"].attrs["units"] == "N" and ds["back_pair_force"].dims == ("time", "back_pair")
    np.testing.assert_allclose(ds["back_mesh_force"], ds["back_pair_force"].sum("back_pair"))
    assert float(ds["back_mesh_force"].max()) == pytest.approx(summary["back_flanks"]["peak_force_N"])
    assert main(["run", str(case), "--back-flanks", "off", "--out", str(tmp_path / "off")]) == 0
    assert "back_pair_force" not in xr.open_dataset(tmp_path / "off" / "result.nc")
    capsys.readouterr()
    case.write_text(case.read_text().replace("max_cycles = 6\n", "max_cycles = 6\nback_flanks = \"yes\"\n"))
    assert main(["run", str(case), "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err
    assert "run.back_flanks" in err and err.count("\n") == 1 and not (tmp_path / "bad").exists()
