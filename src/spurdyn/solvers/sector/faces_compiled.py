"""A crack's faces in the compiled implicit loop (docs/faults.md, "The crack's faces in
motion"): their rows beside the pairs' in one complementarity problem, twin of
:func:`spurdyn.solvers.sector.implicit_numpy._with_faces` and
:meth:`spurdyn.sector.faces.CrackFaces.blocks` (the faces' data a
:data:`~spurdyn.sector.packs.FacePack`, gear 0's face pairs first).
"""

from __future__ import annotations

import numpy as np

from spurdyn.jit import njit
from spurdyn.solvers.sector.bearings_compiled import trans_back
from spurdyn.solvers.sector.rows_compiled import _modal_rows, lcp_pivot


@njit
def _by_flanks(table, loads, idx, cnt, at, sd):
    """``(S_g, p)`` the pairs' unit loads (each on its body tooth ``at`` and flank ``sd``,
    over its nonzeros ``idx``, ``cnt``) through a face table by flank ``(count, sides, f,
    S_g)``: ``b^T table[at, sd]``, the pairs' modal rows' product with a face table."""
    return _modal_rows(loads, idx, cnt, table, at, sd).T


@njit
def face_blocks(fp, rows, lo0, lo1, sd, hub_cols):
    """``(W_fc, W_fd, R_fc)`` ``(S, p)``: the faces' rows through ``S^-1`` on the pairs'
    whole rows and on their hub entries alone, and the residual compliance between the faces
    and the pairs' loads (``lo0``, ``lo1`` of
    :func:`~spurdyn.solvers.sector.rows_compiled.rows_and_loads`; twin of
    :meth:`~spurdyn.sector.faces.CrackFaces.blocks`)."""
    coef0, coef1 = rows[2], rows[3]
    z0, z1 = hub_cols
    s0 = fp.modal0.shape[0]
    s, p = fp.r_ff.shape[0], coef0.size
    w_fc, w_fd, r_fc = np.zeros((s, p)), np.zeros((s, p)), np.zeros((s, p))
    if s0:
        w_fd[:s0] = np.outer(fp.modal0 @ z0[1:], coef0)
        w_fc[:s0] = w_fd[:s0] + _by_flanks(fp.reach0, lo0[0], lo0[1], lo0[2], lo0[3], sd)
        r_fc[:s0] = _by_flanks(fp.cross0, lo0[0], lo0[1], lo0[2], lo0[3], sd)
    if s > s0:
        w_fd[s0:] = np.outer(fp.modal1 @ z1[1:], coef1)
        w_fc[s0:] = w_fd[s0:] + _by_flanks(fp.reach1, lo1[0], lo1[1], lo1[2], lo1[3], sd)
        r_fc[s0:] = _by_flanks(fp.cross1, lo1[0], lo1[1], lo1[2], lo1[3], sd)
    return w_fc, w_fd, r_fc


@njit
def face_rows(fp, x, na):
    """``(S,)`` the faces' rows ``B^T Phi eta`` times the run's coordinates ``x``."""
    s0 = fp.modal0.shape[0]
    out = np.empty(fp.r_ff.shape[0])
    out[:s0] = fp.modal0 @ x[1:na]
    out[s0:] = fp.modal1 @ x[na + 1:na + 1 + fp.modal1.shape[1]]
    return out


@njit
def face_accelerations(x0, q_hat, last_faces, fp, pairs, rows, lo0, lo1, sd, hub_cols, cfg, trans):
    """The step's accelerations with the pairs and the crack's faces in contact: ``(qdd, F,
    face forces, found, R_fc, openings)``, the faces' openings at the step's end those of its
    problem (``W (F, lam) + v``: the NumPy loop's ``B^T Phi eta + C_res (F, lam)`` of the new
    state, to round-off); ``pairs`` the pairs' blocks of
    :func:`~spurdyn.solvers.sector.step_compiled._pair_blocks` (``x0`` changed by their
    damper), ``last_faces`` the face forces of the step before, ``trans`` the pairs' rows on the
    hubs' translations and their ``S_tt^-1`` (the faces' rows have none)."""
    full0, full1, w0, w_gd, k_w, d_x0, _, vv, guess = pairs
    bp = cfg.bp
    na, nb = full0.shape[0], full0.shape[0] + full1.shape[0]
    p, s = vv.size, fp.r_ff.shape[0]
    w_fc, w_fd, r_fc = face_blocks(fp, rows, lo0, lo1, sd, hub_cols)
    n = p + s
    w_all = np.empty((n, n))
    w_all[:p, :p] = w0
    w_all[p:, :p] = w_fc
    w_all[:p, p:] = w_fc.T
    w_all[p:, p:] = fp.w_ff
    w_gd_all = np.empty((n, p))
    w_gd_all[:p] = w_gd
    w_gd_all[p:] = w_fd
    res = np.empty((n, n))
    res[:p, :p] = rows[6]
    res[p:, :p] = r_fc
    res[:p, p:] = r_fc.T
    res[p:, p:] = fp.r_ff
    w = bp * (w_all - w_gd_all @ k_w @ w_gd_all.T) + res
    for a in range(p):
        w[a, a] += cfg.c_h
    v = np.empty(n)
    v[:p] = vv
    v[p:] = face_rows(fp, q_hat + bp * x0, na) - bp * (w_fd @ (k_w @ d_x0))
    act = np.zeros(n, np.bool_)
    for a in range(p):
        act[a] = ((guess >> a) & 1) == 1
    for j in range(s):
        act[p + j] = last_faces[j] > 0.0
    w = 0.5 * (w + w.T)
    lam, found = lcp_pivot(w, v, act)
    opening = (w @ lam + v)[p:]
    s0 = fp.modal0.shape[0]
    qdd_new = x0.copy()
    qdd_new[:na] += fp.columns0 @ lam[p:p + s0]
    qdd_new[na:nb] += fp.columns1 @ lam[p + s0:]
    if p:
        qdd_new[:na] += full0 @ lam[:p]
        qdd_new[na:nb] += full1 @ lam[:p]
        kd = k_w @ (d_x0 + w_gd_all.T @ lam)
        coef0, coef1 = rows[2], rows[3]
        z0, z1 = hub_cols
        qdd_new[:na] -= (coef0 @ kd) * z0
        qdd_new[na:nb] -= (coef1 @ kd) * z1
        trans_back(qdd_new, nb, lam[:p] - kd, trans)
    return qdd_new, lam[:p].copy(), lam[p:].copy(), found, r_fc, opening


@njit
def face_record(out, step, faces, opening):
    """Step ``step``'s faces into ``out.faces``: their largest force, least and largest opening."""
    out.faces[step, 0] = faces.max()
    out.faces[step, 1] = opening.min()
    out.faces[step, 2] = opening.max()


__all__ = ["face_accelerations", "face_blocks", "face_record", "face_rows"]
