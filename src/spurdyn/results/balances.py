"""Angular momentum and energy balances of a running FE pair (checks of the solver).

For each gear, about its fixed centre, the only external moments are the centre torque
of the Fig. 7 schedule and the moment of the contact force; the pin reaction has no
moment and the root multipliers are internal (disk <-> tooth). So

    L_g(t) - L_g(0) = int_0^t (tau_g + M_contact,g) dt                  (per gear)

with ``L_g = J_g omega_g + sum_i m_i (y_i x v_i)`` (world z, the tooth nodes relative to
the centre). The energy ``E = sum_g (1/2 J_g omega_g^2 + 1/2 v^T M v + 1/2 w^T K w)``
changes by the work of the centre torques and of the contact force:

    E(t) - E(0) = int_0^t (sum_g tau_g omega_g + P_contact) dt,

``P_contact = sum_j f_j . v_j`` over the contact nodes, plus the torques the strip's
contact row puts on the disks times their speeds (its pair rolls with them,
docs/solver.md section 11.3), zero while the contact points move together along the
normal: frictionless, no penetration rate. The elastic torque
on the disks (``keep_theta_term``) is part of ``dE/dt`` of the strain energy, so with it
kept the balance is exact up to the time discretisation; an impact that the velocity
stage stops within one step takes out the kinetic energy of the relative normal motion
of the contact region, which shows up as a drop of ``E`` not matched by any work.

Everything is computed from a :class:`~spurdyn.solvers.paper.stepper_compiled.CompiledStepper`'s state
(``stepper.S``) after each step; :func:`track` steps the stepper itself and integrates
the moments and powers by the trapezoidal rule. World z is counter-clockwise positive;
``theta``, ``omega`` and the torques of the run are along each gear's own sense.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.geometry.involute import rot
from spurdyn.model.loading import gear_torques
from spurdyn.model.system import PairSystem


@dataclass(frozen=True)
class Snapshot:
    """Momentum, energy, external moments and powers of the pair at one instant.

    Attributes
    ----------
    t
        Time (s).
    theta
        Rotation of each disk since the start, along its own sense (rad) ``(2,)``.
    momentum
        Angular momentum of each gear about its centre (kg m^2/s, world z) ``(2,)``.
    kinetic, strain
        Kinetic energy of each gear (disk and tooth) and strain energy of each tooth (J)
        ``(2,)``.
    torque_moment, contact_moment
        Moments about each centre (N m, world z) of the centre torque and of the contact
        force ``(2,)``.
    torque_power, contact_power
        Power (W) of both centre torques and of the contact force on both teeth.
    contact_force
        Contact force (N), compression positive.
    """

    t: float
    theta: NDArray[np.float64]
    momentum: NDArray[np.float64]
    kinetic: NDArray[np.float64]
    strain: NDArray[np.float64]
    torque_moment: NDArray[np.float64]
    contact_moment: NDArray[np.float64]
    torque_power: float
    contact_power: float
    contact_force: float

    @property
    def energy(self) -> float:
        """Total mechanical energy (J)."""
        return float(self.kinetic.sum() + self.strain.sum())


def state_snapshot(system: PairSystem, tau0: float, t: float, theta: NDArray[np.float64],
                   omega: NDArray[np.float64], u: NDArray[np.float64], v: NDArray[np.float64],
                   p: float, contact_nodes: NDArray[np.int64], contact_weights: NDArray[np.float64],
                   normal: NDArray[np.float64], theta_row: NDArray[np.float64] | None = None) -> Snapshot:
    """The balance quantities of a state given by its arrays.

    Parameters
    ----------
    system
        The pair system the state belongs to.
    tau0
        The torque ``tau_0`` of the run (N m).
    t, theta, omega, u, v
        Time, disk rotations and speeds (each along its own sense), absolute nodal
        displacements and velocities of both teeth (A's first).
    p
        Contact multiplier (N; negative is compression, the solver's sign).
    contact_nodes, contact_weights, normal
        The contact nodes (A's three, then B's three, indices into the stacked nodes),
        their shape-function weights and the contact normal: the force on A's nodes is
        ``+w_j n p``, on B's ``-w_j n p``.
    theta_row
        The contact row's entries on the disks (the strip's pair rolling with them,
        docs/solver.md section 11.3; None: zero): the contact force puts ``theta_row p``
        on each disk along its own sense, and its moment and power count.
    """
    o = system.offsets
    n_a = o[1] // 2
    torques = gear_torques(system.pair, tau0, float(theta[0]), float(theta[1]))
    tau = np.array([float(torques[0]), float(torques[1])])
    momentum, kinetic, strain = np.zeros(2), np.zeros(2), np.zeros(2)
    positions = []
    for g, gb in enumerate(system.gears):
        ub, vb = u[o[g]:o[g + 1]], v[o[g]:o[g + 1]]
        y = (gb.Y + ub).reshape(-1, 2)
        vv = vb.reshape(-1, 2)
        m = gb.mass.reshape(-1, 2)[:, 0]
        momentum[g] = gb.inertia * gb.sense * omega[g] + np.sum(m * (y[:, 0] * vv[:, 1] - y[:, 1] * vv[:, 0]))
        w = (y @ rot(gb.sense * theta[g])).ravel() - gb.Y
        kinetic[g] = 0.5 * gb.inertia * omega[g] ** 2 + 0.5 * float(np.sum(gb.mass * vb * vb))
        strain[g] = 0.5 * float(w @ (gb.stiffness @ w))
        positions.append(y)
    contact_moment = np.zeros(2)
    contact_power = 0.0
    vv_all = v.reshape(-1, 2)
    for j, (node, wj) in enumerate(zip(contact_nodes, contact_weights)):
        g = 0 if node < n_a else 1
        sign = 1.0 if g == 0 else -1.0
        f = sign * wj * p * np.asarray(normal, dtype=float)
        y = positions[g][node - (0 if g == 0 else n_a)]
        contact_moment[g] += y[0] * f[1] - y[1] * f[0]
        contact_power += float(f @ vv_all[node])
    senses = np.array([gb.sense for gb in system.gears])
    if theta_row is not None:
        disk = np.asarray(theta_row, dtype=float) * p
        contact_moment += senses * disk
        contact_power += float(disk @ np.asarray(omega, dtype=float))
    return Snapshot(t=float(t), theta=np.array(theta, dtype=float), momentum=momentum, kinetic=kinetic, strain=strain,
                    torque_moment=tau * senses, contact_moment=contact_moment,
                    torque_power=float(tau @ np.asarray(omega, dtype=float)),
                    contact_power=contact_power, contact_force=float(-p))


def snapshot(stepper: Any) -> Snapshot:
    """The balance quantities of a :class:`~spurdyn.solvers.paper.stepper_compiled.CompiledStepper` now."""
    S = stepper.S
    return state_snapshot(stepper.system, stepper.settings.torque, float(S.t[0]), S.theta, S.omega,
                          S.u, S.v, float(S.x[-1]), S.cn, S.cw, S.normal, S.gth)


@dataclass(frozen=True)
class BalanceRecord:
    """Time histories of the balances along a run (one row per step, the start first).

    Attributes
    ----------
    t, angle, contact_force
        Time (s), rotation of gear A (rad), contact force (N).
    momentum
        ``(n, 2)`` angular momentum of each gear (world z).
    angular_impulse
        ``(n, 2)`` time integral of the external moments (torque + contact) on each gear.
    energy, strain
        Total mechanical energy and the teeth's strain energy (J).
    torque_work, contact_work
        Time integrals of the torque and contact powers (J).
    status
        The stepper's status of the last step (0: all stages converged).
    """

    t: NDArray[np.float64]
    angle: NDArray[np.float64]
    contact_force: NDArray[np.float64]
    momentum: NDArray[np.float64]
    angular_impulse: NDArray[np.float64]
    energy: NDArray[np.float64]
    strain: NDArray[np.float64]
    torque_work: NDArray[np.float64]
    contact_work: NDArray[np.float64]
    status: int = 0

    @property
    def momentum_error(self) -> NDArray[np.float64]:
        """``(n, 2)``: ``L(t) - L(0) - angular impulse`` (kg m^2/s)."""
        return self.momentum - self.momentum[0] - self.angular_impulse

    @property
    def energy_error(self) -> NDArray[np.float64]:
        """``E(t) - E(0) - torque work - contact work`` (J): negative where energy is lost."""
        return self.energy - self.energy[0] - self.torque_work - self.contact_work


def track(stepper: Any, steps: int | None = None, angle: float | None = None) -> BalanceRecord:
    """Step ``stepper`` and record the balances after every step.

    Parameters
    ----------
    stepper
        A fresh :class:`~spurdyn.solvers.paper.stepper_compiled.CompiledStepper` (or anything with the same
        ``S``, ``system``, ``settings`` and ``step()``).
    steps
        Number of steps to take, or
    angle
        take steps until gear A has turned this angle (rad).

    The moments and powers are integrated by the trapezoidal rule over each step; the
    run stops early at a step whose status is not 0.
    """
    if (steps is None) == (angle is None):
        raise ValueError("give exactly one of steps and angle")
    dt = stepper.settings.dt
    n_max = steps if steps is not None else int(np.ceil(angle / (stepper.S.omega[0] * dt) * 1.5)) + 10
    rows = [snapshot(stepper)]
    status = 0
    for _ in range(n_max):
        if angle is not None and stepper.S.theta[0] >= angle:
            break
        status = stepper.step()
        rows.append(snapshot(stepper))
        if status:
            break
    t = np.array([r.t for r in rows])
    h = np.diff(t)

    def integral(values: NDArray[np.float64]) -> NDArray[np.float64]:
        values = np.asarray(values, dtype=float)
        mid = 0.5 * (values[1:] + values[:-1])
        inc = mid * (h if values.ndim == 1 else h[:, None])
        return np.concatenate([np.zeros((1,) + values.shape[1:]), np.cumsum(inc, axis=0)])

    moments = np.array([r.torque_moment + r.contact_moment for r in rows])
    return BalanceRecord(
        t=t,
        angle=np.array([r.theta[0] for r in rows]),
        contact_force=np.array([r.contact_force for r in rows]),
        momentum=np.array([r.momentum for r in rows]),
        angular_impulse=integral(moments),
        energy=np.array([r.energy for r in rows]),
        strain=np.array([r.strain.sum() for r in rows]),
        torque_work=integral(np.array([r.torque_power for r in rows])),
        contact_work=integral(np.array([r.contact_power for r in rows])),
        status=int(status),
    )
