"""Pictures of a steady-state run's settled mesh cycle (the sector model), read at a glance.

``mesh_cycle.png``
    Each tooth pair's force over the last mesh cycle against the driver's roll angle of its
    contact point, the teeth numbered on their curves, beside the quasi-static force of a
    pair along the path (dashed, the run's ``static_pair_force``).
``transmission_error.png``
    The transmission error over the last mesh cycle beside the loaded static one, and the
    amplitudes of its harmonics of the mesh frequency (:func:`harmonic_amplitudes`) over the
    last whole cycles of the settled window, dynamic and static side by side.

Titles say what ran: the cycles done, settled or NOT settled, the speeds, the torque and the
mesh damper. A run without a whole mesh cycle, or without a steady-state record, gets no
picture (the functions return ``None``).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from numpy.typing import NDArray

from spurdyn.results.frames import speeds_label
from spurdyn.results.plots import save_figure, stopped_early, wrap_title

MESH_CYCLE_PNG = "mesh_cycle.png"
TE_PNG = "transmission_error.png"
#: Harmonics of the mesh frequency drawn in the spectrum.
HARMONICS = 8
#: The qualitative colours the teeth take in turn (by tooth number, so a tooth keeps its
#: colour from picture to picture).
TOOTH_COLOURS = tuple(f"C{i}" for i in range(10))


def run_info(ds: xr.Dataset) -> dict[str, Any]:
    """The run's ``info`` record (JSON attribute), ``{}`` without one."""
    return json.loads(ds.attrs.get("info", "{}") or "{}")


def tooth_colour(tooth: int) -> str:
    return TOOTH_COLOURS[int(tooth) % len(TOOTH_COLOURS)]


def steady_title(ds: xr.Dataset, what: str) -> str:
    """``"<case>: <what> over the last of N mesh cycles done, settled|NOT settled; speeds,
    torque, mesh damping"`` (and why the run stopped early, if it did)."""
    info = run_info(ds)
    steady = info.get("steady") or {}
    done = steady.get("cycles_done", 0)
    complete = ds.attrs.get("status") == "complete"
    if steady.get("settled") and complete:
        state = f"settled (change < {100 * steady['settle_tolerance']:g} % a cycle)"
    elif not complete:
        state = "NOT settled (stopped early)"
    else:
        state = f"NOT settled (a cycle's change still >= {100 * steady.get('settle_tolerance', 0.0):g} %"
        limit = steady.get("max_cycles")
        state += f", at the limit of {limit} cycles)" if limit is not None and done >= limit else ")"
    torque = json.loads(ds.attrs["case"])["run"]["torque"]
    zeta = info.get("damping_ratio")
    damper = "no mesh damper" if not zeta else f"mesh damping ratio {zeta:g}"
    title = (f"{ds.attrs['case_name']}: {what} over the last of {done} mesh cycles done, {state}; "
             f"{speeds_label(ds)}, {torque:g} N m, {damper}")
    return title + stopped_early(ds)


def last_cycles(ds: xr.Dataset, cycles: int) -> slice | None:
    """The samples of the run's last ``cycles`` whole mesh cycles, both ends included
    (``None`` if the run has no steady-state record or fewer cycles)."""
    steady = run_info(ds).get("steady") or {}
    period = steady.get("mesh_period_s")
    time = ds["time"].values
    if not period or time.size < 2 or cycles < 1 or steady.get("cycles_done", 0) < cycles:
        return None
    per_cycle = int(round(period / float(np.median(np.diff(time)))))
    n = cycles * per_cycle + 1
    return slice(time.size - n, time.size) if per_cycle > 0 and n <= time.size else None


def harmonic_amplitudes(x: NDArray[np.float64], cycles: int, count: int) -> NDArray[np.float64]:
    """Amplitudes of harmonics ``1 .. count`` of the fundamental of ``x``.

    Parameters
    ----------
    x
        Samples equally spaced over exactly ``cycles`` periods, the end of the last period
        left out (``x[0]`` starts a period, ``x[-1]`` is one sample short of its end).
    cycles
        The whole periods ``x`` spans: harmonic ``h`` is the DFT's bin ``h * cycles``.
    count
        Harmonics wanted.

    Returns
    -------
    ndarray
        ``(count,)``: ``2 |X_k| / n`` of bin ``k = h cycles``, the amplitude of a cosine at
        ``h`` times the fundamental; NaN for a harmonic at or above the Nyquist frequency
        (not resolved by the samples).
    """
    x = np.asarray(x, float)
    spec = np.fft.rfft(x) / x.size
    bins = np.arange(1, count + 1) * int(cycles)
    out = np.full(count, np.nan)
    ok = 2 * bins < x.size
    out[ok] = 2.0 * np.abs(spec[bins[ok]])
    return out


def _static_force_along_path(ds: xr.Dataset) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The quasi-static force of one tooth pair along its path: pair ``j``'s column of the
    cycle, ``j`` pitches on (driver's roll in deg, N)."""
    roll = ds["cycle_roll_deg"].values
    pitch = float(roll[-1] - roll[0])
    force = ds["static_pair_force"].values
    x = np.concatenate([roll + j * pitch for j in range(force.shape[1])])
    return x, np.concatenate([force[:, j] for j in range(force.shape[1])])


def mesh_cycle_figure(ds: xr.Dataset) -> Figure | None:
    """Each pair's force over the last mesh cycle against its roll angle, the teeth
    numbered, the quasi-static force dashed (module docstring); ``None`` (nothing drawn)
    without pair forces and rolls or a whole cycle."""
    sel = last_cycles(ds, 1)
    if sel is None or "pair_force" not in ds or "pair_roll_deg" not in ds:
        return None
    force, roll = ds["pair_force"].values[sel], ds["pair_roll_deg"].values[sel]
    teeth = ds["pair"].values if "pair" in ds.coords else np.arange(force.shape[1])
    fig = Figure(figsize=(8, 5), dpi=110)
    ax = fig.subplots()
    top = 0.0
    for j in np.flatnonzero(np.nanmax(force, axis=0, initial=0.0) > 0.0):
        on = np.isfinite(roll[:, j])
        colour = tooth_colour(teeth[j])
        ax.plot(roll[on, j], force[on, j], color=colour, lw=1.3)
        i = int(np.argmax(np.where(on, force[:, j], -np.inf)))
        ax.annotate(f"tooth {int(teeth[j])}", (roll[i, j], force[i, j]), xytext=(0, 4),
                    textcoords="offset points", ha="center", va="bottom", fontsize=8,
                    color=colour, fontweight="bold")
        top = max(top, float(force[i, j]))
    ax.plot([], [], color="0.4", lw=1.3, label="dynamic, last mesh cycle: the driver's tooth k "
            "(on the driven gear's -k) named on its curve")
    if "static_pair_force" in ds:
        x, f = _static_force_along_path(ds)
        ax.plot(x, f, color="k", ls="--", lw=1.0, label="quasi-static, same torque")
        top = max(top, float(f.max()))
    ax.set_ylim(0.0, 1.25 * top if top > 0 else 1.0)
    ax.set_xlabel("driver's roll angle of the pair's contact point (deg)")
    ax.set_ylabel("normal force of the tooth pair (N)")
    ax.grid(True, lw=0.3, alpha=0.6)
    ax.legend(loc="upper center", fontsize=8, ncol=1, framealpha=0.9)
    ax.set_title(wrap_title(steady_title(ds, "tooth pair forces")), fontsize=9)
    fig.tight_layout()
    return fig


def plot_mesh_cycle(ds: xr.Dataset, png: str | Path) -> Path | None:
    """Write :func:`mesh_cycle_figure` to ``png``; ``None`` (no file) where it draws nothing."""
    return save_figure(mesh_cycle_figure(ds), png)


def _te_spectra(ds: xr.Dataset) -> tuple[NDArray[np.float64], NDArray[np.float64] | None, int, int]:
    """The dynamic TE's harmonic amplitudes over the settled window's whole cycles, the static
    TE's (``None`` without it; NaN above a quarter of its positions, where the few positions
    alias), the cycles and the static positions used."""
    steady = run_info(ds)["steady"]
    m = max(1, min(int(steady.get("last_cycles", 1)), int(steady["cycles_done"])))
    sel = last_cycles(ds, m)
    if sel is None:
        m, sel = 1, last_cycles(ds, 1)
    dyn = harmonic_amplitudes(ds["transmission_error"].values[sel][:-1], m, HARMONICS)
    if "static_transmission_error" not in ds:
        return dyn, None, m, 0
    te = ds["static_transmission_error"].values[:-1]   # the last position is the first's again
    static = harmonic_amplitudes(te, 1, HARMONICS)
    static[np.arange(1, HARMONICS + 1) > te.size // 4] = np.nan
    return dyn, static, m, te.size


def transmission_error_figure(ds: xr.Dataset) -> Figure | None:
    """The TE over the last mesh cycle beside the static one, and its harmonics'
    amplitudes (module docstring); ``None`` without a TE or a whole cycle."""
    sel = last_cycles(ds, 1)
    if sel is None or "transmission_error" not in ds:
        return None
    steady = run_info(ds)["steady"]
    period = float(steady["mesh_period_s"])
    time = ds["time"].values[sel]
    fig = Figure(figsize=(8, 7), dpi=110)
    ax_t, ax_h = fig.subplots(2, 1, gridspec_kw={"height_ratios": [1.3, 1.0]})
    ax_t.plot((time - time[0]) / period, ds["transmission_error"].values[sel] * 1e6, color="C3",
              lw=1.2, label="dynamic, last mesh cycle")
    if "static_transmission_error" in ds:
        roll = ds["cycle_roll_deg"].values
        ax_t.plot((roll - roll[0]) / (roll[-1] - roll[0]), ds["static_transmission_error"].values * 1e6,
                  color="k", ls="--", lw=1.0, marker=".", ms=4, label="loaded static")
    ax_t.set_xlabel("mesh phase (fraction of the mesh cycle from the first pair's entry)")
    ax_t.set_ylabel("transmission error (µm)")
    ax_t.set_xlim(0.0, 1.0)
    ax_t.grid(True, lw=0.3, alpha=0.6)
    ax_t.legend(loc="best", fontsize=8)
    dyn, static, m, positions = _te_spectra(ds)
    h = np.arange(1, HARMONICS + 1)
    width = 0.38 if static is not None else 0.7
    ax_h.bar(h - (width / 2 if static is not None else 0.0), dyn * 1e6, width, color="C3",
             label="dynamic, over the last " + (f"{m} mesh cycles" if m > 1 else "mesh cycle"))
    if static is not None:
        ax_h.bar(h + width / 2, static * 1e6, width, color="0.55",
                 label=f"loaded static ({positions} positions: harmonics 1-{positions // 4})")
    ax_h.set_xticks(h)
    ax_h.set_xlabel(f"harmonic of the mesh frequency ({1.0 / period:,.0f} Hz)")
    ax_h.set_ylabel("amplitude (µm)")
    ax_h.grid(True, axis="y", lw=0.3, alpha=0.6)
    ax_h.legend(loc="upper right", fontsize=8)
    ax_t.set_title(wrap_title(steady_title(ds, "transmission error")), fontsize=9)
    fig.tight_layout()
    return fig


def plot_transmission_error(ds: xr.Dataset, png: str | Path) -> Path | None:
    """Write :func:`transmission_error_figure` to ``png``; ``None`` (no file) where it draws nothing."""
    return save_figure(transmission_error_figure(ds), png)


__all__ = ["HARMONICS", "MESH_CYCLE_PNG", "TE_PNG", "harmonic_amplitudes", "last_cycles",
           "mesh_cycle_figure", "plot_mesh_cycle", "transmission_error_figure", "plot_transmission_error", "run_info", "steady_title",
           "tooth_colour"]
