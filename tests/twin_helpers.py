"""Shared by the twin tests (test_paper_dynamics, test_paper_response,
test_paper_iteration, test_contact_search_twins): the compiled kernels one by one against
their NumPy counterparts.

Each test calls one compiled kernel on a realistic state of the paper's pair (1,500 steps
of the 20,000 rpm run: the torque is on its ramp and the teeth carry ~200 N) and compares
it with the same quantity computed by :mod:`spurdyn.solvers.paper.step_numpy`,
:mod:`spurdyn.contact.search_numpy`, :mod:`spurdyn.solvers.paper.iteration_numpy`,
:mod:`spurdyn.model.loading`, or, where there is no NumPy counterpart, by the formula of
docs/solver.md written out here in NumPy/SciPy. (The spline kernels, ``delta_at`` and the
contact search are compared in tests/test_contact.py; ``predict``/``superpose`` in
tests/test_paper_step_twins.py.)

The tolerances are round-off bounds of the computation compared, never fitted: ``EPS``
times the size of the terms that are summed (``|K| |v|`` for a product with the
stiffness, ``|G| M^-1 |G|^T`` for the Gram matrix...). Where a quantity is a difference of
large numbers the bound is set by those: the elastic displacement ``w = R^T (Y + u) - Y``
is a difference of ~5 cm positions leaving micrometres, so two correct codes that round
``w`` differently part by ``EPS |Y|`` in ``w`` and ``EPS |K| |Y|`` in the forces (a part in
1e9 of them; tests/test_paper_step_twins.py's module docstring). Those comparisons are also
made with the kernel's own ``w`` fed to the NumPy side, where the bound is the plain
product's. Each test checks too that a small change of an input moves the kernel's output
by much more than its tolerance, so a tolerance that hid a real error would show.
"""

import math

import numpy as np
import scipy.sparse as sp

from spurdyn.contact import search_numpy as cref
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper
from spurdyn.solvers.paper import dynamics_numpy as dyn_np
from spurdyn.solvers.paper import step_numpy as sref
from spurdyn.settings import RPM, RunSettings
from spurdyn.model.system import build_system

EPS = np.finfo(float).eps


JZ = np.array([[0.0, -1.0], [1.0, 0.0]])


class Loaded:
    """A loaded state of the paper's pair and everything the comparisons need."""

    def __init__(self, steps: int = 1500) -> None:
        self.case = RunSettings(contact="point", speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE)
        self.system = build_system(paper_pair(), self.case)
        self.fast = CompiledStepper(self.system, self.case)
        for _ in range(steps):
            assert self.fast.step() == 0
        self.S, self.P = self.fast.S, self.fast.P
        self.ref = sref.PaperMethod(self.system, self.case)
        self.na = self.system.gears[0].mesh.n_nodes          # nodes of A (B's are offset by it)
        self.K = sp.block_diag([g.stiffness for g in self.system.gears], format="csr")
        self.absK = abs(self.K)
        self.contact = self.ref.contact_at(self.S.theta, self.S.u, (self.S.cpar[0], self.S.cpar[1]))

    def rows(self, c):
        """``cn, cw`` (stacked node numbers, weights) of a reference contact pair."""
        cn = np.concatenate([c.nodes_a, c.nodes_b + self.na]).astype(np.int64)
        return cn, np.concatenate([c.weights_a, c.weights_b])

    @staticmethod
    def gth(c):
        """The contact row's disk entries of a reference contact pair."""
        return np.array(c.theta_row, dtype=float)

    def block(self, g, vec):
        o = self.system.offsets
        return vec[o[g]:o[g + 1]]


def elastic_np(system, theta, u):
    """``w``, ``K w`` of both teeth in NumPy (docs/solver.md section 2)."""
    w = np.empty_like(u)
    for g, gb in enumerate(system.gears):
        o = system.offsets
        r = dyn_np.rot(gb.sense * theta[g])
        w[o[g]:o[g + 1]] = ((gb.Y + u[o[g]:o[g + 1]]).reshape(-1, 2) @ r).ravel() - gb.Y
    return w


def tangent_np(st, theta, w, kw, d_th, d_u, keep=True):
    """``dF/dq . (d_th, d_u)`` without the torque schedule's slope, from the formulas of
    docs/solver.md (the tangent of the forces): ``dw = R^T du - s d_th Jz (w + Y)``,
    ``df = -s d_th R Jz K w - R K dw``, ``dQ = s sum (dw x K w + w x K dw)``."""
    out_th, out_u = np.zeros(2), np.zeros_like(w)
    for g, gb in enumerate(st.system.gears):
        o = st.system.offsets
        sl = slice(o[g], o[g + 1])
        s, r = gb.sense, dyn_np.rot(gb.sense * theta[g])
        w2, kw2 = w[sl].reshape(-1, 2), kw[sl].reshape(-1, 2)
        dw = d_u[sl].reshape(-1, 2) @ r - s * d_th[g] * (w2 + gb.Y.reshape(-1, 2)) @ JZ.T
        kdw = (gb.stiffness @ dw.ravel()).reshape(-1, 2)
        out_u[sl] = (-(s * d_th[g] * kw2 @ JZ.T + kdw) @ r.T).ravel()
        if keep:
            out_th[g] = s * np.sum(dw[:, 0] * kw2[:, 1] - dw[:, 1] * kw2[:, 0]
                                   + w2[:, 0] * kdw[:, 1] - w2[:, 1] * kdw[:, 0])
    return out_th, out_u


def q_bound(st, g, y, w, kw):
    """Round-off bound of gear ``g``'s disk torque ``Q = s sum w x K w`` from the rounding of
    ``w`` (``~EPS |y|``) and of the product. ``K`` is symmetric, so an error ``dw`` moves
    ``Q`` by ``sum dw x K w + (K Jz w) . dw``: both against forces of the size of ``K w``."""
    stiff = st.system.gears[g].stiffness
    w2, y2, kw2 = st.block(g, w), st.block(g, y), st.block(g, kw)
    kjw = stiff @ (w2.reshape(-1, 2) @ JZ.T).ravel()
    return (4 * EPS * (cross_size(y2, kw2) + cross_size(y2, kjw))
            + 8 * EPS * cross_size(w2, abs(stiff) @ np.abs(w2)))


def tangent_q_bound(st, g, y, w, dw):
    """Round-off bound of gear ``g``'s tangent torque ``dQ = s sum (dw x K w + w x K dw)``
    evaluated from the rounded ``w`` and ``K w`` of the state (as the compiled step does): an
    error ``dw_r ~ EPS |y|`` of ``w`` moves it by ``sum dw_r . (K Jz dw) + dw_r x K dw`` (``K``
    symmetric), and the products round against ``|K| |w|`` and ``|K| |dw|``. A rough ``dw``
    (random on every node) makes ``K dw`` large, so this bound is far above ``q_bound``."""
    stiff = st.system.gears[g].stiffness
    d2, y2, w2 = st.block(g, dw), st.block(g, y), st.block(g, w)
    kdw = stiff @ d2
    kjdw = stiff @ (d2.reshape(-1, 2) @ JZ.T).ravel()
    return (4 * EPS * (cross_size(y2, kdw) + cross_size(y2, kjdw))
            + 8 * EPS * (cross_size(d2, abs(stiff) @ np.abs(w2)) + cross_size(w2, abs(stiff) @ np.abs(d2))))


def node_size(v):
    """``|v_x| + |v_y|`` of each node, for both its components: a bound on the size of either
    component of the vector turned by any angle."""
    return np.repeat(np.abs(v).reshape(-1, 2).sum(1), 2)


def cross_size(a, b):
    """``sum_i (|a_i,x| + |a_i,y|)(|b_i,x| + |b_i,y|)``: a bound on ``sum_i |a_i x b_i|``."""
    return float(np.sum(np.abs(a).reshape(-1, 2).sum(1) * np.abs(b).reshape(-1, 2).sum(1)))


def worst(got, want):
    return float(np.max(np.abs(np.asarray(got) - np.asarray(want))))


def rigid_plus_noise(st, theta, size, seed):
    """Displacements of both teeth turned rigidly by ``theta`` plus random ones of ``size``."""
    rng = np.random.default_rng(seed)
    u = np.empty(st.system.n_u)
    for g, gb in enumerate(st.system.gears):
        y = gb.Y.reshape(-1, 2)
        st.block(g, u)[:] = (y @ dyn_np.rot(gb.sense * theta[g]).T - y).ravel()
    return u + size * rng.standard_normal(u.size)


def _synthetic_contact(st, alpha, beta, angle, theta_row=(0.0, 0.0)):
    """A contact pair at ``(alpha, beta)`` with a unit normal at ``angle`` and the disk
    entries ``theta_row`` of a strip's rolling pair (docs/solver.md 11.3; the Gram matrix
    needs only the rows, the normal and those)."""
    fa, fb = st.system.gears[0].flank, st.system.gears[1].flank
    na, wa, _ = fa.locate(alpha)
    nb, wb, _ = fb.locate(beta)
    return cref.ContactPair(alpha=alpha, beta=beta, mode=cref.FLANK,
                            normal=np.array([math.cos(angle), math.sin(angle)]), s=0.0,
                            nodes_a=na, weights_a=wa, nodes_b=nb, weights_b=wb,
                            delta_a=np.zeros(2), delta_b=np.zeros(2), theta_row=tuple(theta_row))


#: Disk entries of a contact row of the size a strip's rolling pair has (m/rad).
ROLLING = (2.0e-7, -1.5e-7)


def _gram_ref(st, theta, c):
    """``G M^-1 G^T`` and the size of its terms, ``|G| M^-1 |G|^T`` with the disk entries of
    the root rows (components of ``-s R Jz Y_i``, each rounded to ``EPS |Y_i|``) taken as
    ``|Y_i|``."""
    g = dyn_np.jacobian(st.system, theta, c)
    minv = dyn_np.inverse_mass(st.system)
    size = np.abs(g)
    ynorm = np.abs(st.P.Y[2 * st.P.rnode]) + np.abs(st.P.Y[2 * st.P.rnode + 1])
    size[np.arange(2 * ynorm.size), np.repeat(st.P.rgear, 2)] = np.repeat(ynorm, 2)
    return (g * minv) @ g.T, (size * minv) @ size.T

