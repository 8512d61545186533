"""A gear of the sector model as the time loop sees it: the whole finite-element body, or its
reduction to modes and residual flexibility (docs/sector.md, sections 6.3 and 6.6).

Both give the loop the same few things for a step's matrix ``S = M + gamma' C + beta' K``
(factorised once a run) over the gear's coordinates ``(theta, ...)``:

- :meth:`solve`: ``S^-1 x``;
- :meth:`forces`: ``C v + K q``;
- :meth:`rows`: the pairs' rows ``E`` on the gear's elastic coordinates from their unit
  strip loads (in tooth 0's frame, :meth:`~spurdyn.sector.system.GearBlock.flank_loads`)
  on teeth ``k``, on their right (drive) or left (back) flanks: the flank DOFs and the loads
  turned (and mirrored) there, or ``Phi^T`` of them (with ``full`` false, what a modal
  body's fillet maps read alone: its teeth, flanks and loads; none on a whole body);
- :meth:`elastic`: ``E x`` (``x`` one vector of the gear's coordinates or columns of them);
- :meth:`columns`: ``S^-1 E^T``, the full columns;
- :meth:`residual`: the instantaneous compliance between the pairs' loads (zero for the whole
  body, ``b_i^T R b_j`` for the reduced one);
- :meth:`static`: the coordinates of the body's static deflection under loads;
- :meth:`kinetic`, :meth:`strain`: its energies; :meth:`momentum`: its hub's momentum.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from spurdyn.fem.factor import factor_spd
from spurdyn.sector.packs import ModalGear
from spurdyn.sector.reduction import Reduction
from spurdyn.sector.system import GearBlock


class FullRows(NamedTuple):
    """The pairs' rows on a whole body: ``(p, f)`` flank coordinates and turned unit loads,
    and each flank's ``S^-1`` of unit loads on it."""

    dofs: NDArray[np.intp]
    weights: NDArray[np.float64]
    response: list[NDArray[np.float64]]


class ModalRows(NamedTuple):
    """The pairs' rows on a modal body: the teeth (body numbers from its first) and flanks
    (0 right, 1 left), the unit loads in tooth 0's frame and ``(p, m)`` their modal rows
    ``Phi^T b`` (``None``: not formed)."""

    teeth: NDArray[np.intp]
    sides: NDArray[np.intp]
    loads: NDArray[np.float64]
    modal: NDArray[np.float64] | None


def _tooth_frames(reduced: Reduction, sides: int = 1) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The modes at each flank seen in its own frame, ``(count, sides, f, m)``
    (``Phi_k^T T_k b = (T_k^T Phi_k)^T b`` for a load ``b`` on tooth 0's right flank, ``T_k``
    the turn to tooth ``k``'s flank and, on a left flank, the mirror before it), and the
    static flexibility between two flanks in their frames, ``T_i^T E_i^T K^-1 E_j T_j``:
    ``(count, sides, sides, f, f)`` by the teeth's distance round a ring of identical teeth
    (the same for every pair of teeth that far apart), ``(count, sides, count, sides, f, f)``
    on a sector or a faulty whole gear, zeros on a missing tooth. ``sides`` 1 keeps the
    right (drive) flanks, 2 the left (back) ones as well."""
    blk = reduced.block
    teeth = [blk.first + t for t in range(blk.count)]
    present = [k for k in teeth if k not in blk.missing]
    n_side = blk.flank_dofs(present[0]).size // 2
    turns = [[np.kron(np.eye(n_side), blk.turn_of(k, s)) for s in range(sides)] for k in teeth]
    # every flank's modes at once, each node's vector turned back by its flank's Q (Q^T v)
    dofs = np.concatenate([blk.flank_dofs(k, s) for k in present for s in range(sides)])
    phi = reduced.phi_rows(dofs).reshape(len(present), sides, n_side, 2, reduced.m)
    q = np.array([[blk.turn_of(k, s) for s in range(sides)] for k in present])
    modes = np.zeros((len(teeth), sides, 2 * n_side, reduced.m))
    modes[[teeth.index(k) for k in present]] = np.einsum("tsba,tsnbm->tsnam", q, phi).reshape(
        len(present), sides, 2 * n_side, reduced.m)
    if blk.cyclic:
        ring = {(s, t): reduced.flank_flex(s, t) for s in range(sides) for t in range(sides)}
        flex = np.array([[[turns[d][s].T @ ring[s, t][d] @ turns[0][t] for t in range(sides)]
                          for s in range(sides)] for d in range(blk.count)])
    else:
        flex = _pair_flex(reduced, sides, turns)
    return modes, flex


def _pair_flex(reduced: Reduction, sides: int, turns: list[list[NDArray[np.float64]]]) -> NDArray[np.float64]:
    """``(count, sides, count, sides, f, f)`` the static flexibility between every two flanks
    in their frames (:func:`_tooth_frames`), a flank's response solved once (on a whole gear
    by the body's factor, not kept: a ring's worth of responses is some hundred MB)."""
    blk = reduced.block
    count, f = blk.count, turns[0][0].shape[0]
    present = [t for t in range(count) if blk.first + t not in blk.missing]
    flex = np.zeros((count, sides, count, sides, f, f))
    rows = np.concatenate([blk.flank_dofs(blk.first + i, s) for i in present for s in range(sides)])
    for j in present:
        for t in range(sides):
            if blk.whole:
                dofs = blk.flank_dofs(blk.first + j, t)
                rhs = np.zeros((blk.mass.size, dofs.size))
                rhs[dofs, np.arange(dofs.size)] = 1.0
                resp = blk.body.solve_free(rhs)[rows]
            else:
                resp = reduced.static_response(blk.first + j, t)[rows]
            resp = resp.reshape(len(present), sides, f, f)
            for a, i in enumerate(present):
                for s in range(sides):
                    flex[i, s, j, t] = turns[i][s].T @ resp[a, s] @ turns[j][t]
    return flex


def arrow_solve(u: NDArray[np.float64], dinv: NDArray[np.float64], schur: float,
                x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``S^-1 x`` (``x`` a vector or columns) for the arrow ``S = [[J, c^T], [c, diag(d)]]``
    given by ``u = c / d``, ``1 / d`` and ``schur = J - c^T u``: the hub's part
    ``(x_0 - u^T x_e) / schur``, then each mode's ``x_j / d_j - u_j`` times it (block
    elimination of the modes; twin of :func:`spurdyn.solvers.sector.rows_compiled.arrow`)."""
    x = np.asarray(x, dtype=float)
    y = np.empty_like(x)
    y[0] = (x[0] - u @ x[1:]) / schur
    y[1:] = (dinv * x[1:].T).T - np.multiply.outer(u, y[0])
    return y


class FullBody:
    """The whole finite-element body: ``(theta, u)``."""

    def __init__(self, block: GearBlock, gp: float, bp: float, rayleigh: tuple[float, float]) -> None:
        self.block = block
        self.rayleigh = rayleigh
        self.n = block.n
        self._lu = factor_spd(block.matrix(1.0, gp, bp, rayleigh))
        self._resp: dict[tuple[int, int], tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]] = {}

    def solve(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return self._lu.solve(np.ascontiguousarray(x))

    def forces(self, q: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.block.forces(q, v, self.rayleigh)

    def _tooth(self, k: int, side: int = 0) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
        """Tooth ``k``'s flank ``side`` (0 right, 1 left): its coordinates, the map from tooth
        0's right flank to it and ``S^-1`` of unit loads there (computed when the flank first
        comes near its path)."""
        key = (self.block.tooth(k), side)
        if key not in self._resp:
            dofs = self.block.flank_dofs(k, side) + 1
            rhs = np.zeros((self.n, dofs.size))
            rhs[dofs, np.arange(dofs.size)] = 1.0
            self._resp[key] = (dofs, self.block.turn_of(k, side), self.solve(rhs))
        return self._resp[key]

    def rows(self, ks: NDArray[np.intp], loads: NDArray[np.float64],
             sides: NDArray[np.intp] | None = None, full: bool = True) -> FullRows | None:
        if not full:    # the fillets of a whole body read its coordinates alone
            return None
        sides = np.zeros(len(ks), np.intp) if sides is None else sides
        teeth = [self._tooth(int(k), int(s)) for k, s in zip(ks, sides)]
        dofs = np.array([t[0] for t in teeth])
        turned = np.array([(ld.reshape(-1, 2) @ t[1].T).ravel() for ld, t in zip(loads, teeth)])
        return FullRows(dofs, turned, [t[2] for t in teeth])

    def elastic(self, rows: FullRows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.einsum("pf,pf...->p...", rows.weights, x[rows.dofs])

    def columns(self, rows: FullRows) -> NDArray[np.float64]:
        return np.column_stack([resp @ w for resp, w in zip(rows.response, rows.weights)])

    def residual(self, rows: FullRows) -> NDArray[np.float64]:
        return np.zeros((rows.dofs.shape[0],) * 2)

    def static(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        """The elastic coordinates of the held body under the free DOFs' ``loads``."""
        return self.block.body.solve_free(loads)

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
    """The body on its modes: ``(theta, eta)`` (:mod:`spurdyn.sector.reduced`);
    ``sides`` 2 makes the left (back) flanks contacts too (:func:`_tooth_frames`)."""

    def __init__(self, reduced: Reduction, gp: float, bp: float, rayleigh: tuple[float, float],
                 sides: int = 1) -> None:
        self.reduced = reduced
        self.block = reduced.block
        m = reduced.m
        self.n = 1 + m
        a, b = rayleigh
        self.damp = a + b * reduced.omega2
        mat = np.zeros((self.n, self.n))
        mat[0, 0] = self.block.inertia
        mat[0, 1:] = mat[1:, 0] = reduced.coupling
        mat[1:, 1:] = np.eye(m)
        self.mass = mat
        # S is an arrow (the hub's row and column beside a diagonal): solved in O(n)
        d = 1.0 + gp * self.damp + bp * reduced.omega2
        self.u = reduced.coupling / d
        self.dinv = 1.0 / d
        self.schur = float(self.block.inertia - reduced.coupling @ self.u)
        self._modes, self._flex = _tooth_frames(reduced, sides)

    def solve(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return arrow_solve(self.u, self.dinv, self.schur, x)

    @property
    def flank_modes(self) -> NDArray[np.float64]:
        """``(count, sides, f, m)`` the modes at each flank in its own frame (:func:`_tooth_frames`)."""
        return self._modes

    def compiled(self) -> ModalGear:
        """The body's twin for the compiled loops (:data:`~spurdyn.sector.packs.ModalGear`):
        ``S`` (or ``M``) as :func:`arrow_solve` reads it, the modes' damping and ``omega^2``, the modes in each tooth's
        frame, the static blocks, the flank's geometry, the body's first tooth and count."""
        blk = self.block
        fl = blk.body.flank
        geo = np.array([fl.r0, fl.r_tip, float(fl.ny), fl.base_radius, blk.gear.half_angle_base])
        flex = self._flex
        if not blk.cyclic:
            # by the pair of teeth, ``(i, j)`` at ``i count + j``
            c, sd, f = blk.count, flex.shape[1], flex.shape[-1]
            flex = flex.transpose(0, 2, 1, 3, 4, 5).reshape(c * c, sd, sd, f, f)
        return ModalGear(np.ascontiguousarray(self.u), np.ascontiguousarray(self.dinv), self.schur,
                         np.ascontiguousarray(self.damp), np.ascontiguousarray(self.reduced.omega2),
                         np.ascontiguousarray(self._modes), np.ascontiguousarray(flex), geo,
                         blk.first, blk.count, int(blk.cyclic))

    def forces(self, q: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.zeros_like(q)
        out[1:] = self.damp * v[1:] + self.reduced.omega2 * q[1:]
        return out

    def rows(self, ks: NDArray[np.intp], loads: NDArray[np.float64],
             sides: NDArray[np.intp] | None = None, full: bool = True) -> ModalRows:
        blk = self.block
        sides = np.zeros(len(ks), np.intp) if sides is None else np.asarray(sides, np.intp)
        at = np.asarray(ks, dtype=np.intp) - blk.first
        if blk.whole:
            at %= blk.count
        elif at.min() < 0 or at.max() >= blk.count:
            blk.tooth(int(ks[np.argmax((at < 0) | (at >= blk.count))]))     # raises, naming it
        if not full:
            return ModalRows(at, sides, loads, None)
        return ModalRows(at, sides, loads, np.einsum("pf,pfm->pm", loads, self._modes[at, sides]))

    def elastic(self, rows: ModalRows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return rows.modal @ x[1:]

    def columns(self, rows: ModalRows) -> NDArray[np.float64]:
        return self.solve(np.vstack([np.zeros((1, rows.modal.shape[0])), rows.modal.T]))

    def residual(self, rows: ModalRows) -> NDArray[np.float64]:
        """``b_i^T R b_j`` of the pairs' loads: the static flexibility in the teeth's frames
        less the modes' part, ``b_i^T Phi Omega^-2 Phi^T b_j`` (the rows' own)."""
        at, sd = rows.teeth, rows.sides
        if self.block.cyclic:
            flex = self._flex[(at[:, None] - at[None, :]) % self.block.count, sd[:, None], sd[None, :]]
        else:
            flex = self._flex[at[:, None], sd[:, None], at[None, :], sd[None, :]]
        b = rows.loads
        static = (b[:, None, None, :] @ (flex @ b[None, :, :, None]))[:, :, 0, 0]
        return static - (rows.modal / self.reduced.omega2) @ rows.modal.T

    def static(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        # the modal part of K^-1 f; the rest is the residual flexibility's, held by the forces
        return self.reduced.static_modal(loads) / self.reduced.omega2

    def momentum(self, v: NDArray[np.float64]) -> float:
        """The hub's generalised momentum ``(M v)_theta`` (kg m^2/s)."""
        return float(self.mass[0] @ v)

    def kinetic(self, v: NDArray[np.float64]) -> float:
        return 0.5 * float(v @ (self.mass @ v))

    def strain(self, q: NDArray[np.float64]) -> float:
        return 0.5 * float(q[1:] @ (self.reduced.omega2 * q[1:]))


__all__ = ["FullBody", "FullRows", "ModalBody", "ModalRows", "arrow_solve"]
