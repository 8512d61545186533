"""One step of the implicit integrator in NumPy (docs/implicit.md, section 2): the twin of
:func:`spurdyn.solvers.implicit.step_compiled.step`.

Generalized-alpha in the form of Arnold and Bruls for constrained mechanical systems: the
equations of motion and the constraints hold at ``t_{n+1}``,

    M qddot_{n+1} = F(q_{n+1}, qdot_{n+1}, t_{n+1}) + G(q_{n+1})^T x_{n+1},
    -Phi(q_{n+1}) = 0,      s(q_{n+1}) + c_H p_{n+1} = 0 while in contact (else p = 0),

and an acceleration-like sequence ``a`` carries the numerical dissipation,

    (1 - am) a_{n+1} + am a_n = (1 - af) qddot_{n+1} + af qddot_n,
    q_{n+1} = q_n + h qdot_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1},
    qdot_{n+1} = qdot_n + h (1 - gamma) a_n + h gamma a_{n+1}.

Newton on ``(q_{n+1}, x_{n+1})``, the contact's active set decided in each iterate
(semismooth: in contact while ``p - kappa (s + c_H p) < 0``). The iteration matrix
``S = M / beta' + (gamma' / beta') C + K_T`` has, per tooth, the block
``R (m (1 / beta' + a gamma' / beta') + K (1 + b gamma' / beta')) R^T``: the matrix in
brackets is the same at every step (the lumped mass is the same in every direction), so
it is factorised once for the run and each solve only turns the vectors into the disk's
frame and back. The constraints enter by their Schur complement ``G S^-1 G^T``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.linalg import splu

from spurdyn.contact.hertz import strip_compliance
from spurdyn.contact.search_numpy import ContactPair
from spurdyn.geometry.involute import rot
from spurdyn.iso6336.dynamics import reduced_mass
from spurdyn.model.alpha import GeneralizedAlpha
from spurdyn.model.damper import mesh_damper_coefficient
from spurdyn.model.loading import static_force
from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.layout import FAIL_NAN, FAIL_NEWTON, FAIL_STRIP, OK
from spurdyn.solvers.paper.constants import MAX_RELOCATE, RELOCATE
from spurdyn.solvers.implicit.damping import rayleigh_forces
from spurdyn.solvers.paper.dynamics_numpy import (
    blocks, contact_at, elastic, jacobian, root_phi, strip_law, torques,
)
from spurdyn.solvers.paper.step_numpy import initial_state


@dataclass
class ImplicitState:
    """Positions, velocities, accelerations, the scheme's ``a`` and the forces at ``t``."""

    t: float
    theta: NDArray[np.float64]   # (2,)
    omega: NDArray[np.float64]   # (2,)
    u: NDArray[np.float64]       # (n_u,)
    v: NDArray[np.float64]       # (n_u,)
    x: NDArray[np.float64]       # (n_x,) [lambda_A, lambda_B, p]
    contact: ContactPair
    qdd: NDArray[np.float64]     # (2 + n_u,) accelerations [alpha_A, alpha_B, u_ddot]
    acc: NDArray[np.float64]     # (2 + n_u,) the scheme's acceleration-like variable a


@dataclass(frozen=True)
class ImplicitScheme:
    """What both implicit steppers read of a run besides the model: the scheme's
    coefficients ``coef`` and ``bp = beta'``, ``gp = gamma'`` at the step; the strip's
    ``law`` ``(E*, L)`` (None for the point contact) and its compliance ``c_h``; ``mq`` the
    masses of ``q = [theta, u]``; ``base`` ``(r_bA, -r_bB)``; ``c_mesh`` the mesh damper."""

    coef: GeneralizedAlpha
    bp: float
    gp: float
    law: tuple[float, float] | None
    c_h: float
    mq: NDArray[np.float64]
    base: NDArray[np.float64]
    c_mesh: float


def implicit_scheme(system: PairSystem, settings: RunSettings) -> ImplicitScheme:
    """The :class:`ImplicitScheme` of a run (the mesh damper from the pair's static
    stiffness at the pitch point, when ``settings.damping_ratio`` asks for one)."""
    coef = GeneralizedAlpha(settings.rho_inf)
    h = settings.dt
    law = strip_law(system) if settings.contact == "hertz" else None
    ra, rb = (g.base_radius for g in system.gears)
    c_mesh = 0.0
    if settings.mesh_damping > 0.0:
        from spurdyn.solvers.paper.statics import static_stiffness

        pair = system.pair
        k = static_stiffness(system, pair.pitch_roll_a, static_force(pair, settings.torque),
                             settings.contact).stiffness
        m_e = reduced_mass(system.gears[0].inertia, system.gears[1].inertia, ra, rb)
        c_mesh = mesh_damper_coefficient(settings.mesh_damping, k, m_e)
    return ImplicitScheme(
        coef=coef, bp=coef.beta_prime(h), gp=coef.gamma_prime(h), law=law,
        c_h=strip_compliance(*law) if law is not None else 0.0,
        mq=np.concatenate([[g.inertia for g in system.gears], system.mass]),
        base=np.array([ra, -rb]),    # d(delta)/d(theta): delta = r_bA th_A - r_bB th_B
        c_mesh=c_mesh)


def generalized_forces(system: PairSystem, settings: RunSettings, scheme: ImplicitScheme,
                       theta: NDArray[np.float64], omega: NDArray[np.float64],
                       u: NDArray[np.float64], v: NDArray[np.float64],
                       touching: bool) -> NDArray[np.float64]:
    """``F(q, qdot)``: torques, elastic and damping forces, stacked like ``q``."""
    s = system
    out = np.empty(2 + s.n_u)
    out[:2] = torques(s, settings.torque, theta)
    fu = blocks(s, out[2:])
    for g, (gb, ub, vb) in enumerate(zip(s.gears, blocks(s, u), blocks(s, v))):
        q, f = elastic(gb, theta[g], ub, settings.keep_theta_term)
        out[g] += q
        fu[g][:] = f
        if any(settings.rayleigh):
            qd, fd = rayleigh_forces(gb, theta[g], omega[g], ub, vb, *settings.rayleigh)
            out[g] += qd
            fu[g] += fd
    if touching and scheme.c_mesh:
        out[:2] -= scheme.c_mesh * float(scheme.base @ omega) * scheme.base
    return out


def state_at(system: PairSystem, settings: RunSettings, scheme: ImplicitScheme,
             theta: NDArray[np.float64], omega: NDArray[np.float64], u: NDArray[np.float64],
             v: NDArray[np.float64], x: NDArray[np.float64], contact: ContactPair,
             t: float = 0.0) -> ImplicitState:
    """The state at ``t`` with the accelerations of the forces ``x`` (``a = qddot``)."""
    touching = bool(x[-1] < 0.0)
    f = generalized_forces(system, settings, scheme, theta, omega, u, v, touching)
    gmat = jacobian(system, theta, contact)
    qdd = (f + gmat.T @ x) / scheme.mq
    return ImplicitState(t=t, theta=theta.copy(), omega=omega.copy(), u=u.copy(), v=v.copy(),
                         x=x.copy(), contact=contact, qdd=qdd, acc=qdd.copy())


def initial_implicit_state(system: PairSystem, settings: RunSettings,
                           scheme: ImplicitScheme) -> ImplicitState:
    """The implicit steppers' start: the paper's
    (:func:`~spurdyn.solvers.paper.step_numpy.initial_state`: the teeth just touching,
    turning rigidly, with the forces of an acceleration stage at ``t = 0``) with the
    accelerations those forces give."""
    s0 = initial_state(system, settings)
    return state_at(system, settings, scheme, s0.theta, s0.omega, s0.u, s0.v, s0.x, s0.contact,
                    s0.t)


class ImplicitMethod:
    """The generalized-alpha step of the paper's model (one tooth per gear, one contact)."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        self.system, self.case = system, settings
        self.scheme = sc = implicit_scheme(system, settings)
        self.coef, self.bp, self.gp, self.law, self.c_h = sc.coef, sc.bp, sc.gp, sc.law, sc.c_h
        self.mq, self.base, self.c_mesh = sc.mq, sc.base, sc.c_mesh
        self.contact_at = lambda theta, u, guess, load=0.0: contact_at(
            system, theta, u, guess, load, self.law)
        ratio = self.gp / self.bp
        a, b = settings.rayleigh
        # the teeth's blocks of S in the disk frame, factorised once
        self.lu = [splu(sp.csc_matrix(sp.diags(g.mass * (1.0 / self.bp + a * ratio))
                                      + (1.0 + b * ratio) * g.stiffness)) for g in system.gears]
        # ... and their inverses' columns at the root DOFs, (n_u, n_root, 2) per gear: the
        # root constraints' columns of S^-1 G^T are these turned by R
        self.root_inv = []
        for g, lu in zip(system.gears, self.lu):
            eye = np.zeros((g.n_u, g.root_dofs.size))
            eye[g.root_dofs, np.arange(g.root_dofs.size)] = 1.0
            self.root_inv.append(lu.solve(eye).reshape(g.n_u, -1, 2))

    # -- forces -------------------------------------------------------------------------
    def forces(self, theta: NDArray[np.float64], omega: NDArray[np.float64], u: NDArray[np.float64],
               v: NDArray[np.float64], touching: bool) -> NDArray[np.float64]:
        """``F(q, qdot)`` (:func:`generalized_forces`)."""
        return generalized_forces(self.system, self.case, self.scheme, theta, omega, u, v, touching)

    # -- the iteration matrix -----------------------------------------------------------
    def theta_block(self, touching: bool) -> NDArray[np.float64]:
        """The disks' 2 x 2 block of ``S`` (their inertia, the mesh damper in contact)."""
        stt = np.diag(self.mq[:2] / self.bp)
        if touching and self.c_mesh:
            stt += (self.gp / self.bp) * self.c_mesh * np.outer(self.base, self.base)
        return stt

    def solve(self, theta: NDArray[np.float64], rhs: NDArray[np.float64], touching: bool) -> NDArray[np.float64]:
        """``S^-1 rhs`` for a vector stacked like ``q``."""
        s = self.system
        out = np.empty_like(rhs)
        out[:2] = np.linalg.solve(self.theta_block(touching), rhs[:2])
        for g, (gb, lu) in enumerate(zip(s.gears, self.lu)):
            lo, hi = 2 + s.offsets[g], 2 + s.offsets[g + 1]
            r = rot(gb.sense * theta[g])
            local = rhs[lo:hi].reshape(-1, 2) @ r          # R^T b, node by node
            out[lo:hi] = (lu.solve(local.ravel()).reshape(-1, 2) @ r.T).ravel()
        return out

    def root_columns(self, theta: NDArray[np.float64], gmat: NDArray[np.float64],
                     touching: bool) -> NDArray[np.float64]:
        """``S^-1 G_root^T`` (n_q, n_root) from the factors' root columns: a root row of
        ``G`` is ``-1`` at one root DOF and ``-Phi_theta`` at its disk."""
        s = self.system
        n_root = sum(s.n_lambda)
        out = np.zeros((2 + s.n_u, n_root))
        out[:2] = np.linalg.solve(self.theta_block(touching), gmat[:n_root, :2].T)
        k = 0
        for g, gb in enumerate(s.gears):
            lo, hi = 2 + s.offsets[g], 2 + s.offsets[g + 1]
            r = rot(gb.sense * theta[g])
            p3 = self.root_inv[g]
            nr = p3.shape[1]
            # A^-1 R^T e_(i,d) = sum_e P[:, i, e] R[d, e], then R node by node, times -1
            cols = p3 @ r.T                                  # (n_u, nr, 2)
            cols = cols.reshape(-1, 2, nr * 2)               # rows node by node
            world = np.einsum("ab,nbk->nak", r, cols)
            out[lo:hi, k:k + 2 * nr] = -world.reshape(hi - lo, 2 * nr)
            k += 2 * nr
        return out

    def root_errors(self, theta: NDArray[np.float64], u: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate([-root_phi(gb, theta[g], ub).ravel()
                               for g, (gb, ub) in enumerate(zip(self.system.gears, blocks(self.system, u)))])

    # -- the step -----------------------------------------------------------------------
    def step(self, st: ImplicitState) -> tuple[ImplicitState, float, int, int]:
        """Advance one step; return the new state, the last residual (m), the Newton
        iterations and the status."""
        settings, sys_, coef = self.case, self.system, self.coef
        h, bp, gp, am, af = settings.dt, self.bp, self.gp, coef.alpha_m, coef.alpha_f
        q_n = np.concatenate([st.theta, st.u])
        v_n = np.concatenate([st.omega, st.v])
        # the predictor: the accelerations of the step before
        qdd = st.qdd.copy()
        acc = ((1.0 - af) * qdd + af * st.qdd - am * st.acc) / (1.0 - am)
        q = q_n + h * v_n + h * h * ((0.5 - coef.beta) * st.acc + coef.beta * acc)
        qd = v_n + h * ((1.0 - coef.gamma) * st.acc + coef.gamma * acc)
        x = st.x.copy()
        load = abs(float(st.x[-1])) if self.law is not None else 0.0
        guess = (st.contact.alpha, st.contact.beta)
        n_root = x.size - 1
        radius = max(float(np.abs(gb.Y).max()) for gb in sys_.gears)
        was = None
        residual = np.inf
        phi, predicted, gap_before = 1.0, None, 0.0
        c_force, moves = None, 0
        z_root, z_touch = None, False
        for it in range(settings.max_iter + 1):
            theta, u = q[:2], q[2:]
            try:
                c = self.contact_at(theta, u, guess, load)
            except FloatingPointError:
                return st, residual, it, FAIL_STRIP
            guess = (c.alpha, c.beta)
            # The force acts where the first iterate found the contact pair, and moves with
            # it only when the pair moves by more than RELOCATE (as in the paper's step):
            # a force that follows every iterate's pair makes G jump at round-off and
            # the iteration cycle at the 1e-12 m level.
            if c_force is None or (abs(c.alpha - c_force.alpha) + abs(c.beta - c_force.beta)
                                   > RELOCATE and moves < MAX_RELOCATE):
                moves += c_force is not None
                c_force = c
                gmat = jacobian(sys_, theta, c_force)
            else:                                   # the root rows turn with the disks
                gmat[:n_root] = jacobian(sys_, theta, c_force)[:n_root]
            gap = c.s + self.c_h * x[-1]           # penetration beyond what the strip allows
            # S with the mesh damper as the force now has it; its solves of G's columns
            was_touching = bool(x[-1] < 0.0)
            # The root columns at the step's first iterate serve its later ones: the disks
            # turn by ~1e-8 rad between iterates, and the residuals stay exact.
            if it == 0 or was_touching != z_touch:
                z_root, z_touch = self.root_columns(theta, gmat, was_touching), was_touching
            z = np.column_stack([z_root, self.solve(theta, gmat[-1], was_touching)])
            # semismooth active set: kappa scales the penetration to a force (the contact
            # row's own dynamic stiffness, 1 / (G S^-1 G^T + c_H)_cc)
            kappa = 1.0 / float(gmat[-1] @ z[:, -1] + self.c_h)
            touching = bool(x[-1] - kappa * gap < 0.0)
            f = self.forces(theta, qd[:2], u, qd[2:], touching)
            r = self.mq * qdd - f - gmat.T @ x
            # minus the constraints c = [-Phi; gap], whose Jacobian is G: c + G dq + D dx = 0
            e = -np.append(self.root_errors(theta, u), gap)
            rows = n_root + 1 if touching else n_root
            g_act = gmat[:rows]
            if not touching:                        # the force goes to zero
                r = r + gmat[-1] * x[-1]
            s_r = self.solve(theta, r, was_touching)
            residual = max(float(np.abs(s_r[2:]).max()), float(np.abs(s_r[:2]).max()) * radius,
                           float(np.abs(e[:rows]).max()) if rows else 0.0,
                           0.0 if touching else abs(float(x[-1])) * kappa ** -1)
            if residual <= settings.tol_disp and touching == was:
                break
            if it == settings.max_iter or not np.isfinite(residual):
                status = FAIL_NEWTON if np.isfinite(residual) else FAIL_NAN
                return st, residual, it, status
            was = touching
            z = z[:, :rows]
            g_con = g_act
            if touching:
                # The point contact measures its gap on splines through the flank's data
                # points but acts through the edge's shape functions, so the gap moves by
                # phi times what the row predicts; phi is learnt from the iterates (a
                # secant on the one contact row; the strip's row is its gap's gradient in u, its
                # pair sitting on the rigid flanks: docs/solver.md 11.2).
                if was and predicted is not None and abs(predicted) > 1e-18:
                    phi = min(max((gap - gap_before) / predicted, 0.1), 10.0)
                g_con = g_act.copy()
                g_con[-1] *= phi
            cmat = g_con @ z
            if touching:
                cmat[-1, -1] += self.c_h
            dx = np.linalg.solve(cmat, e[:rows] + g_con @ s_r)
            dq = z @ dx - s_r
            predicted = float(g_act[-1] @ dq + self.c_h * dx[-1]) if touching else None
            gap_before = gap
            x[:rows] += dx
            if not touching:
                x[-1] = 0.0
            q += dq
            qdd += dq / bp
            qd += dq * (gp / bp)
        acc = ((1.0 - af) * qdd + af * st.qdd - am * st.acc) / (1.0 - am)
        if self.law is not None:
            # the next step's strip is the one of the force now; the gap kept is the one the
            # constraint holds, the strip's mean deformed gap s_bar - c_H |p|
            try:
                c = self.contact_at(q[:2], q[2:], guess, abs(float(x[-1])))
            except FloatingPointError:
                return st, residual, it, FAIL_STRIP
            c = replace(c, s=c.s + self.c_h * float(x[-1]))
        new = ImplicitState(t=st.t + h, theta=q[:2].copy(), omega=qd[:2].copy(), u=q[2:].copy(),
                            v=qd[2:].copy(), x=x, contact=c, qdd=qdd, acc=acc)
        return new, residual, it, OK

    def initial(self, theta: NDArray[np.float64], omega: NDArray[np.float64], u: NDArray[np.float64],
                v: NDArray[np.float64], x: NDArray[np.float64], contact: ContactPair,
                t: float = 0.0) -> ImplicitState:
        """The state at ``t`` with the accelerations of the forces ``x`` (:func:`state_at`)."""
        return state_at(self.system, self.case, self.scheme, theta, omega, u, v, x, contact, t)
