"""One-sided amplitude spectrum of a sampled signal, and a tone read between its bins.

The amplitude of a sine ``A sin(2 pi f t + phi)`` with ``f`` on a bin is read as ``A`` at
that bin: the windowed DFT is divided by the window's sum (its coherent gain times the
length) and the one-sided bins doubled. Off a bin the nearest bin reads ``A |W(d)| / W(0)``
(``d`` the offset in bins, ``W`` the window's transform): the scalloping loss, at most
:func:`scalloping_loss` at half a bin. :func:`read_tone` undoes it from the two largest
bins. ``docs/diagnostics.md``, section 1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.diagnostics.checks import as_signal, positive
from spurdyn.errors import InputError

#: A window as :func:`scipy.signal.get_window` names it: ``"hann"``, ``"boxcar"``,
#: ``"flattop"``, ``("kaiser", 8.0)``, ...
Window = str | tuple


@dataclass(frozen=True)
class Spectrum:
    """A one-sided amplitude spectrum.

    Attributes
    ----------
    frequency
        Bin frequencies ``k / (n dt)`` (Hz), ``k = 0 .. n // 2``.
    amplitude
        Amplitude at each bin, in the signal's unit (a sine on a bin reads its amplitude).
    window
        The window the signal was weighted with.
    n
        Number of samples transformed.
    dt
        Time step (s).
    """

    frequency: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    window: Window
    n: int
    dt: float

    @property
    def resolution(self) -> float:
        """Bin spacing ``1 / (n dt)`` (Hz)."""
        return 1.0 / (self.n * self.dt)


@dataclass(frozen=True)
class Tone:
    """A sinusoid read from a spectrum: frequency (Hz) and amplitude (signal's unit)."""

    frequency: float
    amplitude: float


def window_values(window: Window, n: int) -> NDArray[np.float64]:
    """The ``n`` weights of ``window`` (periodic, as for a DFT), refused naming ``window``."""
    # imported when used: scipy.signal brings scipy.stats (~0.5 s), which a run that only
    # writes its summary (results.io imports this module) never needs
    from scipy.signal import get_window

    try:
        return np.asarray(get_window(window, n, fftbins=True), dtype=np.float64)
    except (ValueError, TypeError) as err:
        raise InputError("window", f"{window!r} is not a window scipy.signal.get_window "
                                   f"knows ({err}); e.g. 'hann', 'flattop', 'boxcar'") from None


def spectrum(signal: ArrayLike, dt: float, window: Window = "hann") -> Spectrum:
    """One-sided amplitude spectrum of ``signal`` sampled every ``dt`` seconds.

    Parameters
    ----------
    signal
        Samples, uniformly spaced in time.
    dt
        Time step (s).
    window
        Window weighting the record (any :func:`scipy.signal.get_window` name).

    Returns
    -------
    Spectrum
        ``amplitude[k] = c_k |sum_n w_n x_n exp(-2 pi i k n / N)| / sum_n w_n`` with
        ``c_k = 2`` for ``0 < k < N/2`` and ``1`` at 0 and at Nyquist: a sine of
        amplitude ``A`` on bin ``k`` reads ``A`` (the coherent gain is corrected).
    """
    x = as_signal(signal, "signal")
    step = positive(dt, "dt")
    w = window_values(window, x.size)
    amplitude = np.abs(np.fft.rfft(w * x)) / np.sum(w)
    amplitude[1:(x.size + 1) // 2] *= 2.0          # both sides of a bin below Nyquist
    frequency = np.fft.rfftfreq(x.size, step)
    return Spectrum(frequency, amplitude, window, x.size, step)


def window_response(window: Window, n: int, offset: ArrayLike) -> NDArray[np.float64]:
    """``|W(d)| / W(0)``: the reading, relative to the amplitude, of a tone ``d`` bins off.

    ``W(d) = sum_n w_n exp(-2 pi i d n / N)`` is the window's transform at ``d`` bins.
    """
    w = window_values(window, n)
    d = np.atleast_1d(np.asarray(offset, dtype=np.float64))
    step = -2j * np.pi * np.arange(n) / n           # one offset at a time: memory O(n)
    return np.array([abs(np.dot(w, np.exp(step * di))) for di in d]) / np.sum(w)


def scalloping_loss(window: Window, n: int) -> float:
    """Largest relative shortfall of a nearest-bin reading: ``1 - |W(1/2)| / W(0)``.

    Hann: ``1 - 8 / (3 pi) = 0.151`` (1.42 dB) as ``n`` grows; boxcar ``1 - 2/pi = 0.363``.
    """
    return float(1.0 - window_response(window, n, 0.5)[0])


def read_tone(spec: Spectrum, near: float, half_width: float | None = None) -> Tone:
    """The tone whose peak is the largest bin within ``near +- half_width``, read between bins.

    The offset ``d`` (bins) of the tone from that bin ``k``, towards its larger neighbour,
    solves ``|W(1 - d)| / |W(d)| = A_neighbour / A_k``; then ``f = (k +- d) df`` and
    ``A = A_k W(0) / |W(d)|``. Exact for one tone (its mirror at ``-f`` aside, whose leak
    falls as the window's side lobes), whichever the window.

    Parameters
    ----------
    spec
        The spectrum.
    near
        Where to look (Hz).
    half_width
        Half the band searched (Hz); two bins if not given.
    """
    df = spec.resolution
    centre = positive(near, "near")
    half = 2.0 * df if half_width is None else positive(half_width, "half_width")
    inside = np.flatnonzero(np.abs(spec.frequency - centre) <= half)
    if inside.size == 0 or centre - half > spec.frequency[-1]:
        raise InputError("near", f"{centre} Hz +- {half} Hz holds no bin of this spectrum "
                                 f"(0 .. {spec.frequency[-1]} Hz every {df} Hz)")
    k = int(inside[np.argmax(spec.amplitude[inside])])
    if k == 0 or k == spec.amplitude.size - 1:
        return Tone(float(spec.frequency[k]), float(spec.amplitude[k]))
    side = 1 if spec.amplitude[k + 1] >= spec.amplitude[k - 1] else -1
    ratio = spec.amplitude[k + side] / spec.amplitude[k] if spec.amplitude[k] > 0 else 0.0

    def mismatch(d: float) -> float:
        r = window_response(spec.window, spec.n, [d, 1.0 - d])
        return r[1] / r[0] - ratio

    from scipy.optimize import brentq      # imported when used: scipy.optimize is slow to load

    lo, hi = mismatch(0.0), mismatch(0.5)
    d = 0.0 if lo >= 0 else 0.5 if hi <= 0 else brentq(mismatch, 0.0, 0.5, xtol=1e-12)
    gain = window_response(spec.window, spec.n, d)[0]
    return Tone(float((k + side * d) * df), float(spec.amplitude[k] / gain))
