"""The lumped model's steady state over many mesh cycles (docs/lumped.md, "Steady state"):
its start, its load balance, its damping, its settled test, the case keys and the sweep's
ISO K_v."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from spurdyn.case import preset_case, resolve_cases
from spurdyn.lumped import mesh_stiffness_table
from spurdyn.lumped.steady import pair_rolls, simulate_steady
from spurdyn.settings import RPM

CASE = preset_case("paper-fig8")
TABLE = mesh_stiffness_table(CASE.pair, 4, 14)
PITCH = 2 * math.pi / CASE.pair.gear_a.teeth


def _run(rpm: float, zeta: float, cycles: int):
    run = CASE.run.with_(speed_a=rpm * RPM, speed_b=rpm * RPM)
    return simulate_steady(CASE.pair, run, TABLE, zeta, cycles)


def _k(phi: np.ndarray) -> np.ndarray:
    """The mesh stiffness at A's rotations ``phi``: periodic in the pitch, and within one
    pitch of the start the pairs that entered up to two pitches before (contact ratio < 2)."""
    phase = np.asarray(phi, dtype=float) % PITCH
    return np.asarray(TABLE(pair_rolls(CASE.pair, phase, np.arange(-2, 1)))).sum(axis=0)


def _start_deviation(rpm: float) -> float:
    """Largest ``|k delta / F_0 - 1|`` before the pairs in contact first change."""
    r = _run(rpm, 0.05, 1)
    k_now = _k(r.angle)
    jumps = np.flatnonzero(np.abs(np.diff(k_now)) > 1e-3 * k_now.max())
    before = slice(0, jumps[0])
    return float(np.abs(k_now[before] * -r.gap[before] / r.info["static_force"] - 1.0).max())


@pytest.mark.slow
def test_a_slow_run_starts_in_static_equilibrium():
    """The run starts at the static compression, so before the pairs in contact first
    change the mesh carries the static force; what remains is the lag behind the
    equilibrium that moves with the stiffness, first order in the speed (a start from an
    uncompressed mesh would swing by 100 %)."""
    d30, d300 = _start_deviation(30.0), _start_deviation(300.0)
    assert d30 < 3e-4
    assert d300 / d30 == pytest.approx(10.0, rel=0.2)


@pytest.mark.slow
def test_a_slow_damped_run_holds_the_load_between_changes_of_pairs():
    """At 30 rpm, away from the changes of the pairs in contact (the last 20 % of each
    stretch between them, where what the change set ringing has died out), ``k(phi) delta
    = F_0`` to 1e-3: the pairs' forces sum to the static force."""
    r = _run(30.0, 0.05, 3)
    f0 = r.info["static_force"]
    k_now = _k(r.angle)
    delta = -r.gap
    jumps = np.flatnonzero(np.abs(np.diff(k_now)) > 1e-3 * k_now.max())
    edges = np.concatenate([[0], jumps + 1, [r.angle.size]])
    checked = 0
    for lo, hi in zip(edges[:-1], edges[1:]):
        if hi - lo < 50:
            continue
        sel = slice(lo + int(0.8 * (hi - lo)), hi)
        assert np.abs(k_now[sel] * delta[sel] / f0 - 1.0).max() < 1e-3
        checked += 1
    assert checked >= 4


def test_the_free_oscillation_after_a_change_of_pairs_decays_at_the_damping_ratio():
    """In the single-contact stretch at 1,000 rpm the pair rings at its torsional frequency
    after the second pair leaves; the logarithmic decrement of the excursion from the static
    compression gives the damping ratio asked for within 10 %."""
    for zeta in (0.02, 0.05):
        r = _run(1000.0, zeta, 2)
        f0 = r.info["static_force"]
        phi, delta = r.angle, -r.gap
        k_now = _k(phi)
        exc = delta - f0 / k_now
        jumps = np.flatnonzero(np.abs(np.diff(k_now)) > 1e-3 * k_now.max())
        # the longest stretch without a change of pairs after the first jump
        edges = np.concatenate([jumps + 1, [phi.size]])
        lengths = np.diff(edges)
        i = int(np.argmax(lengths))
        seg = exc[edges[i] + 2:edges[i + 1] - 2]
        peaks = [j for j in range(1, seg.size - 1) if seg[j] > seg[j - 1] and seg[j] >= seg[j + 1] and seg[j] > 0]
        amps = seg[peaks]
        assert amps.size >= 3
        dec = np.log(amps[0] / amps[-1]) / (amps.size - 1)
        measured = dec / math.sqrt(4 * math.pi ** 2 + dec ** 2)
        assert measured == pytest.approx(zeta, rel=0.10)


@pytest.mark.slow
def test_the_settled_test_needs_the_run_to_settle():
    assert not _run(15000.0, 0.0, 4).info["steady"]["settled"]
    assert _run(4000.0, 0.05, 20).info["steady"]["settled"]


@pytest.mark.slow
def test_cycles_from_the_case_and_the_command_line(tmp_path, monkeypatch, capsys):
    from spurdyn.case import case_from_dict, case_to_dict
    from spurdyn.cli.main import main

    case = resolve_cases("paper-fig8", {"run.cycles": 12})[0]
    assert case.run.cycles == 12
    assert case_from_dict(case_to_dict(case), check_step=False).run.cycles == 12
    assert case.angle == pytest.approx(12 * PITCH)
    monkeypatch.chdir(tmp_path)
    assert main(["run", "paper-fig8", "--model", "lumped", "--cycles", "6", "--damping", "0.05",
                 "--quiet", "--out", "r"]) == 0
    s = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert s["cycles"] == 6 and isinstance(s["settled"], bool) and s["dynamic_factor"] > 1.0
    assert s["transmission_error_pp_m"] > s["transmission_error_rms_m"] > 0
    capsys.readouterr()
    for argv in (["run", "paper-fig8", "--model", "lumped", "--cycles", "0"],
                 ["run", "paper-fig8", "--cycles", "5"],
                 ["sweep", "paper-fig8", "--rpm", "4000", "--cycles", "5"]):
        assert main(argv + ["--out", "bad"]) == 2
        err = capsys.readouterr().err
        assert err.startswith("spurdyn: error: --cycles:") and err.count("\n") == 1
    assert not (tmp_path / "bad").exists()


def test_the_sweep_picture_takes_iso_kv_from_the_iso_module():
    from spurdyn.iso6336.rating import dynamic_factor_at, iso_pair, rate
    from spurdyn.sweep.resonance import resonance_estimate

    est = resonance_estimate(CASE)
    rating = rate(iso_pair(CASE.pair), CASE.run.torque)
    rpm = np.array([1000.0, 9000.0, 12000.0, 16000.0, 20000.0])
    assert est.iso_kv(rpm) == pytest.approx([dynamic_factor_at(rating, n * RPM) for n in rpm], rel=1e-12)
    assert est.iso_resonance_rpm == pytest.approx(rating.resonance_speed / RPM)


def test_the_sweep_file_holds_iso_kv_at_each_speed_and_torque():
    from spurdyn.iso6336.rating import dynamic_factor_at, iso_pair, rate
    from spurdyn.sweep.resonance import iso_kv_grid

    rpm, torque = [2000.0, 12000.0], [0.0, 22.25, 60.0]
    kv = iso_kv_grid(CASE, rpm, torque)
    assert np.isnan(kv[:, 0]).all()           # no torque: ISO's line load is zero
    for j, tq in enumerate(torque[1:], start=1):
        r = rate(iso_pair(CASE.pair), tq)
        assert kv[:, j] == pytest.approx([dynamic_factor_at(r, n * RPM) for n in rpm], rel=1e-12)
    assert kv[0, 1] != kv[0, 2]     # below resonance K_v depends on the line load (N_S)


def _at_each(cycle, phase: np.ndarray) -> np.ndarray:
    """``cycle.at`` at each of ``phase`` ``(rows, n)``: its arithmetic on its dense table
    (``cycle.tables()``), element by element, in arrays (a Python call a sample took seconds
    on the 3-rpm run's ~140,000 samples)."""
    dense, bounds, h, _, _ = cycle.tables()
    x = phase / h
    i = np.clip(x.astype(np.int64), 0, dense.shape[1] - 2)     # int() truncates, as astype
    w = x - i
    inside = (bounds[:, :1] <= phase) & (phase <= bounds[:, 1:])
    return np.where(inside, dense[:, i] + w * (dense[:, i + 1] - dense[:, i]), 0.0)


def _assert_close(got: np.ndarray, want: np.ndarray, rel: float) -> None:
    """``got == pytest.approx(want, rel=rel)`` (each within ``max(rel |want|, 1e-12)``,
    NaN never), in arrays: pytest.approx compares a long array a Python object an element."""
    bad = ~(np.abs(got - want) <= np.maximum(rel * np.abs(want), 1e-12))
    assert not bad.any(), f"{bad.sum()} of {bad.size} off by more than {rel:g}; first at {np.argmax(bad)}: " \
                          f"{got[bad][0]!r} against {want[bad][0]!r}"


@pytest.mark.slow
def test_the_sector_stiffness_feeds_the_steady_state(tmp_path, monkeypatch, capsys):
    """``stiffness = "sector"``: the pairs' effective stiffnesses are their shares of the
    sector's mesh stiffness, so a slow damped run carries each pair's static share of the
    load, and the summary's mean mesh stiffness is the sector analysis'."""
    from spurdyn.cli.main import main
    from spurdyn.lumped.cycle import SectorCycle
    from spurdyn.lumped.sources import quasi_static_cycle

    # sector.statics.mesh_cycle on the case's mesh, whole gears, 41 positions, kept in the
    # process (as the command below takes it: computed once)
    mc = quasi_static_cycle(CASE.pair, CASE.run.torque, 4, 14, None, 1.0, positions=41)
    cycle = SectorCycle.from_mesh_cycle(CASE.pair, mc)
    # at the analysis' own positions the cycle returns its forces over the static compression
    for i in (3, 20, 35):
        k = cycle.at(float(cycle.phase[i]))
        delta = mc.load / mc.stiffness[i]
        assert np.array(k) * delta == pytest.approx(mc.force[i], rel=1e-9, abs=1e-9 * mc.load)
    run = CASE.run.with_(speed_a=3 * RPM, speed_b=3 * RPM)
    r = simulate_steady(CASE.pair, run, cycle, 0.05, 2)
    assert r.info["steady"]["mesh_stiffness_mean_N_per_m"] == pytest.approx(mc.stiffness_mean, rel=2e-3)
    # slow (3 rpm) and damped: away from the changes of pairs (the last 20 % of each stretch, where
    # the ringing the change set off has died out) the most loaded pair carries the
    # analysis' largest share of the load
    phase = r.angle - cycle.pitch * np.floor(r.angle / cycle.pitch)
    ks = _at_each(cycle, phase)
    picks = np.linspace(0, phase.size - 1, 200).astype(int)
    assert np.array_equal(ks[:, picks], np.array([cycle.at(float(phase[j])) for j in picks]).T)
    k_tot = ks.sum(axis=0)
    expected = mc.load * ks.max(axis=0) / k_tot
    jumps = np.flatnonzero(np.abs(np.diff(k_tot)) > 1e-3 * k_tot.max())
    edges = np.concatenate([[0], jumps + 1, [r.angle.size]])
    checked = 0
    for lo, hi in zip(edges[:-1], edges[1:]):
        if hi - lo >= 50:
            sel = slice(lo + int(0.8 * (hi - lo)), hi)
            _assert_close(r.contact_force[sel], expected[sel], rel=1e-3)
            checked += 1
    assert checked >= 3
    monkeypatch.chdir(tmp_path)
    assert main(["run", "paper-fig8", "--model", "lumped", "--cycles", "4", "--stiffness", "sector",
                 "--quiet", "--out", "s"]) == 0
    s = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert s["mesh_stiffness_mean_N_per_m"] == pytest.approx(mc.stiffness_mean, rel=2e-3)
    capsys.readouterr()
    for argv in (["run", "paper-fig8", "--model", "lumped", "--stiffness", "sector"],
                 ["run", "paper-fig8", "--stiffness", "sector", "--cycles", "3"],
                 ["run", "paper-fig8", "--model", "lumped", "--stiffness", "rim", "--cycles", "3"]):
        assert main(argv + ["--out", "bad"]) == 2
        err = capsys.readouterr().err
        assert err.startswith("spurdyn: error: --stiffness:") and err.count("\n") == 1
    assert not (tmp_path / "bad").exists()


@pytest.mark.slow
def test_a_sweep_down_in_speed_stays_on_the_upper_branch(tmp_path, capsys):
    """Continuation (``--continuation down``): each speed starts from the previous speed's
    end state, so below the resonance the softening pair stays on the branch of large
    amplitude that a start from rest does not reach: the jump of the nonlinear response."""
    import xarray as xr

    from spurdyn.cli.main import build_parser, main
    from spurdyn.cli.sweep import build_plan
    from spurdyn.sweep.point import PointTask, run_point

    common = ["sweep", "paper-fig8", "--model", "lumped", "--cycles", "40", "--damping", "0.05",
              "--stiffness", "sector", "--quiet"]
    assert main(common + ["--rpm", "9000,10000,11000", "--continuation", "down", "--out", str(tmp_path / "down")]) == 0
    # each speed from rest: only the two the chain is compared at, each the point a sweep's
    # worker computes (run_point on the plan's case), here in this process: a cluster's
    # worker process took three quarters of this test's time to start and build the sector's
    # mesh cycle again (the sweeps over a cluster have tests of their own, tests/test_sweep.py)
    plan = build_plan(build_parser().parse_args(common + ["--rpm", "9000,11000", "--out", str(tmp_path / "alone")]))
    alone = {k.rpm: run_point(PointTask(k, plan.point_case(k))) for k in plan.keys()}
    assert all(o.status == "complete" for o in alone.values())
    down = xr.open_dataset(tmp_path / "down" / "sweep.nc").sel(model="lumped")
    assert float(down.dynamic_factor.sel(rpm=11000)) == pytest.approx(
        alone[11000.0].figures["dynamic_factor"], rel=1e-12)       # the chain's first point
    assert float(down.dynamic_factor.sel(rpm=9000)) > 1.5 * alone[9000.0].figures["dynamic_factor"]
    records = [json.loads(p.read_text()) for p in (tmp_path / "down" / "points").glob("*.json")]
    assert all(r["end_transmission_error"] is not None for r in records)
    capsys.readouterr()
    assert main(["sweep", "paper-fig8", "--model", "lumped", "--rpm", "9000,10000",
                 "--continuation", "down", "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("spurdyn: error: --continuation:") and err.count("\n") == 1


@pytest.mark.slow
def test_the_lumped_run_goes_on_until_it_settles_and_max_cycles_bounds_it(tmp_path, capsys):
    """Above the resonance (18,000 rpm, zeta = 0.05) twenty cycles are too short for the
    transient to decay: asked exactly (``max_cycles = cycles``) the run has not settled; by
    default it goes on, a cycle at a time, and settles before its bound. ``--max-cycles``
    without ``--cycles``, or below them, is refused in one line naming it, nothing written."""
    from spurdyn.cli.main import main
    from spurdyn.geometry.presets import paper_pair
    from spurdyn.settings import RPM, SETTLE_CYCLES_FACTOR
    from spurdyn.simulators import MODELS
    from spurdyn.solvers.check import run_settings

    pair = paper_pair()
    s = run_settings(pair, 18000 * RPM, 22.25, cycles=20, damping_ratio=0.05, stiffness="sector")
    exact = MODELS["lumped"](pair, s.with_(max_cycles=20)).info["steady"]
    more = MODELS["lumped"](pair, s).info["steady"]
    assert not exact["settled"] and exact["cycles_done"] == 20
    assert more["settled"] and 20 < more["cycles_done"] < SETTLE_CYCLES_FACTOR * 20
    assert more["max_cycles"] == SETTLE_CYCLES_FACTOR * 20
    # the first cycles are the exact run's (the extension only appends)
    n = len(exact["peak_mesh_force_per_cycle_N"])
    np.testing.assert_allclose(more["peak_mesh_force_per_cycle_N"][:n], exact["peak_mesh_force_per_cycle_N"],
                               rtol=1e-12)
    for argv, label in ((["--max-cycles", "5"], "--max-cycles"),
                        (["--model", "lumped", "--cycles", "5", "--max-cycles", "3"], "--max-cycles")):
        capsys.readouterr()
        assert main(["run", "paper-fig8", *argv, "--out", str(tmp_path / "bad")]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"spurdyn: error: {label}:") and err.count("\n") == 1
        assert not (tmp_path / "bad").exists()
