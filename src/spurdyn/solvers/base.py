"""The stepper contract: a base class owns the bookkeeping, each method supplies the steps.

In the manner of SciPy's ``OdeSolver``: :meth:`Stepper.advance` counts the steps, keeps
the failure status and builds the one message a failure is reported with; a method
supplies :meth:`Stepper._advance` (take up to ``n`` steps, return a status code of
:mod:`spurdyn.solvers.layout`), the state it carries (``t``, ``theta``, ``omega``, ``u``,
``v``, ``x``) and the history row of its current state. Failure is a status, not an
exception: the time loop (:mod:`spurdyn.solvers.loop`) keeps what was computed and says why.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.model.system import PairSystem
from spurdyn.result import STAGES
from spurdyn.settings import RunSettings
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_LCP, FAIL_NAN, FAIL_NEWTON, FAIL_STRIP, OK

Frames = list[tuple[float, NDArray[np.float64], NDArray[np.float64]]]
#: The failures that are not a stage's: reported by their step (and ``detail``) alone.
PLAIN = (FAIL_NAN, FAIL_STRIP, FAIL_NEWTON, FAIL_BEYOND, FAIL_LCP)


@dataclass(frozen=True)
class Failure:
    """Why a step failed: its number, for a stage that did not converge, the stage's final
    residual, tolerance and iteration cap, and what the method adds (``detail``: where the
    sector model's driver had turned)."""

    status: int
    step: int
    residual: float = float("nan")
    tol: float = float("nan")
    iterations: int = 0
    detail: str = ""

    @property
    def stage(self) -> str:
        return "" if self.status in PLAIN else STAGES[self.status - 1]

    def message(self) -> str:
        """The one message of a failed step."""
        if self.status == FAIL_NAN:
            return f"the solution became NaN at step {self.step}"
        if self.status == FAIL_BEYOND:
            return f"at step {self.step} {self.detail}"
        if self.status == FAIL_LCP:
            return (f"step {self.step}: the contact problem of the pairs near the path (and of "
                    "a crack's faces, if any) had no solution within its pivots")
        if self.status == FAIL_STRIP:
            return (f"step {self.step}: the contact strip spread over more elements than the run "
                    f"allowed for (a force over 50 times the static one); check the load")
        if self.status == FAIL_NEWTON:
            return (f"step {self.step}: the implicit step's Newton iteration did not converge in "
                    f"{self.iterations} iterations (residual {self.residual:.3e} m, tolerance "
                    f"{self.tol:.3e} m); try a smaller --dt")
        return (f"step {self.step}: the {self.stage} stage did not converge in {self.iterations} "
                f"iterations (residual {self.residual:.3e}, tolerance {self.tol:.3e})")


class Stepper:
    """Base of the time steppers: step count, failure status and its message.

    Subclasses set ``self.residual`` (3,) and ``self.iterations`` (3,) after each step (the
    failing stage's where a step fails), implement :meth:`_advance` and :meth:`row`, and
    hold their state in ``self.state``, which the properties below read.
    """

    def __init__(self, system: PairSystem | Any, settings: RunSettings) -> None:
        # ``system``: the model stepped (the paper's PairSystem, the SectorModel)
        self.system = system
        self.settings = settings
        self.index = 0                       # steps taken
        self.failure: Failure | None = None
        self.residual = np.zeros(3)
        self.iterations = np.zeros(3, dtype=np.int64)

    # -- what a method supplies -----------------------------------------------------------
    def _advance(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
                 frames_every: int, frames: Frames) -> tuple[int, int, int]:
        """Take up to ``n`` steps; return ``(steps, rows_written, status)``.

        Stops early once gear A has turned ``angle_end`` or a step fails (``status`` not
        ``OK``; the failing step is not counted). Writes every ``save_every``-th step's
        history row into ``rows`` and appends ``(t, theta, u)`` every ``frames_every``-th
        step to ``frames``.
        """
        raise NotImplementedError

    def failure_detail(self, status: int) -> str:
        """What the method adds to the message of a failure ``status`` (none by default)."""
        return ""

    def row(self) -> NDArray[np.float64]:
        """The history row (columns :data:`spurdyn.solvers.layout.HISTORY`) of the current state."""
        raise NotImplementedError

    #: The method's state: anything with ``t``, ``theta``, ``omega``, ``u``, ``v``, ``x``
    #: (the NumPy ``State``, the compiled ``CompiledState``, whose ``t`` is a 1-array).
    state: Any

    @property
    def t(self) -> float:
        return float(np.asarray(self.state.t).reshape(-1)[0])

    @property
    def theta(self) -> NDArray[np.float64]:
        return self.state.theta

    @property
    def omega(self) -> NDArray[np.float64]:
        return self.state.omega

    @property
    def u(self) -> NDArray[np.float64]:
        return self.state.u

    @property
    def v(self) -> NDArray[np.float64]:
        return self.state.v

    @property
    def x(self) -> NDArray[np.float64]:
        return self.state.x

    # -- the bookkeeping ------------------------------------------------------------------
    @property
    def theta_a(self) -> float:
        return float(self.theta[0])

    def advance(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
                frames_every: int, frames: Frames) -> tuple[int, int, str]:
        """Take up to ``n`` steps; return ``(steps, rows_written, stop_reason)``, the reason
        ``""`` unless the run cannot go on (then :attr:`failure` says why)."""
        done, written, status = self._advance(n, angle_end, save_every, rows, frames_every, frames)
        self.index += done
        if status == OK:
            return done, written, ""
        s = self.settings
        k = status - 1
        tols = (s.tol_disp, s.tol_vel, s.tol_acc)
        if status == FAIL_NEWTON:   # the Newton iteration reports in the displacement columns
            k = 0
        plain = status in (FAIL_NAN, FAIL_STRIP, FAIL_BEYOND, FAIL_LCP)
        self.failure = (Failure(status, self.index + 1, detail=self.failure_detail(status)) if plain else
                        Failure(status, self.index + 1, float(self.residual[k]), tols[k], s.max_iter))
        return done, written, self.failure.message()
