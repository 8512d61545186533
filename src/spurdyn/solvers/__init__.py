"""Time stepping: the stepper contract, the methods, the run check and the time loop.

- :mod:`~spurdyn.solvers.base`: :class:`~spurdyn.solvers.base.Stepper` owns the step count
  and the failure status; each method supplies its steps.
- :mod:`~spurdyn.solvers.layout`: typed packs for compiled code (model arrays, state,
  configuration, prediction, history columns), each defined once.
- :mod:`~spurdyn.solvers.check`: the one run check (stable step, angle, step count).
- :mod:`~spurdyn.solvers.limits`: the bounds of the settings against the pair, and the
  size of a run allowed unasked.
- :mod:`~spurdyn.solvers.paper`: the paper's method, NumPy and compiled twins side by side.
- :mod:`~spurdyn.solvers.implicit`: the implicit integrator (generalized-alpha), NumPy
  and compiled twins.
- :mod:`~spurdyn.solvers.loop`: ``simulate(pair, settings) -> Result`` and the registry of
  steppers by integrator and backend.
- :mod:`~spurdyn.solvers.warmup`: whether the compiled solver still has to be compiled.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for
#: (the package's modules import one another, so an eager facade would make circles).
_EXPORTS = {
    "Failure": "base", "Stepper": "base", "RunPlan": "check", "check_run": "check",
    "default_dt": "check", "run_settings": "check", "stable_step": "check", "HISTORY": "layout",
    "NCOL": "layout", "HistoryRow": "layout", "STEPPERS": "loop", "make_stepper": "loop",
    "simulate": "loop", "needs_compiling": "warmup",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
