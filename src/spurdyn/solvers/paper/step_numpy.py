"""The paper's step in plain NumPy: the twin the compiled step is tested against.

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

from spurdyn.contact.constants import FLANK
from spurdyn.contact.hertz import strip_compliance
from spurdyn.contact.search_numpy import ContactPair, sliding_acceleration, strip_half_width
from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.geometry.involute import rot
from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.layout import FAIL_ACC, FAIL_DISP, FAIL_NAN, FAIL_VEL, OK
from spurdyn.solvers.paper.constants import BAND_MARGIN, MAX_RELOCATE, RELOCATE
from spurdyn.solvers.paper.dynamics_numpy import (
    accelerations, blocks, constraint_force, contact_at, inverse_mass, jacobian, paper_flanks,
    rigid_flanks, rigid_velocities, root_acceleration_errors, root_phi, root_phi_theta, strip_law, torques,
)
from spurdyn.solvers.paper.iteration_numpy import accelerated_update, band_value


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
    p_held: float = 0.0          # the contact force the last displacement stage held (N)
    jump: float = 0.0            # the gap's move when the last step re-spread its strip (m)

    def copy(self) -> "State":
        return replace(self, theta=self.theta.copy(), omega=self.omega.copy(), u=self.u.copy(),
                       v=self.v.copy(), x=self.x.copy())


#: What the displacement stage hands on: status, ``x``, the force's pair and its
#: ``G M^-1 G^T``, the pair at t + dt, ``theta`` and ``u`` at t + dt.
StageOne = tuple[int, NDArray[np.float64], ContactPair, NDArray[np.float64], ContactPair,
                 NDArray[np.float64], NDArray[np.float64]]


@dataclass
class StepReport:
    """What a step leaves besides the new state: its status
    (:data:`~spurdyn.solvers.layout.OK` or the failure code), and each stage's residual
    and iterations (those of the failing stage where it failed)."""

    residual: NDArray[np.float64]     # (3,)
    iterations: NDArray[np.int64]     # (3,)
    p_bar: float
    s: float
    status: int = OK


class PaperMethod:
    """The paper's method, step by step, in NumPy (slow, plain): the twin of
    :func:`spurdyn.solvers.paper.step_compiled.step`."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        self.system = system
        self.case = settings
        self.minv = inverse_mass(system)
        self.tau0 = settings.torque
        # The distributed contact: its (E*, L) and the strip's compliance c_H.
        self.law = strip_law(system) if settings.contact == "hertz" else None
        self.c_h = strip_compliance(*self.law) if self.law is not None else 0.0

    # -- equations of motion -----------------------------------------------------------
    def torques(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        return torques(self.system, self.tau0, theta)

    def accelerations(self, theta: NDArray[np.float64], u: NDArray[np.float64],
                      f_theta: NDArray[np.float64], f_u: NDArray[np.float64]
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return accelerations(self.system, self.case, theta, u, f_theta, f_u)

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
    def contact_at(self, theta: NDArray[np.float64], u: NDArray[np.float64], guess: tuple[float, float],
                   load: float = 0.0) -> ContactPair:
        return contact_at(self.system, theta, u, guess, load, self.law)

    def restrip(self, c: ContactPair, load: float) -> ContactPair:
        """``c`` with its rows averaged over the strip of the force ``load`` (the same pair)."""
        if self.law is None or c.mode != FLANK:
            return c
        fa, fb = paper_flanks(self.system)
        hw = strip_half_width(fa, fb, c.alpha, c.beta, load, self.law)
        na, wa, da = strip_rows(fa, c.alpha, hw)
        nb, wb, db = strip_rows(fb, c.beta, hw)
        return replace(c, nodes_a=na, weights_a=wa, delta_a=da, nodes_b=nb, weights_b=wb,
                       delta_b=db, half_width=hw)

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
        return root_acceleration_errors(self.system, theta, omega, alpha, a)

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

    def respread_jump(self, old: ContactPair, new: ContactPair, theta: NDArray[np.float64],
                      u: NDArray[np.float64]) -> float:
        """How much re-spreading a strip (``old`` rows to ``new``, the same pair) moves the
        gap its rows hold at ``(theta, u)`` (0 unless both are strips)."""
        if self.law is None or old.half_width <= 0.0 or new.half_width <= 0.0:
            return 0.0
        x = np.concatenate([(g.X + ub.reshape(-1, 2)).ravel()
                            for g, ub in zip(self.system.gears, blocks(self.system, u))])
        mats = tuple(rot(g.sense * th) for g, th in zip(self.system.gears, theta))
        return self.normal_of(new, x, mats) - self.normal_of(old, x, mats)

    @staticmethod
    def roll_rate(c: ContactPair, rates: NDArray[np.float64]) -> float:
        """What the strip's pair rolling with the disks adds to its gap's rate for the
        disks' turning ``rates`` (velocities or accelerations; 0 for the point contact)."""
        return 0.0 if c.roll is None else float(np.dot(c.roll, rates))

    # -- the step ----------------------------------------------------------------------
    def step(self, st: State, index: int = 0) -> tuple[State, StepReport]:
        """Advance one time step by the paper's three stages."""
        residual = np.zeros(3)
        iters = np.zeros(3, dtype=np.int64)
        status, x, c_force, cbase, c1, th1, u1 = self.displacement_stage(st, residual, iters)
        p_bar = x[-1]
        if status == OK:
            status, x, om2, v2 = self.velocity_stage(st, x, c_force, cbase, c1, th1, residual, iters)
        if status == OK:
            status, x = self.acceleration_stage(th1, u1, om2, v2, x, c1, p_bar, residual, iters)
        if status != OK:
            return st, StepReport(residual, iters, float("nan"), float("nan"), status)
        # The next step spreads its force over the strip of the force now (same pair); the gap
        # kept is the one the constraint holds, for a strip its mean deformed gap s_bar - c_H |p|.
        spread = self.restrip(replace(c1, s=c1.s + self.c_h * p_bar), abs(float(x[-1])))
        new = State(t=st.t + self.case.dt, theta=th1, omega=om2, u=u1, v=v2, x=x, contact=spread,
                    p_held=float(p_bar) if self.law is not None else 0.0,
                    jump=self.respread_jump(c1, spread, th1, u1))
        return new, StepReport(residual=residual, iterations=iters, p_bar=float(p_bar), s=c1.s)

    def displacement_stage(self, st: State, residual: NDArray[np.float64],
                           iters: NDArray[np.int64]) -> StageOne:
        """Stage 1: ``(status, x, the force's pair, its G M^-1 G^T, the pair at t + dt, theta
        and u at t + dt)``; the stage's residual and iterations into ``residual[0]``,
        ``iters[0]``.

        The distributed contact spreads the force of this step, and averages its gap, over
        the strip of the force at t (docs/solver.md, section 11): st.contact's rows. The
        contact force acts where the contact pair is: when an iterate finds the pair moved
        (by more than RELOCATE in flank coordinates), the force moves with it for the next
        iterates.
        """
        settings, sys_ = self.case, self.system
        h, nlev, cap = settings.dt, settings.accel_levels, settings.max_iter
        load = abs(float(st.x[-1])) if self.law is not None else 0.0
        c_force = st.contact
        gmat = jacobian(sys_, st.theta, c_force)
        cbase = (gmat * self.minv) @ gmat.T
        guess = (st.contact.alpha, st.contact.beta)
        c_h = self.c_h
        x = st.x.copy()
        moves = 0
        for m in range(cap + 1):
            f_theta, f_u = constraint_force(sys_, st.theta, c_force, x)
            th1, om1_, u1, v1_ = self.rk4(st, f_theta, f_u)
            if not (np.isfinite(th1).all() and np.isfinite(u1).all()
                    and np.isfinite(om1_).all() and np.isfinite(v1_).all()):
                return FAIL_NAN, x, c_force, cbase, st.contact, th1, u1
            c1 = self.contact_at(th1, u1, guess, load)
            touching = x[-1] < 0.0 or c1.s > 0.0
            # The strip's mean curvature separation c_H |p| is an overlap the force allows.
            pi = c1.s + c_h * x[-1] if touching else 0.0
            e = np.append(self.root_errors(th1, u1), pi)
            residual[0] = np.abs(e).max()
            if residual[0] <= settings.tol_disp:
                break
            if m == cap:
                iters[0] = m
                return FAIL_DISP, x, c_force, cbase, c1, th1, u1
            if m == 0:
                # A penetration the band accepts is held, one outside brought just inside
                # it: removing an accepted penetration within one step is the 1/dt^2 spike.
                # The root rows aim at zero as before (their kicks do not reach the force).
                target_p = band_value(e[-1], settings.tol_disp, BAND_MARGIN)
            active = np.ones(e.size, dtype=bool)
            active[-1] = touching
            e_up = e.copy()
            e_up[-1] = e[-1] - target_p if touching else 0.0
            c_disp = 0.5 * h * h * cbase
            c_disp[-1, -1] += c_h
            x = accelerated_update(x, e_up, c_disp, nlev, active)
            if abs(c1.alpha - c_force.alpha) + abs(c1.beta - c_force.beta) > RELOCATE \
                    and moves < MAX_RELOCATE:
                moves += 1
                c_force = c1
                gmat = jacobian(sys_, st.theta, c_force)
                cbase = (gmat * self.minv) @ gmat.T
        iters[0] = m
        return OK, x, c_force, cbase, c1, th1, u1

    def velocity_stage(self, st: State, x: NDArray[np.float64], c_force: ContactPair,
                       cbase: NDArray[np.float64], c1: ContactPair, th1: NDArray[np.float64],
                       residual: NDArray[np.float64], iters: NDArray[np.int64]
                       ) -> tuple[int, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Stage 2 (positions from stage 1, same force directions): ``(status, x, omega and
        v at t + dt)``; the stage's residual and iterations into ``residual[1]``, ``iters[1]``."""
        settings, sys_ = self.case, self.system
        h, c_h, p_bar = settings.dt, self.c_h, x[-1]
        for m in range(settings.max_iter + 1):
            f_theta, f_u = constraint_force(sys_, st.theta, c_force, x)
            _, om2, _, v2 = self.rk4(st, f_theta, f_u)
            # The velocity to reach is the secant of the gap the rows hold over this step:
            # the strip's pair rolls with the disks (its row's theta entries, section 11.3),
            # the overlap c_H |p| grows with the force (from the forces this and the last
            # displacement stage held), and re-spreading the strip at the last step's end
            # moved the gap by st.jump (section 11.4).
            sh = (self.normal_of(c1, v2, self.velocity_mats(th1, om2)) + self.roll_rate(c1, om2)
                  + c_h * (p_bar - st.p_held) / h + st.jump / h)
            pih = sh if (p_bar < 0.0 and (sh > 0.0 or x[-1] < 0.0)) else 0.0
            e = np.append(self.root_velocity_errors(th1, om2, v2), pih)
            residual[1] = np.abs(e).max()
            # At least one iteration: the displacement stage's constant force leaves a
            # velocity error up to tol/dt that would carry the gap across the band next step.
            if residual[1] <= settings.tol_vel and m > 0:
                break
            if m == settings.max_iter:
                iters[1] = m
                return FAIL_VEL, x, om2, v2
            x = accelerated_update(x, e, h * cbase, settings.accel_levels)
            if p_bar == 0.0:
                x[-1] = 0.0
        iters[1] = m
        return OK, x, om2, v2

    def acceleration_stage(self, th1: NDArray[np.float64], u1: NDArray[np.float64],
                           om2: NDArray[np.float64], v2: NDArray[np.float64], x: NDArray[np.float64],
                           c1: ContactPair, p_bar: float, residual: NDArray[np.float64],
                           iters: NDArray[np.int64]) -> tuple[int, NDArray[np.float64]]:
        """Stage 3, accelerations at t + dt with the constraint directions there:
        ``(status, x)``; the stage's residual and iterations into ``residual[2]``, ``iters[2]``."""
        settings, sys_ = self.case, self.system
        g1 = jacobian(sys_, th1, c1)
        ca = (g1 * self.minv) @ g1.T
        extra = self.sliding_term(th1, u1, om2, v2, c1)
        zero = np.zeros(sys_.n_x)
        alpha0, a0 = self.accelerations(th1, u1, *constraint_force(sys_, th1, c1, zero))
        for m in range(settings.max_iter + 1):
            dq = self.minv * (g1.T @ x)
            alpha, a = alpha0 + dq[:2], a0 + dq[2:]
            st_ = (self.normal_of(c1, a, self.acceleration_mats(th1, om2, alpha)) + extra
                   + self.roll_rate(c1, alpha))
            pit = st_ if (p_bar < 0.0 and (st_ > 0.0 or x[-1] < 0.0)) else 0.0
            e = np.append(self.root_acceleration_errors(th1, om2, alpha, a), pit)
            residual[2] = np.abs(e).max()
            # At least one iteration: the stage is algebraic and its C exact, so one update
            # costs little and keeps the force from lagging the load by up to m tol/dt^2.
            if residual[2] <= settings.tol_acc and m > 0:
                break
            if m == settings.max_iter:
                iters[2] = m
                return FAIL_ACC, x
            x = accelerated_update(x, e, ca, settings.accel_levels)
            if p_bar == 0.0:
                x[-1] = 0.0
        iters[2] = m
        return OK, x

    def sliding_term(self, th1: NDArray[np.float64], u1: NDArray[np.float64],
                     om2: NDArray[np.float64], v2: NDArray[np.float64], c1: ContactPair) -> float:
        """What the contact points' sliding along the flanks adds to the normal acceleration
        of the pair ``c1`` at t + dt."""
        sys_ = self.system
        ua, ub = blocks(sys_, u1)
        va, vb = blocks(sys_, v2)
        ra, rb = (rot(g.sense * th) for g, th in zip(sys_.gears, th1))
        ma, mb = self.velocity_mats(th1, om2)
        extra, _, _ = sliding_acceleration(
            *paper_flanks(sys_),
            sys_.gears[0].X + ua.reshape(-1, 2), sys_.gears[1].X + ub.reshape(-1, 2), ra, rb,
            va.reshape(-1, 2), vb.reshape(-1, 2), ma, mb, c1,
            None if self.law is None else tuple(rigid_flanks(sys_, th1, om2)))
        return extra


def initial_contact_guess(system: PairSystem) -> tuple[float, float]:
    """Flank coordinates where the teeth touch at the start of contact: B's tip on A."""
    pair = system.pair
    fa, fb = paper_flanks(system)
    r_start = float(pair.gear_a.radius_at_roll_angle(pair.start_roll_a))
    ts = np.linspace(fa.t0, fa.t1, 4 * fa.n_data)
    xa = system.gears[0].X
    radii = np.array([np.hypot(*(fa.locate(t)[1] @ xa[fa.locate(t)[0]])) for t in ts])
    return float(np.interp(r_start, radii, ts)), fb.t1


def initial_state(system: PairSystem, settings: RunSettings) -> State:
    """Teeth just touching at the start of contact, rigid rotation, consistent forces.

    The forces come from an acceleration stage at ``t = 0`` (the torques are zero there).
    The teeth touch (gap and normal velocity within the tolerances), so the contact is
    closed: it takes the force that stops the normal acceleration of the contact points if
    they approach, none if they part (docs/solver.md, section 9). Both steppers start
    from this state.
    """
    sys_ = system
    ref = PaperMethod(sys_, settings)
    minv = ref.minv
    theta = np.zeros(2)
    omega = np.array([settings.speed_a, settings.speed_b])
    u = np.zeros(sys_.n_u)
    v = rigid_velocities(sys_, omega)
    contact = contact_at(sys_, theta, u, initial_contact_guess(sys_))
    s_hat = ref.normal_of(contact, v, ref.velocity_mats(theta, omega))
    closed = abs(contact.s) <= settings.tol_disp and abs(s_hat) <= settings.tol_vel
    g0 = jacobian(sys_, theta, contact)
    ca = (g0 * minv) @ g0.T
    alpha0, a0 = accelerations(sys_, settings, theta, u, np.zeros(2), np.zeros(sys_.n_u))
    ua, ub = blocks(sys_, u)
    va, vb = blocks(sys_, v)
    ma, mb = ref.velocity_mats(theta, omega)
    extra, _, _ = sliding_acceleration(
        sys_.gears[0].flank, sys_.gears[1].flank,
        sys_.gears[0].X + ua.reshape(-1, 2), sys_.gears[1].X + ub.reshape(-1, 2), rot(0.0), rot(0.0),
        va.reshape(-1, 2), vb.reshape(-1, 2), ma, mb, contact)
    x = np.zeros(sys_.n_x)
    for m in range(settings.max_iter):
        dq = minv * (g0.T @ x)
        alpha, a = alpha0 + dq[:2], a0 + dq[2:]
        st_ = ref.normal_of(contact, a, ref.acceleration_mats(theta, omega, alpha)) + extra
        pit = st_ if (closed and (st_ > 0.0 or x[-1] < 0.0)) else 0.0
        e = np.append(root_acceleration_errors(sys_, theta, omega, alpha, a), pit)
        # at least one iteration, as in the step's acceleration stage
        if np.abs(e).max() <= settings.tol_acc and m > 0:
            break
        x = accelerated_update(x, e, ca, settings.accel_levels)
    return State(t=0.0, theta=theta, omega=omega, u=u, v=v, x=x, contact=contact)
