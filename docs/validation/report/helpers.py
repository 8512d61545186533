"""Pure helpers of the report: functions of arrays and numbers, no solver, no files.

Moving average, dynamic factor, zone masks, contact episodes, spectra and number
formatting (and :func:`~validation.common.table`, shared with the other pages); ``tests/test_validation_script.py`` checks them on synthetic data.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from validation.common import table  # noqa: F401 - the report's tables, shared by all pages

from .settings import WINDOW
from .spurdyn_api import window_means


def moving_average(t: NDArray[np.float64], f: NDArray[np.float64],
                   window: float = WINDOW) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centred moving average of ``f`` over ``window`` seconds, by spurdyn's own rule.

    The average is :func:`spurdyn.results.headline.window_means`, the one that makes the
    dynamic factor of ``spurdyn run`` (the piecewise-linear force integrated over the
    window, steps weighted by their length). Returns ``(f_avg, t_avg)`` for the windows
    wholly inside the record: the mean and the centre of the window about each sample
    at least ``window / 2`` from both ends.
    """
    t = np.asarray(t, dtype=float)
    f = np.asarray(f, dtype=float)
    if t.size < 2:
        raise ValueError("need at least two samples")
    if window > t[-1] - t[0]:
        raise ValueError("the window is longer than the record")
    centre, mean, keep = window_means(t, f, window)
    whole = centre == t[keep]
    return mean[whole], centre[whole]


def window_gain(freq: float, window: float = WINDOW) -> float:
    """Amplitude kept by the moving average for a sinusoid of ``freq`` Hz: ``|sinc|``."""
    x = math.pi * freq * window
    return 1.0 if x == 0 else abs(math.sin(x) / x)


def dynamic_factor(force: NDArray[np.float64], static: float) -> float:
    """The raw factor: the largest force over the quasi-static force (NaN when there is no
    contact). The dynamic factor ``spurdyn run`` reports is that of the 10-us average
    (:func:`moving_average`)."""
    force = np.asarray(force, dtype=float)
    peak = float(np.nanmax(force)) if force.size else 0.0
    if not static > 0:
        raise ValueError("the static force must be positive")
    return peak / static if peak > 0 else float("nan")


def zone_masks(angle: NDArray[np.float64], theta_2: float, theta_s: float) -> dict[str, NDArray[np.bool_]]:
    """Masks of the three zones of the engagement by the rotation of A (same unit).

    ``double_in`` = [0, theta_2), ``single`` = [theta_2, theta_s - theta_2],
    ``double_out`` = (theta_s - theta_2, theta_s]; ``double`` is both double zones.
    """
    a = np.asarray(angle, dtype=float)
    lo, hi = theta_2, theta_s - theta_2
    if not 0 < lo <= hi:
        raise ValueError("need 0 < theta_2 <= theta_s / 2")
    masks = {"double_in": (a >= 0) & (a < lo), "single": (a >= lo) & (a <= hi),
             "double_out": (a > hi) & (a <= theta_s)}
    masks["double"] = masks["double_in"] | masks["double_out"]
    return masks


def contact_episodes(t: NDArray[np.float64], angle: NDArray[np.float64],
                     force: NDArray[np.float64]) -> list[dict[str, float]]:
    """Maximal runs of samples with a positive force.

    Each episode: ``t_on``, ``t_off`` (first and last sample in contact), ``angle_on``,
    ``angle_off``, ``peak`` and ``t_peak``, ``angle_peak``; ``open_end`` is True when
    the record ends in contact.
    """
    t, angle = np.asarray(t, float), np.asarray(angle, float)
    on = np.nan_to_num(np.asarray(force, float), nan=0.0) > 0.0
    out = []
    if not on.any():
        return out
    edges = np.diff(on.astype(np.int8))
    starts = list(np.flatnonzero(edges == 1) + 1)
    ends = list(np.flatnonzero(edges == -1))
    if on[0]:
        starts.insert(0, 0)
    if on[-1]:
        ends.append(on.size - 1)
    f = np.asarray(force, float)
    for a, b in zip(starts, ends):
        j = a + int(np.argmax(f[a:b + 1]))
        out.append({"t_on": float(t[a]), "t_off": float(t[b]), "angle_on": float(angle[a]),
                    "angle_off": float(angle[b]), "peak": float(f[j]), "t_peak": float(t[j]),
                    "angle_peak": float(angle[j]), "open_end": bool(b == on.size - 1)})
    return out


def on_common_grid(series: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]],
                   step: float) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
    """Interpolate several ``(t, f)`` series onto one uniform grid of ``step`` over the
    span they all cover."""
    lo = max(float(s[0][0]) for s in series)
    hi = min(float(s[0][-1]) for s in series)
    if hi <= lo:
        raise ValueError("the series do not overlap")
    n = int(math.floor((hi - lo) / step + 1e-9))
    grid = np.minimum(lo + step * np.arange(n + 1), hi)
    return grid, [np.interp(grid, s[0], s[1]) for s in series]


def rms(x: NDArray[np.float64]) -> float:
    """Root mean square."""
    x = np.asarray(x, dtype=float)
    return float(np.sqrt(np.mean(x * x)))


def ls_spectrum(t: NDArray[np.float64], x: NDArray[np.float64],
                freqs: NDArray[np.float64]) -> NDArray[np.float64]:
    """Least-squares amplitude spectrum of ``x(t)`` (a Lomb-Scargle periodogram with a
    mean and a linear trend taken out): at each frequency, the amplitude of the best fit
    ``a cos + b sin + c + d t``. For records only a few periods long, where an FFT's
    bins (1 / record length) are too coarse to locate a peak."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    tc = t - t.mean()
    base = np.column_stack([np.ones_like(tc), tc / (np.ptp(tc) or 1.0)])
    q, _ = np.linalg.qr(base)
    r = x - q @ (q.T @ x)
    out = np.empty(np.size(freqs))
    for i, fr in enumerate(np.atleast_1d(freqs)):
        w = 2 * math.pi * fr * tc
        m = np.column_stack([np.cos(w), np.sin(w)])
        m = m - q @ (q.T @ m)
        coef, *_ = np.linalg.lstsq(m, r, rcond=None)
        out[i] = math.hypot(*coef)
    return out


def dominant_frequency(t: NDArray[np.float64], x: NDArray[np.float64], f_lo: float, f_hi: float,
                       n: int = 4000) -> tuple[float, float]:
    """Frequency (Hz) and amplitude of the highest peak of :func:`ls_spectrum` in
    ``[f_lo, f_hi]``: a scan of ``n`` log-spaced frequencies, refined once around the best."""
    freqs = np.geomspace(f_lo, f_hi, n)
    i = int(np.argmax(ls_spectrum(t, x, freqs)))
    fine = np.linspace(freqs[max(i - 2, 0)], freqs[min(i + 2, n - 1)], 401)
    amp = ls_spectrum(t, x, fine)
    j = int(np.argmax(amp))
    return float(fine[j]), float(amp[j])


def spectrum_peak(t: NDArray[np.float64], x: NDArray[np.float64], f_lo: float,
                  f_hi: float | None = None) -> tuple[float, float]:
    """Frequency (Hz) and amplitude of the largest peak of the Hann-windowed, 8x
    zero-padded spectrum of ``x`` above ``f_lo`` (and below ``f_hi``)."""
    x = np.asarray(x, float) - np.mean(x)
    dt = float(t[1] - t[0])
    win = np.hanning(x.size)
    nfft = 1 << int(math.ceil(math.log2(8 * x.size)))
    spec = np.abs(np.fft.rfft(x * win, nfft)) * 2.0 / win.sum()
    freq = np.fft.rfftfreq(nfft, dt)
    sel = freq >= f_lo
    if f_hi is not None:
        sel &= freq <= f_hi
    i = int(np.argmax(np.where(sel, spec, -1.0)))
    return float(freq[i]), float(spec[i])


def first_crossing(x: NDArray[np.float64], y: NDArray[np.float64], level: float) -> float:
    """First ``x`` where ``y`` reaches ``level`` from below (linear interpolation); NaN if never."""
    y = np.asarray(y, float)
    idx = np.flatnonzero(y >= level)
    if idx.size == 0:
        return float("nan")
    j = int(idx[0])
    if j == 0:
        return float(x[0])
    return float(x[j - 1] + (level - y[j - 1]) * (x[j] - x[j - 1]) / (y[j] - y[j - 1]))


def relative(a: float, b: float) -> float:
    """``a / b - 1``."""
    return a / b - 1.0


def zero_crossing_frequency(t: NDArray[np.float64], x: NDArray[np.float64]) -> tuple[float, int]:
    """Mean frequency (Hz) of an oscillation from its zero crossings about its mean:
    ``(crossings - 1) / (2 (last - first))``; returns the frequency and the number of
    crossings (NaN with fewer than three)."""
    t = np.asarray(t, float)
    x = np.asarray(x, float) - np.mean(x)
    s = np.signbit(x)
    idx = np.flatnonzero(s[1:] != s[:-1])
    if idx.size < 3:
        return float("nan"), int(idx.size)
    tz = t[idx] - x[idx] * (t[idx + 1] - t[idx]) / (x[idx + 1] - x[idx])
    return float((tz.size - 1) / (2.0 * (tz[-1] - tz[0]))), int(tz.size)


# -- formatting -----------------------------------------------------------------------

def n0(x: float) -> str:
    """A whole number with thousands separators."""
    return f"{x:,.0f}"


def n1(x: float) -> str:
    return f"{x:,.1f}"


def n2(x: float) -> str:
    return f"{x:,.2f}"


def n3(x: float) -> str:
    return f"{x:,.3f}"


def pct(x: float, digits: int = 1) -> str:
    """A fraction as a signed percentage (no sign when it rounds to zero)."""
    if round(100 * x, digits) == 0:
        return f"{0:.{digits}f} %"
    return f"{100 * x:+.{digits}f} %"


def upct(x: float, digits: int = 1) -> str:
    """A fraction as an unsigned percentage."""
    return f"{100 * x:.{digits}f} %"


def sci(x: float, digits: int = 2) -> str:
    """``1.23 × 10⁻⁴`` style."""
    if x == 0 or not math.isfinite(x):
        return str(x)
    e = int(math.floor(math.log10(abs(x))))
    m = x / 10**e
    if round(abs(m), digits) >= 10:
        m, e = m / 10, e + 1
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"{m:.{digits}f} × 10{sup}"
