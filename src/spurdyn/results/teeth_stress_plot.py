"""The root stress of every tooth over a revolution (the sector model): ``root_stress.png``.

One panel a gear: each tooth's largest tensile root stress against the gear's rotation, a
colour and its number per tooth, and its compressive stress drawn below zero, dashed. The
run's variables ``root_stress_a`` and ``root_stress_b`` (``stress_time``, ``tooth_a`` /
``tooth_b``; Pa) and ``root_stress_compressive_a`` / ``_b``; a run without them gets no
picture. Each panel shows its gear's last revolution, or what the run covers of one, and
the title says which.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from spurdyn.results.cycle_plot import tooth_colour
from spurdyn.results.frames import speeds_label
from spurdyn.results.plots import save_figure, stopped_early, wrap_title

ROOT_STRESS_PNG = "root_stress.png"
_GEARS = ("a", "b")


def has_teeth_stress(ds: xr.Dataset) -> bool:
    """Whether the run holds each tooth's root stress of both gears."""
    return all(f"root_stress_{g}" in ds for g in _GEARS) and "stress_time" in ds.coords


#: Teeth whose peak is below this fraction of the gear's largest are drawn but not numbered.
NAMED_FRACTION = 0.25


def _rotation_deg(ds: xr.Dataset, g: str) -> np.ndarray:
    """Gear ``g``'s rotation since the start (deg) at the stress samples."""
    return np.degrees(np.interp(ds["stress_time"].values, ds["time"].values, ds[f"theta_{g}"].values))


def _draw_gear(ax: Axes, ds: xr.Dataset, g: str) -> str:
    """Gear ``g``'s teeth on ``ax`` over its last revolution; what that covers, in words."""
    turn = _rotation_deg(ds, g)
    span = float(turn[-1] - turn[0]) if turn.size else 0.0
    keep = turn >= turn[-1] - 360.0 if span >= 360.0 else np.ones(turn.size, bool)
    x = turn[keep]
    tension = ds[f"root_stress_{g}"].values[keep] / 1e6
    name = f"root_stress_compressive_{g}"
    compression = -np.abs(ds[name].values[keep]) / 1e6 if name in ds else None
    teeth = ds[f"tooth_{g}"].values
    peaks = np.nanmax(np.abs(tension), axis=0, initial=0.0)
    loaded = np.flatnonzero(peaks > 0.0)
    named = 0
    for j in loaded:
        colour = tooth_colour(teeth[j])
        ax.plot(x, tension[:, j], color=colour, lw=1.0)
        if compression is not None:
            ax.plot(x, compression[:, j], color=colour, lw=0.7, ls="--")
        if peaks[j] < NAMED_FRACTION * peaks.max():
            continue        # a tooth away from the mesh: the rim's bending, unnamed
        i = int(np.nanargmax(tension[:, j]))
        # alternate heights, so that neighbouring teeth's numbers do not overlap
        ax.annotate(f"{int(teeth[j])}", (x[i], tension[i, j]), xytext=(0, 3 + 9 * (named % 2)),
                    textcoords="offset points", ha="center", va="bottom", fontsize=7, color=colour)
        named += 1
    ax.axhline(0.0, color="0.5", lw=0.5)
    ax.margins(y=0.18)
    ax.set_ylabel(f"gear {g.upper()}: root stress (MPa)")
    ax.set_xlabel(f"rotation of gear {g.upper()} since the start (deg)")
    ax.grid(True, lw=0.3, alpha=0.6)
    if span >= 360.0:
        return f"the last revolution of {g.upper()}"
    return f"{span:.0f} deg of {g.upper()}'s revolution"


def teeth_stress_figure(ds: xr.Dataset) -> Figure | None:
    """Each tooth's root stress of both gears (module docstring); ``None`` (nothing
    drawn) when the run has no such variables or no samples."""
    if not has_teeth_stress(ds) or ds.sizes["stress_time"] < 2:
        return None
    fig = Figure(figsize=(8, 7.5), dpi=110)
    axes = fig.subplots(2, 1)
    covers = [_draw_gear(ax, ds, g) for ax, g in zip(axes, _GEARS)]
    keys = [Line2D([], [], color="0.3", lw=1.0, label="tension (a colour and number per tooth)")]
    if any(f"root_stress_compressive_{g}" in ds for g in _GEARS):
        keys.append(Line2D([], [], color="0.3", lw=0.7, ls="--", label="compression, drawn below zero"))
    # below the panels, where it covers no curve
    fig.legend(handles=keys, loc="lower center", ncol=len(keys), fontsize=8, frameon=False)
    torque = json.loads(ds.attrs["case"])["run"]["torque"]
    title = (f"{ds.attrs['case_name']}: root stress of each tooth over {covers[0]} and "
             f"{covers[1]}; {speeds_label(ds)}, {torque:g} N m") + stopped_early(ds)
    axes[0].set_title(wrap_title(title), fontsize=9)
    fig.tight_layout(rect=(0.0, 0.03, 1.0, 1.0))
    return fig


def plot_teeth_stress(ds: xr.Dataset, png: str | Path) -> Path | None:
    """Write :func:`teeth_stress_figure` to ``png``; ``None`` (no file) where it draws nothing."""
    return save_figure(teeth_stress_figure(ds), png)


__all__ = ["ROOT_STRESS_PNG", "has_teeth_stress", "plot_teeth_stress", "teeth_stress_figure"]
