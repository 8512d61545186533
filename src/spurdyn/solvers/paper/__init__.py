"""The paper's method (RK4, unilateral constraints, the accelerated three-stage iteration).

Twins in mirrored files, each NumPy module beside its compiled counterpart and tested
against it by name:

=====================  =======================  ==========================================
NumPy                  compiled                 what
=====================  =======================  ==========================================
``dynamics_numpy``     ``dynamics_compiled``    equations of motion, constraint forces
``iteration_numpy``    ``iteration_compiled``   the accelerated iteration (Appendix B)
``step_numpy``         ``step_compiled``        one step: three stages (with
                       (+ ``response_compiled``) the compiled superposition)
``stepper_numpy``      ``stepper_compiled``     the :class:`~spurdyn.solvers.base.Stepper`
=====================  =======================  ==========================================

``constants`` holds what both read (the force's relocation limits).
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for
#: (the compiled twins load Numba's code only when used).
_EXPORTS = {
    "PaperMethod": "step_numpy", "initial_state": "step_numpy", "NumpyStepper": "stepper_numpy",
    "CompiledStepper": "stepper_compiled", "StaticStiffness": "statics",
    "static_stiffness": "statics",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
