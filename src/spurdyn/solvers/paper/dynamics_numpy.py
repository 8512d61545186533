"""Equations of motion and constraint forces of the paper's model in plain NumPy.

The twin of :mod:`spurdyn.solvers.paper.dynamics_compiled`. Generalised coordinates
(paper eq. 1): per gear the disk rotation ``theta[g]`` and the absolute nodal
displacements ``u`` of its tooth in the world frame (docs/solver.md); the constraint
forces are ``G^T x`` with ``x = [lambda_A, lambda_B, p]``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from spurdyn.contact.hertz import effective_modulus
from spurdyn.contact.search_numpy import ContactPair, find_contact, roll_entries
from spurdyn.geometry.involute import rot
from spurdyn.model.loading import gear_torques
from spurdyn.model.flank import Flank
from spurdyn.model.system import GearBody, PairSystem
from spurdyn.settings import RunSettings


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


def torques(system: PairSystem, tau0: float, theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """External torques on the two disks at their rotations ``theta`` (Fig. 7 schedule)."""
    ta, tb = gear_torques(system.pair, tau0, theta[0], theta[1])
    return np.array([float(ta), float(tb)])


def accelerations(system: PairSystem, settings: RunSettings, theta: NDArray[np.float64],
                  u: NDArray[np.float64], f_theta: NDArray[np.float64], f_u: NDArray[np.float64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``alpha = (tau + Q + f_theta) / J`` and ``a = (f_el + f_u) / m`` with the constraint
    forces ``(f_theta, f_u)`` given."""
    s = system
    tau = torques(system, settings.torque, theta)
    alpha = np.zeros(2)
    a = np.empty(s.n_u)
    for g, (gb, ub, ab) in enumerate(zip(s.gears, blocks(s, u), blocks(s, a))):
        q, f = elastic(gb, theta[g], ub, settings.keep_theta_term)
        alpha[g] = (tau[g] + q + f_theta[g]) / gb.inertia
        ab[:] = f
    a += f_u
    a /= s.mass
    return alpha, a


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
    """Generalised constraint force ``G^T x = -Phi_q^T lambda + s_q^T p`` ``(f_theta, f_u)``;
    the contact's part on the disks is ``contact.theta_row`` (the strip's)."""
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
    f_theta += np.asarray(contact.theta_row) * p
    fa, fb = fu[0].reshape(-1, 2), fu[1].reshape(-1, 2)
    np.add.at(fa, contact.nodes_a, np.outer(contact.weights_a, contact.normal) * p)
    np.add.at(fb, contact.nodes_b, -np.outer(contact.weights_b, contact.normal) * p)
    return f_theta, f_u


def jacobian(system: PairSystem, theta: NDArray[np.float64], contact: ContactPair) -> NDArray[np.float64]:
    """Dense ``G = [-Phi_q; s_q]`` over ``q = [theta_A, theta_B, u]`` (the contact row's
    disk entries: ``contact.theta_row``, the strip's)."""
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
    g_mat[-1, :2] = contact.theta_row
    return g_mat


def inverse_mass(system: PairSystem) -> NDArray[np.float64]:
    return np.concatenate([[1.0 / system.gears[0].inertia, 1.0 / system.gears[1].inertia],
                           1.0 / system.mass])


def rigid_velocities(system: PairSystem, omega: NDArray[np.float64]) -> NDArray[np.float64]:
    """Nodal velocities of both teeth turning rigidly with their disks at ``theta = 0``."""
    v = np.empty(system.n_u)
    for g, (gb, vb) in enumerate(zip(system.gears, blocks(system, v))):
        y = gb.Y.reshape(-1, 2)
        vb.reshape(-1, 2)[:] = gb.sense * omega[g] * np.column_stack([-y[:, 1], y[:, 0]])
    return v


def root_acceleration_errors(system: PairSystem, theta: NDArray[np.float64], omega: NDArray[np.float64],
                             alpha: NDArray[np.float64], a: NDArray[np.float64]) -> NDArray[np.float64]:
    """``-(Phi_q qddot + (Phi_q qdot)_q qdot)`` of the root constraints, both gears stacked."""
    out = []
    for g, (gb, ab) in enumerate(zip(system.gears, blocks(system, a))):
        pt = root_phi_theta(gb, theta[g])
        r = rot(gb.sense * theta[g])
        y = gb.Y.reshape(-1, 2)[gb.root_nodes]
        out.append(-(ab.reshape(-1, 2)[gb.root_nodes] + pt * alpha[g] + (y @ r.T) * omega[g] ** 2).ravel())
    return np.concatenate(out)


def paper_flanks(system: PairSystem) -> tuple[Flank, Flank]:
    """The two flanks of the paper's method, which constrains exactly one contact pair."""
    if len(system.contacts) != 1:
        raise ValueError(f"the paper's method constrains one flank pair; this system has "
                         f"{len(system.contacts)}")
    return system.flanks(system.contacts[0])


def strip_law(system: PairSystem) -> tuple[float, float]:
    """``(E*, L)`` of the pair's Hertzian contact: both materials, the narrower face."""
    ga, gb = system.pair.gear_a, system.pair.gear_b
    estar = effective_modulus(ga.material.young, ga.material.poisson,
                              gb.material.young, gb.material.poisson)
    return estar, min(ga.face_width, gb.face_width)


def rigid_flanks(system: PairSystem, theta: NDArray[np.float64],
                 omega: NDArray[np.float64] | None = None) -> list[NDArray[np.float64]]:
    """Nodal positions ``(N, 2)`` of both teeth turned rigidly with their disks by ``theta``,
    then (with ``omega``) their velocities: the flanks a strip's pair is located on
    (docs/solver.md, section 11.2)."""
    out, vel = [], []
    for i, (g, th) in enumerate(zip(system.gears, theta)):
        y = (g.X - g.centre) @ rot(g.sense * th).T
        out.append(g.centre + y)
        if omega is not None:
            vel.append(g.sense * omega[i] * np.column_stack([-y[:, 1], y[:, 0]]))
    return out + vel


def contact_at(system: PairSystem, theta: NDArray[np.float64], u: NDArray[np.float64],
               guess: tuple[float, float], load: float = 0.0,
               law: tuple[float, float] | None = None) -> ContactPair:
    """The contact pair on the flanks at ``(theta, u)``, searched from ``guess``; with a
    ``law`` (:func:`strip_law`) located on the rigidly turned flanks, averaged over the
    strip of the force ``load``, and with its row's entries for the pair's roll with the
    disks (docs/solver.md, sections 11.2-11.3)."""
    s = system
    ua, ub = blocks(s, u)
    xa = s.gears[0].X + ua.reshape(-1, 2)
    xb = s.gears[1].X + ub.reshape(-1, 2)
    ra, rb = (rot(g.sense * th) for g, th in zip(s.gears, theta))
    if law is None:
        return find_contact(*paper_flanks(s), xa, xb, ra, rb, guess, load)
    rigid = rigid_flanks(s, theta, np.ones(2))
    c = find_contact(*paper_flanks(s), xa, xb, ra, rb, guess, load, law, tuple(rigid[:2]))
    jz = np.array([[0.0, -1.0], [1.0, 0.0]])
    turns = [g.sense * r @ jz for g, r in zip(s.gears, (ra, rb))]
    roll, row = roll_entries(*paper_flanks(s), c, xa, xb, ra, rb, (*rigid, *turns))
    return replace(c, roll=roll, theta_row=row)
