"""A crack's faces as a unilateral contact in the sector model's dynamic runs (docs/faults.md,
"The crack's faces in motion"): the faces' rows against the static solve, the pivoting
solver against the enumeration, the compiled step against the NumPy one, the faces never
passing through each other, and the RK4 reference's refusal."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.faces import closed_start
from spurdyn.sector.lcp import lcp, lcp_pivot
from spurdyn.sector.model import SectorModel
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.crack_faces import face_openings
from spurdyn.solvers.sector.stepper import SectorRecord, make_stepper

PAIR = paper_pair()
SMALL = GearPair(gear_a=replace(PAIR.gear_a, teeth=18), gear_b=replace(PAIR.gear_b, teeth=18), driver="a")
#: the 18-tooth pair's crack needs 2 x 6 (at 2 x 4 its mouth's edge reaches the contacts)
CRACK_MESH = dict(nx=2, ny=6)
#: tooth 1 enters the mesh a cycle after the start: the tooth ahead loads the rim under it and
#: closes its faces, then its own load opens them
CRACK = Fault("a", 1, "crack", depth=1e-3)


@pytest.fixture(scope="module")
def model():
    s = run_settings(SMALL, 8000 * RPM, 22.25, model="sector", cycles=1, faults=(CRACK,), **CRACK_MESH)
    return SectorModel.build(SMALL, s)


def test_the_faces_openings_at_a_static_state_are_the_static_solves(model):
    """At the modal coordinates of a static state (``eta = Omega^-2 Phi^T f``) the faces'
    rows and their residual coupling with the pairs sum to ``B^T K^-1 f``."""
    force = np.zeros(model.c_teeth.size)
    rows = model.rows_at(-0.7 * model.pitch, force)
    modal = rows.sides[0][1]
    assert 1 in modal.teeth + model.blocks[0].first or -1 in modal.teeth + model.blocks[0].first
    f = np.linspace(200.0, 400.0, rows.on.size)
    q = np.zeros(model.n)
    q[1:model.na] = (f @ modal.modal) / model.gears[0].reduced.omega2
    r_fc = model.faces.blocks(rows, model.z_theta)[2]
    got = model.faces.rows(model.parts, q) + r_fc @ f
    blk = model.blocks[0]
    load = np.zeros(blk.mass.size)
    for fc, at, side, ld in zip(f, modal.teeth, modal.sides, modal.loads):
        k = blk.first + int(at)
        load[blk.flank_dofs(k, int(side))] += fc * (ld.reshape(-1, 2) @ blk.turn_of(k, int(side)).T).ravel()
    body = blk.body
    want = body.seam_loads[body.free_dofs].T @ body.solve_free(load)
    assert np.abs(want).max() > 0.0
    assert np.abs(got - want).max() <= 1e-9 * np.abs(want).max()


def test_the_faces_couplings_are_their_matrices(model):
    """The faces' couplings with the pairs by the flanks' tables are the products written
    out: ``W_fc = (B^T Phi) (S^-1 G^T)`` on the modes, ``W_fd`` its hub part alone."""
    rows = model.rows_at(-0.7 * model.pitch, np.zeros(model.c_teeth.size))
    w_fc, w_fd, _ = model.faces.blocks(rows, model.z_theta)
    cols = model.compliance(rows)[4]
    gf = model.faces.gears[0]
    want = gf.modal @ cols[0][1:]
    assert np.abs(w_fc - want).max() <= 1e-9 * np.abs(want).max()
    coef = rows.sides[0][0]
    assert np.abs(w_fd - np.outer(gf.modal @ model.z_theta[0][1:], coef)).max() == 0.0


def test_the_faces_static_compliance_is_the_bodys():
    """``R_ff`` plus the modes' part is ``B^T K^-1 B``, positive definite."""
    s = run_settings(SMALL, 8000 * RPM, 22.25, model="sector", cycles=1, faults=(CRACK,), **CRACK_MESH)
    m = SectorModel.build(SMALL, s)
    gf = m.faces.gears[0]
    body = m.blocks[0].body
    b = body.seam_loads[body.free_dofs]
    want = b.T @ body.solve_free(b)
    got = gf.residual + gf.scaled @ gf.modal.T
    assert np.abs(got - want).max() <= 1e-9 * np.abs(want).max()
    assert np.linalg.eigvalsh(m.faces.r_ff + m.bp * m.faces.w_ff).min() > 0.0
    assert m.faces.gears[1] is None


@pytest.mark.parametrize("seed", range(6))
def test_the_pivoting_solver_finds_the_enumerations_solution(seed):
    """On random positive definite problems of six unknowns (the enumeration's reach) the
    block pivoting solver, NumPy and compiled, from any guess, finds the one solution."""
    from spurdyn.solvers.sector.rows_compiled import lcp_pivot as compiled

    rng = np.random.default_rng(seed)
    a = rng.normal(size=(6, 6))
    w = a @ a.T + 0.1 * np.eye(6)
    v = rng.normal(size=6)
    want, found = lcp(w, v)
    assert found and 0 < np.count_nonzero(want) < 6
    for guess in (np.zeros(6, bool), np.ones(6, bool), rng.random(6) < 0.5):
        for solve in (lcp_pivot, compiled):
            got, ok = solve(w, v, guess)
            assert ok
            assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()


def test_a_static_start_closes_the_faces_where_they_overlap(model):
    start = model.start()
    rows0 = model.rows_at(0.0, start.force)
    r_fc = model.faces.blocks(rows0, model.z_theta)[2]
    before = model.faces.rows(model.parts, start.q) + r_fc @ start.force[rows0.on]
    assert before.min() < -1e-9                 # the free faces overlap at the start
    q = start.q.copy()
    lam = closed_start(model.faces, model.parts, q, r_fc, start.force[rows0.on])
    opening = model.faces.rows(model.parts, q) + r_fc @ start.force[rows0.on] + model.faces.r_ff @ lam
    scale = np.abs(before).max()
    assert opening.min() >= -1e-12 * scale and lam.min() >= 0.0 and lam.max() > 0.0
    assert np.abs(lam * opening).max() <= 1e-12 * scale * lam.max()


def test_the_compiled_steps_with_the_faces_are_the_numpy_ones(model):
    """Two mesh cycles of the cracked tooth's approach and entry: the compiled loop's pair
    and face forces are the NumPy loop's to 1e-9 of their peaks, the faces carry a force and
    never pass through each other (their least opening zero to round-off of the largest)."""
    n = 2 * model.per_cycle
    out = []
    for backend in ("numba", "numpy"):
        record = SectorRecord(model, model.per_cycle * model.cycles)
        stepper = make_stepper(model, record, "implicit", backend)
        assert stepper.steps(n) == ""
        out.append((record.force[:n + 1], record.faces[:n + 1]))
    (fast, faces_fast), (slow, faces_slow) = out
    assert np.nanmax(np.abs(fast - slow)) <= 1e-9 * np.nanmax(fast)
    peak = faces_slow[:, 0].max()
    assert peak > 0.0 and 0.0 < (faces_slow[:, 0] > 0.0).mean() < 1.0
    assert np.abs(faces_fast[:, 0] - faces_slow[:, 0]).max() <= 1e-9 * peak
    widest = faces_slow[:, 2].max()
    assert np.abs(faces_fast[:, 1:] - faces_slow[:, 1:]).max() <= 1e-9 * widest
    for faces in (faces_fast, faces_slow):
        assert faces[:, 1].min() >= -1e-12 * faces[:, 2].max()
        assert faces[:, 2].max() > 1e-7         # and they open under the tooth's own load
    # what summary.json's crack_faces says of the same steps
    said = face_openings(model, SimpleNamespace(faces=faces_slow), n + 1)
    assert said["least_opening_m"] == faces_slow[:, 1].min() >= -1e-12 * widest
    assert said["largest_opening_m"] == widest and said["largest_face_force_N"] == peak
    assert said["closed_fraction"] == (faces_slow[:, 0] > 0.0).mean()
    assert said["largest_force_at_s"] == pytest.approx(faces_slow[:, 0].argmax() * model.h, abs=0.0)


def test_a_run_without_a_crack_says_nothing_of_faces():
    record = SimpleNamespace(faces=np.full((5, 3), np.nan))
    assert face_openings(SimpleNamespace(faces=None, h=1e-6), record, 5) is None


def test_the_rk4_reference_refuses_a_crack(model):
    for backend in ("numpy", "numba"):
        with pytest.raises(InputError) as err:
            make_stepper(model, SectorRecord(model, 10), "rk4", backend)
        assert err.value.field == "fault"


def test_the_compiled_steps_with_the_faces_and_bearings_are_the_numpy_ones(model):
    """Half of the cracked gear's first mesh cycle (its faces closed) with the hubs on two
    unlike bearings (docs/sector.md, 6.12): the compiled loop's pair and face forces and the
    hubs' translations are the NumPy loop's to 1e-9 of their largest (7e-12 measured over the
    whole cycle)."""
    from spurdyn.settings import Bearing

    bearings = (Bearing(1e8, 1e3), Bearing(5e7, 0.0))
    m = SectorModel.build(SMALL, model.settings.with_(bearings=bearings))     # the modes cached
    n = m.per_cycle // 2
    out = []
    for backend in ("numba", "numpy"):
        record = SectorRecord(m, m.per_cycle * m.cycles)
        assert make_stepper(m, record, "implicit", backend).steps(n) == ""
        out.append((record.force[:n + 1], record.faces[:n + 1, 0], record.hubs[:n + 1]))
    for fast, slow in zip(*out):
        assert np.abs(fast - slow).max() <= 1e-9 * np.abs(slow).max()
    assert out[1][1].max() > 1.0         # the faces carry their force (N)
