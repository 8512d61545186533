"""The implicit integrator as a :class:`~spurdyn.solvers.base.Stepper`
(``integrator="implicit"``, both backends: NumPy and SciPy's sparse factors)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.base import Frames, Stepper
from spurdyn.solvers.implicit.step import ImplicitMethod, ImplicitState
from spurdyn.solvers.layout import NCOL, OK, H
from spurdyn.solvers.paper.dynamics_numpy import torques
from spurdyn.solvers.paper.step_numpy import initial_state


class ImplicitStepper(Stepper):
    """Steps :class:`~spurdyn.solvers.implicit.step.ImplicitMethod` from the paper's start
    (:func:`~spurdyn.solvers.paper.step_numpy.initial_state`: the teeth just touching,
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

    def row(self) -> NDArray[np.float64]:
        st, c = self.state, self.state.contact
        row = np.zeros(NCOL)
        row[H.t] = st.t
        row[H.theta_a], row[H.theta_b] = st.theta
        row[H.omega_a], row[H.omega_b] = st.omega
        row[H.tau_a], row[H.tau_b] = torques(self.system, self.settings.torque, st.theta)
        row[H.p] = st.x[-1]
        row[H.s], row[H.alpha], row[H.beta], row[H.mode] = c.s, c.alpha, c.beta, c.mode
        row[H.res1] = self.residual[0]
        row[H.it1] = self.iterations[0]
        row[H.half_width] = c.half_width
        return row

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
            new, residual, its, status = self.method.step(self.state)
            self.residual[0], self.iterations[0] = residual, its
            if status != OK:
                return k, written, status
            self.state = new
            index = self.index + k + 1
            if index % save_every == 0:
                rows[written] = self.row()
                written += 1
            if frames_every and index % frames_every == 0:
                frames.append((new.t, new.theta.copy(), new.u.copy()))
        return n, written, OK
