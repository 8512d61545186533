"""How far a crack's faces opened in a dynamic run (docs/faults.md, section 8).

A dynamic run carries a crack with its faces free (their unilateral contact is the
statics'): the faces may pass through each other where the tooth is pushed back. This
measures it at the run's kept samples. The faces' normal openings are ``B^T u``
(:attr:`~spurdyn.sector.body.SectorBody.seam_loads`, positive open), and a modal body's
displacement is its modes' part and the residual flexibility's under the contacts' loads,

    B^T u = (B^T Phi) eta + sum_c F_c (B^T K^-1 e_c - (B^T Phi) Omega^-2 Phi^T e_c),

``e_c`` contact ``c``'s unit load on the gear: at a static state (``eta = Omega^-2 Phi^T
f``) the sum is ``B^T K^-1 f`` exactly.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.sector.rules import stress_steps

if TYPE_CHECKING:  # annotations only
    from spurdyn.sector.model import SectorModel


class FaceMap:
    """One cracked gear's maps from its coordinates and its contacts' loads to its crack
    faces' openings: ``B^T Phi`` ``(S, m)``, ``(K^-1 B)^T`` ``(S, n)`` on the free DOFs."""

    def __init__(self, model: SectorModel, g: int) -> None:
        gear = model.gears[g]
        self.g, self.block = g, model.blocks[g]
        body = self.block.body
        b = body.seam_loads[body.free_dofs]
        self.modal = b.T @ gear.reduced.phi
        self.static = body.solve_free(b).T
        self.omega2 = gear.reduced.omega2

    def openings(self, eta: NDArray[np.float64], rows: Any, force: NDArray[np.float64]) -> NDArray[np.float64]:
        """``(S,)`` the openings (m) at modal coordinates ``eta`` with the contacts' modal
        rows ``rows`` (:class:`~spurdyn.sector.bodies.ModalRows`, ``None``: none) carrying
        ``force`` (N)."""
        out = self.modal @ eta
        if rows is None:
            return out
        blk = self.block
        for f, at, side, load, phi_e in zip(force, rows.teeth, rows.sides, rows.loads, rows.modal):
            if not f:
                continue
            k = blk.first + int(at)
            dofs = blk.flank_dofs(k, int(side))
            e = (load.reshape(-1, 2) @ blk.turn_of(k, int(side)).T).ravel()
            out += f * (self.static[:, dofs] @ e - self.modal @ (phi_e / self.omega2))
        return out


def face_openings(model: SectorModel, record: Any, n_kept: int, offset: int = 0) -> dict[str, Any] | None:
    """The least and the largest opening (m) of the cracked gears' faces over the run's
    kept samples below ``n_kept``, and when the least was; ``None`` for a run without a
    crack or without kept samples."""
    cracked = [g for g in range(2) if model.faults and model.faults[g].cracks and model.modes]
    steps = stress_steps(model.per_cycle, record.gap.size - 1)
    keep = (steps < n_kept) & np.isfinite(record.states[:steps.size, 0])
    if not cracked or not keep.any():
        return None
    maps = [FaceMap(model, g) for g in cracked]
    least, most, when = np.inf, -np.inf, 0.0
    for i, q in zip(steps[keep], record.states[:steps.size][keep]):
        force = np.nan_to_num(record.force[i])
        rows = model.rows_at(float(q[0]), force, offset)
        for fm in maps:
            part = model.parts[fm.g]
            opening = fm.openings(q[part][1:], None if rows is None else rows.sides[fm.g][1],
                                  force[rows.on] if rows is not None else np.zeros(0))
            if opening.min() < least:
                least, when = float(opening.min()), float(i * model.h)
            most = max(most, float(opening.max()))
    return {"least_opening_m": least, "largest_opening_m": most, "least_at_s": when}


__all__ = ["FaceMap", "face_openings"]
