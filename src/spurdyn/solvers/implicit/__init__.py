"""The implicit time integrator beside the paper's RK4: generalized-alpha with the root
and contact constraints enforced at the end of each step (docs/implicit.md).

The scheme's coefficients and the default step (:mod:`spurdyn.model.alpha`) and the mesh
damper's coefficient (:mod:`spurdyn.model.damper`) are data of a run's settings and live a
floor lower, where the sector model reads them too; this package holds the damping forces
(:mod:`~spurdyn.solvers.implicit.damping`: Rayleigh's on the teeth, the mesh damper on the
disks), :mod:`~spurdyn.solvers.implicit.step_numpy` one
step in NumPy and SciPy (Newton on the positions and the constraint forces, with the
contact's active set) and :mod:`~spurdyn.solvers.implicit.step_compiled` its Numba twin,
and :mod:`~spurdyn.solvers.implicit.stepper` the :class:`~spurdyn.solvers.base.Stepper` s
(``backend="numpy"`` and ``"numba"``) the time loop drives.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for
#: (the compiled twin loads Numba's code only when used).
_EXPORTS = {
    "GeneralizedAlpha": "spurdyn.model.alpha", "accuracy_step": "spurdyn.model.alpha",
    "mesh_damper_coefficient": "spurdyn.model.damper",
    "rayleigh_from_ratio": "spurdyn.solvers.implicit.damping",
    "ImplicitMethod": "spurdyn.solvers.implicit.step_numpy",
    "CompiledImplicitStepper": "spurdyn.solvers.implicit.stepper",
    "ImplicitStepper": "spurdyn.solvers.implicit.stepper",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
