"""The direction a crack grows by the maximum tangential stress criterion of Erdogan & Sih
(1963), and the equivalent mode I factor it gives (docs/fracture.md, section 6)."""

from __future__ import annotations

import math

from spurdyn.errors import InputError

__all__ = ["driving_k", "equivalent_k", "growth_angle", "tangential_stress"]


def _checked(k_i: float, k_ii: float) -> tuple[float, float]:
    for key, value in (("k_i", k_i), ("k_ii", k_ii)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                not math.isfinite(value):
            raise InputError(key, f"must be a finite stress intensity factor in Pa sqrt(m) "
                             f"(got {value!r})")
    if k_i <= 0.0 and k_ii == 0.0:
        raise InputError("k_i", f"a crack pressed shut (K_I = {k_i:g}, K_II = 0) has no "
                         "direction of growth by the tangential stress; give K_I > 0 or "
                         "K_II != 0")
    return float(k_i), float(k_ii)


def growth_angle(k_i: float, k_ii: float) -> float:
    """The angle (rad) from the crack's line ahead of the tip at which the tangential stress
    ``sigma_tt sqrt(2 pi r)`` is largest: ``theta_c = 2 atan[(K_I - sqrt(K_I^2 + 8 K_II^2))
    / (4 K_II)]``, counter-clockwise positive in the tip's frame (so of sign opposite to
    K_II).

    Written as ``-2 atan[2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2))]``, the same number (multiply
    the fraction above and below by ``K_I + sqrt(...)``), which stays defined at K_II = 0.

    Raises
    ------
    InputError
        ``k_i``/``k_ii`` not finite, or ``k_i`` for a crack with K_I <= 0 and K_II = 0.
    """
    k_i, k_ii = _checked(k_i, k_ii)
    return -2.0 * math.atan(2.0 * k_ii / (k_i + math.sqrt(k_i * k_i + 8.0 * k_ii * k_ii)))


def tangential_stress(k_i: float, k_ii: float, theta: float) -> float:
    """``sigma_tt sqrt(2 pi r)`` (Pa sqrt(m)) of the near-tip field at angle ``theta``:
    ``cos(theta / 2) [K_I cos^2(theta / 2) - 3/2 K_II sin(theta)]``."""
    c = math.cos(0.5 * theta)
    return c * (k_i * c * c - 1.5 * k_ii * math.sin(theta))


def equivalent_k(k_i: float, k_ii: float) -> float:
    """The mode I factor (Pa sqrt(m)) with the same largest tangential stress:
    ``tangential_stress`` at :func:`growth_angle`."""
    return tangential_stress(k_i, k_ii, growth_angle(k_i, k_ii))


def driving_k(k_i: float, k_ii: float) -> float:
    """The equivalent factor that drives growth (Pa sqrt(m)): :func:`equivalent_k` of a tip
    open in mode I, 0 for a tip closed (``K_I <= 0``).

    The maximum tangential stress criterion takes the tip open: with ``K_I <= 0`` its angle
    runs past +-70.5 deg toward the crack's own faces (K_I = -1, K_II = 0.01 gives -178 deg),
    which a closed tip does not do; such a load position is taken not to grow the crack.
    """
    if isinstance(k_i, bool) or not isinstance(k_i, (int, float)) or not math.isfinite(k_i):
        raise InputError("k_i", f"must be a finite stress intensity factor in Pa sqrt(m) (got {k_i!r})")
    return 0.0 if k_i <= 0.0 else equivalent_k(k_i, k_ii)
