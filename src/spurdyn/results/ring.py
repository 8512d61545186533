"""The pair's ring after a pair leaves, measured (docs/sector.md, section 6.5).

After the exit of a pair the remaining pair carries the load alone, and the mesh force rings
about the static force ``W`` at the pair's torsional frequency. Its frequency and damping
ratio come from a least-squares fit of a damped cosine (with an offset and a slope for the
slow drift of the quasi-static force) to the mesh force over the steps where one pair alone
touches: from a tenth of a pitch after the exit up to the step before the next pair touches
(early, at its tip corner). Zero crossings and peaks are not used: once the ring has decayed
to a few newtons, the teeth's own modes (near 30 kHz) and the next pair's first touch cross
zero and raise the peaks, which made a damped ring on 4 x 14 teeth look like 7.6 kHz and a
decrement of 0.10.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from spurdyn.geometry.pair import GearPair
from spurdyn.result import Result
from spurdyn.sector.statics import driving_pair


def single_contact_window(run: Result, pair: GearPair, after: float = 0.1) -> NDArray[np.intp]:
    """The steps of ``run``'s first stretch of single contact: from ``after`` of a pitch past
    the end of double contact (``contact_ratio % 1`` of the driver's pitch) until a second
    pair touches."""
    dp = driving_pair(pair)
    phase = run.theta[:, 0] / (2.0 * math.pi / dp.gear_a.teeth)
    start = np.flatnonzero(phase > dp.contact_ratio % 1.0 + after)[0]
    two = np.flatnonzero((run.pair_force[start:] > 0.0).sum(axis=1) > 1)
    stop = start + (two[0] if two.size else run.time.size - start)
    return np.arange(start, stop)


def damped_ring(t: NDArray[np.float64], x: NDArray[np.float64]) -> tuple[float, float, float]:
    """``(frequency Hz, damping ratio, rms residual / amplitude)`` of the fit
    ``x = A exp(-s t) cos(w t + p) + B + C t`` (module docstring). The frequency's first
    guess is the mean crossings' of ``x``'s mean; the phase's, eight starts round the circle."""
    t = np.asarray(t, dtype=float) - float(t[0])
    x = np.asarray(x, dtype=float)
    mid = float(x.mean())
    ups = np.flatnonzero((x[:-1] < mid) & (x[1:] >= mid))
    w0 = 2.0 * math.pi * (ups.size - 1) / float(t[ups[-1]] - t[ups[0]])
    amp = 0.5 * float(np.ptp(x))

    def residual(a: NDArray[np.float64]) -> NDArray[np.float64]:
        return a[0] * np.exp(-a[1] * t) * np.cos(a[2] * t + a[3]) + a[4] + a[5] * t - x

    best = None
    for p0 in np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False):
        fit = least_squares(residual, [amp, 0.05 * w0, w0, p0, mid, 0.0],
                            x_scale=[amp, 0.05 * w0, w0, 1.0, amp, amp / float(t[-1])])
        if best is None or fit.cost < best.cost:
            best = fit
    a = best.x
    return (float(a[2] / (2.0 * math.pi)), float(a[1] / math.hypot(a[1], a[2])),
            float(math.sqrt(2.0 * best.cost / t.size) / abs(a[0])))


__all__ = ["damped_ring", "single_contact_window"]
