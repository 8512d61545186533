"""A gear of the sector model as the time loop sees it: the whole finite-element body, or its
reduction to modes and residual flexibility (docs/sector.md, sections 6.3 and 6.6).

Both give the loop the same few things for a step's matrix ``S = M + gamma' C + beta' K``
(factorised once a run) over the gear's coordinates ``(theta, ...)``:

- :meth:`solve`: ``S^-1 x``;
- :meth:`forces`: ``C v + K q``;
- :meth:`row`: where a pair's strip load on tooth ``k`` enters the coordinates and with what
  weights (the flank DOFs and the load; or all the modes and ``Phi^T`` of the load);
- :meth:`response`: ``S^-1`` of unit loads there;
- :meth:`residual`: the instantaneous compliance between two pairs' loads (zero for the whole
  body, ``b_i^T R b_j`` for the reduced one);
- :meth:`static`: the coordinates of the body's static deflection under loads;
- :meth:`kinetic`, :meth:`strain`: its energies; :meth:`momentum`: its hub's momentum.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cho_factor, cho_solve

from spurdyn.fem.factor import factor_spd
from spurdyn.solvers.sector.reduced import ReducedGear
from spurdyn.solvers.sector.system import GearBlock


class FullBody:
    """The whole finite-element body: ``(theta, u)``."""

    def __init__(self, block: GearBlock, gp: float, bp: float, rayleigh: tuple[float, float]) -> None:
        self.block = block
        self.rayleigh = rayleigh
        self.n = block.n
        self._lu = factor_spd(block.matrix(1.0, gp, bp, rayleigh))
        self._resp: dict[int, NDArray[np.float64]] = {}

    def solve(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return self._lu.solve(np.ascontiguousarray(x))

    def forces(self, q: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.block.forces(q, v, self.rayleigh)

    def row(self, k: int, r: float, b: float) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
        """``(coordinates, weights, flank load)`` of a pair's unit load on tooth ``k``."""
        load = self.block.flank_load(k, r, b)
        return self.block.flank_dofs(k) + 1, load, load

    def response(self, k: int) -> NDArray[np.float64]:
        key = self.block.tooth(k)
        if key not in self._resp:       # computed when the tooth first comes near the path
            dofs = self.block.flank_dofs(k) + 1
            rhs = np.zeros((self.n, dofs.size))
            rhs[dofs, np.arange(dofs.size)] = 1.0
            self._resp[key] = self.solve(rhs)
        return self._resp[key]

    def residual(self, i: int, li: NDArray[np.float64], j: int, lj: NDArray[np.float64]) -> float:
        return 0.0

    def static(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        """The elastic coordinates of the held body under the free DOFs' ``loads``."""
        body = self.block.body
        full = np.zeros(body.mesh.n_dof)
        full[body._free] = loads
        return body.solve(full)[body._free]

    def momentum(self, v: NDArray[np.float64]) -> float:
        """The hub's generalised momentum ``(M v)_theta`` (kg m^2/s)."""
        blk = self.block
        return blk.inertia * v[0] + float((blk.mass * blk.rot) @ v[1:])

    def kinetic(self, v: NDArray[np.float64]) -> float:
        blk = self.block
        vel = v[1:]
        return 0.5 * (blk.inertia * v[0] ** 2 + 2.0 * v[0] * float((blk.mass * blk.rot) @ vel)
                      + float(vel @ (blk.mass * vel)))

    def strain(self, q: NDArray[np.float64]) -> float:
        return 0.5 * float(q[1:] @ (self.block.stiffness @ q[1:]))


class ModalBody:
    """The body on its modes: ``(theta, eta)`` (:mod:`spurdyn.solvers.sector.reduced`)."""

    def __init__(self, reduced: ReducedGear, gp: float, bp: float, rayleigh: tuple[float, float]) -> None:
        self.reduced = reduced
        self.block = reduced.block
        m = reduced.m
        self.n = 1 + m
        a, b = rayleigh
        self._damp = a + b * reduced.omega2
        mat = np.zeros((self.n, self.n))
        mat[0, 0] = self.block.inertia
        mat[0, 1:] = mat[1:, 0] = reduced.coupling
        mat[1:, 1:] = np.eye(m)
        self.mass = mat.copy()
        mat[1:, 1:] += np.diag(gp * self._damp + bp * reduced.omega2)
        self._cho = cho_factor(mat)
        self._dofs = np.arange(1, self.n)
        self._resp = self.solve(np.vstack([np.zeros((1, m)), np.eye(m)]))

    def solve(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return cho_solve(self._cho, x)

    def forces(self, q: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.zeros_like(q)
        out[1:] = self._damp * v[1:] + self.reduced.omega2 * q[1:]
        return out

    def row(self, k: int, r: float, b: float) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
        load = self.block.flank_load(k, r, b)
        return self._dofs, self.reduced.modes_at(k).T @ load, load

    def response(self, k: int) -> NDArray[np.float64]:
        return self._resp

    def residual(self, i: int, li: NDArray[np.float64], j: int, lj: NDArray[np.float64]) -> float:
        return float(li @ self.reduced.residual(i, j) @ lj)

    def static(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        # the modal part of K^-1 f; the rest is the residual flexibility's, held by the forces
        return (self.reduced.phi.T @ loads) / self.reduced.omega2

    def momentum(self, v: NDArray[np.float64]) -> float:
        """The hub's generalised momentum ``(M v)_theta`` (kg m^2/s)."""
        return float(self.mass[0] @ v)

    def kinetic(self, v: NDArray[np.float64]) -> float:
        return 0.5 * float(v @ (self.mass @ v))

    def strain(self, q: NDArray[np.float64]) -> float:
        return 0.5 * float(q[1:] @ (self.reduced.omega2 * q[1:]))


__all__ = ["FullBody", "ModalBody"]
