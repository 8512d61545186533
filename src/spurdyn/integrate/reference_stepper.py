"""The NumPy reference method driven by the time loop."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from spurdyn.solver.case import RunCase
from spurdyn.solver.reference import ConvergenceError, NonFiniteError, ReferenceStepper, initial_state
from spurdyn.solver.system import PairSystem


class ReferenceLoopStepper:
    """Adapter of :class:`~spurdyn.solver.reference.ReferenceStepper` to the loop."""

    def __init__(self, system: PairSystem, case: RunCase) -> None:
        self.system = system
        self.method = ReferenceStepper(system, case)
        self.state = initial_state(self.method)
        self.residual = np.zeros(3)
        self.iterations = np.zeros(3)
        self.index = 0

    @property
    def theta_a(self) -> float:
        return float(self.state.theta[0])

    @property
    def theta(self) -> NDArray[np.float64]:
        return self.state.theta

    @property
    def u(self) -> NDArray[np.float64]:
        return self.state.u

    @property
    def t(self) -> float:
        return self.state.t

    def row(self) -> NDArray[np.float64]:
        st, c = self.state, self.state.contact
        tau = self.method.torques(st.theta)
        return np.array([st.t, *st.theta, *st.omega, *tau, st.x[-1], c.s, c.alpha, c.beta, c.mode,
                         *self.residual, *self.iterations])

    def advance(self, n, angle_end, save_every, rows, frames_every, frames):
        written = 0
        for _ in range(n):
            if self.state.theta[0] >= angle_end:
                break
            try:
                self.state, rep = self.method.step(self.state, self.index + 1)
            except (ConvergenceError, NonFiniteError) as err:
                # What was computed before the failing step stays in ``rows``.
                return _count(self, n), written, str(err)
            self.index += 1
            self.residual, self.iterations = rep.residual, rep.iterations
            if not np.all(np.isfinite(self.state.u)):
                return _count(self, n), written, f"the solution became NaN at step {self.index}"
            if self.index % save_every == 0:
                rows[written] = self.row()
                written += 1
            if frames_every and self.index % frames_every == 0:
                frames.append((self.state.t, self.state.theta.copy(), self.state.u.copy()))
        return _count(self, n), written, ""


def _count(stepper: ReferenceLoopStepper, n: int) -> int:
    done = stepper.index - getattr(stepper, "_last", 0)
    stepper._last = stepper.index
    return done
