"""The settled test of a steady-state run and its figures, shared by every model that runs
mesh cycles under constant torques (the lumped model, :mod:`spurdyn.lumped.steady`; the
sector model, :mod:`spurdyn.solvers.sector`).

A run samples each mesh cycle at the same ``per_cycle`` phases; cycle by cycle it keeps the
peak mesh force and the RMS of the transmission error about its cycle's mean, and counts as
settled when both change from the last cycle but one to the last by less than
:data:`SETTLE_TOL` of their last values (docs/lumped.md, "Steady state").
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

#: Relative cycle-to-cycle change of the peak mesh force and of the transmission error's
#: RMS below which a run counts as settled.
SETTLE_TOL = 1e-3


def last_cycles(cycles: int) -> int:
    """How many of the last cycles the settled figures are taken over: a quarter of the
    run, at least 1 and at most 5."""
    return max(1, min(5, cycles // 4))


def per_cycle_figures(mesh: NDArray[np.float64], te: NDArray[np.float64], per_cycle: int,
                      cycles: int) -> tuple[list[float], list[float]]:
    """The peak mesh force and the transmission error's RMS about its mean of each of the
    first ``cycles`` cycles of ``per_cycle`` samples (module docstring)."""
    peaks, rms = [], []
    for cyc in range(cycles):
        sel = slice(cyc * per_cycle, (cyc + 1) * per_cycle)
        peaks.append(float(mesh[sel].max()))
        d = te[sel]
        rms.append(float(np.sqrt(np.mean((d - d.mean()) ** 2))))
    return peaks, rms


def is_settled(peaks: list[float], rms: list[float]) -> bool:
    """Whether the last two cycles' peaks and RMS differ by less than :data:`SETTLE_TOL` of
    the last ones (the settled test)."""
    if len(peaks) < 2:
        return False
    dp = abs(peaks[-1] - peaks[-2]) / max(peaks[-1], 1e-300)
    dr = abs(rms[-1] - rms[-2]) / max(rms[-1], 1e-300)
    return bool(dp < SETTLE_TOL and dr < SETTLE_TOL)


def settled_after(mesh: NDArray[np.float64], te: NDArray[np.float64], per_cycle: int, cycles: int) -> bool:
    """The settled test over the cycles ``cycles - 1`` and ``cycles`` of a run still going:
    what decides whether a run that may go on (``max_cycles``) stops there."""
    if cycles < 2:
        return False
    start = (cycles - 2) * per_cycle
    return is_settled(*per_cycle_figures(mesh[start:], te[start:], per_cycle, 2))


def cycle_figures(time: NDArray[np.float64], mesh: NDArray[np.float64], te: NDArray[np.float64],
                  per_cycle: int, cycles: int, max_cycles: int | None = None) -> dict[str, Any]:
    """The settled test and the figures over the last cycles.

    Parameters
    ----------
    time, mesh, te
        ``(n,)`` samples (s), mesh force (N) and transmission error (m), ``per_cycle`` a
        cycle from the start.
    per_cycle
        Samples per mesh cycle.
    cycles
        The cycles the run was asked for.
    max_cycles
        The most it could go on to if it had not settled (``None``: as many as asked).

    Returns
    -------
    dict
        ``cycles``, ``cycles_done``, ``last_cycles``, ``window_s`` (the last cycles' span),
        ``settled``, ``settle_tolerance``, ``max_cycles``, ``peak_mesh_force_per_cycle_N``,
        ``transmission_error_rms_per_cycle_m`` and the transmission error's RMS, peak-to-peak
        and mean over the window (``None`` without samples).
    """
    n = time.size
    done = (n - 1) // per_cycle
    peaks, rms = per_cycle_figures(mesh, te, per_cycle, done)
    settled = is_settled(peaks, rms)
    m = last_cycles(cycles)
    last = slice(max(n - 1 - m * per_cycle, 0), n)
    window = (float(time[last][0]), float(time[-1])) if n else (0.0, 0.0)
    w = te[last]
    return {
        "cycles": cycles,
        "cycles_done": done,
        "last_cycles": m,
        "window_s": [float(window[0]), float(window[1])],
        "settled": settled,
        "settle_tolerance": SETTLE_TOL,
        "max_cycles": max_cycles,
        "peak_mesh_force_per_cycle_N": peaks,
        "transmission_error_rms_per_cycle_m": rms,
        "transmission_error_rms_m": float(np.sqrt(np.mean((w - w.mean()) ** 2))) if w.size else None,
        "transmission_error_pp_m": float(w.max() - w.min()) if w.size else None,
        "transmission_error_mean_m": float(w.mean()) if w.size else None,
    }


def steady_record(fig: dict[str, Any], period: float, static_pair_max: float, stiffness_mean: float,
                  end_state: list[float] | None = None,
                  start_state: list[float] | None = None) -> dict[str, Any]:
    """A run's ``info["steady"]``, which the summary reads
    (:func:`spurdyn.results.pairs.steady_figures`): the settled test and figures of
    :func:`cycle_figures`, the mesh period (s), the largest quasi-static pair force (N), the
    mean mesh stiffness (N/m), and where a continuation ends and started."""
    return {
        **{k: fig[k] for k in ("cycles", "cycles_done")},
        "mesh_period_s": period,
        **{k: fig[k] for k in ("last_cycles", "window_s", "settled", "settle_tolerance", "max_cycles",
                               "peak_mesh_force_per_cycle_N", "transmission_error_rms_per_cycle_m")},
        "static_pair_force_max_N": static_pair_max,
        "mesh_stiffness_mean_N_per_m": stiffness_mean,
        **{k: fig[k] for k in ("transmission_error_rms_m", "transmission_error_pp_m",
                               "transmission_error_mean_m")},
        "end_state": end_state,
        "start_state": start_state,
    }


__all__ = ["SETTLE_TOL", "cycle_figures", "is_settled", "last_cycles", "per_cycle_figures", "settled_after",
           "steady_record"]
