"""The generalized-alpha scheme's coefficients and the implicit integrator's default step.

Pure functions of numbers (docs/implicit.md, sections 1 and 4). They are data of a run's
settings, not of a step, so they sit below both their readers: the implicit integrator's
step (:mod:`spurdyn.solvers.implicit`) and the sector model, whose bodies are factorised
for the scheme's ``beta'`` and ``gamma'`` and whose step and modal cutoff resolve
:data:`KEEP_FREQUENCY` (:mod:`spurdyn.sector.model`, :mod:`spurdyn.sector.rules`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: The highest frequency (Hz) the default step resolves: the pair's torsional mode
#: (~7.5 kHz for the paper's pair), the contact ripple (~120 kHz) and the free tooth's first
#: mode (95 kHz on the paper's 4 x 14 mesh) lie below it; the tooth's higher modes (217 kHz
#: and up, the highest ~13 MHz) are damped out by the scheme's dissipation. The sector model
#: takes it too, as its step's and its modal bodies' cutoff (docs/sector.md, 6.3).
KEEP_FREQUENCY = 150e3
#: Steps per period of :data:`KEEP_FREQUENCY`.
STEPS_PER_KEPT_PERIOD = 10
#: Steps per mesh period (one base pitch of rotation): the contact point must cross each
#: element along the flank in several steps. At 175 it crosses one of the paper's 4 x 14
#: mesh in 21 steps or more at 20,000 rpm (measured on Fig. 9), and the step of Fig. 9,
#: 6.1e-7 s, is 20 times RK4's (docs/implicit.md, section 4); 200 gave 5.3e-7 s, 17.6 times.
STEPS_PER_MESH_PERIOD = 175


@dataclass(frozen=True)
class GeneralizedAlpha:
    """Chung and Hulbert's generalized-alpha coefficients for a spectral radius
    ``rho_inf`` at infinite frequency (second order, unconditionally stable for linear
    systems, the least low-frequency dissipation for a given high-frequency one)."""

    rho_inf: float

    @property
    def alpha_m(self) -> float:
        return (2.0 * self.rho_inf - 1.0) / (self.rho_inf + 1.0)

    @property
    def alpha_f(self) -> float:
        return self.rho_inf / (self.rho_inf + 1.0)

    @property
    def gamma(self) -> float:
        return 0.5 - self.alpha_m + self.alpha_f

    @property
    def beta(self) -> float:
        return 0.25 * (1.0 - self.alpha_m + self.alpha_f) ** 2

    def beta_prime(self, h: float) -> float:
        """``d q_{n+1} / d qddot_{n+1}`` at fixed ``n`` data: ``h^2 beta (1 - af) / (1 - am)``."""
        return h * h * self.beta * (1.0 - self.alpha_f) / (1.0 - self.alpha_m)

    def gamma_prime(self, h: float) -> float:
        """``d qdot_{n+1} / d qddot_{n+1}``: ``h gamma (1 - af) / (1 - am)``."""
        return h * self.gamma * (1.0 - self.alpha_f) / (1.0 - self.alpha_m)


def accuracy_step(speed_a: float, teeth_a: int) -> float:
    """The implicit integrator's step (s) for accuracy: the smaller of a tenth of the period
    of :data:`KEEP_FREQUENCY` and 1/:data:`STEPS_PER_MESH_PERIOD` of the mesh period
    ``2 pi / (z_A omega_A)`` (the run check rounds it down to two digits)."""
    return min(1.0 / (STEPS_PER_KEPT_PERIOD * KEEP_FREQUENCY),
               2.0 * math.pi / (teeth_a * abs(speed_a)) / STEPS_PER_MESH_PERIOD)
