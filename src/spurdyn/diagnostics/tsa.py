"""Time-synchronous average over a shaft's revolutions, and the signals derived from it.

The record, sampled uniformly in time, is resampled onto ``N`` points per revolution of
the chosen shaft from the shaft's angle at each sample (a cubic spline of the signal
against the angle: computed order tracking, so the speed may vary), and the whole
revolutions are averaged (Braun 1975; McFadden 1987). Point ``n`` of the average sits at
shaft angle ``2 pi n / N`` (modulo a turn) along the rotation. The average's DFT bin ``q``
is shaft order ``q`` exactly, so the regular, residual and difference signals remove
whole orders. ``docs/diagnostics.md``, sections 3 and 4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.diagnostics.checks import as_signal, count
from spurdyn.errors import InputError

#: Shaft orders 1 .. this removed with the mesh harmonics from the residual and
#: difference signals (the shaft's unbalance and misalignment, orders 1 and 2).
SHAFT_ORDERS = 2


@dataclass(frozen=True)
class SynchronousAverage:
    """A time-synchronous average.

    Attributes
    ----------
    signal
        The average over one revolution, ``N`` points; point ``n`` at shaft angle
        ``2 pi n / N`` along the rotation.
    revolutions
        Number of whole revolutions averaged.
    """

    signal: NDArray[np.float64]
    revolutions: int

    @property
    def angle(self) -> NDArray[np.float64]:
        """Shaft angle of each point (rad), ``2 pi n / N``."""
        return 2.0 * np.pi * np.arange(self.signal.size) / self.signal.size


def _travel(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """The angle as travelled along the rotation (increasing), refused if not monotonic."""
    step = np.diff(angle)
    if np.all(step > 0.0):
        return angle
    if np.all(step < 0.0):
        return -angle
    raise InputError("angle", "must rise (or fall) strictly from sample to sample: give the "
                              "unwrapped shaft angle (rad) of a shaft that does not stop or turn back")


def synchronous_average(signal: ArrayLike, angle: ArrayLike, points: int) -> SynchronousAverage:
    """Average ``signal`` over the whole revolutions of the shaft whose angle is ``angle``.

    Parameters
    ----------
    signal
        Samples, uniformly spaced in time (the spline needs no time step).
    angle
        The shaft's unwrapped angle (rad) at each sample; strictly monotonic (the speed
        may vary). Revolution ``r`` spans angles ``2 pi r .. 2 pi (r + 1)``.
    points
        ``N``, points per revolution. Content above shaft order ``N/2`` aliases: take
        ``N`` at least the samples per revolution, or low-pass the signal first.

    Returns
    -------
    SynchronousAverage
        ``y[n] = (1/R) sum_r x(theta = 2 pi (r + n/N))`` over the ``R`` whole
        revolutions the record covers, ``x(theta)`` the cubic spline (not-a-knot)
        through ``(angle_i, signal_i)``.
    """
    x = as_signal(signal, "signal", least=4)
    theta = _travel(as_signal(angle, "angle", least=4))
    if theta.size != x.size:
        raise InputError("angle", f"has {theta.size} samples, the signal {x.size}: give one angle per sample")
    n = count(points, "points", 4)
    first = math.ceil(theta[0] / (2.0 * np.pi))
    last = math.floor(theta[-1] / (2.0 * np.pi))   # revolutions first .. last - 1 are whole
    if last - first < 1:
        turns = (theta[-1] - theta[0]) / (2.0 * np.pi)
        raise InputError("angle", f"covers {turns:.3g} revolutions and no whole one (from one "
                                  "multiple of 2 pi to the next): give a longer record")
    # imported when used: results.io imports this module for every run's summary
    from scipy.interpolate import CubicSpline

    grid = 2.0 * np.pi * (np.arange(first, last)[:, None] + np.arange(n)[None, :] / n)
    resampled = CubicSpline(theta, x)(grid.ravel()).reshape(grid.shape)
    return SynchronousAverage(resampled.mean(axis=0), last - first)


def order_amplitudes(tsa: ArrayLike) -> NDArray[np.float64]:
    """Amplitude of each shaft order ``q = 0 .. N/2`` of one revolution's average:
    ``2 |Y_q| / N`` (``|Y_q| / N`` at 0 and at Nyquist). No window: the average is one period."""
    y = as_signal(tsa, "tsa", least=4)
    a = np.abs(np.fft.rfft(y)) / y.size
    a[1:(y.size + 1) // 2] *= 2.0
    return a


def order_sideband_energy_ratio(tsa: ArrayLike, teeth: int, sidebands: int = 6, harmonic: int = 1) -> float:
    """The sideband energy ratio of a revolution's average read on its shaft orders:
    ``sum_{j=1..J} (A_{kz+j} + A_{kz-j}) / A_{kz}`` (the spectrum's
    :func:`~spurdyn.diagnostics.marks.sideband_energy_ratio` without its leakage: the
    average is one period, so every order sits on its own bin). NaN where the mesh
    harmonic's amplitude is zero or a sideband lies beyond the average's orders."""
    a = order_amplitudes(tsa)
    z = count(teeth, "teeth", 1) * count(harmonic, "harmonic", 1)
    j = count(sidebands, "sidebands", 1)
    if z + j >= a.size or z - j < 1 or a[z] == 0.0:
        return math.nan
    return float((a[z - j:z].sum() + a[z + 1:z + j + 1].sum()) / a[z])


def mesh_orders(points: int, teeth: int, harmonics: int | None = None) -> NDArray[np.int64]:
    """Shaft orders ``k z`` of the mesh harmonics ``k = 1 .. H`` resolved by ``points`` per
    revolution (``k z <= N/2``); ``H`` all of them if not given."""
    z = count(teeth, "teeth", 1)
    top = points // 2 // z
    if top < 1:
        raise InputError("teeth", f"the mesh order {z} is above the average's highest order "
                                  f"{points // 2}: average onto at least {2 * z} points")
    h = top if harmonics is None else min(count(harmonics, "harmonics", 1), top)
    return z * np.arange(1, h + 1)


def _orders_mask(points: int, teeth: int, shaft_orders: int, sidebands: int) -> NDArray[np.bool_]:
    """The orders of the regular signal (mean, shaft orders ``1 .. S``, mesh harmonics),
    and the mesh harmonics' sidebands ``k z +- 1 .. J``: the DFT bins to remove."""
    chosen = np.zeros(points // 2 + 1, dtype=bool)
    chosen[: count(shaft_orders, "shaft_orders", 0) + 1] = True
    j = np.arange(-count(sidebands, "sidebands", 0), sidebands + 1)
    orders = (mesh_orders(points, teeth)[:, None] + j[None, :]).ravel()
    chosen[orders[(orders >= 0) & (orders < chosen.size)]] = True
    return chosen


def _remove(tsa: ArrayLike, teeth: int, shaft_orders: int, sidebands: int,
            only: bool = False) -> NDArray[np.float64]:
    """The average less the orders of :func:`_orders_mask` (``only``: those orders alone)."""
    y = as_signal(tsa, "tsa", least=4)
    spec = np.fft.rfft(y)
    mask = _orders_mask(y.size, teeth, shaft_orders, sidebands)
    spec[~mask if only else mask] = 0.0
    return np.fft.irfft(spec, n=y.size)


def regular_signal(tsa: ArrayLike, teeth: int,
                   shaft_orders: int = SHAFT_ORDERS) -> NDArray[np.float64]:
    """Regular signal: the average's mean, shaft orders ``1 .. S`` and mesh harmonics
    ``k z`` (all up to ``N/2``), nothing else (Stewart 1977; Lebold et al. 2000)."""
    return _remove(tsa, teeth, shaft_orders, 0, only=True)


def residual_signal(tsa: ArrayLike, teeth: int,
                    shaft_orders: int = SHAFT_ORDERS) -> NDArray[np.float64]:
    """Residual signal: the average less the regular signal, first-order sidebands kept
    (Zakrajsek, Townsend & Decker 1993, for NA4; Lebold et al. 2000)."""
    return _remove(tsa, teeth, shaft_orders, 0)


def difference_signal(tsa: ArrayLike, teeth: int, shaft_orders: int = SHAFT_ORDERS,
                      sidebands: int = 1) -> NDArray[np.float64]:
    """Difference signal: the average less the regular signal and the mesh harmonics'
    sidebands of orders ``1 .. J`` (first order by default; Stewart 1977, for FM4)."""
    return _remove(tsa, teeth, shaft_orders, count(sidebands, "sidebands", 1))
