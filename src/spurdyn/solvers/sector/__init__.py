"""The sector model in motion (docs/sector.md, section 6): two gears of elastic teeth on
elastic rims, their hubs rigid disks with inertia, every tooth pair on the path of contact a
unilateral contact, stepped by the generalized-alpha scheme (and an RK4 reference).

This package holds the stepping only; the model it steps, built once a run
(:class:`~spurdyn.sector.model.SectorModel` with its bodies, contacts, mesh damper, start
state and rules), is the model data of :mod:`spurdyn.sector`, a floor below.

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

``SectorModel`` is served here too, from :mod:`spurdyn.sector.model`.
"""

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for (the
#: package imports lightly).
_EXPORTS = {
    "simulate_sector": "run", "simulate_sector_rk4": "rk4", "STEPPERS": "stepper",
    "SectorModel": "spurdyn.sector.model",
}

__all__ = sorted(_EXPORTS)

# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
