"""The sector model in motion (docs/sector.md, section 6): two gears of elastic teeth on
elastic rims, their hubs rigid disks with inertia, every tooth pair on the path of contact a
unilateral contact, stepped by the generalized-alpha scheme.

``system``
    The two bodies' matrices in the hubs' frames, the teeth they hold (a sector, or the
    whole gear with its teeth indexed round the ring), a tooth pair's rigid gap on and off
    the path and its strip.
``reduced``
    A body on its modes and flank shapes with the flanks' residual flexibility.
``bodies``
    A gear as the time loop sees it: the whole body or the reduced one, behind one small
    interface.
``run``
    :func:`~spurdyn.solvers.sector.run.simulate_sector`: the static start and the time loop.
``output``
    The run as a :class:`~spurdyn.result.Result` with the pairs' forces, the transmission
    error and the settled test.

It sits above :mod:`spurdyn.sector` (the bodies and the quasi-static mesh cycle it starts
from) and beside :mod:`spurdyn.solvers.implicit`, whose coefficients it steps with.
"""

__all__: list[str] = []
