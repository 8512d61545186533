"""The time loop: ``simulate(pair, case) -> Result``."""

from spurdyn.integrate.run import simulate

__all__ = ["simulate"]
