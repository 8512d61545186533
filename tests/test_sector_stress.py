"""The sector model's root stress on the rim and its pairs' Hertz pressure (issue 35 point 2,
docs/sector.md 6.11): the fillet maps of a modal body against a whole one's and against the
recovery operator applied directly, the sampled steps, the pressure against Hertz's formula
written out, and what result.nc and summary.json hold."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from spurdyn.fem.recovery import surface_stress_operator, tangential_stress
from spurdyn.geometry.presets import paper_pair
from spurdyn.model.root import peaks
from spurdyn.sector.fillets import GearFillets, tooth_fillets
from spurdyn.sector.model import SectorModel
from spurdyn.sector.rules import STRESS_SAMPLES, stress_steps
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector import teeth
from spurdyn.solvers.sector.teeth import MOST_SAMPLES, fillet_stress, sample_runs

PAIR = paper_pair()
MESH = dict(nx=2, ny=8)


def _settings(cycles: int = 1, **more):
    return run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=cycles, max_cycles=cycles,
                        damping_ratio=0.05, **MESH, **more)


@pytest.fixture(scope="module")
def static_models():
    """The loaded pair's static start on modal and on whole bodies (a five-tooth sector)."""
    s = _settings()
    return {modes: SectorModel.build(PAIR, s, modes=modes) for modes in (True, False)}


def _start_stress(model):
    st = model.start()
    # the start's static loads sit where the rigid pair touches (the driver's turn 0, not
    # q[0], which holds the static deflection's turn too)
    rows = model.rows_at(0.0, st.force, st.offset)
    out = []
    for g in range(2):
        fl = GearFillets(model.gears[g])
        out.append((fl, fl.stress(st.q[model.parts[g]], rows.sides[g][1], st.force[rows.on]), st))
    return out


def test_modal_and_whole_bodies_give_the_same_static_root_stress(static_models):
    """At the static start the modal body's displacements, modes plus residual flexibility
    under the same flank loads, are the whole body's ``K^-1 f``: the fillet stresses agree
    to 1e-8 of their peak (only the strip's radii differ, the gap table's against the exact
    ones, by some 1e-10 m)."""
    modal, full = _start_stress(static_models[True]), _start_stress(static_models[False])
    for (fl, a, _), (_, b, _) in zip(modal, full):
        assert a.shape == b.shape == (fl.teeth.size, fl.radius.size)
        assert np.abs(b).max() > 1e7                      # a loaded tooth: tens of MPa
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-8 * np.abs(b).max())


def test_the_fillet_maps_are_the_recovery_operator_on_the_whole_displacements(static_models):
    """The whole body's fillet stress against ``t . (R u) . t`` with the recovery operator
    ``R`` over all the mesh's DOFs, formed here, at every tooth; and the fillets run from
    the cell's edge (half a pitch from the tooth's centre line) up to the form radius."""
    model = static_models[False]
    for g, (fl, sig, st) in enumerate(_start_stress(model)):
        blk = model.blocks[g]
        mesh, gear = blk.body.mesh, blk.gear
        u = np.zeros(mesh.n_dof)
        u[blk.body.free_dofs] = st.q[model.parts[g]][1:]
        for i, k in enumerate(fl.teeth):
            surf = tooth_fillets(mesh, int(k), gear.form_radius, gear.material)
            r = surface_stress_operator(mesh.nodes, mesh.elements, surf.nodes, gear.material)
            direct = tangential_stress(np.einsum("ncj,j->nc", r, u), surf.tangents)
            np.testing.assert_allclose(sig[i], direct, rtol=0, atol=1e-9 * np.abs(direct).max())
            assert surf.radius.max() < gear.form_radius
            assert surf.radius.min() == pytest.approx(gear.root_radius, rel=1e-9)
            xy = mesh.nodes[surf.nodes]
            chi = np.arctan2(xy[:, 0], xy[:, 1]) - mesh.tooth_angle(int(k))
            chi = (chi + math.pi) % (2 * math.pi) - math.pi
            assert np.abs(chi).max() == pytest.approx(0.5 * mesh.pitch_angle, rel=1e-9)


def _stress_by_sample(model, fillets, states, force, offset=0):
    """The NumPy reference of :func:`fillet_stress`: one state at a time, its contacts' rows
    (``rows_at``) through ``GearFillets.stress``, as the root stress was recovered before
    it took all the samples at once."""
    out = [np.empty((len(states), fl.teeth.size, fl.radius.size)) for fl in fillets]
    for s, (q, f) in enumerate(zip(states, force)):
        rows = model.rows_at(float(q[0]), f, offset)
        on = rows.on if rows is not None else np.zeros(0, np.intp)
        for g, fl in enumerate(fillets):
            out[g][s] = fl.stress(q[model.parts[g]], rows.sides[g][1] if rows is not None else None, f[on])
    return out


def _states(model, count=40, seed=0):
    """``count`` states about the static start's across the turns the contacts cover (and
    one beyond them, where no contact is near), the contacts' forces some zero, the others
    up to the start's largest."""
    rng = np.random.default_rng(seed)
    st = model.start()
    q = st.q * (1.0 + 0.2 * rng.standard_normal((count, st.q.size)))
    q[:, 0] = np.linspace(model.theta_lo, model.theta_hi, count)
    q[-1, 0] = model.theta_hi + 3.0 * model.pitch
    force = st.force.max() * rng.uniform(0.0, 1.0, (count, st.force.size))
    force[rng.uniform(size=force.shape) < 0.3] = 0.0
    return q, force


@pytest.fixture(scope="module")
def whole_model():
    """The loaded pair on modal bodies of its whole gears (their fillet maps by the teeth's
    distance round the ring)."""
    return SectorModel.build(PAIR, _settings().with_(teeth=100), modes=True)


@pytest.mark.parametrize("bodies", ["modal", "full", "whole"])
def test_the_samples_stress_at_once_is_the_one_at_a_time(static_models, whole_model, bodies):
    """:func:`fillet_stress` (the rows and stresses of all the samples at once, the root
    stress's path) against the same sums state by state, on modal and whole bodies of a
    five-tooth sector and on modal whole gears: the same to round-off (1e-12 of the peak;
    measured 3e-16 on modal bodies, 9e-15 on whole ones). States with no contact near
    their paths, alone and among others, have the bodies' stress alone."""
    model = {"modal": static_models[True], "full": static_models[False], "whole": whole_model}[bodies]
    assert model.whole == (bodies == "whole")
    fillets = [GearFillets(g) for g in model.gears]
    q, force = _states(model)
    ref = _stress_by_sample(model, fillets, q, force)
    for at in (slice(None), slice(-1, None)):
        for g, got in enumerate(fillet_stress(model, fillets, q[at], force[at])):
            peak = np.abs(ref[g]).max()
            assert peak > 1e7 and got.shape == ref[g][at].shape
            np.testing.assert_allclose(got, ref[g][at], rtol=0, atol=1e-12 * peak)


def test_the_sampled_steps_are_the_same_phases_every_cycle():
    for per_cycle in (200, 237, 2369, 40):
        steps = stress_steps(per_cycle, 3 * per_cycle)
        n = min(STRESS_SAMPLES, per_cycle)
        assert steps.size == 3 * n + 1 and steps[-1] == 3 * per_cycle
        assert np.all(np.diff(steps) >= 1)
        np.testing.assert_array_equal(steps[n:2 * n] - per_cycle, steps[:n])


def _run(bodies: str, seen: dict | None = None):
    """One cycle of the five-tooth sector at 4,000 rpm on ``bodies``; ``seen`` receives what
    its root stress was recovered from (``args``: the model, record, samples kept, offset)."""
    from spurdyn.solvers.sector import output
    from spurdyn.solvers.sector.run import simulate_sector

    recover = output.root_stress

    def kept(*args):
        if seen is not None:
            seen["args"] = args
        return recover(*args)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(output, "root_stress", kept)
        return simulate_sector(PAIR, _settings().with_(bodies=bodies))


@pytest.fixture(scope="module")
def runs():
    seen: dict = {}
    return {"modal": _run("modal", seen), "modal_recovered": seen["args"]}


def test_a_runs_root_stress_is_its_samples_one_at_a_time(runs, monkeypatch):
    """The run's root stress, its samples' rows and stresses formed a few pairs at a time
    (a budget of 8 pairs here: 50-odd runs of samples), against the reference state by state
    and its peaks: the stresses to round-off, their radii the same."""
    model, record, n_kept, offset = runs["modal_recovered"]
    steps = stress_steps(model.per_cycle, record.gap.size - 1)
    steps = steps[steps < n_kept]
    per_pair = teeth.ROWS_BYTES // teeth.pair_budget(model)
    monkeypatch.setattr(teeth, "ROWS_BYTES", 8 * per_pair)
    got = teeth.root_stress(model, record, n_kept, offset)
    assert len(sample_runs(model.near_many(record.states[:steps.size, 0], offset), 8)) > 20
    fillets = [GearFillets(g) for g in model.gears]
    ref = _stress_by_sample(model, fillets, record.states[:steps.size], record.force[steps], offset)
    np.testing.assert_array_equal(got.time, steps * model.h)
    for g, fl in enumerate(fillets):
        want = [v.reshape(steps.size, -1) for v in peaks(ref[g].reshape(-1, fl.radius.size), fl.radius)]
        peak = np.abs(want[0]).max()
        for j in (0, 2):
            for ts in (got, runs["modal"].tooth_stress):
                np.testing.assert_allclose(ts.values[g][j], want[j], rtol=0, atol=1e-12 * peak)
                np.testing.assert_array_equal(ts.values[g][j + 1], want[j + 1])


def test_the_samples_runs_hold_the_budgets_pairs():
    """Consecutive runs covering every sample, each within the pairs' budget (a sample over
    it alone) and MOST_SAMPLES samples."""
    pairs = np.array([3, 3, 3, 0, 5, 9, 1, 0, 0] + [1] * (2 * MOST_SAMPLES))
    runs = sample_runs(pairs, 6)
    assert runs[:5] == [slice(0, 2), slice(2, 4), slice(4, 5), slice(5, 6), slice(6, 14)]
    assert [r.start for r in runs[1:]] == [r.stop for r in runs[:-1]] and runs[-1].stop == pairs.size
    assert all(pairs[r].sum() <= 6 or r.stop - r.start == 1 for r in runs)
    big = sample_runs(pairs, 10**9)
    assert [r.stop - r.start for r in big] == [MOST_SAMPLES, MOST_SAMPLES, pairs.size - 2 * MOST_SAMPLES]
    assert sample_runs(pairs[:0], 6) == []


@pytest.mark.slow
def test_a_run_on_modal_bodies_has_the_whole_ones_root_stress(runs):
    """The same run on the two bodies, sampled at the same times: every tooth's peak over
    the run within 0.5 % of the largest (the runs' peak forces differ by as much:
    test_sector_dynamics), every sample within 2 % (a tooth's stress as its pair comes into
    contact rides on the bodies' ringing, which the modal body follows only so far)."""
    a, b = runs["modal"].tooth_stress, _run("full").tooth_stress
    np.testing.assert_array_equal(a.time, b.time)
    assert a.per_cycle == min(STRESS_SAMPLES, runs["modal"].info["steps_per_cycle"])
    for g in range(2):
        np.testing.assert_array_equal(a.teeth[g], b.teeth[g])
        hi = np.abs(b.values[g][0]).max()
        assert hi > 1e7
        for j in (0, 2):
            np.testing.assert_allclose(np.abs(a.values[g][j]).max(axis=0), np.abs(b.values[g][j]).max(axis=0),
                                       rtol=0, atol=5e-3 * hi)
            np.testing.assert_allclose(a.values[g][j], b.values[g][j], rtol=0, atol=2e-2 * hi)


def test_the_pairs_pressure_is_hertz_for_their_force(runs):
    """Every pair's pressure and half-width against Hertz's line contact written out here:
    ``b = sqrt(4 F R* / (pi E* L))``, ``p = 2 F / (pi b L)`` with the involutes' curvature
    radii at the pair's contact radii; NaN where a pair carries nothing."""
    res = runs["modal"]
    dp = PAIR
    f, roll = res.pair_force, res.pair_roll
    p, b = res.pair_contact_pressure, res.pair_contact_half_width
    on = f > 0
    assert on.sum() > 100
    assert np.isnan(p[~on]).all() and np.isnan(b[~on]).all()
    rho_a = dp.gear_a.base_radius * roll[on]
    rho_b = dp.gear_b.base_radius * np.asarray(dp.roll_b_from_roll_a(roll[on]))
    mat_a, mat_b = dp.gear_a.material, dp.gear_b.material
    e_star = 1.0 / ((1 - mat_a.poisson**2) / mat_a.young + (1 - mat_b.poisson**2) / mat_b.young)
    width = min(dp.gear_a.face_width, dp.gear_b.face_width)
    inside = (roll[on] >= dp.start_roll_a) & (roll[on] <= dp.end_roll_a)
    r_star = rho_a * rho_b / (rho_a + rho_b)
    half = np.sqrt(4 * f[on] * r_star / (math.pi * e_star * width))
    np.testing.assert_allclose(b[on][inside], half[inside], rtol=1e-6)
    np.testing.assert_allclose(p[on][inside], (2 * f[on] / (math.pi * half * width))[inside], rtol=1e-6)
    np.testing.assert_allclose(res.contact_pressure_max, np.nanmax(np.where(on, p, -1.0), axis=1))


def test_result_nc_and_summary_hold_every_tooths_stress(runs, tmp_path):
    """result.nc: every tooth's stress by (stress_time, tooth), the pairs' pressure; the
    summary: the peaks with their tooth and time, and the safety factors of materials with
    allowables."""
    from dataclasses import replace

    from spurdyn.case import case_from_pair
    from spurdyn.results.io import load_run, write_run

    res = runs["modal"]
    mat = replace(PAIR.gear_a.material, sigma_flim=430e6, sigma_hlim=1500e6)
    pair = replace(PAIR, gear_a=replace(PAIR.gear_a, material=mat), gear_b=replace(PAIR.gear_b, material=mat))
    from spurdyn.case.pair_tables import MeshedPair

    case = case_from_pair(MeshedPair(pair, **MESH), {"speed_a_rpm": 4000.0, "torque": 22.25}, "t",
                          check_step=False)
    summary = write_run(res, case, tmp_path, png=False)
    ds = load_run(tmp_path)
    ts = res.tooth_stress
    for g, gear in enumerate("ab"):
        np.testing.assert_array_equal(ds[f"tooth_{gear}"].values, ts.teeth[g])
        assert ds[f"root_stress_{gear}"].dims == ("stress_time", f"tooth_{gear}")
        np.testing.assert_array_equal(ds[f"root_stress_compressive_position_{gear}"].values, ts.values[g][3])
        v = ts.values[g][0]
        s, k = np.unravel_index(np.nanargmax(v), v.shape)
        assert summary["root_stress_max_Pa"][g] == v[s, k]
        assert summary["root_stress_max_position_m"][g] == ts.values[g][1][s, k]
        assert summary["root_stress_max_tooth"][g] == ts.teeth[g][k]
        assert summary["root_stress_max_time_s"][g] == pytest.approx(ts.time[s])
        assert summary["root_stress_compressive_min_Pa"][g] == np.nanmin(ts.values[g][2])
    np.testing.assert_array_equal(ds["stress_time"].values, ts.time)
    assert ds["pair_contact_pressure"].dims == ("time", "pair")
    assert summary["contact_pressure_max_Pa"] == pytest.approx(np.nanmax(res.pair_contact_pressure))
    assert summary["contact_half_width_max_m"] > 0
    # a complete run of one cycle: its last cycle is the dynamic factor's window, the whole run
    assert "over the last 1 mesh cycle(s)" in summary["root_stress_note"]
    assert summary["safety_root_model"] == pytest.approx([860e6 / x for x in summary["root_stress_max_Pa"]])
    assert summary["safety_contact_model"][0] == pytest.approx(1500e6 / summary["contact_pressure_max_Pa"])
    json.dumps(summary)
