"""The headline figures of a run: the 10-us-averaged peak force and its dynamic factor.

The raw step-to-step peak of the contact force is not converged: it carries the ripple of
local tooth modes that the contact point excites as it sweeps across element edges, and
its impacts vary by tens of per cent with settings (mesh, time step, spline points) whose
10-us averages agree to a few per cent (docs/validation.md, section 2). The figures a user
reads, ``summary.json``'s ``peak_force_N`` and ``dynamic_factor``, the command's line and
a sweep's ``dynamic_factor``, are therefore those of the contact force averaged over
:data:`AVERAGING_WINDOW_S`; the raw ones are kept beside them as ``peak_force_raw_N`` and
``dynamic_factor_raw``. This module is the one home of that average, for both models
(the FE solver and the lumped one) and for the validation report.

The average (:func:`moving_average`)
    The saved samples are joined by straight lines (the force as it is drawn) and that
    line is averaged over a *centred* window of :data:`AVERAGING_WINDOW_S`, by its exact
    integral. Samples are weighted by the time they span, so steps of unequal length (a
    last step shorter than the saving interval, an adaptive integrator) are handled; a
    non-finite sample is left out and the line joins its neighbours.
The ends
    Only whole windows inside the record are used: within half a window of either end
    the average is that of the first (last) whole window, held. A record shorter than one
    window has one window, the whole record. A spike at the very first or last sample is
    thus diluted over a whole window, as one in the middle is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Length (s) of the centred moving window of the headline average. It keeps the
#: dynamics at and below the mesh and torsional frequencies (7.5 kHz keeps 99 % of its
#: amplitude) and takes out the ripple of local tooth modes (above 100 kHz, under 20 %).
AVERAGING_WINDOW_S: float = 10e-6


def _finite_record(time: ArrayLike, force: ArrayLike
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """``(t, f, keep)``: the samples with a finite time and force, and their mask.

    Raises
    ------
    ValueError
        If the arrays are not one-dimensional of equal length, or the kept times do not
        increase strictly.
    """
    t = np.asarray(time, dtype=float)
    f = np.asarray(force, dtype=float)
    if t.ndim != 1 or t.shape != f.shape:
        raise ValueError(f"time and force must be 1-D of equal length (got {t.shape} and "
                         f"{f.shape})")
    keep = np.isfinite(t) & np.isfinite(f)
    tk = t[keep]
    if tk.size > 1 and not np.all(np.diff(tk) > 0.0):
        raise ValueError("the times of the samples must increase strictly")
    return tk, f[keep], keep


def window_means(time: ArrayLike, force: ArrayLike, window: float = AVERAGING_WINDOW_S
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Centres and means of the windows, one per finite sample.

    Parameters
    ----------
    time
        Sample times (s), strictly increasing where the force is finite.
    force
        Sampled force; non-finite samples are left out.
    window
        Window length (s), positive.

    Returns
    -------
    centre, mean, keep
        For each finite sample (``keep`` marks them in the input), the centre of its
        window (the sample's time, moved inside the record by at most half a window at the
        ends) and the mean of the piecewise-linear force over that window.
    """
    if not (window > 0.0 and math.isfinite(window)):
        raise ValueError(f"the window must be a positive length of time (got {window!r})")
    t, f, keep = _finite_record(time, force)
    n = t.size
    if n == 0:
        return t.copy(), f.copy(), keep
    span = float(t[-1] - t[0])
    if n == 1 or span <= 0.0:
        return t.copy(), f.copy(), keep
    w = min(float(window), span)
    h = np.diff(t)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * h)])
    slope = np.diff(f) / h

    def integral(x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Integral of the piecewise-linear force from ``t[0]`` to ``x``."""
        x = np.clip(x, t[0], t[-1])
        j = np.clip(np.searchsorted(t, x, side="right") - 1, 0, n - 2)
        s = x - t[j]
        return cum[j] + s * (f[j] + 0.5 * slope[j] * s)

    centre = np.clip(t, t[0] + 0.5 * w, t[-1] - 0.5 * w)
    mean = (integral(centre + 0.5 * w) - integral(centre - 0.5 * w)) / w
    return centre, mean, keep


def moving_average(time: ArrayLike, force: ArrayLike,
                   window: float = AVERAGING_WINDOW_S) -> NDArray[np.float64]:
    """The force averaged over a centred moving window, at each sample.

    See the module's description for the rule (piecewise-linear force, exact integral,
    whole windows only, the ends held).

    Parameters
    ----------
    time
        Sample times (s), strictly increasing where the force is finite.
    force
        Sampled force (any unit).
    window
        Window length (s), default :data:`AVERAGING_WINDOW_S`.

    Returns
    -------
    numpy.ndarray
        Same length as ``force``: the average of the window about each sample, NaN where
        the sample is not finite.
    """
    _, mean, keep = window_means(time, force, window)
    out = np.full(keep.shape, np.nan)
    out[keep] = mean
    return out


def averaged_peak(time: ArrayLike, force: ArrayLike, window: float = AVERAGING_WINDOW_S
                  ) -> tuple[float, float] | None:
    """``(peak, centre)``: the largest window mean and the centre (s) of its window.

    ``None`` when there is no finite sample. The first window wins a tie.
    """
    centre, mean, _ = window_means(time, force, window)
    if mean.size == 0:
        return None
    i = int(np.argmax(mean))
    return float(mean[i]), float(centre[i])


@dataclass(frozen=True)
class Headline:
    """The peak forces of a run and their dynamic factors.

    Attributes
    ----------
    peak_force, peak_angle_deg
        Peak of the averaged contact force (N) and the rotation of A at its window's
        centre; ``None`` when the teeth never touched.
    peak_force_raw, peak_angle_raw_deg
        Largest saved contact force and where; ``None`` when the teeth never touched.
    dynamic_factor, dynamic_factor_raw
        ``peak_force`` and ``peak_force_raw`` over the quasi-static force; ``None`` for a
        run stopped early, one without contact, or without a quasi-static force.
    note
        What ``dynamic_factor`` is, or why there is none.
    window_s
        The averaging window (s).
    """

    peak_force: float | None
    peak_angle_deg: float | None
    peak_force_raw: float | None
    peak_angle_raw_deg: float | None
    dynamic_factor: float | None
    dynamic_factor_raw: float | None
    note: str
    window_s: float = AVERAGING_WINDOW_S


def headline(time: ArrayLike, angle_deg: ArrayLike, force: ArrayLike, static_force: float,
             complete: bool, reason: str = "", window: float = AVERAGING_WINDOW_S) -> Headline:
    """The headline figures of a contact-force history.

    Parameters
    ----------
    time, angle_deg, force
        The saved samples: time (s), rotation of A (deg), contact force (N; 0 apart).
    static_force
        The quasi-static force torque / r_b (N).
    complete
        Whether the run reached its end. A run stopped early gets no dynamic factor: its
        largest force may be the step that stopped it, and the rest of the engagement is
        missing.
    reason
        Why the run stopped (for the note).
    window
        Averaging window (s).

    Returns
    -------
    Headline
    """
    t = np.asarray(time, dtype=float)
    a = np.asarray(angle_deg, dtype=float)
    f = np.asarray(force, dtype=float)
    touched = np.isfinite(f) & (f > 0.0)
    micro = f"{window * 1e6:g}-us"
    if not touched.any():
        return Headline(None, None, None, None, None, None,
                        "none: the teeth never touched" if complete else
                        f"none: the run stopped early ({reason or 'stopped'}) before the "
                        "teeth touched", window)
    raw = float(np.max(f[touched]))
    raw_at = float(a[touched][np.argmax(f[touched])])
    found = averaged_peak(t, f, window)
    assert found is not None  # there is a finite sample
    peak, centre = found
    ok = np.isfinite(a) & np.isfinite(t)
    peak_at = float(np.interp(centre, t[ok], a[ok]))
    if not complete:
        note = (f"none: the run stopped early ({reason or 'stopped'}); the peaks are those "
                "of the part computed, and the largest force may be the step that stopped it")
        return Headline(peak, peak_at, raw, raw_at, None, None, note, window)
    if not static_force > 0.0:
        return Headline(peak, peak_at, raw, raw_at, None, None,
                        "none: no quasi-static force (zero torque)", window)
    note = (f"peak of the contact force averaged over a centred {micro} moving window, over "
            "the quasi-static force torque / r_b; the raw step-to-step peak "
            "(dynamic_factor_raw) carries the ripple of local tooth modes and is not "
            "converged")
    return Headline(peak, peak_at, raw, raw_at, peak / static_force, raw / static_force,
                    note, window)


__all__ = ["AVERAGING_WINDOW_S", "Headline", "averaged_peak", "headline", "moving_average",
           "window_means"]
