"""The steady lumped pair's compiled right-hand side (lumped/steady_compiled.py) against its
Python twin, both stiffness sources, and a whole run on either backend."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.geometry.presets import paper_pair
from spurdyn.lumped.cycle import SectorCycle, TableCycle
from spurdyn.lumped.model import equivalent_mass
from spurdyn.lumped.steady import _steady_equations, simulate_steady
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings

PAIR = paper_pair()


def _cycles():
    from spurdyn.lumped import mesh_stiffness_table
    from spurdyn.sector.statics import mesh_cycle

    table = TableCycle(PAIR, mesh_stiffness_table(PAIR, 2, 8))
    sector = SectorCycle.from_mesh_cycle(PAIR, mesh_cycle(PAIR, 22.25, 2, 8, positions=21))
    return {"tooth": table, "sector": sector}


@pytest.fixture(scope="module")
def cycles():
    return _cycles()


@pytest.mark.parametrize("source", ["tooth", "sector"])
def test_the_compiled_right_hand_side_is_the_python_ones_twin(cycles, source):
    cycle = cycles[source]
    run = run_settings(PAIR, 6000 * RPM, 22.25, model="lumped", cycles=4, start="static")
    zeta = 2.0 * 0.05 * math.sqrt(equivalent_mass(PAIR))
    compiled = _steady_equations(PAIR, run, cycle, zeta)[0]
    python = _steady_equations(PAIR, run.with_(backend="numpy"), cycle, zeta)[0]
    assert compiled.__name__ == "<lambda>" and python.__name__ == "rhs_python"
    rng = np.random.default_rng(5)
    pitch = 2 * math.pi / PAIR.gear_a.teeth
    loaded = 0
    for _ in range(400):
        # across several pitches, in and out of contact, squeezing and parting
        y = np.array([rng.uniform(-pitch, 5 * pitch), 6000 * RPM, rng.uniform(-2e-6, 2e-5),
                      rng.uniform(-0.05, 0.05)])
        a, b = np.asarray(python(0.0, y)), compiled(0.0, y)
        # equal to round-off: Python 3.12's sum() compensates, 3.11's and the kernel's do not
        np.testing.assert_allclose(b, a, rtol=1e-14, atol=0.0)
        loaded += abs(a[1] - python(0.0, np.array([y[0], y[1], -1.0, 0.0]))[1]) > 0.0
    assert loaded > 100          # the mesh force was on at many of the states


@pytest.mark.parametrize("source", ["tooth", "sector"])
def test_a_steady_run_is_the_same_on_either_backend(cycles, source):
    run = run_settings(PAIR, 6000 * RPM, 22.25, model="lumped", cycles=6, start="static")
    a = simulate_steady(PAIR, run, cycles[source], 0.05, 6)
    b = simulate_steady(PAIR, run.with_(backend="numpy"), cycles[source], 0.05, 6)
    assert a.info["steady"]["cycles_done"] == b.info["steady"]["cycles_done"]
    scale = np.abs(b.contact_force).max()
    assert np.abs(a.contact_force - b.contact_force).max() < 1e-9 * scale
