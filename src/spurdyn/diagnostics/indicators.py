"""Condition indicators of a signal and of a gear's time-synchronous average.

RMS, kurtosis and crest factor of any signal; FM0 and FM4 (Stewart 1977) and NA4
(Zakrajsek, Townsend & Decker 1993) of the average of the shaft carrying a gear of
``teeth`` teeth, as Lebold et al. (2000) state them. Each is a ratio of the signal to
itself, so none depends on the signal's scale or on where the record starts.
``docs/diagnostics.md``, section 5.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.diagnostics.checks import as_signal
from spurdyn.diagnostics.tsa import (SHAFT_ORDERS, difference_signal, mesh_orders,
                                     order_amplitudes, residual_signal)
from spurdyn.errors import InputError

#: A centred signal whose RMS is below this fraction of its reference's largest value is
#: zero but for rounding: its kurtosis is not computed (NaN), not a number of the noise.
ROUNDING = 1e-12


def rms(signal: ArrayLike) -> float:
    """Root mean square ``sqrt(mean(x^2))`` (the mean not removed)."""
    x = as_signal(signal, "signal", least=1)
    return float(np.sqrt(np.mean(x * x)))


def _kurtosis(x: NDArray[np.float64], scale: float) -> float:
    """``N sum (x - xbar)^4 / (sum (x - xbar)^2)^2``; NaN if ``x`` is flat to rounding
    relative to ``scale``."""
    d = x - x.mean()
    s2 = float(np.sum(d * d))
    if s2 <= x.size * (ROUNDING * scale) ** 2:
        return float("nan")
    return float(x.size * np.sum(d ** 4) / s2 ** 2)


def kurtosis(signal: ArrayLike) -> float:
    """Normalised fourth moment about the mean: 3 for Gaussian noise, 1.5 for a sine.

    ``K = N sum (x_i - xbar)^4 / (sum (x_i - xbar)^2)^2``; NaN for a constant signal.
    """
    x = as_signal(signal, "signal")
    return _kurtosis(x, float(np.max(np.abs(x))))


def crest_factor(signal: ArrayLike) -> float:
    """Peak over RMS, ``max |x| / rms(x)``: ``sqrt(2)`` for a sine; NaN for all zeros."""
    x = as_signal(signal, "signal", least=1)
    r = rms(x)
    return float(np.max(np.abs(x)) / r) if r > 0.0 else float("nan")


def fm0(tsa: ArrayLike, teeth: int, harmonics: int | None = None) -> float:
    """FM0 = peak-to-peak of the average over the sum of its mesh harmonics' amplitudes
    (Stewart 1977): ``(max y - min y) / sum_{k=1..H} A_{k z}``.

    Parameters
    ----------
    tsa
        One revolution's average (:func:`~spurdyn.diagnostics.tsa.synchronous_average`).
    teeth
        ``z``, teeth of the gear on the averaged shaft.
    harmonics
        ``H``; all harmonics up to ``N/2`` if not given.

    Returns
    -------
    float
        2 for a pure mesh tone; NaN if the mesh harmonics are zero to rounding.
    """
    y = as_signal(tsa, "tsa", least=4)
    total = float(np.sum(order_amplitudes(y)[mesh_orders(y.size, teeth, harmonics)]))
    if total <= ROUNDING * float(np.max(np.abs(y))):
        return float("nan")
    return float(np.ptp(y)) / total


def fm4(tsa: ArrayLike, teeth: int, shaft_orders: int = SHAFT_ORDERS) -> float:
    """FM4 = kurtosis of the difference signal (Stewart 1977).

    About 3 when the difference signal is Gaussian noise (a healthy gear), well above 3
    when one or two teeth stand out (a local fault). NaN when the difference signal is
    zero to rounding (an average of mesh harmonics and shaft orders only).
    """
    y = as_signal(tsa, "tsa", least=4)
    return _kurtosis(difference_signal(y, teeth, shaft_orders), float(np.max(np.abs(y))))


def na4_trend(records: Sequence[ArrayLike] | ArrayLike, teeth: int,
              shaft_orders: int = SHAFT_ORDERS) -> NDArray[np.float64]:
    """NA4 of each record ``M = 1 .. len(records)`` against the records up to it.

    ``NA4_M = N sum_i (r_Mi - rbar_M)^4 / [(1/M) sum_{j=1..M} sum_i (r_ij - rbar_j)^2]^2``,
    ``r_j`` the residual signal of record ``j`` (Zakrajsek, Townsend & Decker 1993). For
    one record it is the residual's kurtosis; the running mean of the variances in the
    denominator lets the figure grow as damage grows.

    Parameters
    ----------
    records
        One average (1-D) or a sequence of averages of equal length, oldest first.
    teeth
        ``z``, teeth of the gear on the averaged shaft.
    shaft_orders
        Shaft orders ``1 .. S`` removed with the mesh harmonics.
    """
    if not hasattr(records, "__len__") or len(records) == 0:
        raise InputError("records", "must be one average or a list of them, oldest first")
    one = np.ndim(records[0]) == 0                 # a single average, not a list of them
    rows = ([as_signal(records, "records", least=4)] if one else
            [as_signal(r, f"records[{j}]", least=4) for j, r in enumerate(records)])
    if len({r.size for r in rows}) != 1:
        raise InputError("records", f"have lengths {sorted({r.size for r in rows})}: "
                                    "average every record onto the same number of points")
    scale = max(float(np.max(np.abs(r))) for r in rows)
    resid = np.array([residual_signal(r, teeth, shaft_orders) for r in rows])
    d = resid - resid.mean(axis=1, keepdims=True)
    s2 = np.sum(d * d, axis=1)
    mean_s2 = np.cumsum(s2) / np.arange(1, len(rows) + 1)
    n = resid.shape[1]
    flat = mean_s2 <= n * (ROUNDING * scale) ** 2
    out = n * np.sum(d ** 4, axis=1) / np.where(flat, 1.0, mean_s2) ** 2
    return np.where(flat, np.nan, out)


def na4(records: Sequence[ArrayLike] | ArrayLike, teeth: int,
        shaft_orders: int = SHAFT_ORDERS) -> float:
    """NA4 of the last of ``records`` (:func:`na4_trend`)."""
    return float(na4_trend(records, teeth, shaft_orders)[-1])
