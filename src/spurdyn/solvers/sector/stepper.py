"""The sector model's time steppers on the :class:`~spurdyn.solvers.base.Stepper` contract,
their registry, and the control that drives them.

:data:`STEPPERS` maps a time integrator and a backend to the stepper that steps a
:class:`~spurdyn.sector.model.SectorModel`: the implicit generalized-alpha loop in
NumPy (:class:`~spurdyn.solvers.sector.implicit_numpy.ImplicitStepper`) and compiled
(:class:`~spurdyn.solvers.sector.stepper_compiled.CompiledImplicitStepper`), the RK4
reference in both (:mod:`spurdyn.solvers.sector.rk4`,
:class:`~spurdyn.solvers.sector.stepper_compiled.CompiledRk4Stepper`). A stepper writes each
step's samples into the run's :class:`SectorRecord` and reports a failure as a status of
:mod:`spurdyn.solvers.layout` through the base's one message builder. :func:`drive` takes
steps to an end with progress and Ctrl-C; :func:`settle` is the settle-until-steady control
around it (one more cycle at a time until the run's settled test passes).
"""

from __future__ import annotations

import importlib
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.sector.model import SectorModel
from spurdyn.sector.rules import stress_steps
from spurdyn.solvers.base import Frames, Stepper
from spurdyn.solvers.layout import FAIL_BEYOND, FAIL_NAN, SectorOut
from spurdyn.solvers.steady import settled_after

Progress = Callable[[int, float, float], None]

#: ``(integrator, backend) -> "module:class"`` of the sector's steppers, imported when used.
STEPPERS: dict[tuple[str, str], str] = {
    ("implicit", "numpy"): "spurdyn.solvers.sector.implicit_numpy:ImplicitStepper",
    ("implicit", "numba"): "spurdyn.solvers.sector.stepper_compiled:CompiledImplicitStepper",
    ("rk4", "numpy"): "spurdyn.solvers.sector.rk4:Rk4Stepper",
    ("rk4", "numba"): "spurdyn.solvers.sector.stepper_compiled:CompiledRk4Stepper",
}


class SectorRecord:
    """A sector run's samples, one row a step: the hubs' ``torque`` at each step's end (driver
    first), turns ``theta`` and speeds ``omega``, the contacts' ``force``, the smallest ``gap``,
    with a crack its ``faces``' largest force, least and largest opening (none without) and,
    if asked, the ``energy`` balance (8 columns: kinetic, strain, strip, the torques'
    work, the hubs' momenta and the pairs' torques on them). Unwritten rows are NaN."""

    def __init__(self, model: SectorModel, n_steps: int, energy: bool = False) -> None:
        n_out = n_steps + 1
        self.torque = model.torques_at(np.arange(n_out))
        self.theta = np.full((n_out, 2), np.nan)
        self.omega = np.full((n_out, 2), np.nan)
        self.force = np.full((n_out, model.c_teeth.size), np.nan)
        self.gap = np.full(n_out, np.nan)
        self.faces = np.full((n_out if model.faces is not None else 0, 3), np.nan)
        self.energy = np.full((n_out, 8), np.nan) if energy else None
        # the hubs' translations and their rates (x_A, y_A, x_B, y_B, then their rates; driver first)
        self.hubs = np.full((n_out if model.bear is not None else 0, 2 * model.nt), np.nan)
        self._sample_states(model, n_steps)

    def _sample_states(self, model: SectorModel, n_steps: int) -> None:
        """The steps whose coordinates are kept (:func:`~spurdyn.sector.rules.stress_steps`)
        and their rows, those kept before carried over."""
        steps = stress_steps(model.per_cycle, n_steps)
        self.sample = np.full(n_steps + 1, -1, dtype=np.int64)
        self.sample[steps] = np.arange(steps.size)
        old = getattr(self, "states", np.zeros((0, model.n)))
        self.states = np.full((steps.size, model.n), np.nan)
        self.states[:old.shape[0]] = old

    def keep_state(self, i: int, q: NDArray[np.float64]) -> None:
        """Keep step ``i``'s coordinates ``q`` if it is a sampled step."""
        if self.sample[i] >= 0:
            self.states[self.sample[i]] = q

    def out(self) -> SectorOut:
        """The saved columns as the compiled loops write them."""
        return SectorOut(self.theta, self.omega, self.force, self.gap, self.states, self.sample, self.faces,
                         self.hubs)

    def extend(self, model: SectorModel, n_steps: int, more: int) -> None:
        """``more`` rows beyond the run's ``n_steps`` (now ``n_steps + more``), their torques."""
        self.theta, self.omega, self.force, self.gap = (
            np.concatenate([x, np.full((more,) + x.shape[1:], np.nan)])
            for x in (self.theta, self.omega, self.force, self.gap))
        if self.faces.size:
            self.faces = np.concatenate([self.faces, np.full((more, 3), np.nan)])
        if self.hubs.size:
            self.hubs = np.concatenate([self.hubs, np.full((more, self.hubs.shape[1]), np.nan)])
        self.torque = np.concatenate([self.torque, model.torques_at(np.arange(n_steps + 1, n_steps + more + 1))])
        if self.energy is not None:
            self.energy = np.concatenate([self.energy, np.full((more, 8), np.nan)])
        self._sample_states(model, n_steps + more)


class SectorStepper(Stepper):
    """Base of the sector's steppers: the model, the record it writes, the state's turn.

    A stepper holds its state in ``self.state`` (with the model's coordinates ``q``,
    velocities ``v`` and the contacts' ``force``), keeps ``self.reached`` (the last step
    whose samples are written, for an interrupt between two) and implements :meth:`_steps`."""

    #: Whether the stepper keeps the energy record (the NumPy implicit loop alone).
    keeps_energy = False

    def __init__(self, model: SectorModel, record: SectorRecord, offset: int = 0, energy: bool = False) -> None:
        super().__init__(model, model.settings)
        self.model, self.record, self.offset, self.energy = model, record, offset, energy
        self.reached = 0

    @classmethod
    def refuse(cls, model: SectorModel, energy: bool) -> None:
        """Refuse, by :class:`~spurdyn.errors.InputError`, a model this stepper does not step."""
        if energy and not cls.keeps_energy:
            raise InputError("energy", "the energy record is kept by the NumPy implicit loop alone: "
                             "give backend='numpy'")

    @staticmethod
    def refuse_bearings(model: SectorModel) -> None:
        """Refuse a model with the hubs on bearings (the implicit loop's alone)."""
        if model.bear is not None:
            raise InputError("gear_a.bearing" if model.settings.bearings[0] is not None else "gear_b.bearing",
                             "the RK4 reference does not step the hubs on bearings: give the implicit integrator")

    @staticmethod
    def refuse_crack(model: SectorModel) -> None:
        """Refuse a model with a crack's faces or a spall over part of the face width (their
        contacts, the faces' and the split pairs', are the implicit loop's alone)."""
        if model.faces is not None:
            raise InputError("fault", "the RK4 reference does not step a crack's faces' contact: "
                             "give the implicit integrator")
        if model.splits:
            raise InputError("fault", "the RK4 reference does not split a pair over a spall on part of the face "
                             "width: give the implicit integrator, or width_fraction = 1")

    def _steps(self, n: int) -> tuple[int, int]:
        """Take up to ``n`` steps; ``(steps done, status)``."""
        raise NotImplementedError

    def _advance(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
                 frames_every: int, frames: Frames) -> tuple[int, int, int]:
        # a state that is not finite (a NaN put into it between two calls) fails the next step
        # as a NaN: a step from it may otherwise fail as another (the contact problem, the
        # driver's turn), raise in a compiled solve or go on
        if not all(np.isfinite(x).all() for x in self.state):
            return 0, 0, FAIL_NAN
        # the sector's samples go to its record, every step: no rows, no frames
        done, status = self._steps(n)
        return done, 0, status

    def steps(self, n: int) -> str:
        """Take up to ``n`` steps; the stop reason (``""`` unless the run cannot go on)."""
        return self.advance(n, np.inf, 1, np.zeros((0, 0)), 0, [])[2]

    def failure_detail(self, status: int) -> str:
        return self.model.beyond(float(self.q[0])) if status == FAIL_BEYOND else ""

    @property
    def q(self) -> NDArray[np.float64]:
        return self.state.q

    @property
    def force(self) -> NDArray[np.float64]:
        return self.state.force

    @property
    def theta_a(self) -> float:
        return float(self.q[0])


def make_stepper(model: SectorModel, record: SectorRecord, integrator: str, backend: str,
                 energy: bool = False, offset: int = 0) -> SectorStepper:
    """The stepper of ``integrator`` on ``backend`` for ``model``; an unknown pair, or a model
    the stepper does not step, is refused (:class:`~spurdyn.errors.InputError`)."""
    if (integrator, backend) not in STEPPERS:
        raise InputError("backend", f"the sector model has no {integrator} integrator on {backend!r}: "
                         f"one of {', '.join('/'.join(k) for k in STEPPERS)}")
    module, name = STEPPERS[(integrator, backend)].split(":")
    cls = getattr(importlib.import_module(module), name)
    cls.refuse(model, energy)
    return cls(model, record, offset, energy)


def drive(stepper: SectorStepper, end: int, every: int, progress: Progress | None,
          total: float) -> tuple[str, str]:
    """Take steps to step ``end``, ``every`` a call of ``progress(step, turn, total)``;
    ``(status, reason)``, ``"incomplete"`` with why where a step failed or Ctrl-C came."""
    try:
        while stepper.index < end:
            stop = stepper.steps(min(every, end - stepper.index))
            if stop:
                return "incomplete", stop
            if progress is not None:
                progress(stepper.index, stepper.theta_a, total)
    except KeyboardInterrupt:
        # the steps whose samples are written, as the FE loop counts them
        return "incomplete", f"interrupted by the user at step {stepper.reached}"
    return "complete", ""


def settle(stepper: SectorStepper, progress: Progress | None) -> tuple[str, str, int, int]:
    """Drive ``stepper`` over the run's cycles, then one more period at a time (a mesh cycle;
    a faulty pair's revolution, ``model.period`` cycles) until the last two periods settle
    (:func:`~spurdyn.solvers.steady.settled_after`) or the run's limit; ``(status, reason,
    rows kept, cycles run)``."""
    model, record = stepper.model, stepper.record
    per_cycle, pitch, period = model.per_cycle, model.pitch, model.period
    target = model.cycles           # the cycles the run goes to: more, a period at a time
    n_steps = per_cycle * target
    every = max(n_steps // 100, 1)
    while True:
        status, reason = drive(stepper, n_steps, every, progress, target * pitch)
        if status != "complete":
            kept = stepper.reached + 1 if reason.startswith("interrupted") else stepper.index + 1
            return status, reason, kept, target
        periods = target // period
        lo, hi = (target - min(periods, 2) * period) * per_cycle, n_steps + 1       # the last two periods
        if target + period > model.most or settled_after(
                record.force[lo:hi].sum(axis=1),
                model.ra * record.theta[lo:hi, 0] - model.rb * record.theta[lo:hi, 1], per_cycle * period,
                min(periods, 2)):
            return status, reason, n_steps + 1, target
        record.extend(model, n_steps, per_cycle * period)        # not settled, and it may go on
        target += period
        n_steps += per_cycle * period


__all__ = ["STEPPERS", "SectorRecord", "SectorStepper", "drive", "make_stepper", "settle"]
