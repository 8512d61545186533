"""The sector model's compiled steppers: the implicit loop
(:func:`~spurdyn.solvers.sector.step_compiled.run_steps`) and the RK4 reference
(:func:`~spurdyn.solvers.sector.rk4_compiled.run_rk4`) on the model's typed packs
(:meth:`~spurdyn.sector.model.SectorModel.packs`), a chunk of steps a call so that
progress shows and an interrupt stops them between chunks. Both step modal bodies of whole
gears (the packs index the teeth round the ring) and refuse any other model."""

from __future__ import annotations

import numpy as np

from spurdyn.errors import InputError
from spurdyn.sector.bearings import bearing_pack
from spurdyn.sector.faces import face_pack
from spurdyn.sector.model import SectorModel
from spurdyn.solvers.layout import OK, SectorRk4State
from spurdyn.solvers.sector.implicit_numpy import ImplicitStepper, check_pit
from spurdyn.solvers.sector.stepper import SectorRecord, SectorStepper


def _refuse_compiled(model: SectorModel) -> None:
    """The compiled loops step modal bodies of whole gears (their packs index the teeth round
    the ring): refuse any other model."""
    if not (model.modes and model.whole):
        raise InputError("backend", "the sector model's compiled loops step modal bodies of whole "
                         "gears (3 cycles or more, bodies='modal'): give backend='numpy'")


class CompiledImplicitStepper(ImplicitStepper):
    """The implicit loop compiled: the NumPy stepper's start and first row, then
    :func:`~spurdyn.solvers.sector.step_compiled.run_steps` a chunk a call."""

    keeps_energy = False

    @classmethod
    def refuse(cls, model: SectorModel, energy: bool) -> None:
        super().refuse(model, energy)
        _refuse_compiled(model)

    def __init__(self, model: SectorModel, record: SectorRecord, offset: int = 0, energy: bool = False) -> None:
        super().__init__(model, record, offset, energy)
        self.gear0, self.gear1, self.contacts, self.table, self.cfg = model.packs(self.start_state.offset)
        self.faces = face_pack(model.faces, model.gears)
        self.bear = bearing_pack(model.bear)

    def _steps(self, n: int) -> tuple[int, int]:
        from spurdyn.solvers.sector.step_compiled import run_steps

        check_pit(self.model, self.state)
        step, status = run_steps(self.index, n, self.state, self.gear0, self.gear1, self.contacts, self.table,
                                 self.cfg, self.record.torque, self.record.out(), self.faces, self.bear)
        if status != OK:
            return step - 1 - self.index, int(status)
        self.reached = step
        return step - self.index, OK


class CompiledRk4Stepper(SectorStepper):
    """The RK4 reference compiled (twin of :class:`~spurdyn.solvers.sector.rk4.Rk4Stepper`)."""

    @classmethod
    def refuse(cls, model: SectorModel, energy: bool) -> None:
        super().refuse(model, energy)
        _refuse_compiled(model)
        cls.refuse_crack(model)
        cls.refuse_bearings(model)

    def __init__(self, model: SectorModel, record: SectorRecord, offset: int = 0, energy: bool = False) -> None:
        super().__init__(model, record, offset, energy)
        start = model.start()
        self.state = SectorRk4State(start.q, start.v, start.force, start.force.copy())
        self.gear0, self.gear1, self.contacts, self.table, self.cfg = model.packs()
        n_steps = record.gap.size - 1
        self.tq_half = np.ascontiguousarray(model.torques(np.arange(2 * n_steps + 1) * (0.5 * model.h)))

    def _steps(self, n: int) -> tuple[int, int]:
        from spurdyn.solvers.sector.rk4_compiled import run_rk4

        step, status = run_rk4(self.index, n, self.state, self.gear0, self.gear1, self.contacts, self.table,
                               self.cfg, self.tq_half, self.record.out())
        if status != OK:
            return step - 1 - self.index, int(status)
        self.reached = step
        return step - self.index, OK


__all__ = ["CompiledImplicitStepper", "CompiledRk4Stepper"]
