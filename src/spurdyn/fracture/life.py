"""Fatigue life of a growing crack by Paris's law with a threshold (docs/fracture.md,
section 9).

Per load cycle the crack grows ``da/dN = C dK^m`` where the range ``dK`` is above the
threshold ``dK_th``, and not at all below it. Between two tips solved, ``dK`` is taken
linear in the crack's length ``a`` and the cycles are ``int da / (C dK(a)^m)`` (8-point Gauss-Legendre on
each increment: the closed form's figure to 1e-9 for the ranges of a tooth's crack); where ``dK`` falls
to the threshold the crack stops and the life beyond is unbounded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError

__all__ = ["Life", "ParisLaw", "paris_cycles"]

_X, _W = np.polynomial.legendre.leggauss(8)


@dataclass(frozen=True)
class ParisLaw:
    """``da/dN = C dK^m`` above ``dK_th``, SI: ``c`` in m per cycle at ``dK = 1 Pa sqrt(m)``,
    ``threshold`` in Pa sqrt(m). Refused naming the key (``crack.<key>``) unless ``c`` and
    ``m`` are positive and ``threshold`` is zero or more."""

    c: float
    m: float
    threshold: float = 0.0

    def __post_init__(self) -> None:
        for key, value, low in (("paris_c", self.c, 0.0), ("paris_m", self.m, 0.0),
                                ("threshold", self.threshold, None)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                    not math.isfinite(value) or (value <= 0.0 if low is not None else value < 0.0):
                need = "a positive number" if low is not None else "a number >= 0"
                raise InputError(f"crack.{key}", f"must be {need} (got {value!r})")

    def rate(self, dk: NDArray[np.float64]) -> NDArray[np.float64]:
        """``da/dN`` (m per cycle) at the ranges ``dk`` (Pa sqrt(m)): 0 at or below the
        threshold."""
        dk = np.asarray(dk, dtype=float)
        return np.where(dk > self.threshold, self.c * np.maximum(dk, 0.0) ** self.m, 0.0)


@dataclass(frozen=True)
class Life:
    """Cycles against crack length.

    Attributes
    ----------
    length
        ``(n,)`` the tips' lengths (m).
    cycles
        ``(n,)`` the cycles to grow from the first length to each (``inf`` beyond an arrest).
    arrested_at
        The length (m) where ``dK`` first reaches the threshold, ``None`` if it never does.
    """

    length: NDArray[np.float64]
    cycles: NDArray[np.float64]
    arrested_at: float | None


def paris_cycles(length: ArrayLike, dk: ArrayLike, law: ParisLaw) -> Life:
    """The cycles to grow through the tips' ``length`` (m, increasing) with the ranges ``dk``
    (Pa sqrt(m)) there (module docstring)."""
    a = np.asarray(length, dtype=float)
    k = np.asarray(dk, dtype=float)
    cycles = np.zeros(a.size)
    arrested = None
    for i in range(a.size - 1):
        if arrested is not None:
            cycles[i + 1] = math.inf
            continue
        lo, hi = k[i], k[i + 1]
        if lo <= law.threshold:
            arrested = float(a[i])
            cycles[i + 1] = math.inf
            continue
        if hi <= law.threshold:
            # dK reaches the threshold inside the increment: the crack stops there
            arrested = float(a[i] + (a[i + 1] - a[i]) * (lo - law.threshold) / (lo - hi))
            cycles[i + 1] = math.inf
            continue
        s = 0.5 * (_X + 1.0)
        rate = law.rate(lo + (hi - lo) * s)
        cycles[i + 1] = cycles[i] + 0.5 * (a[i + 1] - a[i]) * float(np.sum(_W / rate))
    if a.size and arrested is None and k[-1] <= law.threshold:
        arrested = float(a[-1])
    return Life(length=a, cycles=cycles, arrested_at=arrested)
