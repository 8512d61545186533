"""The implicit time integrator beside the paper's RK4: generalized-alpha with the root
and contact constraints enforced at the end of each step (docs/implicit.md).

:mod:`~spurdyn.solvers.implicit.alpha` holds the scheme's coefficients and the default
step, :mod:`~spurdyn.solvers.implicit.damping` the damping forces (Rayleigh's on the
teeth, the mesh damper on the disks), :mod:`~spurdyn.solvers.implicit.step_numpy` one
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
    "GeneralizedAlpha": "alpha", "accuracy_step": "alpha", "mesh_damper_coefficient": "damping",
    "rayleigh_from_ratio": "damping", "ImplicitMethod": "step_numpy",
    "CompiledImplicitStepper": "stepper", "ImplicitStepper": "stepper",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
