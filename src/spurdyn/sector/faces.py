"""A root crack's faces as a unilateral contact in a dynamic run (docs/faults.md, "The crack's
faces in motion").

A cracked gear's faces are node pairs ``s`` whose openings ``o = B^T u`` (positive open,
:attr:`~spurdyn.sector.body.SectorBody.seam_loads`) may not go negative. On a modal body
the displacement is its modes' part and the residual flexibility's under every force on the
body, the pairs' loads ``e_c F_c`` and the faces' own ``B lam``:

    o = (B^T Phi) eta + sum_c (B^T K^-1 e_c - (B^T Phi) Omega^-2 Phi^T e_c) F_c
        + (B^T K^-1 B - (B^T Phi) Omega^-2 (B^T Phi)^T) lam,

a row ``(0, B^T Phi)`` on the gear's coordinates (no hub entry: the two faces' forces are
equal and opposite at one place) beside the pairs' rows, with a residual compliance of its
own and one shared with the pairs. This module holds those numbers, built once a run
(:func:`crack_faces`), and the per-step blocks (:meth:`CrackFaces.blocks`); the implicit step
solves pairs and faces in one complementarity problem
(:mod:`spurdyn.solvers.sector.implicit_numpy`, twin in
:mod:`spurdyn.solvers.sector.faces_compiled`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.sector.packs import FacePack


@dataclass(frozen=True)
class GearFaces:
    """One gear's crack faces as rows of the step (module docstring); ``S`` face pairs (all
    the gear's cracks), ``m`` modes, ``f`` a flank's coordinates.

    Attributes
    ----------
    modal
        ``(S, m)`` ``B^T Phi``.
    scaled
        ``(S, m)`` ``B^T Phi Omega^-2`` (the modes' part of the static flexibility).
    residual
        ``(S, S)`` ``B^T K^-1 B - (B^T Phi) Omega^-2 (B^T Phi)^T``.
    columns
        ``(1 + m, S)`` ``S^-1 (0, B^T Phi)^T``: the step's response to unit face forces.
    cross
        ``(count, sides, f, S)`` the residual flexibility between each flank, in its frame
        (the pairs' loads are written there), and the faces: ``T^T E^T K^-1 B`` less the
        modes' part ``T^T E^T Phi Omega^-2 Phi^T B``; zeros on a missing tooth.
    reach
        ``(count, sides, f, S)`` the faces' step response at each flank in its frame,
        ``T^T E^T Phi`` times ``columns``' modal rows: a pair's load ``b`` on flank ``(k,
        s)`` meets the faces through ``S^-1`` by ``b^T reach[k, s]``.
    """

    modal: NDArray[np.float64]
    scaled: NDArray[np.float64]
    residual: NDArray[np.float64]
    columns: NDArray[np.float64]
    cross: NDArray[np.float64]
    reach: NDArray[np.float64]

    @property
    def size(self) -> int:
        return self.modal.shape[0]


def gear_faces(block: Any, body: Any, sides: int) -> GearFaces:
    """The crack faces of the whole gear ``block`` on its modal ``body``
    (:class:`~spurdyn.sector.bodies.ModalBody`, the step's factor), flanks ``sides``."""
    sb = block.body
    b = sb.seam_loads[sb.free_dofs]
    reduced = body.reduced
    modal = b.T @ reduced.phi
    static = sb.solve_free(b)                   # K^-1 B on the free DOFs, (n, S)
    scaled = modal / reduced.omega2
    residual = b.T @ static - scaled @ modal.T
    modes = body.flank_modes                    # (count, sides, f, m), each flank in its frame
    f = modes.shape[2]
    cross = np.zeros((block.count, sides, f, b.shape[1]))
    for t in range(block.count):
        k = block.first + t
        if k in block.missing:
            continue
        for s in range(sides):
            turn = np.kron(np.eye(f // 2), block.turn_of(k, s))
            cross[t, s] = turn.T @ static[block.flank_dofs(k, s)]
    cross -= modes @ scaled.T
    columns = body.solve(np.vstack([np.zeros((1, modal.shape[0])), modal.T]))
    return GearFaces(modal, scaled, 0.5 * (residual + residual.T), columns, cross, modes @ columns[1:])


@dataclass(frozen=True)
class CrackFaces:
    """A run's crack faces: each gear's :class:`GearFaces` (``None`` on a gear without a
    crack), gear 0's face pairs first in the step's rows, and the faces' constant blocks of
    the step's problem, ``w_ff`` (``B^T Phi S^-1 Phi^T B``, the modes' part without
    ``beta'``) and ``r_ff`` (the residual compliance), block-diagonal by gear."""

    gears: tuple[GearFaces | None, GearFaces | None]
    w_ff: NDArray[np.float64]
    r_ff: NDArray[np.float64]

    @property
    def size(self) -> int:
        return self.w_ff.shape[0]

    def rows(self, parts: tuple[slice, slice], x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``(S,)`` the faces' rows times ``x`` (one vector of the run's coordinates):
        ``B^T Phi eta``, the openings without the residual flexibility's part."""
        return np.concatenate([gf.modal @ x[parts[g]][1:] for g, gf in enumerate(self.gears) if gf is not None])

    def times(self, parts: tuple[slice, slice], lam: NDArray[np.float64], n: int) -> NDArray[np.float64]:
        """``(n,)`` ``S^-1`` of the face forces ``lam`` on the run's coordinates."""
        out, at = np.zeros(n), 0
        for g, gf in enumerate(self.gears):
            if gf is not None:
                out[parts[g]] = gf.columns @ lam[at:at + gf.size]
                at += gf.size
        return out

    def blocks(self, rows: Any, z_theta: list[NDArray[np.float64]]) -> tuple[NDArray[np.float64], ...]:
        """The faces' couplings with the pairs ``rows`` (:class:`~spurdyn.sector.lcp.Rows`,
        ``None``: no pair near the path) at a step: ``(W_fc, W_fd, R_fc)``, ``(S, p)`` each,
        the faces' rows through ``S^-1`` on the pairs' whole rows ``G = (c, E)``, ``(B^T Phi
        z_theta) c^T + (S^-1 G_f^T)^T E^T`` by the flanks' tables (``reach``), and on their
        hub entries alone (``z_theta``, a unit hub torque's response), and the residual
        compliance between the faces and the pairs' loads (``cross``)."""
        out = []
        for g, gf in enumerate(self.gears):
            if gf is None:
                continue
            if rows is None:
                out.append((np.zeros((gf.size, 0)),) * 3)
                continue
            coef, el = rows.sides[g]
            w_fd = np.outer(gf.modal @ z_theta[g][1:], coef)
            w_fc = w_fd + np.einsum("pfs,pf->sp", gf.reach[el.teeth, el.sides], el.loads)
            out.append((w_fc, w_fd, np.einsum("pfs,pf->sp", gf.cross[el.teeth, el.sides], el.loads)))
        return tuple(np.vstack(blk) for blk in zip(*out))


def closed_start(faces: CrackFaces, parts: tuple[slice, slice], q: NDArray[np.float64],
                 r_fc: NDArray[np.float64], force: NDArray[np.float64]) -> NDArray[np.float64]:
    """The face forces of a static state ``q`` (the modes' static deflection under the pairs'
    loads, ``force`` on the pairs near the path, ``r_fc`` their residual coupling with the
    faces) with the faces closed where they would overlap: the statics' problem of the faces
    alone (docs/faults.md, section 6), ``B^T K^-1 B lam + o >= 0``; ``q`` is moved by the
    modes' part of their response, ``Omega^-2 Phi^T B lam``."""
    from spurdyn.sector.lcp import lcp_pivot

    kept = [(g, gf) for g, gf in enumerate(faces.gears) if gf is not None]
    static = _block_diag([gf.residual + gf.scaled @ gf.modal.T for _, gf in kept])
    opening = faces.rows(parts, q) + r_fc @ force
    lam, found = lcp_pivot(0.5 * (static + static.T), opening, np.zeros(opening.size, bool))
    if not found:       # a static problem on a positive definite matrix always has one
        raise RuntimeError("the crack faces' static problem has no solution")
    at = 0
    for g, gf in kept:
        q[parts[g]][1:] += gf.scaled.T @ lam[at:at + gf.size]
        at += gf.size
    return lam


def crack_faces(faults: Any, blocks: tuple[Any, Any], gears: tuple[Any, Any], sides: int) -> CrackFaces | None:
    """The run's :class:`CrackFaces` on its modal bodies ``gears``, ``None`` for a run
    without a crack."""
    if not faults or not any(gf.cracks for gf in faults):
        return None
    per = tuple(gear_faces(blk, body, sides) if gf.cracks else None for blk, body, gf in zip(blocks, gears, faults))
    kept = [gf for gf in per if gf is not None]
    w_ff = _block_diag([gf.modal @ gf.columns[1:] for gf in kept])
    return CrackFaces(per, 0.5 * (w_ff + w_ff.T), _block_diag([gf.residual for gf in kept]))


def face_pack(faces: CrackFaces | None, gears: tuple[Any, Any]) -> FacePack:
    """The compiled loop's :data:`~spurdyn.sector.packs.FacePack` of the run's ``faces`` on
    its modal bodies ``gears`` (empty ones for a run without a crack)."""
    per = []
    for g, body in enumerate(gears):
        gf = faces.gears[g] if faces is not None else None
        if gf is None:
            m, (count, sides, f) = body.n - 1, body.flank_modes.shape[:3]
            gf = GearFaces(np.zeros((0, m)), np.zeros((0, m)), np.zeros((0, 0)), np.zeros((m + 1, 0)),
                           np.zeros((count, sides, f, 0)), np.zeros((count, sides, f, 0)))
        per.append(gf)
    size = faces.size if faces is not None else 0
    w_ff = faces.w_ff if faces is not None else np.zeros((0, 0))
    r_ff = faces.r_ff if faces is not None else np.zeros((0, 0))
    c = np.ascontiguousarray
    return FacePack(*(c(getattr(gf, name)) for name in ("modal", "columns", "cross", "reach") for gf in per),
                    c(w_ff.reshape(size, size)), c(r_ff.reshape(size, size)))


def _block_diag(mats: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    n = sum(m.shape[0] for m in mats)
    out, at = np.zeros((n, n)), 0
    for m in mats:
        out[at:at + m.shape[0], at:at + m.shape[0]] = m
        at += m.shape[0]
    return out


__all__ = ["CrackFaces", "GearFaces", "closed_start", "crack_faces", "face_pack", "gear_faces"]
