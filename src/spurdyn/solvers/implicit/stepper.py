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
from spurdyn.solvers.implicit.step_numpy import (
    ImplicitMethod, ImplicitScheme, ImplicitState, implicit_scheme, initial_implicit_state,
)
from spurdyn.solvers.layout import CP, OK, HistoryRow, ImplicitPack
from spurdyn.solvers.paper.dynamics_numpy import torques


class _Implicit(Stepper):
    """What both implicit steppers share: the history row and the loop over steps; each
    supplies ``_one`` (one step, its status), ``contact_columns`` and ``state``.

    The history's first residual and iteration columns hold the Newton iteration's; the
    other two stay 0 (the scheme has no velocity or acceleration stage).
    """

    def contact_columns(self) -> tuple[float, float, float, float, float]:
        raise NotImplementedError

    def _one(self) -> int:
        raise NotImplementedError

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


class ImplicitStepper(_Implicit):
    """Steps :class:`~spurdyn.solvers.implicit.step_numpy.ImplicitMethod` from the paper's
    start (:func:`~spurdyn.solvers.implicit.step_numpy.initial_implicit_state`: the teeth
    just touching, turning rigidly, with the forces of an acceleration stage at ``t = 0``).
    """

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        super().__init__(system, settings)
        self.method = ImplicitMethod(system, settings)
        self.state: ImplicitState = initial_implicit_state(system, settings, self.method.scheme)

    def contact_columns(self) -> tuple[float, float, float, float, float]:
        c = self.state.contact
        return c.s, c.alpha, c.beta, c.mode, c.half_width

    def _one(self) -> int:
        new, residual, its, status = self.method.step(self.state)
        self.residual[0], self.iterations[0] = residual, its
        if status == OK:
            self.state = new
        return status


def implicit_pack(system: PairSystem, settings: RunSettings, scheme: ImplicitScheme,
                  ns: int) -> ImplicitPack:
    """The compiled step's pack: the coefficients, and the teeth's constant iteration
    blocks as one banded Cholesky factor (reverse Cuthill-McKee order) and their inverse
    at the root DOFs."""
    coef = scheme.coef
    ratio = scheme.gp / scheme.bp
    a, b = settings.rayleigh
    blocks = sp.block_diag([sp.diags(g.mass * (1.0 / scheme.bp + a * ratio))
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
    law = scheme.law or (0.0, 0.0)
    return ImplicitPack(
        h=settings.dt, am=coef.alpha_m, af=coef.alpha_f, beta=coef.beta, gamma=coef.gamma,
        bp=scheme.bp, gp=scheme.gp, mq=scheme.mq, band=np.ascontiguousarray(factor.T), perm=perm,
        root_inv=np.ascontiguousarray(root_inv), base=scheme.base, c_mesh=scheme.c_mesh,
        ray_a=float(a), ray_b=float(b), c_h=scheme.c_h, estar=float(law[0]), face=float(law[1]),
        tol=settings.tol_disp, max_iter=settings.max_iter, ns=np.int64(ns))


class CompiledImplicitStepper(_Implicit):
    """The compiled twin: :func:`spurdyn.solvers.implicit.step_compiled.step` in place on
    the packed model of the paper's compiled stepper, from the NumPy stepper's start
    (:func:`~spurdyn.solvers.implicit.step_numpy.initial_implicit_state`) and scheme; it
    builds no NumPy step (no :class:`~spurdyn.solvers.implicit.step_numpy.ImplicitMethod`)."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        from spurdyn.solvers.paper.stepper_compiled import contact_slots, pack, strip_slots

        super().__init__(system, settings)
        scheme = implicit_scheme(system, settings)
        st = initial_implicit_state(system, settings, scheme)
        c = st.contact
        ns = strip_slots(system, settings)
        cn, cw = contact_slots(system, c, ns)
        self.P = pack(system, settings)
        self.I = implicit_pack(system, settings, scheme, ns)
        self.arrays = dict(
            theta=st.theta.copy(), omega=st.omega.copy(), u=st.u.copy(), v=st.v.copy(),
            x=st.x.copy(), qdd=st.qdd.copy(), acc=st.acc.copy(),
            cpar=np.array([c.alpha, c.beta, float(c.mode), c.s, 0.0, c.half_width, 0.0]),
            cn=cn, cw=cw, normal=c.normal.copy())
        self.time = st.t
        self._res = np.zeros(2)         # the last residual and the iterations
        from spurdyn.solvers.implicit.step_compiled import step

        self._step = step
        # None leaves the strip's code out of the point contact's kernel (step_compiled.step)
        self.strip = True if self.I.estar > 0.0 else None
        self.state = _View(self)

    def contact_columns(self) -> tuple[float, float, float, float, float]:
        cp = self.arrays["cpar"]
        return cp[CP.s], cp[CP.alpha], cp[CP.beta], cp[CP.mode], cp[CP.half_width]

    def _one(self) -> int:
        a = self.arrays
        status = self._step(self.P, self.I, self.strip, a["theta"], a["omega"], a["u"], a["v"],
                            a["x"], a["qdd"], a["acc"], a["cpar"], a["cn"], a["cw"],
                            a["normal"], self._res)
        self.residual[0], self.iterations[0] = self._res[0], int(self._res[1])
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
