"""The implicit integrator as :class:`~spurdyn.solvers.base.Stepper` s: NumPy's
(``backend="numpy"``, :mod:`~spurdyn.solvers.implicit.step_numpy`) and the compiled one
(``backend="numba"``, :mod:`~spurdyn.solvers.implicit.step_compiled`)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.linalg import cholesky_banded
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import splu
from threadpoolctl import threadpool_limits

from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.base import Frames, Stepper
from spurdyn.solvers.implicit.step_numpy import ImplicitMethod, ImplicitState
from spurdyn.solvers.layout import CP, OK, HistoryRow, ImplicitPack
from spurdyn.solvers.paper.dynamics_numpy import torques
from spurdyn.solvers.paper.step_numpy import initial_state


class ImplicitStepper(Stepper):
    """Steps :class:`~spurdyn.solvers.implicit.step_numpy.ImplicitMethod` from the paper's
    start (:func:`~spurdyn.solvers.paper.step_numpy.initial_state`: the teeth just touching,
    turning rigidly, with the forces of an acceleration stage at ``t = 0``).

    The history's first residual and iteration columns hold the Newton iteration's; the
    other two stay 0 (the scheme has no velocity or acceleration stage).
    """

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        super().__init__(system, settings)
        self.method = ImplicitMethod(system, settings)
        s0 = initial_state(system, settings)
        self.state: ImplicitState = self.method.initial(s0.theta, s0.omega, s0.u, s0.v, s0.x,
                                                        s0.contact, s0.t)

    def contact_columns(self) -> tuple[float, float, float, float, float]:
        c = self.state.contact
        return c.s, c.alpha, c.beta, c.mode, c.half_width

    def row(self) -> NDArray[np.float64]:
        st = self.state
        tau = torques(self.system, self.settings.torque, st.theta)
        s, alpha, beta, mode, half = self.contact_columns()
        return np.array(HistoryRow(
            t=self.t, theta_a=st.theta[0], theta_b=st.theta[1], omega_a=st.omega[0],
            omega_b=st.omega[1], tau_a=tau[0], tau_b=tau[1], p=st.x[-1], s=s, alpha=alpha,
            beta=beta, mode=mode, res1=self.residual[0], res2=0.0, res3=0.0,
            it1=self.iterations[0], it2=0, it3=0, half_width=half), dtype=np.float64)

    def _advance(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
                 frames_every: int, frames: Frames) -> tuple[int, int, int]:
        # The step's dense products are tens by hundreds: a second BLAS thread only waits
        # for the first (2.3 times slower on this 2-core machine with another process busy).
        # A diverging Newton iteration ends in a NaN the status reports: no warnings.
        with threadpool_limits(limits=1, user_api="blas"), np.errstate(all="ignore"):
            return self._steps(n, angle_end, save_every, rows, frames_every, frames)

    def _one(self) -> int:
        new, residual, its, status = self.method.step(self.state)
        self.residual[0], self.iterations[0] = residual, its
        if status == OK:
            self.state = new
        return status

    def _steps(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
               frames_every: int, frames: Frames) -> tuple[int, int, int]:
        written = 0
        for k in range(n):
            if self.state.theta[0] >= angle_end:
                return k, written, OK
            status = self._one()
            if status != OK:
                return k, written, status
            index = self.index + k + 1
            if index % save_every == 0:
                rows[written] = self.row()
                written += 1
            if frames_every and index % frames_every == 0:
                frames.append((self.t, self.state.theta.copy(), self.state.u.copy()))
        return n, written, OK


def implicit_pack(system: PairSystem, method: ImplicitMethod, ns: int) -> ImplicitPack:
    """The compiled step's pack: the coefficients, and the teeth's constant iteration
    blocks as one banded Cholesky factor (reverse Cuthill-McKee order) and their inverse
    at the root DOFs."""
    case, coef = method.case, method.coef
    ratio = method.gp / method.bp
    a, b = case.rayleigh_mass, case.rayleigh_stiffness
    blocks = sp.block_diag([sp.diags(g.mass * (1.0 / method.bp + a * ratio))
                            + (1.0 + b * ratio) * g.stiffness for g in system.gears], format="csr")
    perm = reverse_cuthill_mckee(blocks, symmetric_mode=True).astype(np.int64)
    permuted = blocks[perm][:, perm].tocoo()
    bw = int(np.abs(permuted.row - permuted.col).max())
    band = np.zeros((bw + 1, blocks.shape[0]))
    upper = permuted.row <= permuted.col
    band[bw + permuted.row[upper] - permuted.col[upper], permuted.col[upper]] = permuted.data[upper]
    factor = cholesky_banded(band, lower=False)
    offs = np.cumsum([0] + [g.mesh.n_nodes for g in system.gears])
    rnode = np.concatenate([g.root_nodes + offs[i] for i, g in enumerate(system.gears)])
    dofs = np.column_stack([2 * rnode, 2 * rnode + 1]).ravel()
    eye = np.zeros((blocks.shape[0], dofs.size))
    eye[dofs, np.arange(dofs.size)] = 1.0
    root_inv = splu(blocks.tocsc()).solve(eye)
    law = method.law or (0.0, 0.0)
    return ImplicitPack(
        h=case.dt, am=coef.alpha_m, af=coef.alpha_f, beta=coef.beta, gamma=coef.gamma,
        bp=method.bp, gp=method.gp, mq=method.mq, band=np.ascontiguousarray(factor.T), perm=perm,
        root_inv=np.ascontiguousarray(root_inv), base=method.base, c_mesh=method.c_mesh,
        ray_a=float(a), ray_b=float(b), c_h=method.c_h, estar=float(law[0]), face=float(law[1]),
        tol=case.tol_disp, max_iter=case.max_iter, ns=np.int64(ns))


class CompiledImplicitStepper(ImplicitStepper):
    """The compiled twin: :func:`spurdyn.solvers.implicit.step_compiled.step` in place on
    the packed model of the paper's compiled stepper."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        from spurdyn.solvers.paper.stepper_compiled import pack, strip_slots

        super().__init__(system, settings)
        st = self.state
        c = st.contact
        ns = strip_slots(system, settings)
        na = system.gears[0].mesh.n_nodes

        def slots(nodes: NDArray[np.intp], w: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
            pad = ns - nodes.size
            return np.concatenate([nodes, np.full(pad, nodes[0])]), np.concatenate([w, np.zeros(pad)])

        (nsa, wsa), (nsb, wsb) = slots(c.nodes_a, c.weights_a), slots(c.nodes_b, c.weights_b)
        self.P = pack(system, settings)
        self.I = implicit_pack(system, self.method, ns)
        self.arrays = dict(
            theta=st.theta.copy(), omega=st.omega.copy(), u=st.u.copy(), v=st.v.copy(),
            x=st.x.copy(), qdd=st.qdd.copy(), acc=st.acc.copy(),
            cpar=np.array([c.alpha, c.beta, float(c.mode), c.s, 0.0, c.half_width]),
            cn=np.concatenate([nsa, nsb + na]).astype(np.int64), cw=np.concatenate([wsa, wsb]),
            normal=c.normal.copy())
        self.time = st.t
        self._res = np.zeros(1)
        self._its = np.zeros(1, dtype=np.int64)
        from spurdyn.solvers.implicit.step_compiled import step

        self._step = step
        self.state = _View(self)

    def contact_columns(self) -> tuple[float, float, float, float, float]:
        cp = self.arrays["cpar"]
        return cp[CP.s], cp[CP.alpha], cp[CP.beta], cp[CP.mode], cp[CP.half_width]

    def _one(self) -> int:
        a = self.arrays
        status = self._step(self.P, self.I, a["theta"], a["omega"], a["u"], a["v"], a["x"],
                            a["qdd"], a["acc"], a["cpar"], a["cn"], a["cw"], a["normal"],
                            self._res, self._its)
        self.residual[0], self.iterations[0] = self._res[0], self._its[0]
        if status == OK:
            self.time += self.settings.dt
        return int(status)


class _View:
    """The compiled stepper's state read as the base class reads one (``t``, ``theta``...)."""

    def __init__(self, stepper: CompiledImplicitStepper) -> None:
        self._s = stepper

    def __getattr__(self, name: str) -> NDArray[np.float64]:
        if name == "t":
            return self._s.time  # type: ignore[return-value]
        return self._s.arrays[name]
