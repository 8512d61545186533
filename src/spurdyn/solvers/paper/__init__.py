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
