"""The sector model's implicit step in NumPy (docs/sector.md, 6.3), the twin of the compiled
:func:`~spurdyn.solvers.sector.step_compiled.run_steps`, and its stepper.

By generalized-alpha (docs/implicit.md, section 1), with the equations of motion linear and
the contact rows held over a step, a step is one solve per gear with the factor of
``S = M + gamma' C + beta' K`` and a complementarity problem of as many unknowns as pairs
near the path,

    W F + v >= 0,  F >= 0,  F (W F + v) = 0,   W = beta' G S^-1 G^T + c_H I + C_res,

``v`` the pairs' gaps at the end of the step without their forces, ``c_H`` the strip's
curvature compliance and ``C_res`` the modal bodies' residual compliance. The strips'
half-widths follow the forces of the step before. The mesh damper
``c = 2 zeta sqrt(k(phi) m_e)`` acts along the line of action on the rate of the pairs'
whole deflection, ``-D q_dot`` with ``D`` the rows' hub entries, for the pairs in contact at
the step before, shared by their forces; its ``gamma' D^T C D`` is taken by Woodbury's
formula, so the factors stay the run's.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from spurdyn.sector.damper import damper_at
from spurdyn.sector.faces import closed_start
from spurdyn.sector.fault_bodies import row_forces
from spurdyn.sector.lcp import Rows, lcp, lcp_pivot
from spurdyn.sector.model import SectorModel
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_LCP, FAIL_NAN, OK, SectorStepState
from spurdyn.solvers.sector.stepper import SectorRecord, SectorStepper


class ImplicitStep(NamedTuple):
    """One step's outcome: the new ``state`` (the old one where the step failed before its
    update), the ``rows`` it held (``None``: no pair near the path), their residual
    compliance ``c_res`` and mesh damper ``c_pairs``, and the step's ``status``."""

    state: SectorStepState
    rows: Rows | None
    c_res: NDArray[np.float64] | None
    c_pairs: NDArray[np.float64] | None
    status: int


def check_pit(model: SectorModel, st: SectorStepState) -> None:
    """Refuse a state of a model whose pits split contacts without a pit strip's force per
    contact (``st.pit``, -1 where whole): the layout's empty default would restart every
    split pair's strips in proportion at each step (and the compiled loop read past it)."""
    if model.splits and st.pit.size != st.force.size:
        raise ValueError(f"a split model's step state needs pit ({st.force.size},), -1 where a "
                         f"contact is whole; got {st.pit.shape}")


def implicit_step(model: SectorModel, st: SectorStepState, tq: NDArray[np.float64], offset: int = 0) -> ImplicitStep:
    """One generalized-alpha step of ``model`` from ``st`` under the hubs' torques ``tq`` at
    its end (module docstring); ``offset`` the driver's body tooth of pair 0."""
    check_pit(model, st)
    m_, gears, parts = model, model.gears, model.parts
    am, af, beta, gamma, h, bp, gp = m_.am, m_.af, m_.beta, m_.gamma, m_.h, m_.bp, m_.gp
    q, v, acc, qdd, last, last_pit = st.q, st.v, st.acc, st.qdd, st.force, st.pit
    a_part = (af * qdd - am * acc) / (1.0 - am)
    q_hat = q + h * v + h * h * (0.5 - beta) * acc + h * h * beta * a_part
    v_hat = v + h * (1.0 - gamma) * acc + h * gamma * a_part
    r = np.zeros(m_.n)
    r[0], r[m_.na] = tq
    for g in range(2):
        r[parts[g]] -= gears[g].forces(q_hat[parts[g]], v_hat[parts[g]])
    x0 = np.concatenate([gears[g].solve(r[parts[g]]) for g in range(2)]
                        + ([m_.bear.free(q_hat[m_.tpart], v_hat[m_.tpart])] if m_.bear is not None else []))
    rows = m_.rows_at(float(q_hat[0]), last, offset, last_pit if last_pit.size else None)
    force = np.zeros(m_.c_teeth.size)
    pit = np.full(last_pit.size, -1.0)
    faces = np.zeros(st.faces.size)
    c_res = c_pairs = None
    if rows is not None or m_.faces is not None:
        out = _contacts(m_, rows, q_hat, v_hat, x0, st.faces)
        if out is None:
            return ImplicitStep(st, rows, c_res, c_pairs, FAIL_LCP)
        qdd_new, lam, faces, c_res, c_pairs = out
        if rows is not None:     # a split pair's force the sum of its rows'
            np.add.at(force, rows.on, lam)
            if pit.size:
                pit[rows.on[rows.kind == 2]] = lam[rows.kind == 2]
    else:
        qdd_new = x0
    if not np.isfinite(qdd_new).all():
        return ImplicitStep(st, rows, c_res, c_pairs, FAIL_NAN)
    new = SectorStepState(q_hat + bp * qdd_new, v_hat + gp * qdd_new,
                          a_part + (1.0 - af) / (1.0 - am) * qdd_new, qdd_new, force, faces, pit)
    status = OK if m_.theta_lo <= new.q[0] <= m_.theta_hi else FAIL_BEYOND
    return ImplicitStep(new, rows, c_res, c_pairs, status)


def _contacts(m_: SectorModel, rows: Rows | None, q_hat: NDArray[np.float64], v_hat: NDArray[np.float64],
              x0: NDArray[np.float64], last_faces: NDArray[np.float64]) -> Any:
    """The step's accelerations with the pairs ``rows`` in contact (and a crack's faces,
    :func:`_with_faces`): ``(qdd, F, face forces, C_res, c_pairs)``, ``None`` where their
    problem has no solution. ``x0`` the accelerations without them (changed by the mesh
    damper), the rows' forces of the step before ``rows.held`` and the faces'
    ``last_faces``."""
    bp, gp = m_.bp, m_.gp
    if rows is None:        # a crack's faces alone
        p, empty = 0, np.zeros((0, 0))
        cols = [np.zeros((g.n, 0)) for g in m_.gears]
        w0 = w_gd = k_w = w = c_res = empty
        vv = d_x0 = c_pairs = shares = np.zeros(0)
    else:
        p = rows.on.size
        w0, w_gd, w_dd, c_res, cols = m_.compliance(rows)
        # the mesh damper on the rate of the whole approach of the pairs in contact at the
        # step before (the rows' rigid part D, in parallel with the mesh stiffness), shared
        # by their forces: S + gamma' D^T C D, by Woodbury through the pairs' couplings
        shares = rows.held
        c_mesh = damper_at(m_.c_table, m_.pitch, float(q_hat[0]))
        c_pairs = c_mesh * shares / shares.sum() if c_mesh > 0.0 and shares.sum() > 0.0 else np.zeros(p)
        if c_pairs.any():
            x0 -= m_.rigid_columns_times(rows, c_pairs * m_.rigid_rows(rows, v_hat))
        g_x0, d_x0 = m_.gap_rows(rows, x0), m_.rigid_rows(rows, x0)
        k_w = (gp * c_pairs)[:, None] * np.linalg.inv(np.eye(p) + w_dd * (gp * c_pairs)[None, :]) \
            if c_pairs.any() else np.zeros((p, p))
        w = bp * (w0 - w_gd @ k_w @ w_gd.T) + c_res + m_.c_h * np.eye(p)
        vv = rows.const + m_.gap_rows(rows, q_hat) + bp * (g_x0 - w_gd @ k_w @ d_x0)
    if m_.faces is not None:
        return _with_faces(m_, rows, (w0, w_gd, k_w, c_res, cols), q_hat, x0, d_x0, vv,
                           np.concatenate([shares > 0.0, last_faces > 0.0]), c_pairs)
    lam, found = lcp(0.5 * (w + w.T), vv, shares > 0.0)
    if not found:
        return None
    qdd_new = x0 + m_.columns_times(cols, lam) - m_.rigid_columns_times(rows, k_w @ (d_x0 + w_gd.T @ lam))
    return qdd_new, lam, np.zeros(0), c_res, c_pairs


def _with_faces(m_: SectorModel, rows: Rows | None, pairs: tuple[Any, ...], q_hat: NDArray[np.float64],
                x0: NDArray[np.float64], d_x0: NDArray[np.float64], vv: NDArray[np.float64],
                guess: NDArray[np.bool_], c_pairs: NDArray[np.float64]) -> Any:
    """:func:`_contacts` with a crack's faces: their rows beside the pairs' in one problem
    (docs/faults.md, "The crack's faces in motion"), ``pairs`` the pairs' ``(G S^-1 G^T,
    G S^-1 D^T, the damper's Woodbury K, C_res, S^-1 G^T per gear)``; ``C_res`` of the
    result over pairs and faces."""
    fc, bp = m_.faces, m_.bp
    w0, w_gd, k_w, c_res, cols = pairs
    p = vv.size
    w_fc, w_fd, r_fc = fc.blocks(rows, m_.z_theta)
    w_all = np.block([[w0, w_fc.T], [w_fc, fc.w_ff]])
    w_gd_all = np.vstack([w_gd, w_fd])
    res = np.block([[c_res, r_fc.T], [r_fc, fc.r_ff]])
    w = bp * (w_all - w_gd_all @ k_w @ w_gd_all.T) + res
    w[:p, :p] += m_.c_h * np.eye(p)
    v_f = fc.rows(m_.parts, q_hat + bp * x0) - bp * (w_fd @ k_w @ d_x0)
    lam, found = lcp_pivot(0.5 * (w + w.T), np.concatenate([vv, v_f]), guess)
    if not found:
        return None
    qdd_new = x0 + fc.times(m_.parts, lam[p:], m_.n)
    if rows is not None:
        qdd_new += m_.columns_times(cols, lam[:p]) - m_.rigid_columns_times(rows, k_w @ (d_x0 + w_gd_all.T @ lam))
    return qdd_new, lam[:p], lam[p:], res, c_pairs


class ImplicitStepper(SectorStepper):
    """:func:`implicit_step` step by step, every step's samples (and, if asked, the energy
    balance and the hubs' momenta) into the record."""

    keeps_energy = True

    def __init__(self, model: SectorModel, record: SectorRecord, offset: int = 0, energy: bool = False) -> None:
        super().__init__(model, record, offset, energy)
        start = model.start()
        self.start_state = start
        faces = model.faces
        self.state = SectorStepState(start.q, start.v, start.acc, start.qdd, start.force,
                                     np.zeros(faces.size if faces is not None else 0),
                                     np.full(start.force.size, -1.0))
        self.c_res = np.zeros((0, 0))
        self.damper_torque = [0.0, 0.0]     # the mesh damper's torques on the hubs at the last step
        q, na = start.q, model.na
        rows0 = model.rows_at(0.0, start.force, start.offset)
        if rows0 is not None:
            self.c_res = model.compliance(rows0)[3]
        if faces is not None:       # the residual compliance over the pairs and the faces
            r_fc = faces.blocks(rows0, model.z_theta)[2]
            self.c_res = np.block([[self.c_res, r_fc.T], [r_fc, faces.r_ff]])
            if start.reset is None:     # a static start: the faces closed where they would overlap
                # per row: a split pair's strips their shares of its force, not each the whole
                self.state.faces[:] = closed_start(faces, model.parts, q, r_fc,
                                                   rows0.held if rows0 is not None else np.zeros(0))
        # the torques' work (J), by the trapezoid rule between saved steps (exact for constant ones)
        self.work = [float(record.torque[0] @ np.array([q[0], q[na]])), q[0], q[na]]
        self.save(0, rows0)

    def _steps(self, n: int) -> tuple[int, int]:
        model, offset = self.model, self.start_state.offset
        for k in range(n):
            step = self.index + k + 1
            out = implicit_step(model, self.state, self.record.torque[step], offset)
            if out.status in (FAIL_NAN, FAIL_LCP):
                return k, out.status
            self.state = out.state
            if out.status != OK:
                return k, out.status
            if out.c_res is not None:
                self.c_res = out.c_res
            if self.energy:
                self.damper_torque[:] = [0.0, 0.0]
                if out.rows is not None and out.c_pairs.any():
                    rate = out.c_pairs * model.rigid_rows(out.rows, self.state.v)
                    self.damper_torque[:] = [-float(coef @ rate) for coef, _ in out.rows.sides]
            self.save(step, out.rows)
            self.reached = step
        return n, OK

    def save(self, i: int, rows: Rows | None) -> None:
        """Step ``i``'s samples into the record: with a crack its faces' largest force and
        their least and largest opening (``B^T Phi eta + C_res`` of the forces, its rows
        after the pairs')."""
        model, rec, st = self.model, self.record, self.state
        q, v, force = st.q, st.v, st.force
        na, c_res = model.na, self.c_res
        rec.theta[i] = q[0], q[na]
        rec.omega[i] = v[0], v[na]
        rec.force[i] = force
        rec.keep_state(i, q)
        if model.bear is not None:
            rec.hubs[i] = np.concatenate([q[model.tpart], v[model.tpart]])
        fo = np.zeros(0) if rows is None else force[rows.on] if not rows.kind.any() else \
            row_forces(rows.kind, rows.share, force[rows.on], st.pit[rows.on])
        if model.faces is not None:
            fo = np.concatenate([fo, st.faces])
            opening = model.faces.rows(model.parts, q) + c_res[fo.size - st.faces.size:] @ fo
            rec.faces[i] = st.faces.max(), opening.min(), opening.max()
        if rows is not None:
            p = rows.on.size
            gaps = model.gap_rows(rows, q) + rows.const + model.c_h * fo[:p] + c_res[:p] @ fo
            rec.gap[i] = float(gaps.min())
        if rec.energy is not None:
            rec.energy[i] = self.energy_row(i, rows, fo)

    def energy_row(self, i: int, rows: Rows | None, fo: NDArray[np.float64]) -> tuple[Any, ...]:
        """Step ``i``'s energy balance and the hubs' momenta with the pairs' torques on them."""
        model, work = self.model, self.work
        q, v, force = self.state.q, self.state.v, self.state.force
        gears, parts, na, tq = model.gears, model.parts, model.na, self.record.torque
        if i > 0:
            work[0] += 0.5 * float((tq[i - 1] + tq[i]) @ np.array([q[0] - work[1], q[na] - work[2]]))
            work[1:] = q[0], q[na]
        res = 0.5 * float(fo @ self.c_res @ fo) if fo.size else 0.0
        # the hubs' translations and their bearings' springs
        bear = model.bear
        t_kin, t_strain = (bear.kinetic(v[model.tpart]), bear.strain(q[model.tpart])) if bear is not None else (0, 0)
        return (sum(gears[g].kinetic(v[parts[g]]) for g in range(2)) + t_kin,
                sum(gears[g].strain(q[parts[g]]) for g in range(2)) + res + t_strain,
                0.5 * model.c_h * float(force @ force if rows is None or not rows.kind.any() else
                                        fo[:rows.on.size] @ fo[:rows.on.size]), work[0],
                *(gears[g].momentum(v[parts[g]]) for g in range(2)),
                # the pairs' generalised forces on the hubs: the rows' hub entries, and the
                # mesh damper's torques (it acts on the hubs)
                *((float(rows.sides[g][0] @ fo[:rows.on.size]) if rows is not None else 0.0) + self.damper_torque[g]
                  for g in range(2)))


__all__ = ["ImplicitStep", "ImplicitStepper", "check_pit", "implicit_step"]
