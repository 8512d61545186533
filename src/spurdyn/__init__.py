"""spurdyn: dynamic contact analysis of spur gears by the method of Lee and Jang.

The package follows the order of the work: ``geometry`` (involute teeth and trochoidal
fillets) → ``mesh`` (Q8 tooth meshes) → ``fem`` (elements, assembly, lumped mass) →
``model`` → ``contact`` → ``solver`` → ``integrate`` → ``results`` → ``cli``.
"""

from typing import Any

from spurdyn.errors import InputError

__version__ = "0.1.0"

__all__ = ["InputError", "__version__", "simulate"]


def __getattr__(name: str) -> Any:
    # ``spurdyn.simulate`` is the solver's entry point, imported only when asked for.
    if name == "simulate":
        from spurdyn.integrate import simulate

        return simulate
    raise AttributeError(f"module 'spurdyn' has no attribute {name!r}")
