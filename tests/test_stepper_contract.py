"""The stepper contract, one test looped over every stepper (docs/architecture.md).

Each entry of :data:`CONTRACT` is one stepper (:class:`~spurdyn.solvers.base.Stepper`) with
the time loop that drives it: the FE (paper) model's of :data:`spurdyn.solvers.loop.STEPPERS`
and the sector model's of :data:`spurdyn.solvers.sector.stepper.STEPPERS`, every integrator
on both backends. Every one of them:

- *starts*: a fresh stepper has taken no step, has no failure, and its current sample is
  finite;
- *steps*: ``advance(n)`` takes ``n`` steps, writes ``n`` finite samples in time order (the
  FE model's as history rows, the sector model's into its record), the last of them the
  stepper's current state, and counts them;
- *stops on a signal*: a stop signal (SIGTERM, handled as :mod:`spurdyn.signals` handles it
  in a command) that lands while the loop runs stops the loop at its next progress report,
  and the run comes back ``incomplete``, "interrupted by the user at step N", with the N
  steps it made and their samples;
- *reports a failure the same way*: a NaN put into its state stops the next step; the
  stepper keeps its step count, sets :attr:`~spurdyn.solvers.base.Stepper.failure` and
  returns the base class's message (:meth:`~spurdyn.solvers.base.Failure.message`), and the
  loop returns the steps before with that message as the run's reason.

To add a stepper, append one :class:`Entry` to :data:`CONTRACT` (see its fields); every
test below then runs on it.
"""

from __future__ import annotations

import functools
import math
import os
import signal
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import pytest
from numpy.typing import NDArray

from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.model.system import build_system
from spurdyn.result import Result
from spurdyn.sector.model import SectorModel
from spurdyn.settings import RPM, RunSettings
from spurdyn.signals import Interrupts
from spurdyn.solvers.base import Failure, Stepper
from spurdyn.solvers.check import run_settings
from spurdyn.solvers.layout import FAIL_NAN, NCOL
from spurdyn.solvers.loop import STEPPERS, make_stepper, simulate
from spurdyn.solvers.sector import stepper as sector
from spurdyn.solvers.sector.rk4 import PAPER_STEP, simulate_sector_rk4
from spurdyn.solvers.sector.run import simulate_sector

Progress = Callable[[int, float, float], None]
Samples = NDArray[np.float64]


def _poison_velocity(stepper: Stepper) -> None:
    """A NaN in one nodal velocity of the stepper's state."""
    stepper.state.v[7] = np.nan


def _history_samples(stepper: Stepper, rows: Samples, n: int) -> tuple[Samples, Samples]:
    """The history rows the last ``n`` steps wrote into ``rows``, and the row after them."""
    return rows[:n], rows[n]


def _history_row(stepper: Stepper) -> Samples:
    return stepper.row()


@dataclass(frozen=True)
class Entry:
    """One stepper under the contract.

    ``make()`` builds the stepper at the start of its run. ``run(progress, chunk)`` runs its
    time loop (the one the commands use) with that progress callback, reporting every
    ``chunk`` steps, and returns the :class:`~spurdyn.result.Result`; the loop must build
    its stepper as ``make()`` does (the same class), long enough for three reports.
    ``poison(stepper)`` puts a NaN into the stepper's state.

    How to read what a step wrote: ``rows_per_step`` history rows it writes into
    ``advance``'s ``rows`` (the sector's write none: they keep their record);
    ``samples(stepper, rows, n)`` the samples of its last ``n`` steps (one row a step, the
    time first) and what it wrote after them (all NaN: nothing); ``current(stepper)`` the
    sample of its current state, in the same columns.
    """

    name: str
    make: Callable[[], Stepper]
    run: Callable[[Progress | None, int], Result]
    poison: Callable[[Stepper], None] = field(default=_poison_velocity)
    rows_per_step: int = 1
    samples: Callable[[Stepper, Samples, int], tuple[Samples, Samples]] = field(default=_history_samples)
    current: Callable[[Stepper], Samples] = field(default=_history_row)


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


# -- the sector model ----------------------------------------------------------------------
SPEED = 4000 * RPM
#: The sector runs' steps: whole gears (3 cycles, which the compiled loops need); the implicit
#: loop at 100 steps a mesh cycle, so that its run of 300 steps reports every 3 (a hundred
#: reports a run), RK4 at its paper step, its run cut at 300 steps.
SECTOR_STEPS = 300


def _sector_settings(backend: str) -> RunSettings:
    return run_settings(paper_pair(), SPEED, 22.25, model="sector", nx=2, ny=8, cycles=3, max_cycles=3,
                        damping_ratio=0.05, backend=backend)


def _sector_dt(integrator: str) -> float:
    period = 2 * math.pi / paper_pair().gear_a.teeth / SPEED
    return period / 100 if integrator == "implicit" else PAPER_STEP


@functools.lru_cache(maxsize=None)
def _sector_model(integrator: str) -> SectorModel:
    """The model of the sector entries (built once a session; the backend is the stepper's)."""
    return SectorModel.build(paper_pair(), _sector_settings("numpy"), integrator=integrator,
                             dt=_sector_dt(integrator))


def _sector_poison(stepper: Stepper) -> None:
    """A NaN in the velocity of the driver's first mode."""
    stepper.state.v[1] = np.nan


def _sector_sample(stepper: Any, i: int) -> Samples:
    """Step ``i``'s sample of the stepper's record: the time, the hubs' turns and speeds, the
    pairs' forces."""
    rec = stepper.record
    return np.concatenate([[i * stepper.model.h], rec.theta[i], rec.omega[i], rec.force[i]])


def _sector_samples(stepper: Any, rows: Samples, n: int) -> tuple[Samples, Samples]:
    i = stepper.index
    return (np.array([_sector_sample(stepper, k) for k in range(i - n + 1, i + 1)]),
            _sector_sample(stepper, i + 1)[1:])


def _sector_current(stepper: Any) -> Samples:
    model, q, v = stepper.model, stepper.state.q, stepper.state.v
    return np.concatenate([[stepper.index * model.h, q[0], q[model.na], v[0], v[model.na]], stepper.force])


def _sector(integrator: str, backend: str) -> Entry:
    """The sector model of the paper pair (2 x 8 teeth meshes, modal bodies of whole gears) at
    4,000 rpm: ``(integrator, backend)`` of :data:`spurdyn.solvers.sector.stepper.STEPPERS`."""
    settings = _sector_settings(backend)

    def make() -> Stepper:
        model = _sector_model(integrator)
        return sector.make_stepper(model, sector.SectorRecord(model, 4 * SECTOR_STEPS // 100), integrator, backend)

    def run(progress: Progress | None, chunk: int) -> Result:
        assert chunk == SECTOR_STEPS // 100, "the sector loops report every hundredth of their run"
        if integrator == "implicit":
            return simulate_sector(paper_pair(), settings, progress, dt=_sector_dt(integrator))
        return simulate_sector_rk4(paper_pair(), settings, _sector_dt(integrator), progress, steps=SECTOR_STEPS)

    return Entry(f"sector-{integrator}-{backend}", make, run, _sector_poison, 0, _sector_samples, _sector_current)


#: Every stepper under the contract: the FE model's and the sector model's, each from its
#: ``STEPPERS`` (so one added there is here too); append any other's entries below.
CONTRACT: list[Entry] = ([_paper(integrator, backend) for integrator, backend in sorted(STEPPERS)]
                         + [_sector(integrator, backend) for integrator, backend in sorted(sector.STEPPERS)])

IDS = [e.name for e in CONTRACT]
STEPS = 3          # steps a test takes (each a report of the loop in the signal test)


def test_every_registered_fe_stepper_is_under_the_contract():
    assert {e.name for e in CONTRACT} >= {f"fe-{i}-{b}" for i, b in STEPPERS}


def test_every_registered_sector_stepper_is_under_the_contract():
    assert {e.name for e in CONTRACT} >= {f"sector-{i}-{b}" for i, b in sector.STEPPERS}


@pytest.mark.parametrize("entry", CONTRACT, ids=IDS)
def test_starts_and_steps(entry: Entry):
    stepper = entry.make()
    assert stepper.index == 0 and stepper.failure is None
    start = entry.current(stepper)
    assert np.isfinite(start).all()
    t0, theta0 = start[0], stepper.theta_a
    rows = np.full((STEPS + 1, NCOL), np.nan)
    written = entry.rows_per_step * STEPS
    assert stepper.advance(STEPS, math.inf, 1, rows, 0, []) == (STEPS, written, "")
    assert stepper.index == STEPS and stepper.failure is None
    taken, after = entry.samples(stepper, rows, STEPS)
    assert taken.shape == (STEPS,) + start.shape
    assert np.isfinite(taken).all() and np.isnan(after).all()
    assert np.array_equal(taken[-1], entry.current(stepper))
    t = np.concatenate([[t0], taken[:, 0]])
    assert np.all(np.diff(t) > 0) and entry.current(stepper)[0] == t[-1]
    assert stepper.theta_a > theta0                      # gear A turns
    # and goes on from where it stopped
    more = np.full((STEPS + 1, NCOL), np.nan)
    assert stepper.advance(STEPS, math.inf, 1, more, 0, []) == (STEPS, written, "")
    assert stepper.index == 2 * STEPS and entry.samples(stepper, more, STEPS)[0][0, 0] > t[-1]


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
