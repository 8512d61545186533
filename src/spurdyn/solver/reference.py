"""The paper's step in plain NumPy: the reference the compiled solver is tested against.

One step ``t -> t + dt`` (paper section 3, docs/solver.md):

1. displacement stage: iterate ``x = [lambda; p]``; for each iterate integrate the
   equations of motion over the step by classical RK4 with the constraint force
   ``G_n^T x`` held fixed (``G_n`` the constraint Jacobian at the start of the step),
   find the contact pair on the new flanks, and update ``x`` from ``e = [-Phi; pi]``;
2. velocity stage: the same with the velocity errors ``[-Phi_q qdot; pi_hat]``, the
   positions kept from stage 1;
3. acceleration stage: ``qddot = M^-1 (F(q) + G^T x)`` at ``t + dt`` with the errors
   ``[-Phi_q qddot - (Phi_q qdot)_q qdot; pi_tilde]``.

The ``x`` of stage 3 is the force at ``t + dt``: it is reported, and it is the force the
next step starts from. Everything here re-integrates; nothing is superposed.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from spurdyn.contact.reference import ContactPair, find_contact, sliding_acceleration
from spurdyn.model.loading import gear_torques
from spurdyn.solver.case import RunCase
from spurdyn.solver.iteration import accelerated_update
from spurdyn.solver.system import GearBody, PairSystem


#: The contact force moves to the contact pair found by an iterate when the pair has moved
#: by more than this (flank coordinate, i.e. elements) from where the force acts, at most
#: MAX_RELOCATE times a step. Smooth meshing moves the pair ~1e-4 element a step and never
#: triggers it; after an impact, waves on the flanks can make the pair jump a large part
#: of an element within a step, and a force left behind cannot close the gap there.
RELOCATE = 0.05
MAX_RELOCATE = 4


class ConvergenceError(RuntimeError):
    """A stage did not converge within its iteration cap."""

    def __init__(self, step: int, stage: str, residual: float, tol: float, iterations: int) -> None:
        self.step, self.stage, self.residual, self.tol = step, stage, residual, tol
        super().__init__(f"step {step}: the {stage} stage did not converge in {iterations} "
                         f"iterations (residual {residual:.3e}, tolerance {tol:.3e})")


class NonFiniteError(RuntimeError):
    """The state became NaN (or infinite) within a step."""

    def __init__(self, step: int) -> None:
        self.step = step
        super().__init__(f"the solution became NaN at step {step}")


def rot(phi: float) -> NDArray[np.float64]:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


@dataclass
class State:
    """Positions, velocities and the last accurate forces of the system at time ``t``."""

    t: float
    theta: NDArray[np.float64]   # (2,)
    omega: NDArray[np.float64]   # (2,)
    u: NDArray[np.float64]       # (n_u,)
    v: NDArray[np.float64]       # (n_u,)
    x: NDArray[np.float64]       # (n_x,)  [lambda_A, lambda_B, p] at t
    contact: ContactPair         # the contact pair at t

    def copy(self) -> "State":
        return replace(self, theta=self.theta.copy(), omega=self.omega.copy(), u=self.u.copy(),
                       v=self.v.copy(), x=self.x.copy())


@dataclass
class StepReport:
    """What a step leaves besides the new state."""

    residual: NDArray[np.float64]     # (3,)
    iterations: NDArray[np.int64]     # (3,)
    p_bar: float
    s: float


# -- the model ---------------------------------------------------------------------------

def blocks(system: PairSystem, u: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    o = system.offsets
    return [u[o[0]:o[1]], u[o[1]:o[2]]]


def elastic(gb: GearBody, theta: float, u: NDArray[np.float64],
            keep_theta_term: bool = True) -> tuple[float, NDArray[np.float64]]:
    """Elastic generalised forces ``(Q_theta, f_u)`` of one gear: ``-(dw/dq)^T K w``."""
    r = rot(gb.sense * theta)
    y = (gb.Y + u).reshape(-1, 2)
    w = (y @ r).ravel() - gb.Y                 # R^T y - Y, node by node
    kw = gb.stiffness @ w
    f = -(kw.reshape(-1, 2) @ r.T).ravel()     # -R K w
    q = 0.0
    if keep_theta_term:
        w2, k2 = w.reshape(-1, 2), kw.reshape(-1, 2)
        q = gb.sense * float(np.sum(w2[:, 0] * k2[:, 1] - w2[:, 1] * k2[:, 0]))
    return q, f


def root_phi_theta(gb: GearBody, theta: float) -> NDArray[np.float64]:
    """``dPhi/dtheta`` of the root constraints ``(n_root, 2)``: ``-s R Jz Y_i``."""
    r = rot(gb.sense * theta)
    y = gb.Y.reshape(-1, 2)[gb.root_nodes]
    jy = np.column_stack([-y[:, 1], y[:, 0]])
    return -gb.sense * jy @ r.T


def root_phi(gb: GearBody, theta: float, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """Root constraints ``Phi_i = u_i - (R - I) Y_i`` ``(n_root, 2)``."""
    r = rot(gb.sense * theta)
    y = gb.Y.reshape(-1, 2)[gb.root_nodes]
    return u.reshape(-1, 2)[gb.root_nodes] - (y @ r.T - y)


def constraint_force(system: PairSystem, theta: NDArray[np.float64], contact: ContactPair,
                     x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Generalised constraint force ``G^T x = -Phi_q^T lambda + s_q^T p`` ``(f_theta, f_u)``."""
    f_theta = np.zeros(2)
    f_u = np.zeros(system.n_u)
    fu = blocks(system, f_u)
    k = 0
    for g, gb in enumerate(system.gears):
        nr = gb.root_nodes.size
        lam = x[k:k + 2 * nr].reshape(-1, 2)
        k += 2 * nr
        fb = fu[g].reshape(-1, 2)
        fb[gb.root_nodes] -= lam
        f_theta[g] = -float(np.sum(root_phi_theta(gb, theta[g]) * lam))
    p = x[-1]
    fa, fb = fu[0].reshape(-1, 2), fu[1].reshape(-1, 2)
    np.add.at(fa, contact.nodes_a, np.outer(contact.weights_a, contact.normal) * p)
    np.add.at(fb, contact.nodes_b, -np.outer(contact.weights_b, contact.normal) * p)
    return f_theta, f_u


def jacobian(system: PairSystem, theta: NDArray[np.float64], contact: ContactPair) -> NDArray[np.float64]:
    """Dense ``G = [-Phi_q; s_q]`` over ``q = [theta_A, theta_B, u]``."""
    g_mat = np.zeros((system.n_x, 2 + system.n_u))
    k = 0
    for g, gb in enumerate(system.gears):
        off = 2 + system.offsets[g]
        pt = root_phi_theta(gb, theta[g])
        for i, node in enumerate(gb.root_nodes):
            for d in range(2):
                g_mat[k, g] = -pt[i, d]
                g_mat[k, off + 2 * node + d] = -1.0
                k += 1
    for nodes, w, sign, g in ((contact.nodes_a, contact.weights_a, 1.0, 0),
                              (contact.nodes_b, contact.weights_b, -1.0, 1)):
        off = 2 + system.offsets[g]
        for node, wk in zip(nodes, w):
            g_mat[-1, off + 2 * node:off + 2 * node + 2] += sign * wk * contact.normal
    return g_mat


def inverse_mass(system: PairSystem) -> NDArray[np.float64]:
    return np.concatenate([[1.0 / system.gears[0].inertia, 1.0 / system.gears[1].inertia],
                           1.0 / system.mass])


class ReferenceStepper:
    """The paper's method, step by step, in NumPy (slow, plain, the reference)."""

    def __init__(self, system: PairSystem, case: RunCase) -> None:
        self.system = system
        self.case = case
        self.minv = inverse_mass(system)
        self.tau0 = case.torque

    # -- equations of motion -----------------------------------------------------------
    def torques(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        ta, tb = gear_torques(self.system.pair, self.tau0, theta[0], theta[1])
        return np.array([float(ta), float(tb)])

    def accelerations(self, theta: NDArray[np.float64], u: NDArray[np.float64],
                      f_theta: NDArray[np.float64], f_u: NDArray[np.float64]
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        s = self.system
        tau = self.torques(theta)
        alpha = np.zeros(2)
        a = np.empty(s.n_u)
        for g, (gb, ub, ab) in enumerate(zip(s.gears, blocks(s, u), blocks(s, a))):
            q, f = elastic(gb, theta[g], ub, self.case.keep_theta_term)
            alpha[g] = (tau[g] + q + f_theta[g]) / gb.inertia
            ab[:] = f
        a += f_u
        a /= s.mass
        return alpha, a

    def rk4(self, st: State, f_theta: NDArray[np.float64], f_u: NDArray[np.float64]
            ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Classical RK4 over one step with the constraint force held fixed."""
        h = self.case.dt
        th, om, u, v = st.theta, st.omega, st.u, st.v
        k1 = (om, v, *self.accelerations(th, u, f_theta, f_u))
        k2s = (th + 0.5 * h * k1[0], om + 0.5 * h * k1[2], u + 0.5 * h * k1[1], v + 0.5 * h * k1[3])
        k2 = (k2s[1], k2s[3], *self.accelerations(k2s[0], k2s[2], f_theta, f_u))
        k3s = (th + 0.5 * h * k2[0], om + 0.5 * h * k2[2], u + 0.5 * h * k2[1], v + 0.5 * h * k2[3])
        k3 = (k3s[1], k3s[3], *self.accelerations(k3s[0], k3s[2], f_theta, f_u))
        k4s = (th + h * k3[0], om + h * k3[2], u + h * k3[1], v + h * k3[3])
        k4 = (k4s[1], k4s[3], *self.accelerations(k4s[0], k4s[2], f_theta, f_u))
        w = h / 6.0
        return (th + w * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]),
                om + w * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]),
                u + w * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]),
                v + w * (k1[3] + 2 * k2[3] + 2 * k3[3] + k4[3]))

    # -- constraint errors -------------------------------------------------------------
    def contact_at(self, theta: NDArray[np.float64], u: NDArray[np.float64], guess: tuple[float, float]) -> ContactPair:
        s = self.system
        ua, ub = blocks(s, u)
        xa = s.gears[0].X + ua.reshape(-1, 2)
        xb = s.gears[1].X + ub.reshape(-1, 2)
        ra, rb = (rot(g.sense * th) for g, th in zip(s.gears, theta))
        return find_contact(s.gears[0].flank, s.gears[1].flank, xa, xb, ra, rb, guess)

    def root_errors(self, theta: NDArray[np.float64], u: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate([-root_phi(gb, theta[g], ub).ravel()
                               for g, (gb, ub) in enumerate(zip(self.system.gears, blocks(self.system, u)))])

    def root_velocity_errors(self, theta: NDArray[np.float64], omega: NDArray[np.float64],
                             v: NDArray[np.float64]) -> NDArray[np.float64]:
        out = []
        for g, (gb, vb) in enumerate(zip(self.system.gears, blocks(self.system, v))):
            pt = root_phi_theta(gb, theta[g])
            out.append(-(vb.reshape(-1, 2)[gb.root_nodes] + pt * omega[g]).ravel())
        return np.concatenate(out)

    def root_acceleration_errors(self, theta: NDArray[np.float64], omega: NDArray[np.float64],
                                 alpha: NDArray[np.float64], a: NDArray[np.float64]) -> NDArray[np.float64]:
        out = []
        for g, (gb, ab) in enumerate(zip(self.system.gears, blocks(self.system, a))):
            pt = root_phi_theta(gb, theta[g])
            r = rot(gb.sense * theta[g])
            y = gb.Y.reshape(-1, 2)[gb.root_nodes]
            out.append(-(ab.reshape(-1, 2)[gb.root_nodes] + pt * alpha[g] + (y @ r.T) * omega[g] ** 2).ravel())
        return np.concatenate(out)

    def pinned(self, c: ContactPair, theta: NDArray[np.float64], u: NDArray[np.float64]) -> ContactPair:
        """The contact pair ``c`` (where the force acts) with its penetration measured
        along its normal between its material points at ``(theta, u)``: the gap the
        ``"pinned"`` method closes once the deepest point will not settle."""
        pos = np.concatenate([g.X.ravel() for g in self.system.gears]) + u
        mats = tuple(rot(g.sense * th) for g, th in zip(self.system.gears, theta))
        return replace(c, s=self.normal_of(c, pos, mats))

    def normal_of(self, c: ContactPair, vec: NDArray[np.float64], mats: tuple[NDArray[np.float64], NDArray[np.float64]]) -> float:
        """``n . (a_A - a_B)`` of the contact material points for a stacked nodal vector
        (velocities or accelerations), with ``mats`` the disks' action on the offsets ``delta``."""
        va, vb = blocks(self.system, vec)
        pa = c.weights_a @ va.reshape(-1, 2)[c.nodes_a] + mats[0] @ c.delta_a
        pb = c.weights_b @ vb.reshape(-1, 2)[c.nodes_b] + mats[1] @ c.delta_b
        return float(c.normal @ (pa - pb))

    def velocity_mats(self, theta: NDArray[np.float64], omega: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """``sense omega R Jz`` per gear: the velocity of a point fixed to the disk is this times its offset."""
        jz = np.array([[0.0, -1.0], [1.0, 0.0]])
        return tuple(g.sense * omega[i] * rot(g.sense * theta[i]) @ jz for i, g in enumerate(self.system.gears))

    def acceleration_mats(self, theta: NDArray[np.float64], omega: NDArray[np.float64],
                          alpha: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """``sense alpha R Jz - omega^2 R`` per gear."""
        jz = np.array([[0.0, -1.0], [1.0, 0.0]])
        out = []
        for i, g in enumerate(self.system.gears):
            r = rot(g.sense * theta[i])
            out.append(g.sense * alpha[i] * r @ jz - omega[i] ** 2 * r)
        return tuple(out)

    # -- the step ----------------------------------------------------------------------
    def step(self, st: State, index: int = 0) -> tuple[State, StepReport]:
        """Advance one time step by the paper's three stages."""
        case, sys_ = self.case, self.system
        h, nlev, cap = case.dt, case.accel_levels, case.max_iter
        gmat = jacobian(sys_, st.theta, st.contact)
        cbase = (gmat * self.minv) @ gmat.T
        guess = (st.contact.alpha, st.contact.beta)
        residual = np.zeros(3)
        iters = np.zeros(3, dtype=np.int64)

        # Stage 1: displacements. The contact force acts where the contact pair is: when an
        # iterate finds the pair moved (by more than RELOCATE in flank coordinates), the
        # force moves with it for the next iterates.
        x = st.x.copy()
        c_force = st.contact
        moves = 0
        for m in range(cap + 1):
            f_theta, f_u = constraint_force(sys_, st.theta, c_force, x)
            th1, om1_, u1, v1_ = self.rk4(st, f_theta, f_u)
            if not (np.isfinite(th1).all() and np.isfinite(u1).all()
                    and np.isfinite(om1_).all() and np.isfinite(v1_).all()):
                raise NonFiniteError(index)  # before the spline refuses it
            c1 = self.contact_at(th1, u1, guess)
            if case.pin_after and m >= case.pin_after and moves >= MAX_RELOCATE:
                c1 = self.pinned(c_force, th1, u1)   # "pinned": the gap where the force acts
            pi = c1.s if (x[-1] < 0.0 or c1.s > 0.0) else 0.0
            e = np.append(self.root_errors(th1, u1), pi)
            residual[0] = np.abs(e).max()
            if residual[0] <= case.tol_disp:
                break
            if m == cap:
                raise ConvergenceError(index, "displacement", residual[0], case.tol_disp, m)
            x = accelerated_update(x, e, 0.5 * h * h * cbase, nlev)
            if abs(c1.alpha - c_force.alpha) + abs(c1.beta - c_force.beta) > RELOCATE \
                    and moves < MAX_RELOCATE:
                moves += 1
                c_force = c1
                gmat = jacobian(sys_, st.theta, c_force)
                cbase = (gmat * self.minv) @ gmat.T
        iters[0] = m
        x_bar, p_bar = x.copy(), x[-1]

        # Stage 2: velocities (positions from stage 1, same force directions).
        for m in range(cap + 1):
            f_theta, f_u = constraint_force(sys_, st.theta, c_force, x)
            _, om2, _, v2 = self.rk4(st, f_theta, f_u)
            sh = self.normal_of(c1, v2, self.velocity_mats(th1, om2))
            pih = sh if (p_bar < 0.0 and (sh > 0.0 or x[-1] < 0.0)) else 0.0
            e = np.append(self.root_velocity_errors(th1, om2, v2), pih)
            residual[1] = np.abs(e).max()
            if residual[1] <= case.tol_vel:
                break
            if m == cap:
                raise ConvergenceError(index, "velocity", residual[1], case.tol_vel, m)
            x = accelerated_update(x, e, h * cbase, nlev)
            if p_bar == 0.0:
                x[-1] = 0.0
        iters[1] = m

        # Stage 3: accelerations at t + dt, with the constraint directions there.
        g1 = jacobian(sys_, th1, c1)
        ca = (g1 * self.minv) @ g1.T
        ua, ub = blocks(sys_, u1)
        va, vb = blocks(sys_, v2)
        ra, rb = (rot(g.sense * th) for g, th in zip(sys_.gears, th1))
        ma, mb = self.velocity_mats(th1, om2)
        extra, _, _ = sliding_acceleration(
            sys_.gears[0].flank, sys_.gears[1].flank,
            sys_.gears[0].X + ua.reshape(-1, 2), sys_.gears[1].X + ub.reshape(-1, 2), ra, rb,
            va.reshape(-1, 2), vb.reshape(-1, 2), ma, mb, c1)
        zero = np.zeros(sys_.n_x)
        alpha0, a0 = self.accelerations(th1, u1, *constraint_force(sys_, th1, c1, zero))
        for m in range(cap + 1):
            dq = self.minv * (g1.T @ x)
            alpha, a = alpha0 + dq[:2], a0 + dq[2:]
            st_ = self.normal_of(c1, a, self.acceleration_mats(th1, om2, alpha)) + extra
            pit = st_ if (p_bar < 0.0 and (st_ > 0.0 or x[-1] < 0.0)) else 0.0
            e = np.append(self.root_acceleration_errors(th1, om2, alpha, a), pit)
            residual[2] = np.abs(e).max()
            if residual[2] <= case.tol_acc:
                break
            if m == cap:
                raise ConvergenceError(index, "acceleration", residual[2], case.tol_acc, m)
            x = accelerated_update(x, e, ca, nlev)
            if p_bar == 0.0:
                x[-1] = 0.0
        iters[2] = m
        new = State(t=st.t + h, theta=th1, omega=om2, u=u1, v=v2, x=x, contact=c1)
        return new, StepReport(residual=residual, iterations=iters, p_bar=float(p_bar), s=c1.s)


def initial_contact_guess(system: PairSystem) -> tuple[float, float]:
    """Flank coordinates where the teeth touch at the start of contact: B's tip on A."""
    pair = system.pair
    fa = system.gears[0].flank
    r_start = float(pair.gear_a.radius_at_roll_angle(pair.start_roll_a))
    ts = np.linspace(fa.t0, fa.t1, 4 * fa.n_data)
    xa = system.gears[0].X
    radii = np.array([np.hypot(*(fa.locate(t)[1] @ xa[fa.locate(t)[0]])) for t in ts])
    return float(np.interp(r_start, radii, ts)), system.gears[1].flank.t1


def rigid_velocities(system: PairSystem, omega: NDArray[np.float64]) -> NDArray[np.float64]:
    """Nodal velocities of both teeth turning rigidly with their disks at ``theta = 0``."""
    v = np.empty(system.n_u)
    for g, (gb, vb) in enumerate(zip(system.gears, blocks(system, v))):
        y = gb.Y.reshape(-1, 2)
        vb.reshape(-1, 2)[:] = gb.sense * omega[g] * np.column_stack([-y[:, 1], y[:, 0]])
    return v


def initial_state(stepper: ReferenceStepper) -> State:
    """Teeth just touching at the start of contact, rigid rotation, consistent root forces.

    The forces come from the acceleration stage at ``t = 0`` with the contact inactive
    (the torques are zero there).
    """
    sys_, case = stepper.system, stepper.case
    theta = np.zeros(2)
    omega = np.array([case.speed_a, case.speed_b])
    u = np.zeros(sys_.n_u)
    v = rigid_velocities(sys_, omega)
    contact = stepper.contact_at(theta, u, initial_contact_guess(sys_))
    g0 = jacobian(sys_, theta, contact)
    ca = (g0 * stepper.minv) @ g0.T
    alpha0, a0 = stepper.accelerations(theta, u, np.zeros(2), np.zeros(sys_.n_u))
    x = np.zeros(sys_.n_x)
    for _ in range(case.max_iter):
        dq = stepper.minv * (g0.T @ x)
        e = np.append(stepper.root_acceleration_errors(theta, omega, alpha0 + dq[:2], a0 + dq[2:]), 0.0)
        if np.abs(e).max() <= case.tol_acc:
            break
        x = accelerated_update(x, e, ca, case.accel_levels)
    return State(t=0.0, theta=theta, omega=omega, u=u, v=v, x=x, contact=contact)
