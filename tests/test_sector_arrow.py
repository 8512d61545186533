"""A modal gear's ``S = M + gamma' C + beta' K`` is an arrow (the hub's row and column beside
a diagonal): its O(n) solve, NumPy and compiled, is the dense solve's."""

from __future__ import annotations

import numpy as np

from spurdyn.sector.bodies import arrow_solve
from spurdyn.sector.packs import ModalGear
from spurdyn.solvers.sector.rows_compiled import arrow, hub_column


def _arrow(m: int, seed: int):
    rng = np.random.default_rng(seed)
    c = rng.normal(size=m) * 0.1
    d = 1.0 + rng.uniform(0.0, 1e3, m)
    j = 1.0 + float(c @ (c / d))            # positive definite
    s = np.diag(np.concatenate([[j], d]))
    s[0, 1:] = s[1:, 0] = c
    # the other fields as a run's (the same compiled signature), unread here
    gear = ModalGear(c / d, 1.0 / d, j - float(c @ (c / d)), np.zeros(m), np.ones(m), np.zeros((1, 1, 1, m)),
                     np.zeros((1, 1, 1, 1, 1)), np.zeros(5), 0, 1, 1)
    return s, gear


def test_the_arrow_solve_is_the_dense_one():
    for m in (1, 7, 300):
        s, gear = _arrow(m, m)
        x = np.random.default_rng(1).normal(size=(m + 1, 3))
        want = np.linalg.solve(s, x)
        got = arrow_solve(gear.u, gear.dinv, gear.schur, x)
        np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-13 * np.abs(want).max())
        np.testing.assert_allclose(arrow(gear, x[:, 0].copy()), want[:, 0], rtol=1e-11,
                                   atol=1e-13 * np.abs(want).max())
        np.testing.assert_allclose(hub_column(gear), np.linalg.solve(s, np.eye(m + 1)[:, 0]), rtol=1e-11,
                                   atol=1e-15)
