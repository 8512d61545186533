"""spurdyn: dynamic contact analysis of spur gears by the method of Lee and Jang.

Floors, each using only those below it (docs/architecture.md): ``errors``, ``settings``,
``result`` → ``fem`` (elements, assembly, stable step) → ``geometry`` (involute teeth,
fillets, relief, pairs) → ``mesh`` (Q8 tooth meshes) → ``model`` (what a run builds once:
bodies, flanks, loading, stiffness) → ``contact`` (flank search, NumPy and compiled) →
``solvers`` (the stepper contract, the paper's method in NumPy and compiled, the time
loop) → ``lumped`` → ``results`` (files, plots) → ``sweep`` → ``casefile``/``cases`` →
``cli``. Compiled code comes in through one gate, :mod:`spurdyn.jit`.
"""

from typing import Any

from spurdyn.errors import InputError

from spurdyn.version import __version__

__all__ = ["InputError", "__version__", "run_settings", "simulate"]


def __getattr__(name: str) -> Any:
    # ``simulate`` and ``run_settings`` are the solver's entry points, imported when asked for.
    if name == "simulate":
        from spurdyn.solvers.loop import simulate

        return simulate
    if name == "run_settings":
        from spurdyn.solvers.check import run_settings

        return run_settings
    raise AttributeError(f"module 'spurdyn' has no attribute {name!r}")
