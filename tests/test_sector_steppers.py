"""The sector model's steppers and compiled pieces (issue 33): one model built once, the
steppers of the registry on the base's contract, the NumPy implicit step against the
compiled one step by step, and each shared compiled kernel against its NumPy twin."""

from __future__ import annotations

import numpy as np
import pytest

from spurdyn.contact.hertz import half_width, involute_curvature_radius
from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.damper import damper_at
from spurdyn.sector.lcp import lcp
from spurdyn.sector.model import SectorModel
from spurdyn.settings import RPM
from spurdyn.solvers.base import Failure
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_LCP, OK, SectorOut, SectorStepState
from spurdyn.solvers.sector.implicit_numpy import implicit_step
from spurdyn.solvers.sector.stepper import STEPPERS, SectorRecord, make_stepper

PAIR = paper_pair()
MESH = {"nx": 2, "ny": 8}


@pytest.fixture(scope="module")
def model() -> SectorModel:
    """Modal bodies of whole gears (3 cycles), the mesh damper on."""
    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=3, max_cycles=3, damping_ratio=0.05, **MESH)
    return SectorModel.build(PAIR, s)


def test_the_numpy_implicit_step_is_the_compiled_steps_twin(model: SectorModel) -> None:
    """Step by step from the same state, ``implicit_step`` and ``run_steps`` give the same
    state and forces to round-off (each step restarts both from the NumPy state)."""
    from spurdyn.sector.bearings import bearing_pack
    from spurdyn.sector.faces import face_pack
    from spurdyn.solvers.sector.step_compiled import run_steps

    start = model.start()
    st = SectorStepState(start.q, start.v, start.acc, start.qdd, start.force)
    packs = model.packs(start.offset)
    tq = model.torques_at(np.arange(60))
    out = SectorOut(np.zeros((60, 2)), np.zeros((60, 2)), np.zeros((60, model.c_teeth.size)), np.zeros(60))
    touched = 0
    for step in range(1, 60):
        ref = implicit_step(model, st, tq[step], start.offset)
        assert ref.status == OK
        twin = SectorStepState(*(x.copy() for x in st))
        done, status = run_steps(step - 1, 1, twin, *packs, tq, out, face_pack(None, model.gears),
                                 bearing_pack(model.bear))
        assert (done, status) == (step, OK)
        for a, b in zip(twin, ref.state):
            assert a.shape == b.shape
            if not b.size:      # no crack: no face forces
                continue
            np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-12 * (np.abs(b).max() + 1e-300))
        touched = max(touched, int((ref.state.force > 0).sum()))
        st = ref.state
    assert touched >= 2


def test_the_shared_kernels_are_their_numpy_twins(model: SectorModel) -> None:
    """The compiled gap table, mesh damper, Hertz half-width and contact rows (with the
    residual compliance) against the NumPy ones."""
    from spurdyn.contact.strip_compiled import hertz_half_width, involute_curvature
    from spurdyn.solvers.sector.rows_compiled import contact_rows, damper_coefficient, table_at

    gear0, gear1, con, table, cfg = model.packs()
    for x in np.linspace(model.table.rho[1], model.table.rho[-2], 7):
        np.testing.assert_allclose(table_at(table, x), [float(v[0]) for v in model.table.at(np.array([x]))],
                                   rtol=1e-13, atol=1e-18)
    for theta in (0.0, 0.013, 0.11, 0.4):
        assert damper_coefficient(model.c_table, model.pitch, theta) == damper_at(model.c_table, model.pitch, theta)
    for f, r_a, r_b in ((100.0, 0.045, 0.046), (0.0, 0.045, 0.046), (-3.0, 0.042, 0.047)):
        rho_a, rho_b = involute_curvature_radius(r_a, 0.0418), involute_curvature_radius(r_b, 0.0418)
        assert involute_curvature(r_a, 0.0418) == rho_a
        assert hertz_half_width(f, rho_a, rho_b, 1.1e11, 0.006) == pytest.approx(
            half_width(f, rho_a, rho_b, 1.1e11, 0.006), rel=1e-15, abs=0.0)
    start = model.start()
    rows = model.rows_at(0.02, start.force)
    on, const, coef0, coef1, rows0, rows1, res = contact_rows(0.02, start.force, gear0, gear1, con, table, cfg)
    np.testing.assert_array_equal(on, rows.on)
    np.testing.assert_allclose(const, rows.const, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(coef0, rows.sides[0][0], rtol=1e-12)
    np.testing.assert_allclose(rows0, rows.sides[0][1].modal, rtol=1e-10, atol=1e-12 * np.abs(rows0).max())
    np.testing.assert_allclose(rows1, rows.sides[1][1].modal, rtol=1e-10, atol=1e-12 * np.abs(rows1).max())
    np.testing.assert_allclose(res, model.compliance(rows)[3], rtol=1e-8, atol=1e-12 * np.abs(res).max())


def test_the_lcp_reports_no_solution_as_a_status() -> None:
    """Both twins say when the active sets give no solution, rather than raise."""
    from spurdyn.solvers.sector.rows_compiled import lcp_ordered, mask_orders

    w = np.array([[-1.0]])      # not positive definite: no complementary point
    v = np.array([-1.0])
    assert not lcp(w, v)[1]
    assert not lcp_ordered(w, v, 0, mask_orders())[1]
    f, found = lcp(np.eye(2), np.array([-1.0, 2.0]))
    assert found and np.array_equal(f, [1.0, 0.0])


def test_the_registry_refuses_what_a_stepper_does_not_step(model: SectorModel) -> None:
    """An unknown integrator or backend, the compiled loops on whole bodies, the energy
    record on a compiled loop: each refused in one line, never run on another stepper."""
    assert set(STEPPERS) == {("implicit", "numpy"), ("implicit", "numba"), ("rk4", "numpy"), ("rk4", "numba")}
    record = SectorRecord(model, 10)
    with pytest.raises(InputError, match="no newmark integrator"):
        make_stepper(model, record, "newmark", "numpy")
    with pytest.raises(InputError, match="energy"):
        make_stepper(model, record, "implicit", "numba", energy=True)
    s = run_settings(PAIR, 4000 * RPM, 22.25, dt=1e-6, cycles=1, max_cycles=1, **MESH)
    full = SectorModel.build(PAIR, s, modes=False)
    with pytest.raises(InputError, match="modal bodies of whole"):
        make_stepper(full, SectorRecord(full, 10), "implicit", "numba")


def test_a_stepper_reports_its_failures_through_the_base(model: SectorModel) -> None:
    """The sector's failure codes have one message each, built by the base's Failure."""
    assert "contact problem" in Failure(FAIL_LCP, 7).message()
    assert Failure(FAIL_BEYOND, 7, detail="the driver had turned").message() == "at step 7 the driver had turned"
    stepper = make_stepper(model, SectorRecord(model, 20), "implicit", "numpy")
    assert stepper.steps(5) == "" and stepper.index == 5 and stepper.reached == 5
    assert np.isfinite(stepper.record.theta[:6]).all() and np.isnan(stepper.record.theta[6:]).all()
