"""The pair's ring measured on a sector run: where its super-harmonic resonances fall.

After each change of the number of tooth pairs in contact the pair rings at the torsional
frequency of the stretch it enters: ``f_1`` over single contact, ``f_2`` over double (a
contact ratio ``1 < eps < 2``). Over a mesh period ``T`` the ring's phase turns by
``2 pi (f_1 t_1 + f_2 t_2)``, ``t_1 = (2 - eps) T`` and ``t_2 = (eps - 1) T`` the times of
single and double contact, so it is back in phase with the mesh after ``k`` turns when the
mesh frequency is ``f_bar / k``, with the time-weighted ring frequency

    f_bar = (2 - eps) f_1 + (eps - 1) f_2

(docs/report.md, "Why the dynamic factor jumps between neighbouring speeds"). Each ring
frequency is measured from the zero crossings of the mesh force about its static value,
over the stretch after a change of pairs (from :data:`SKIP_S` to :data:`SPAN_S` after it,
or to the next change), the median over the stretches of a run.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: A stretch's ring is read from this long after the change of pairs (s): the change
#: itself (a step of the contact forces over a few samples) left out ...
SKIP_S = 20e-6
#: ... to at most this long after it (s): some three decay times ``1 / (zeta omega)`` of a
#: pair ringing near 9 kHz with the mesh damper's 0.05, after which the ring is lost in the
#: mesh force's quasi-static ripple.
SPAN_S = 0.8e-3
#: Fewest zero crossings (two a period) a stretch needs for its frequency to count.
MIN_CROSSINGS = 4
#: A pair carries load when its force is above this fraction of the static force.
IN_CONTACT = 1e-3


def zone_frequencies(t: NDArray[np.float64], mesh_force: NDArray[np.float64],
                     pairs: NDArray[np.int64], static: float) -> dict[int, float]:
    """The ring frequency (Hz) over the stretches of each number of pairs in contact.

    Parameters
    ----------
    t
        Sample times (s), increasing.
    mesh_force
        The mesh force at each sample (N).
    pairs
        Pairs in contact at each sample.
    static
        The static mesh force (N), about which the force rings.

    Returns
    -------
    dict
        Pairs in contact -> the median over the stretches with at least
        :data:`MIN_CROSSINGS` zero crossings; numbers of pairs without such a stretch are
        left out.
    """
    f = np.asarray(mesh_force, float) - static
    changes = np.nonzero(np.diff(pairs))[0]
    ends = [*changes[1:], len(t) - 1]
    found: dict[int, list[float]] = {}
    for a, b in zip(changes, ends):
        x, y = t[a + 1:b + 1], f[a + 1:b + 1]
        keep = (x > t[a] + SKIP_S) & (x < t[a] + SPAN_S)
        x, y = x[keep], y[keep]
        if x.size < 2 * MIN_CROSSINGS:
            continue
        y = y - y.mean()             # about the stretch's own mean (the dynamic offset out)
        cross = np.nonzero(np.signbit(y[1:]) != np.signbit(y[:-1]))[0]
        if cross.size < MIN_CROSSINGS:
            continue
        tz = x[cross] - y[cross] * (x[cross + 1] - x[cross]) / (y[cross + 1] - y[cross])
        found.setdefault(int(pairs[a + 1]), []).append((cross.size - 1) / 2.0 / (tz[-1] - tz[0]))
    return {n: float(np.median(v)) for n, v in found.items()}


def mean_ring(freqs: dict[int, float], eps: float) -> float | None:
    """``f_bar = (2 - eps) f_1 + (eps - 1) f_2`` (Hz), or ``None`` where the contact ratio
    is not between 1 and 2 or a stretch's frequency is missing."""
    if not 1.0 < eps < 2.0 or 1 not in freqs or 2 not in freqs:
        return None
    return (2.0 - eps) * freqs[1] + (eps - 1.0) * freqs[2]


def measured_ring(result_nc: Path, eps: float, teeth_a: int, estimate_hz: float
                  ) -> dict[str, Any] | None:
    """The ring of the sector run in ``result_nc`` and the main resonance speed of gear A
    it gives, ``60 f_bar / z_A`` (rpm); ``None`` where it cannot be read, or where
    ``f_bar`` is not within a factor 2 of the estimate ``estimate_hz`` (a run too fast for
    its stretches to ring)."""
    import xarray as xr

    try:
        with xr.open_dataset(result_nc) as ds:
            t = np.asarray(ds["time"].values, float)
            force = np.asarray(ds["mesh_force"].values, float)
            static = float(ds.attrs["static_force_N"])
            pairs = (np.asarray(ds["pair_force"].values, float) > IN_CONTACT * static).sum(axis=1)
    except (OSError, KeyError, ValueError):
        return None
    freqs = zone_frequencies(t, force, pairs, static)
    f_bar = mean_ring(freqs, eps)
    if f_bar is None or not math.isfinite(f_bar) or not 0.5 < f_bar / estimate_hz < 2.0:
        return None
    return {"single_contact_hz": freqs[1], "double_contact_hz": freqs[2],
            "mean_hz": f_bar, "resonance_rpm": 60.0 * f_bar / teeth_a}


__all__ = ["mean_ring", "measured_ring", "zone_frequencies"]
