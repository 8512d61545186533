"""The paper's method in NumPy as a :class:`~spurdyn.solvers.base.Stepper` (``backend="numpy"``)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.base import Frames, Stepper
from spurdyn.solvers.layout import FAIL_NAN, OK, HistoryRow
from spurdyn.solvers.paper.step_numpy import PaperMethod, State, initial_state


class NumpyStepper(Stepper):
    """Steps :class:`~spurdyn.solvers.paper.step_numpy.PaperMethod` one by one."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        super().__init__(system, settings)
        self.method = PaperMethod(system, settings)
        self.state: State = initial_state(system, settings)

    def row(self) -> NDArray[np.float64]:
        st, c = self.state, self.state.contact
        tau = self.method.torques(st.theta)
        res, its = self.residual, self.iterations
        return np.array(HistoryRow(
            t=st.t, theta_a=st.theta[0], theta_b=st.theta[1], omega_a=st.omega[0],
            omega_b=st.omega[1], tau_a=tau[0], tau_b=tau[1], p=st.x[-1], s=c.s, alpha=c.alpha,
            beta=c.beta, mode=c.mode, res1=res[0], res2=res[1], res3=res[2], it1=its[0],
            it2=its[1], it3=its[2], half_width=c.half_width), dtype=np.float64)

    def _advance(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
                 frames_every: int, frames: Frames) -> tuple[int, int, int]:
        written = 0
        for k in range(n):
            if self.state.theta[0] >= angle_end:
                return k, written, OK
            new, rep = self.method.step(self.state, self.index + k + 1)
            self.residual, self.iterations = rep.residual, rep.iterations
            if rep.status != OK:
                return k, written, rep.status     # what was computed before stays in rows
            if not np.all(np.isfinite(new.u)):
                return k, written, FAIL_NAN
            self.state = new
            index = self.index + k + 1
            if index % save_every == 0:
                rows[written] = self.row()
                written += 1
            if frames_every and index % frames_every == 0:
                frames.append((new.t, new.theta.copy(), new.u.copy()))
        return n, written, OK
