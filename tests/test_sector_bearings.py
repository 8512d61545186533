"""The sector model's hubs on radial bearings (docs/sector.md, 6.12): the case's tables and
their refusals, the NumPy step against the compiled one, the static deflection, the
energy and momentum balances with the translations, and the stiff bearing's limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.case.file import case_from_dict, case_to_dict
from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.model import SectorModel
from spurdyn.settings import RPM, Bearing
from spurdyn.simulators import MODELS
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.layout import OK, SectorOut, SectorStepState
from spurdyn.solvers.sector.implicit_numpy import implicit_step
from spurdyn.solvers.sector.stepper import SectorRecord, make_stepper

PAIR = paper_pair()
MESH = {"nx": 2, "ny": 8}
#: Two bearings of different stiffness (the paper's gears are alike: this tells them apart).
BEARINGS = (Bearing(1e8, 1e3), Bearing(5e7, 0.0))
CASE = {"gear_a": {"teeth": 28, "module": 0.003175, "face_width": 0.00635,
                   "bearing": {"stiffness": 1e8, "damping": 1e3}},
        "run": {"torque": 22.25, "speed_a_rpm": 4000, "cycles": 3}, "model": {"kind": "sector"}}


def _model(speed_rpm: float = 4000.0, bearings=BEARINGS, per_cycle: int | None = None, **kw) -> SectorModel:
    """Modal bodies of whole gears (3 cycles), the mesh damper on unless ``kw`` says, the
    default step or ``per_cycle`` steps a mesh cycle."""
    kw = {"damping_ratio": 0.05, **kw}
    s = run_settings(PAIR, speed_rpm * RPM, 22.25, dt=1e-6, cycles=3, max_cycles=3, bearings=bearings, **MESH, **kw)
    dt = None if per_cycle is None else 2 * math.pi / PAIR.gear_a.teeth / s.speed_a / per_cycle
    return SectorModel.build(PAIR, s, dt=dt)


def test_a_case_gives_its_bearings_and_a_bad_one_is_refused_by_its_key():
    case = case_from_dict(CASE, check_step=False)
    assert case.run.bearings == (Bearing(1e8, 1e3), Bearing(1e8, 1e3))      # gear B's table is A's
    back = case_from_dict(case_to_dict(case), check_step=False)
    assert back.run.bearings == case.run.bearings
    for table, key in (({"stiffness": -1.0}, "gear_a.bearing.stiffness"), ({"damping": 1.0}, "gear_a.bearing.stiffness"),
                       ({"stiffness": 1e8, "damping": -2.0}, "gear_a.bearing.damping"),
                       ({"stiffness": 1e8, "mass": 1.0}, "gear_a.bearing.mass"), (3.0, "gear_a.bearing")):
        bad = {**CASE, "gear_a": {**CASE["gear_a"], "bearing": table}}
        with pytest.raises(InputError) as err:
            case_from_dict(bad, check_step=False)
        assert err.value.field == key
    with pytest.raises(InputError) as err:
        MODELS["lumped"].refuse(case.run, {})
    assert err.value.field == "gear_a.bearing"


def test_a_continuation_sweep_with_bearings_is_refused_before_it_starts(tmp_path, capsys):
    """A continuation carries the gears' modal state, not the hubs' translations: refused
    up front, naming the option, not at its second speed under a key the user never gave."""
    from spurdyn.cli.main import main

    case = tmp_path / "bearing.toml"
    case.write_text("[gear_a]\nteeth = 28\nmodule = 0.003175\nface_width = 0.00635\n"
                    "[gear_a.bearing]\nstiffness = 1e8\ndamping = 1e3\n"
                    "[run]\ntorque = 22.25\nspeed_a_rpm = 4000\n[model]\nkind = \"sector\"\n"
                    "[mesh]\nnx = 2\nny = 8\n")
    out = tmp_path / "sw"
    code = main(["sweep", str(case), "--cycles", "4", "--rpm", "4000,5000", "--continuation", "up",
                 "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith("spurdyn: error: --continuation:") and "bearing" in err
    assert not out.exists()


def test_the_numpy_step_with_bearings_is_the_compiled_steps_twin():
    """Step by step from the same state, with the translations, the mesh damper on them and
    the two bearings unlike: the same state and forces to round-off; the RK4 reference
    refuses bearings by their key."""
    from spurdyn.sector.bearings import bearing_pack
    from spurdyn.sector.faces import face_pack
    from spurdyn.solvers.sector.step_compiled import run_steps

    model = _model()
    start = model.start()
    st = SectorStepState(start.q, start.v, start.acc, start.qdd, start.force)
    packs = model.packs(start.offset)
    n = 120
    tq = model.torques_at(np.arange(n))
    out = SectorOut(np.zeros((n, 2)), np.zeros((n, 2)), np.zeros((n, model.c_teeth.size)), np.zeros(n),
                    hubs=np.zeros((n, 8)))
    for step in range(1, n):
        ref = implicit_step(model, st, tq[step], start.offset)
        assert ref.status == OK
        twin = SectorStepState(*(x.copy() for x in st))
        assert run_steps(step - 1, 1, twin, *packs, tq, out, face_pack(None, model.gears),
                         bearing_pack(model.bear)) == (step, OK)
        for a, b in zip(twin, ref.state):
            if b.size:
                np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-12 * np.abs(b).max())
        np.testing.assert_array_equal(out.hubs[step], np.concatenate([twin.q[model.tpart], twin.v[model.tpart]]))
        st = ref.state
    # the hubs moved about their static deflection (some 2 to 10 um)
    assert (np.ptp(out.hubs[1:, :4], axis=0) > 1e-3 * np.abs(out.hubs[1, :4])).all()
    record = SectorRecord(model, 10)
    with pytest.raises(InputError) as err:
        make_stepper(model, record, "rk4", "numpy")
    assert err.value.field == "gear_a.bearing"


def test_the_hubs_static_deflection_is_the_mesh_force_over_the_stiffness():
    """At 10 rpm from rest, the torques ramped up over a mesh cycle of 200 steps (each far
    longer than the pair's and the bearings' periods, which rho_inf = 0.8 damps), each hub
    comes to ``F n / k`` along the drive line of action in its gear's frame, ``n = (sin
    alpha_w, cos alpha_w)``, ``F`` the pairs' total force, and stays there step by step as the
    load moves between one and two pairs (opposite in the common frame, the frames being each
    other's mirror image): to 1e-3 of the deflection, the hubs' inertia ``m x_ddot`` under the
    forces' step-to-step ripple being 4e-4 of it."""
    model = _model(10.0, per_cycle=200, start="rest")
    record = SectorRecord(model, 300)
    assert make_stepper(model, record, "implicit", "numpy").steps(300) == ""
    assert (record.hubs[0] == 0.0).all()
    f = record.force.sum(axis=1)[220:]
    alpha = PAIR.working_pressure_angle
    n = np.array([math.sin(alpha), math.cos(alpha)])
    for g, b in enumerate(BEARINGS):
        expect = f[:, None] * n[None, :] / b.stiffness
        np.testing.assert_allclose(record.hubs[220:, 2 * g:2 * g + 2], expect, rtol=0,
                                   atol=1e-3 * np.abs(expect).max())
    assert f.min() > 0.99 * model.load


def _balance_run(bearings):
    """Half a mesh cycle through an exit at 1,000 rpm, rho_inf = 1, nothing damped: the
    model, its record and the energy's largest drift (J)."""
    model = _model(1000.0, bearings=bearings, damping_ratio=0.0, rho_inf=1.0, rayleigh_mass=0.0,
                   rayleigh_stiffness=0.0)
    n = model.per_cycle // 2
    record = SectorRecord(model, n, energy=True)
    assert make_stepper(model, record, "implicit", "numpy", energy=True).steps(n) == ""
    e = record.energy
    total = e[:, 0] + e[:, 1] + e[:, 2] - e[:, 3]
    return model, record, float(np.abs(total - total[0]).max())


@pytest.mark.slow
def test_the_balances_hold_with_the_hubs_on_bearings():
    """The energy with the translations' kinetic energy and the bearings' springs drifts as
    the held hubs' does over the same steps (the model's left-out terms, 4.8 % of the bodies'
    largest strain energy on both through this exit): within 2 % of the held run's drift,
    where a leak of a hundredth of the springs' energy would show; and each gear's
    translation momentum ``m x_dot`` changes by the trapezoidal impulse of the contacts'
    forces less the bearing's, to round-off."""
    model, record, drift = _balance_run((Bearing(1e8, 0.0), Bearing(5e7, 0.0)))
    _, _, held = _balance_run(None)
    bear = model.bear
    x, v = record.hubs[:, :4], record.hubs[:, 4:]
    springs = (0.5 * bear.k * x**2).sum(axis=1)
    assert springs.max() > 50.0 * drift      # the springs hold energy, much beyond the drift
    assert abs(drift - held) < 0.02 * held
    force = record.force @ bear.rows[model.c_side] - bear.k * x
    impulse = np.concatenate([np.zeros((1, 4)), np.cumsum(0.5 * model.h * (force[1:] + force[:-1]), axis=0)])
    p = bear.mass * v
    assert (np.abs(p - p[0]).max(axis=0) > 1e-6).all()
    np.testing.assert_allclose(p - p[0], impulse, rtol=0, atol=1e-9 * np.abs(impulse).max())


def test_a_gears_translating_mass_is_its_sections():
    """The gear's mass (the meshed body's, its held hub circle's and the blank's inside it)
    is the density times the face width times the gear's section: the root circle's disk and
    the teeth above it (``int 2 chi(r) r dr`` over each, the outline's polar half-angle),
    within the mesh's outline."""
    from spurdyn.sector.bearings import gear_mass

    model = _model()
    g = PAIR.gear_a
    nodes, weights = np.polynomial.legendre.leggauss(16)
    tooth = 0.0
    for lo, hi in ((g.root_radius, g.form_radius), (g.form_radius, g.tip_radius)):
        r = lo + (hi - lo) * (nodes + 1.0) / 2.0
        chi = np.array([math.atan2(*g.right_side_point(float(ri))) for ri in r])
        tooth += (hi - lo) / 2.0 * float(np.sum(weights * 2.0 * chi * r))
    section = math.pi * g.root_radius**2 + g.teeth * tooth
    expected = g.material.density * g.face_width * section
    assert gear_mass(model.blocks[0]) == pytest.approx(expected, rel=5e-3)


def test_a_stiff_bearing_tends_to_the_held_hub():
    """The pairs' forces over 200 compiled steps at 4,000 rpm: a bearing of 1e12 N/m (its
    mode at 290 kHz) moves them by less than 1e-3 of the largest from the held hubs', one of
    1e8 N/m (2.9 kHz) by more than 1e-2."""
    def forces(bearings):
        model = _model(bearings=bearings)
        record = SectorRecord(model, 200)
        assert make_stepper(model, record, "implicit", "numba").steps(200) == ""
        return record.force.sum(axis=1)

    held = forces(None)
    top = held.max()
    assert np.abs(forces((Bearing(1e12), Bearing(1e12))) - held).max() < 1e-3 * top
    assert np.abs(forces((Bearing(1e8), Bearing(1e8))) - held).max() > 1e-2 * top


def test_the_result_carries_each_hubs_translation_and_its_bearings_force():
    """``result.nc``'s sensors with gear A on a bearing and gear B's centre held: A's bearing
    force is ``k x + c x_dot`` of its recorded translation, B's the contacts' force, the
    followed gear's (the driver's) in ``bearing_force_transverse``, each saying which."""
    from spurdyn.results.vibration import result_sensors
    from spurdyn.solvers.sector.run import simulate_sector

    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=1, max_cycles=1, teeth=28,
                     bearings=(Bearing(1e8, 1e3), None), **MESH)
    run = simulate_sector(PAIR, s)
    assert run.info["bearings"][1] is None and run.info["bearings"][0]["mass_kg"] > 0.0
    hubs = run.hub_translation
    assert (hubs[:, 2:4] == 0.0).all() and (hubs[:, 6:] == 0.0).all()     # B's centre held
    out = result_sensors(run, PAIR.working_pressure_angle)
    np.testing.assert_array_equal(out["bearing_force_transverse_a"].values, 1e8 * hubs[:, 1] + 1e3 * hubs[:, 5])
    np.testing.assert_array_equal(out["hub_displacement_separating_a"].values, hubs[:, 0])
    assert out["bearing_force_transverse_b"].attrs["source"].startswith("the contacts' force")
    np.testing.assert_array_equal(out["bearing_force_transverse"].values, out["bearing_force_transverse_a"].values)
    assert "gear A's bearing" in out["bearing_force_transverse"].attrs["source"]
    # over the cycle A's bearing carries the contacts' mean force but for its hub's own ring,
    # 0.09 of critical, which a cycle does not damp out
    last = slice(-run.info["steps_per_cycle"], None)
    rigid = out["bearing_force_transverse_b"].values[last].mean()
    assert out["bearing_force_transverse_a"].values[last].mean() == pytest.approx(rigid, rel=1e-2)
