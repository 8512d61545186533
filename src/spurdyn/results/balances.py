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
from typing import Any, NamedTuple

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
    one = States(np.array([t], dtype=float), *(np.asarray(a, dtype=float)[None] for a in (theta, omega, u, v)),
                 np.array([p], dtype=float), np.asarray(contact_nodes)[None],
                 np.asarray(contact_weights, dtype=float)[None], np.asarray(normal, dtype=float)[None],
                 None if theta_row is None else np.asarray(theta_row, dtype=float)[None])
    b = batch_balances(system, tau0, one)
    return Snapshot(t=float(t), theta=np.array(theta, dtype=float), momentum=b.momentum[0], kinetic=b.kinetic[0],
                    strain=b.strain[0], torque_moment=b.torque_moment[0], contact_moment=b.contact_moment[0],
                    torque_power=float(b.torque_power[0]), contact_power=float(b.contact_power[0]),
                    contact_force=float(b.contact_force[0]))


class States(NamedTuple):
    """``B`` states of a run, each field :func:`state_snapshot`'s argument with a leading
    axis of ``B`` (``theta_row`` None: no disk entries)."""

    t: NDArray[np.float64]
    theta: NDArray[np.float64]
    omega: NDArray[np.float64]
    u: NDArray[np.float64]
    v: NDArray[np.float64]
    p: NDArray[np.float64]
    contact_nodes: NDArray[np.int64]
    contact_weights: NDArray[np.float64]
    normal: NDArray[np.float64]
    theta_row: NDArray[np.float64] | None


class Balances(NamedTuple):
    """:class:`Snapshot`'s quantities of ``B`` states, each with a leading axis of ``B``."""

    momentum: NDArray[np.float64]
    kinetic: NDArray[np.float64]
    strain: NDArray[np.float64]
    torque_moment: NDArray[np.float64]
    contact_moment: NDArray[np.float64]
    torque_power: NDArray[np.float64]
    contact_power: NDArray[np.float64]
    contact_force: NDArray[np.float64]


def batch_balances(system: PairSystem, tau0: float, s: States) -> Balances:
    """The balance quantities of the states ``s`` at once (the one home of the formulas in
    the module docstring; :func:`state_snapshot` is its batch of one)."""
    o, n_a, count = system.offsets, system.offsets[1] // 2, s.t.size
    tau_a, tau_b = gear_torques(system.pair, tau0, s.theta[:, 0], s.theta[:, 1])
    tau = np.column_stack([np.broadcast_to(tau_a, (count,)), np.broadcast_to(tau_b, (count,))]).astype(float)
    senses = np.array([gb.sense for gb in system.gears], dtype=float)
    momentum, kinetic, strain = np.zeros((count, 2)), np.zeros((count, 2)), np.zeros((count, 2))
    positions = []
    for g, gb in enumerate(system.gears):
        ub, vb = s.u[:, o[g]:o[g + 1]], s.v[:, o[g]:o[g + 1]]
        y = (gb.Y + ub).reshape(count, -1, 2)
        vv = vb.reshape(count, -1, 2)
        m = gb.mass.reshape(-1, 2)[:, 0]
        momentum[:, g] = (gb.inertia * gb.sense * s.omega[:, g]
                          + np.sum(m * (y[..., 0] * vv[..., 1] - y[..., 1] * vv[..., 0]), axis=1))
        # each state's nodes turned back by its disk's rotation R^T y (rot's (2, 2, B) stack,
        # written out: einsum took two thirds of this function's time)
        r = rot(gb.sense * s.theta[:, g])[..., None]
        w = np.stack([y[..., 0] * r[0, 0] + y[..., 1] * r[1, 0], y[..., 0] * r[0, 1] + y[..., 1] * r[1, 1]],
                     axis=-1).reshape(count, -1) - gb.Y
        kinetic[:, g] = 0.5 * gb.inertia * s.omega[:, g] ** 2 + 0.5 * np.sum(gb.mass * vb * vb, axis=1)
        strain[:, g] = 0.5 * np.sum(w * (gb.stiffness @ w.T).T, axis=1)
        positions.append(y)
    contact_moment, contact_power = _contact(s, n_a, np.concatenate(positions, axis=1))
    if s.theta_row is not None:
        disk = s.theta_row * s.p[:, None]
        contact_moment += senses * disk
        contact_power += np.sum(disk * s.omega, axis=1)
    return Balances(momentum, kinetic, strain, tau * senses, contact_moment, np.sum(tau * s.omega, axis=1),
                    contact_power, -s.p)


def _contact(s: States, n_a: int, y_all: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The contact force's moment on each gear ``(B, 2)`` and its power on the teeth
    ``(B,)``, the nodes' positions ``y_all`` ``(B, nodes, 2)`` (A's, then B's)."""
    count = s.t.size
    rows = np.arange(count)
    v_all = s.v.reshape(count, -1, 2)
    contact_moment, contact_power = np.zeros((count, 2)), np.zeros(count)
    for j in range(s.contact_nodes.shape[1]):
        node = s.contact_nodes[:, j]
        on_a = node < n_a
        f = (np.where(on_a, 1.0, -1.0) * s.contact_weights[:, j] * s.p)[:, None] * s.normal
        y = y_all[rows, node]
        moment = y[:, 0] * f[:, 1] - y[:, 1] * f[:, 0]
        contact_moment[:, 0] += np.where(on_a, moment, 0.0)
        contact_moment[:, 1] += np.where(on_a, 0.0, moment)
        contact_power += np.sum(f * v_all[rows, node], axis=1)
    return contact_moment, contact_power


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


def track(stepper: Any, steps: int | None = None, angle: float | None = None,
          block: int = 1024) -> BalanceRecord:
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
    block
        States kept before their balances are taken together (:func:`batch_balances`):
        the arithmetic of a state in a batch, ~13 MB held a block of
        1,024 on the paper's pair.

    The moments and powers are integrated by the trapezoidal rule over each step; the
    run stops early at a step whose status is not 0.
    """
    if (steps is None) == (angle is None):
        raise ValueError("give exactly one of steps and angle")
    if block < 2:
        raise ValueError(f"block must be at least 2 states (got {block})")
    dt = stepper.settings.dt
    n_max = steps if steps is not None else int(np.ceil(angle / (stepper.S.omega[0] * dt) * 1.5)) + 10
    kept: list[tuple[Any, ...]] = [_state_of(stepper.S)]
    parts: list[Balances] = []
    times: list[float] = []
    angles: list[float] = []
    status = 0
    for _ in range(n_max):
        if angle is not None and stepper.S.theta[0] >= angle:
            break
        status = stepper.step()
        kept.append(_state_of(stepper.S))
        if len(kept) == block:
            parts.append(_take(stepper, kept, times, angles))
        if status:
            break
    if kept:
        parts.append(_take(stepper, kept, times, angles))
    b = Balances(*(np.concatenate(field) for field in zip(*parts)))
    t = np.array(times)
    h = np.diff(t)

    def integral(values: NDArray[np.float64]) -> NDArray[np.float64]:
        mid = 0.5 * (values[1:] + values[:-1])
        inc = mid * (h if values.ndim == 1 else h[:, None])
        return np.concatenate([np.zeros((1,) + values.shape[1:]), np.cumsum(inc, axis=0)])

    return BalanceRecord(
        t=t, angle=np.array(angles), contact_force=b.contact_force, momentum=b.momentum,
        angular_impulse=integral(b.torque_moment + b.contact_moment),
        energy=b.kinetic.sum(axis=1) + b.strain.sum(axis=1), strain=b.strain.sum(axis=1),
        torque_work=integral(b.torque_power), contact_work=integral(b.contact_power), status=int(status),
    )


def _state_of(S: Any) -> tuple[Any, ...]:
    """A copy of what :func:`snapshot` reads of a compiled state."""
    return (float(S.t[0]), S.theta.copy(), S.omega.copy(), S.u.copy(), S.v.copy(), float(S.x[-1]),
            S.cn.copy(), S.cw.copy(), S.normal.copy(), S.gth.copy())


def _take(stepper: Any, kept: list[tuple[Any, ...]], times: list[float], angles: list[float]) -> Balances:
    """The balances of the states ``kept`` (emptied), their times and A's angles appended."""
    t, theta, omega, u, v, p, cn, cw, normal, gth = (np.array(field) for field in zip(*kept))
    kept.clear()
    times.extend(t.tolist())
    angles.extend(theta[:, 0].tolist())
    return batch_balances(stepper.system, stepper.settings.torque, States(t, theta, omega, u, v, p, cn, cw, normal, gth))
