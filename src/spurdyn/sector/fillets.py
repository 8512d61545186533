"""The fillets of every tooth of a sector body and the stress along them, as linear maps of
the body's coordinates (docs/sector.md, section 6.11).

A tooth's fillets on its rim are the body's free outline inside the tooth's cell (half a
pitch either side of its centre line) below the form radius: down the rim's fillet and
along the root land to the cell's edge, not only the part inside the single-tooth mesh.
The stress along them is recovered as the FE model's (:mod:`spurdyn.model.root`:
Gauss points extrapolated, averaged at the surface nodes, the tangential stress at the
free surface), a fixed matrix ``T_k`` on the body's displacements.

:class:`GearFillets` applies it to a gear's recorded coordinates: on a whole body
``sigma_k = T_k u``; on a modal one, whose displacements are ``u = Phi eta + R f`` (the
modes and the residual flexibility under the pairs' flank loads ``f``),

    sigma_k = (T_k Phi) (eta - Omega^-2 Phi^T f) + T_k K^-1 f,

the small matrices ``T_k Phi`` and ``T_k K^-1 E_j`` (the stress at tooth ``k``'s fillets
under unit loads on tooth ``j``'s flank) computed once. Round a whole ring the latter
depend on ``k - j`` only: the tangential stress is a scalar, the same when the ring and
its loads are turned by a pitch.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from spurdyn import store
from spurdyn.fem.recovery import outline_tangents, surface_stress_columns
from spurdyn.mesh.sector import SectorMesh, turn
from spurdyn.model.root import RootSurface


#: Teeth whose modes at the fillets are formed at once.
MODE_CHUNK = 8


def boundary_edges(elements: NDArray[np.intp]) -> NDArray[np.intp]:
    """``(B, 3)`` the free edges of a Q8 mesh, each ``(corner, mid-side, corner)``: an edge
    whose mid-side node belongs to one element only."""
    corners = elements[:, [0, 1, 2, 3, 1, 2, 3, 0]].reshape(-1, 2, 4)
    edges = np.stack([corners[:, 0], elements[:, 4:8], corners[:, 1]], axis=-1).reshape(-1, 3)
    mids, count = np.unique(edges[:, 1], return_counts=True)
    return edges[np.isin(edges[:, 1], mids[count == 1])]


def _chain(edges: NDArray[np.intp], start: int) -> NDArray[np.intp]:
    """The nodes of the path of ``edges`` (each ``(a, mid, b)``) from its end ``start``."""
    nxt: dict[int, list[int]] = {}
    for a, m, b in edges.tolist():
        for u, v in ((a, m), (m, b)):
            nxt.setdefault(u, []).append(v)
            nxt.setdefault(v, []).append(u)
    out, prev = [start], -1
    while True:
        ahead = [v for v in nxt[out[-1]] if v != prev]
        if not ahead:
            return np.asarray(out, dtype=np.intp)
        prev = out[-1]
        out.append(ahead[0])


def tooth_fillets(mesh: SectorMesh, k: int, form_radius: float, material: Any,
                  edges: NDArray[np.intp] | None = None,
                  holding: Any = None) -> RootSurface:
    """The :class:`~spurdyn.model.root.RootSurface` of tooth ``k`` of a sector ``mesh``:
    its right fillet from the cell's edge up to the form radius, then its left, their
    stress operator on the sector's displacements (gear frame). ``edges`` the mesh's
    :func:`boundary_edges` and ``holding`` its node-element incidence (sparse, nodes by
    elements), if the caller has them (computed here otherwise)."""
    half = 0.5 * mesh.pitch_angle
    edges = boundary_edges(mesh.elements) if edges is None else edges
    on = np.unique(edges)
    chi, r = np.full(mesh.n_nodes, np.inf), np.zeros(mesh.n_nodes)
    local = turn(mesh.nodes[on], -mesh.tooth_angle(k))          # tooth k along +y
    chi[on] = np.arctan2(local[:, 0], local[:, 1])
    r[on] = np.hypot(local[:, 0], local[:, 1])
    tol = 1e-9
    inside = (np.abs(chi) <= half + tol) & (r < form_radius) & (r > mesh.inner_radius * (1 + tol))
    edges = edges[inside[edges].all(axis=1)]
    nodes, side = [], []
    for s, sign in enumerate((1.0, -1.0)):
        mine = edges[(sign * chi[edges] >= -tol).all(axis=1)]
        ends = mine[:, [0, 2]].ravel()
        start = int(ends[np.argmax(sign * chi[ends])])        # at the cell's edge
        path = _chain(mine, start)
        nodes.append(path)
        side.append(np.full(path.size, s, dtype=np.int8))
    all_nodes = np.concatenate(nodes)
    tangents = np.concatenate([outline_tangents(mesh.nodes[p]) for p in nodes])
    holding = incidence(mesh) if holding is None else holding
    near = np.unique(holding[all_nodes].indices)
    operator, dofs = surface_stress_columns(mesh.nodes, mesh.elements[near], all_nodes, material)
    return RootSurface(nodes=all_nodes, side=np.concatenate(side), radius=r[all_nodes],
                       tangents=tangents, operator=operator, dofs=dofs)


def incidence(mesh: SectorMesh) -> sp.csr_matrix:
    """``(N, E)`` which elements hold each node (a sparse pattern)."""
    el = mesh.elements
    rows = el.ravel()
    cols = np.repeat(np.arange(el.shape[0]), el.shape[1])
    return sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(mesh.n_nodes, el.shape[0]))


def tangential_operator(surface: RootSurface) -> NDArray[np.float64]:
    """``(n, d)`` ``T`` with ``T @ u[surface.dofs]`` the surface's tangential stress (Pa)."""
    t = surface.tangents
    c = np.stack([t[:, 0] ** 2, t[:, 1] ** 2, 2.0 * t[:, 0] * t[:, 1]], axis=1)
    return np.einsum("nc,ncj->nj", c, surface.operator)


class GearFillets:
    """The fillets of a gear body's teeth and the stress along them from its coordinates
    (module docstring).

    Attributes
    ----------
    teeth
        ``(K,)`` the body's tooth numbers, ``first .. first + K - 1``.
    radius
        ``(n,)`` each fillet node's distance from the gear centre (the same on every tooth).
    side
        ``(n,)`` 0 a node of the right fillet, 1 the left.
    """

    def __init__(self, gear: Any) -> None:
        blk = self.block = gear.block
        body = blk.body
        self.teeth = blk.first + np.arange(blk.count)
        self._edges, self._holding = boundary_edges(body.mesh.elements), incidence(body.mesh)
        first = self._surface(int(self.teeth[0]))
        self.radius, self.side = first.radius, first.side
        self.reduced = getattr(gear, "reduced", None)
        if self.reduced is None:
            self._ops, self._rows = self._operators(first)
            return
        self._gear = gear                       # its flank modes, read by stress_many
        # the maps from the mode store when a run before made them for the same body and
        # modes (a whole ring's static response costs its harmonics' solves); every tooth's
        # stress operator is made only to make them (72 teeth: ~0.5 s of a design pair's run)
        mesh, mat = body.mesh, blk.gear.material
        key = store.digest("fillets", store.code_revision(__name__, type(self.reduced).__module__),
                           mesh.nodes, mesh.elements, mesh.width, mesh.hub_nodes, mat.young,
                           mat.poisson, blk.first, blk.count, blk.gear.form_radius,
                           self.reduced.omega2, self.reduced.coupling)
        found = store.load(key)
        if found is None:
            self._ops, self._rows = self._operators(first)
            found = dict(zip(("modes", "static"), self._modal_maps()))
            store.save(key, **found)
        self._modes, self._static = found["modes"], found["static"]

    def _surface(self, k: int) -> RootSurface:
        """:func:`tooth_fillets` of the body's tooth ``k``."""
        blk = self.block
        return tooth_fillets(blk.body.mesh, k, blk.gear.form_radius, blk.gear.material, self._edges,
                             self._holding)

    def _operators(self, first: RootSurface) -> tuple[list[NDArray[np.float64]], list[NDArray[np.intp]]]:
        """Every tooth's :func:`tangential_operator` on the free DOFs (a held hub DOF moves
        by nothing) and the free DOFs it reads; ``first`` the first tooth's surface."""
        body = self.block.body
        free_of = np.full(body.mesh.n_dof, -1, dtype=np.intp)
        free_of[body.free_dofs] = np.arange(body.free_dofs.size)
        ops, rows = [], []
        for i, k in enumerate(self.teeth):
            s = first if i == 0 else self._surface(int(k))
            op, at = tangential_operator(s), free_of[s.dofs]
            ops.append(op[:, at >= 0])
            rows.append(at[at >= 0])
        return ops, rows

    def _modal_maps(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``T_k Phi`` ``(K, n, m)`` and the static maps ``T_k K^-1 E_j`` of unit loads in
        tooth 0's frame: ``(K, sides, n, f)`` by ``k - j`` round a whole ring, else
        ``(K, K, sides, n, f)``."""
        red, blk = self.reduced, self.block
        rows = np.concatenate(self._rows)
        at = np.cumsum([0] + [r.size for r in self._rows])
        # the modes at the fillets' rows a few teeth at a time (a whole gear's 53 teeth and
        # 514 modes: 66 MB at once)
        modes = []
        for lo in range(0, len(self._ops), MODE_CHUNK):
            hi = min(lo + MODE_CHUNK, len(self._ops))
            phi = red.phi_rows(rows[at[lo]:at[hi]])
            modes += [self._ops[i] @ phi[at[i] - at[lo]:at[i + 1] - at[lo]] for i in range(lo, hi)]
        modes = np.array(modes)
        sides = 2
        f = blk.flank_dofs(blk.first).size
        n_side = f // 2

        def mapped(j: int) -> NDArray[np.float64]:
            """``(K, sides, n, f)``: every tooth's fillets under tooth ``j``'s flank loads."""
            resp = red.static_rows(int(j), rows)
            turns = [np.kron(np.eye(n_side), blk.turn_of(int(j), s)) for s in range(sides)]
            return np.array([[op @ resp[at[i]:at[i + 1], s] @ turns[s] for s in range(sides)]
                             for i, op in enumerate(self._ops)])

        if blk.whole:
            return modes, mapped(blk.first)
        return modes, np.stack([mapped(j) for j in self.teeth], axis=1)

    def _static_maps(self, tooth: int, side: int) -> NDArray[np.float64]:
        """``(K, n, f)`` every tooth's fillet stress under unit loads on flank ``side`` of the
        body's tooth ``tooth`` (from its first): round a whole ring by the teeth's distance."""
        if self.block.whole:
            return self._static[(np.arange(self.teeth.size) - tooth) % self.teeth.size, side]
        return self._static[:, tooth, side]

    def stress(self, q: NDArray[np.float64], rows: Any = None,
               force: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """``(K, n)`` the tangential stress (Pa) along every tooth's fillets for the gear's
        coordinates ``q`` (its hub's turn first) and, on a modal body, the pairs' rows on it
        (:class:`~spurdyn.sector.bodies.ModalRows`, ``None`` for no contact) and their
        forces ``force``."""
        u = q[1:]
        if self.reduced is None:
            return np.array([op @ u[r] for op, r in zip(self._ops, self._rows)])
        eta = u.copy()
        if rows is None or not len(force):
            return self._modes @ eta
        eta -= (force @ rows.modal) / self.reduced.omega2
        out = self._modes @ eta
        for fp, tp, sp_, w in zip(force, rows.teeth, rows.sides, rows.loads):
            if fp == 0.0:
                continue
            out += fp * (self._static_maps(tp, sp_) @ w)
        return out

    def stress_many(self, q: NDArray[np.float64], sample: NDArray[np.intp] | None = None, rows: Any = None,
                    force: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """:meth:`stress` of several states at once: ``(S, K, n)`` for the gear's coordinates
        ``q`` ``(S, 1 + d)`` and, on a modal body, the pairs' rows of all of them
        (:meth:`~spurdyn.sector.model.SectorModel.rows_many`: entry ``e`` a pair in state
        ``sample[e]``, ``None`` for no contact; their modal rows are not read, so they need
        not be formed) and their forces ``force`` ``(E,)``. The same sums as :meth:`stress`,
        as matrix products over the states and the flanks loaded."""
        u = q[:, 1:]
        count, n = self.teeth.size, self.radius.size
        if self.reduced is None:
            return np.stack([u[:, r] @ op.T for op, r in zip(self._ops, self._rows)], axis=1)
        modes = self._modes.reshape(count * n, -1).T
        live = np.zeros(0, np.intp) if rows is None else np.flatnonzero(force != 0.0)
        if not live.size:
            return (u @ modes).reshape(-1, count, n)
        w, flank, maps = self._flank_loads(u.shape[0], sample[live], rows.teeth[live], rows.sides[live],
                                           force[live, None] * rows.loads[live])
        # eta less the loads' modal part Omega^-2 Phi^T f, then the static part T_k K^-1 f
        eta = u - (w @ flank) / self.reduced.omega2
        return (eta @ modes + w @ maps).reshape(-1, count, n)

    def _flank_loads(self, states: int, sample: NDArray[np.intp], teeth: NDArray[np.intp],
                     sides: NDArray[np.intp], loads: NDArray[np.float64]
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``(w, flank, maps)`` of the loads ``loads`` ``(E, f)`` (forces times unit loads)
        of entries in states ``sample`` on the body's teeth ``teeth``, flanks ``sides``:
        per flank loaded (``G`` of them) ``w`` ``(S, G f)`` the sum of its loads in each
        state, ``flank`` ``(G f, m)`` the modes at it (its ``Phi^T`` rows) and ``maps``
        ``(G f, K n)`` the fillets' stress under its unit loads."""
        key, at = np.unique(teeth * 2 + sides, return_inverse=True)
        f = loads.shape[1]
        w = np.zeros((states, key.size, f))
        np.add.at(w, (sample, at.ravel()), loads)       # a split pair's two rows in one state
        tooth, side = np.divmod(key, 2)
        maps = [self._static_maps(int(t), int(sd)).reshape(-1, f).T for t, sd in zip(tooth, side)]
        flank = self._gear.flank_modes[tooth, side].reshape(key.size * f, -1)
        return w.reshape(states, -1), flank, np.concatenate(maps)


__all__ = ["GearFillets", "boundary_edges", "incidence", "tangential_operator", "tooth_fillets"]
