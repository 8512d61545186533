"""The stepper contract, one test looped over every stepper (docs/architecture.md).

Each entry of :data:`CONTRACT` is one stepper (:class:`~spurdyn.solvers.base.Stepper`) with
the time loop that drives it. Every one of them, whatever its model, integrator and
backend:

- *starts*: a fresh stepper has taken no step, has no failure, and its history row is
  finite;
- *steps*: ``advance(n)`` takes ``n`` steps, writes ``n`` finite rows in time order, the
  last of them the stepper's current row, and counts them;
- *stops on a signal*: a stop signal (SIGTERM, handled as :mod:`spurdyn.signals` handles it
  in a command) that lands while the loop runs stops the loop at its next progress report,
  and the run comes back ``incomplete``, "interrupted by the user at step N", with the N
  steps it made and their rows;
- *reports a failure the same way*: a NaN put into its state stops the next step; the
  stepper keeps its step count, sets :attr:`~spurdyn.solvers.base.Stepper.failure` and
  returns the base class's message (:meth:`~spurdyn.solvers.base.Failure.message`), and the
  loop returns the steps before with that message as the run's reason.

To add a stepper, append one :class:`Entry` to :data:`CONTRACT` (see its fields); every
test below then runs on it.
"""

from __future__ import annotations

import math
import os
import signal
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import pytest

from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.model.system import build_system
from spurdyn.result import Result
from spurdyn.settings import RPM, RunSettings
from spurdyn.signals import Interrupts
from spurdyn.solvers.base import Failure, Stepper
from spurdyn.solvers.layout import FAIL_NAN, NCOL
from spurdyn.solvers.loop import STEPPERS, make_stepper, simulate

Progress = Callable[[int, float, float], None]


def _poison_velocity(stepper: Stepper) -> None:
    """A NaN in one nodal velocity of the stepper's state."""
    stepper.state.v[7] = np.nan


@dataclass(frozen=True)
class Entry:
    """One stepper under the contract.

    ``make()`` builds the stepper at the start of its run. ``run(progress, chunk)`` runs its
    time loop (the one the commands use) with that progress callback, reporting every
    ``chunk`` steps, and returns the :class:`~spurdyn.result.Result`; the loop must build
    its stepper as ``make()`` does (the same class), long enough for three reports.
    ``poison(stepper)`` puts a NaN into the stepper's state.
    """

    name: str
    make: Callable[[], Stepper]
    run: Callable[[Progress | None, int], Result]
    poison: Callable[[Stepper], None] = field(default=_poison_velocity)


def _paper(integrator: str, backend: str) -> Entry:
    """The paper pair's FE model: ``(integrator, backend)`` of
    :data:`spurdyn.solvers.loop.STEPPERS`, at 4,000 rpm under the paper's torque."""
    pair = paper_pair()
    settings = RunSettings(speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE,
                           integrator=integrator, backend=backend, frames_every=0,
                           angle=math.radians(0.5))
    if integrator == "implicit":
        settings = settings.with_(dt=6.6e-7)

    def make() -> Stepper:
        return make_stepper(build_system(pair, settings), settings)

    def run(progress: Progress | None, chunk: int) -> Result:
        return simulate(pair, settings, progress, chunk=chunk)

    return Entry(f"fe-{integrator}-{backend}", make, run)


#: Every stepper under the contract. The FE model's come from ``STEPPERS`` (so one added
#: there is here too); append the others' entries (e.g. the sector model's) below.
CONTRACT: list[Entry] = [_paper(integrator, backend) for integrator, backend in sorted(STEPPERS)]

IDS = [e.name for e in CONTRACT]
STEPS = 3          # steps a test takes (each a report of the loop in the signal test)


def test_every_registered_fe_stepper_is_under_the_contract():
    assert {e.name for e in CONTRACT} >= {f"fe-{i}-{b}" for i, b in STEPPERS}


@pytest.mark.parametrize("entry", CONTRACT, ids=IDS)
def test_starts_and_steps(entry: Entry):
    stepper = entry.make()
    assert stepper.index == 0 and stepper.failure is None
    start = stepper.row()
    assert start.shape == (NCOL,) and np.isfinite(start).all()
    t0, theta0 = stepper.t, stepper.theta_a
    rows = np.full((STEPS + 1, NCOL), np.nan)
    assert stepper.advance(STEPS, math.inf, 1, rows, 0, []) == (STEPS, STEPS, "")
    assert stepper.index == STEPS and stepper.failure is None
    assert np.isfinite(rows[:STEPS]).all() and np.isnan(rows[STEPS]).all()
    assert np.array_equal(rows[STEPS - 1], stepper.row())
    t = np.concatenate([[t0], rows[:STEPS, 0]])
    assert np.all(np.diff(t) > 0) and stepper.t == t[-1]
    assert stepper.theta_a > theta0                      # gear A turns
    # and goes on from where it stopped
    more = np.full((STEPS + 1, NCOL), np.nan)
    assert stepper.advance(STEPS, math.inf, 1, more, 0, []) == (STEPS, STEPS, "")
    assert stepper.index == 2 * STEPS and more[0, 0] > t[-1]


@pytest.mark.parametrize("entry", CONTRACT, ids=IDS)
def test_a_stop_signal_stops_the_loop_at_its_next_report(entry: Entry):
    """A SIGTERM sent during the loop (after its first report, as a user's would come) is
    counted, the stepper goes on to the next report, and the loop stops there, keeping
    the steps made."""
    reports: list[int] = []

    def progress(step: int, angle: float, total: float) -> None:
        reports.append(step)
        Interrupts.checkpoint()             # what the command's progress callback does
        if len(reports) == 1:
            os.kill(os.getpid(), signal.SIGTERM)

    Interrupts.reset()
    try:
        with Interrupts.installed(), Interrupts.checkpoints():
            r = entry.run(progress, STEPS)
        assert Interrupts.count == 1 and Interrupts.stopped() == "interrupted by SIGTERM"
    finally:
        Interrupts.reset()
    assert reports == [STEPS, 2 * STEPS]
    assert r.status == "incomplete"
    assert r.reason == f"interrupted by the user at step {2 * STEPS}", r.reason
    assert r.steps == 2 * STEPS and r.time.size == 2 * STEPS + 1
    assert np.all(np.diff(r.time) > 0) and np.isfinite(r.omega).all()


@pytest.mark.parametrize("entry", CONTRACT, ids=IDS)
def test_a_failure_is_reported_with_the_base_message(entry: Entry):
    stepper = entry.make()
    rows = np.full((STEPS + 1, NCOL), np.nan)
    assert stepper.advance(STEPS, math.inf, 1, rows, 0, [])[2] == ""
    entry.poison(stepper)
    done, written, reason = stepper.advance(STEPS, math.inf, 1, rows, 0, [])
    assert (done, written) == (0, 0) and stepper.index == STEPS
    assert stepper.failure == Failure(FAIL_NAN, STEPS + 1)
    assert reason == stepper.failure.message() == f"the solution became NaN at step {STEPS + 1}"


@pytest.mark.parametrize("entry", CONTRACT, ids=IDS)
def test_the_loop_reports_a_failure_with_the_steppers_message(entry: Entry, monkeypatch):
    """The NaN put into the state after the loop's first report: the run comes back
    ``incomplete`` with the stepper's message and the steps before, none of them NaN."""
    cls = type(entry.make())
    advance = cls._advance

    def poisoned(self, *args: Any):
        if self.index:                      # from the second chunk on
            entry.poison(self)
        return advance(self, *args)

    monkeypatch.setattr(cls, "_advance", poisoned)
    r = entry.run(None, STEPS)
    assert r.status == "incomplete"
    assert r.reason == Failure(FAIL_NAN, STEPS + 1).message(), r.reason
    assert r.steps == STEPS and r.time.size == STEPS + 1
    assert np.isfinite(r.omega).all() and np.isfinite(r.contact_force).all()
