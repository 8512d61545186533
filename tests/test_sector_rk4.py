"""The sector model's RK4 reference on modal bodies (spurdyn.solvers.sector.rk4; issue 16,
docs/sector_rk4_validation.md): it refuses what it does not step, it is the implicit loop's
model (at a tenth of the implicit default step the two agree over a loaded mesh cycle), it is
stable at its step, and its compiled loop is the NumPy loop's twin."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.rules import steps_per_cycle
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.sector.rk4 import highest_frequency, simulate_sector_rk4
from spurdyn.solvers.sector.run import simulate_sector

PAIR = paper_pair()
MESH = dict(nx=2, ny=8)
SPEED = 20000 * RPM
#: The reference's step in the short checks (s): stable on 2 x 8 (omega_max h = 0.8, below
#: RK4's 2.8), a mesh cycle in 1,072 steps.
RK4_STEP = 1e-7

#: Steps of the implicit loop and of the reference over the loaded cycle: a tenth of the
#: implicit default step (200 a cycle at 20,000 rpm), and RK4 at the same instants (5.4e-8 s),
#: so that the two are compared sample for sample (a pair's entry rises by 600 N/us: a
#: straight line between another run's samples would be off by several newtons).
PER_CYCLE = 2000


@pytest.mark.parametrize("change", [dict(bodies="full"), dict(back_flanks=True), dict(row_grading=4.0)])
def test_the_reference_refuses_what_it_does_not_step(change):
    s = run_settings(PAIR, SPEED, 22.25, model="sector", cycles=1, **MESH, **change)
    with pytest.raises(InputError):
        simulate_sector_rk4(PAIR, s)


@pytest.fixture(scope="module")
def runs():
    """One loaded mesh cycle at 20,000 rpm from the static start, mesh damper 0.05 and the
    bodies' default damping: RK4 at 1e-7 s, and the implicit loop at a tenth of its default
    step (0.03 us)."""
    s = run_settings(PAIR, SPEED, 22.25, model="sector", cycles=1, damping_ratio=0.05, backend="numpy", **MESH)
    period = 2 * math.pi / PAIR.gear_a.teeth / SPEED
    assert steps_per_cycle(SPEED, PAIR.gear_a.teeth) * 10 == PER_CYCLE
    return s, simulate_sector(PAIR, s, dt=period / PER_CYCLE), simulate_sector_rk4(PAIR, s, dt=period / PER_CYCLE)


@pytest.mark.slow
def test_rk4_and_the_implicit_loop_at_a_small_step_agree(runs):
    """Sample for sample, pair by pair, the forces through the cycle (an exit and an entry,
    the tip corners' early and late contact) within 0.3 % of the largest, the transmission
    error within 0.2 % of its largest, the hubs' speeds within 1e-5; the contacts made and
    broken at the same samples (within one)."""
    _, imp, rk = runs
    assert imp.status == rk.status == "complete"
    assert rk.info["integrator"] == "rk4" and rk.steps == imp.steps == PER_CYCLE
    np.testing.assert_allclose(rk.time, imp.time, rtol=1e-12)
    fi, fr = np.nan_to_num(imp.pair_force), np.nan_to_num(rk.pair_force)
    top = fi.max()
    assert np.abs(fr - fi).max() < 3e-3 * top          # measured 1.3e-3 (0.59 N of 456)
    on_i, on_r = fi > 0, fr > 0
    changes = 0
    for j in range(fi.shape[1]):
        ti = imp.time[1:][on_i[1:, j] != on_i[:-1, j]]
        tr = rk.time[1:][on_r[1:, j] != on_r[:-1, j]]
        assert ti.size == tr.size
        if ti.size:
            changes += ti.size
            assert np.abs(ti - tr).max() <= 1.01 * (rk.time[1] - rk.time[0])     # measured: same sample
    assert changes >= 2
    te = rk.transmission_error
    # measured 5e-4 of the largest (2.7e-9 m of 5.2e-6 m)
    assert np.abs(te - imp.transmission_error).max() < 2e-3 * np.abs(imp.transmission_error).max()
    # the hubs turn alike
    np.testing.assert_allclose(rk.omega, imp.omega, rtol=1e-5)      # measured 2.7e-6


@pytest.mark.slow
def test_the_reference_is_stable_at_the_papers_step():
    """The stiffest mode of the constrained modal system (the pairs in contact held by their
    compliance) at the paper's step is far inside RK4's stability bound, and RK4's
    amplification over the damped system's eigenvalues is at most 1."""
    s = run_settings(PAIR, SPEED, 22.25, model="sector", cycles=1, damping_ratio=0.05, **MESH)
    top = highest_frequency(PAIR, s)
    assert top["pairs_in_contact"] == 2
    assert top["omega_dt"] < 0.5
    assert highest_frequency(PAIR, s, dt=RK4_STEP)["rk4_amplification_max"] <= 1.0 + 1e-8


@pytest.mark.slow
def test_the_compiled_reference_is_the_numpy_ones_twin():
    """On whole gears (3 cycles) the compiled loop's first 300 steps, across its chunks, are
    the NumPy loop's to round-off."""
    s = run_settings(PAIR, SPEED, 22.25, model="sector", cycles=3, damping_ratio=0.05, **MESH)
    fast = simulate_sector_rk4(PAIR, s, dt=RK4_STEP, steps=300, backend="numba")
    ref = simulate_sector_rk4(PAIR, s, dt=RK4_STEP, steps=300, backend="numpy")
    fa, fr = np.nan_to_num(fast.pair_force), np.nan_to_num(ref.pair_force)
    assert fast.steps == ref.steps == 300
    np.testing.assert_allclose(fa, fr, rtol=0, atol=1e-9 * fr.max())
    np.testing.assert_allclose(fast.transmission_error, ref.transmission_error, rtol=0,
                               atol=1e-9 * np.abs(ref.transmission_error).max())
    np.testing.assert_allclose(fast.omega, ref.omega, rtol=1e-12)
