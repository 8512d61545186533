"""What a gear body reduced to modes gives the time loop, however its modes were found
(docs/sector.md, sections 6.6 and 6.9): the modes at the flanks, the residual flexibility
between flanks and the static response to flank loads.

:class:`Reduction` holds what both reductions share; a reduction supplies
:meth:`Reduction.phi_rows` (the modes at given free DOFs) and
:meth:`Reduction.static_response`. The whole-ring eigen-solve is
:class:`spurdyn.sector.reduced.ReducedGear`, the harmonics of one cell
:class:`spurdyn.sector.cyclic.CyclicGear`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from spurdyn.sector.system import GearBlock


def turn_block(angle: float, n_nodes: int) -> NDArray[np.float64]:
    """``(2n, 2n)`` block rotation turning each node's vector clockwise by ``angle``
    (:func:`spurdyn.mesh.sector.turn` as a matrix)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.kron(np.eye(n_nodes), np.array([[c, s], [-s, c]]))


class Reduction:
    """A gear body on its modes (SI units): ``block``, ``omega2`` ``(m,)`` and ``coupling``
    ``(m,)`` ``Phi^T M s``, set by the subclass, which also supplies :meth:`phi_rows` and
    :meth:`static_response`."""

    block: GearBlock
    omega2: NDArray[np.float64]
    coupling: NDArray[np.float64]

    @property
    def m(self) -> int:
        return self.omega2.size

    def phi_rows(self, dofs: NDArray[np.intp]) -> NDArray[np.float64]:
        """``(len(dofs), m)`` the M-orthonormal modes at the free DOFs ``dofs``."""
        raise NotImplementedError

    def static_response(self, k: int, side: int = 0) -> NDArray[np.float64]:
        """``K^-1 E_k``: the held body's response (all free DOFs) to unit loads on tooth
        ``k``'s flank DOFs of ``side``."""
        raise NotImplementedError

    def static_rows(self, k: int, dofs: NDArray[np.intp]) -> NDArray[np.float64]:
        """``(len(dofs), 2, f)``: :meth:`static_response` of tooth ``k``'s right and left
        flanks at the free DOFs ``dofs`` alone."""
        return np.stack([self.static_response(k, side)[dofs] for side in (0, 1)], axis=1)

    def modes_at(self, k: int, side: int = 0) -> NDArray[np.float64]:
        """``(2 (2 ny + 1), m)`` the modes at tooth ``k``'s flank DOFs (``side`` 0 the right
        flank, 1 the left)."""
        return self.phi_rows(self.block.flank_dofs(k, side))

    def flank_flex(self, s: int, t: int) -> NDArray[np.float64]:
        """``(count, f, f)`` ``E_{first+d,s}^T K^-1 E_{first,t}`` for ``d = 0 .. count-1``:
        the static flexibility between tooth ``first + d``'s flank ``s`` and the first
        tooth's flank ``t`` (gear frame)."""
        blk = self.block
        base = self.static_response(blk.first, t)
        return np.array([base[blk.flank_dofs(blk.first + d, s)] for d in range(blk.count)])

    def residual(self, i: int, j: int) -> NDArray[np.float64]:
        """``E_i^T R E_j``: the residual flexibility between the flank DOFs of teeth ``i``
        and ``j`` (m/N)."""
        blk = self.block
        if blk.whole:
            # the ring is the same under a turn by a pitch: in the teeth's frames the block
            # of teeth (i, j) is that of (i - j, 0)
            d = (i - j) % blk.count
            n_side = blk.body.flank.side_nodes.size
            angle = blk.body.mesh.tooth_angle
            t_i, t_j = (turn_block(angle(blk.tooth(k)), n_side) for k in (i, j))
            t_d = turn_block(angle(blk.tooth(blk.first + d)), n_side)
            t_0 = turn_block(angle(blk.first), n_side)
            full = t_i @ (t_d.T @ self.flank_flex(0, 0)[d] @ t_0) @ t_j.T
        else:
            full = self.static_response(j)[blk.flank_dofs(i)]
        phi_i, phi_j = self.modes_at(i), self.modes_at(j)
        return full - (phi_i / self.omega2) @ phi_j.T

    def static_modal(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        """``Phi^T f``: the modal loads of the free DOFs' loads ``loads`` (read where they
        are not zero)."""
        nz = np.flatnonzero(loads)
        return self.phi_rows(nz).T @ loads[nz]


__all__ = ["Reduction", "turn_block"]
