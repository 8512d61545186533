"""The sector model in motion (docs/sector.md, section 6): two gears of elastic teeth on
elastic rims, their hubs rigid disks with inertia, every tooth pair on the path of contact a
unilateral contact, stepped by the generalized-alpha scheme (and an RK4 reference).

``system``, ``reduced``, ``bodies``, ``state``, ``lcp``, ``damper``
    The model's pieces: the two bodies' matrices in the hubs' frames and the teeth they hold,
    a tooth pair's rigid gap and its strip; a body on its modes; a gear as the loops see it
    (whole or modal, behind one small interface, with its compiled twin); a continuation's
    state; the pairs' complementarity problem; the mesh damper.
``model``
    :class:`~spurdyn.solvers.sector.model.SectorModel`: all of them for one run, built once.
``stepper``
    The steppers' registry (``STEPPERS``, by integrator and backend) on the
    :class:`~spurdyn.solvers.base.Stepper` contract, the record they write and the
    settle-until-steady control.
``implicit_numpy``, ``step_compiled``, ``rk4``, ``rk4_compiled``, ``rows_compiled``, ``stepper_compiled``
    The implicit step and the RK4 reference in NumPy and compiled, the compiled pieces they
    share, and the compiled steppers.
``run``
    :func:`~spurdyn.solvers.sector.run.simulate_sector`: build, step until settled, write.
``output``
    The run as a :class:`~spurdyn.result.Result` with the pairs' forces, the transmission
    error and the settled test.

It sits above :mod:`spurdyn.sector` (the bodies and the quasi-static mesh cycle it starts
from) and beside :mod:`spurdyn.solvers.implicit`, whose coefficients it steps with.
"""

__all__ = ["simulate_sector", "simulate_sector_rk4", "SectorModel", "STEPPERS"]


def __getattr__(name: str):  # type: ignore[no-untyped-def]
    """The facade's names, imported when first asked for (the package imports lightly)."""
    if name == "simulate_sector":
        from spurdyn.solvers.sector.run import simulate_sector
        return simulate_sector
    if name == "simulate_sector_rk4":
        from spurdyn.solvers.sector.rk4 import simulate_sector_rk4
        return simulate_sector_rk4
    if name == "SectorModel":
        from spurdyn.solvers.sector.model import SectorModel
        return SectorModel
    if name == "STEPPERS":
        from spurdyn.solvers.sector.stepper import STEPPERS
        return STEPPERS
    raise AttributeError(name)
