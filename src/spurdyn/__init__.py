"""spurdyn: dynamic contact analysis of spur gears by the method of Lee and Jang.

Floors, each using only those below it (docs/architecture.md, tests/test_floor_plan.py):
``errors``, ``version``, ``result``, ``jit``, ``signals``, ``lazy`` → ``fem`` (elements, assembly,
stable step) → ``geometry`` (involute teeth, fillets, relief, pairs) → ``iso6336`` →
``mesh`` (Q8 meshes of a tooth and of a sector) → ``settings`` → ``model`` (what a run
builds once: bodies, flanks, loading, stiffness) → ``contact`` (flank search, Hertzian
strips, NumPy and compiled) → ``sector`` (the sector model's body and quasi-static mesh
cycle) → ``solvers`` (the stepper contract, the paper's method and the implicit
integrator, the time loop) → ``lumped`` → ``case`` (presets, case files, pair and
torque tables) → ``results`` (files, plots) → ``simulators`` → ``sweep`` → ``cli``.
Compiled code comes in through one gate, :mod:`spurdyn.jit`.
"""

from typing import Any, Callable

from spurdyn.errors import InputError
from spurdyn.lazy import lazy_facade

from spurdyn.version import __version__

__all__ = ["InputError", "__version__", "run_settings", "simulate"]


def simulate(pair: Any, settings: Any, progress: Callable[[int, float, float], None] | None = None,
             *, model: str | None = None) -> Any:
    """Simulate ``pair`` with the run ``settings`` by ``model`` (one of
    :data:`spurdyn.simulators.MODELS`: ``"fe"``, ``"lumped"``, ``"sector"``; by default
    :data:`spurdyn.settings.DEFAULT_MODEL`, the sector model) and return its
    :class:`~spurdyn.result.Result`.

    The model's entry first refuses, naming the field, a setting it does not read that
    differs from its default (:meth:`spurdyn.simulators.ModelEntry.refuse`), so that nothing
    given is ignored in silence.
    """
    from spurdyn.settings import DEFAULT_MODEL
    from spurdyn.simulators import MODELS

    model = DEFAULT_MODEL if model is None else model
    if model not in MODELS:
        raise InputError("model", f"must be one of {', '.join(MODELS)} (got {model!r})")
    entry = MODELS[model]
    entry.refuse(settings, None, pair)
    return entry(pair, settings, progress)


# ``run_settings`` is the solver's entry point, imported when asked for (spurdyn.lazy)
__getattr__, __dir__ = lazy_facade(__name__, {"run_settings": "solvers.check"}, globals())
