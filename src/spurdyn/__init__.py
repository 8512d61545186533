"""spurdyn: dynamic contact analysis of spur gears by the method of Lee and Jang.

Floors, each using only those below it (docs/architecture.md, tests/test_floor_plan.py):
``errors``, ``version``, ``result``, ``jit``, ``signals`` → ``fem`` (elements, assembly,
stable step) → ``geometry`` (involute teeth, fillets, relief, pairs) → ``iso6336`` →
``mesh`` (Q8 meshes of a tooth and of a sector) → ``settings`` → ``model`` (what a run
builds once: bodies, flanks, loading, stiffness) → ``contact`` (flank search, Hertzian
strips, NumPy and compiled) → ``sector`` (the sector model's body and quasi-static mesh
cycle) → ``solvers`` (the stepper contract, the paper's method and the implicit
integrator, the time loop) → ``lumped`` → ``case`` (presets, case files, pair and
torque tables) → ``results`` (files, plots) → ``simulators`` → ``sweep`` → ``cli``.
Compiled code comes in through one gate, :mod:`spurdyn.jit`.
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
