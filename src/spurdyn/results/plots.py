"""Contact-force pictures of one or several runs (Matplotlib, no screen needed)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import matplotlib
import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.layout_engine import TightLayoutEngine

from spurdyn.results.frames import speeds_label
from spurdyn.results.headline import AVERAGING_WINDOW_S, headline, moving_average

# Figures are made with the object API (Figure, saved through the Agg canvas), not pyplot:
# no GUI backend, nothing global, and a quicker start (pyplot costs ~0.3 s to import).


def _labels(runs: Sequence[xr.Dataset]) -> list[str]:
    """Case name and speeds of each run; the run folder too when names repeat."""
    names = [str(ds.attrs["case_name"]) for ds in runs]
    labels = []
    for ds, name in zip(runs, names):
        label = f"{name} ({speeds_label(ds)})"
        if names.count(name) > 1 and ds.encoding.get("source"):
            label = f"{Path(ds.encoding['source']).parent.name}: {label}"
        if ds.attrs.get("status") != "complete":
            label += " [incomplete]"
        labels.append(label)
    return labels


def draw_contact_force(ax: Axes, runs: Sequence[xr.Dataset], *, zones: bool = True,
                       legend: bool = True) -> None:
    """Draw the contact force of ``runs`` against the rotation of A on ``ax``.

    The first run's double-contact zones are shaded and its single-contact zone marked;
    each distinct quasi-static force (torque over the driver's base radius) is a dashed
    line. Each run is drawn thin as computed and thick averaged over the headline window
    of :mod:`spurdyn.results.headline`, the peak of that average marked (for one run,
    with its dynamic factor). The angle axis spans the longest angle a run set out to
    cover.
    """
    first = runs[0]
    theta_s = float(first.attrs["theta_s_deg"])
    xmax = max(max(float(ds.attrs.get("angle_target_deg", theta_s)),
                   float(np.nanmax(ds["angle_deg"].values, initial=0.0))) for ds in runs)
    z0, z1 = (float(v) for v in np.asarray(first.attrs["single_zone_deg"]).reshape(2))
    if zones:
        ax.axvspan(0.0, min(z0, xmax), color="0.88", lw=0, label="double contact (one pair modelled)")
        if z1 < xmax:
            ax.axvspan(z1, theta_s, color="0.88", lw=0)
        for z in (z0, z1):
            if z < xmax:
                ax.axvline(z, color="0.5", lw=0.8, ls=":")
        if z0 < xmax:
            right = min(z1, xmax)
            ax.annotate("single contact", xy=((z0 + right) / 2, 1.0),
                        xycoords=("data", "axes fraction"), xytext=(0, -12),
                        textcoords="offset points", ha="center", va="top", fontsize=8,
                        color="0.35")
            ax.annotate("", xy=(z0, 0.97), xytext=(right, 0.97),
                        xycoords=("data", "axes fraction"),
                        arrowprops={"arrowstyle": "<->" if z1 <= xmax else "<-",
                                    "color": "0.5", "lw": 0.8})
    statics: list[float] = []
    colours = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    single = len(runs) == 1
    labels = _labels(runs) if not single else ["contact force" + (
        "" if first.attrs.get("status") == "complete" else " [incomplete]")]
    window = f"{AVERAGING_WINDOW_S * 1e6:g}-µs average"
    for i, (ds, label) in enumerate(zip(runs, labels)):
        colour = colours[i % len(colours)]
        angle = ds["angle_deg"].values
        force = ds["contact_force"].values
        ax.plot(angle, force, color=colour, lw=0.6 if single else 0.5, alpha=0.55,
                label=label + (", raw" if single else ""))
        _draw_average(ax, ds, colour, window if single else None)
        static = float(ds.attrs["static_force_N"])
        if not any(np.isclose(static, s, rtol=1e-9) for s in statics):
            statics.append(static)
            ax.axhline(static, color="k" if len(runs) == 1 else colour, ls="--", lw=0.9,
                       label=f"quasi-static torque/r_b = {static:,.0f} N")
    if not single:
        ax.plot([], [], color="0.3", lw=1.6, label=f"thick: {window}; thin: raw")
    ax.set_xlim(0.0, xmax)
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("rotation of gear A since the start of contact (deg)")
    ax.set_ylabel("contact force (N)")
    ax.grid(True, lw=0.3, alpha=0.6)
    if legend:
        ax.legend(loc="best", fontsize=8)


def _draw_average(ax: Axes, ds: xr.Dataset, colour: str, label: str | None) -> None:
    """The run's contact force averaged over the headline window, and its peak marked.

    The peak is the one of ``summary.json``'s ``peak_force_N`` and ``dynamic_factor``
    (:mod:`spurdyn.results.headline`); with ``label`` the line and the peak get legend
    entries, the peak's with its dynamic factor, or the word that there is none.
    """
    time = ds["time"].values.astype(float)
    angle = ds["angle_deg"].values.astype(float)
    force = ds["contact_force"].values.astype(float)
    if not np.isfinite(force).any():
        return
    ax.plot(angle, moving_average(time, force), color=colour, lw=1.6, label=label)
    head = headline(time, angle, force, float(ds.attrs["static_force_N"]),
                    ds.attrs.get("status") == "complete", str(ds.attrs.get("reason", "")))
    if head.peak_force is None:
        return
    if head.dynamic_factor is not None:
        text = f"peak of the average {head.peak_force:,.1f} N = {head.dynamic_factor:.3f} x static"
    else:
        text = f"peak so far {head.peak_force:,.1f} N (stopped early: no dynamic factor)"
    ax.plot([head.peak_angle_deg], [head.peak_force], ls="none", marker="o", ms=5,
            mfc="white", mec=colour, mew=1.4, zorder=5, label=text if label else None)


#: Characters per title line that fit the 8-inch picture at font size 10, and the most
#: lines a title may take.
TITLE_WIDTH, TITLE_LINES = 95, 4


def save_figure(fig: Any, png: str | Path) -> Path | None:
    """Write ``fig`` to ``png``; ``None`` (no file) where there is no figure (it drew nothing)."""
    if fig is None:
        return None
    png = Path(png)
    fig.savefig(png)
    return png


def stopped_early(ds: xr.Dataset) -> str:
    """What a picture's title adds for a run that stopped early: ``" (incomplete: reason)"``,
    or nothing."""
    if ds.attrs.get("status") == "complete":
        return ""
    return f" (incomplete: {ds.attrs.get('reason', '')})"


def wrap_title(title: str) -> str:
    """``title`` in lines that fit the picture (a long reason would be cut at both edges)."""
    import textwrap

    return textwrap.fill(title, TITLE_WIDTH, max_lines=TITLE_LINES, placeholder=" ...")


def plot_contact_force(runs: Sequence[xr.Dataset], png: str | Path,
                       title: str | None = None) -> Path:
    """Write a picture of the contact force of one run or several overlaid.

    Parameters
    ----------
    runs
        Datasets as :func:`spurdyn.results.io.load_run` returns them.
    png
        File to write.
    title
        Title; default: the case name(s) and the speeds.
    """
    if not runs:
        raise ValueError("no runs to plot")
    if title is None:
        if len(runs) == 1:
            ds = runs[0]
            title = f"{ds.attrs['case_name']}: contact force, {speeds_label(ds)}"
            title += stopped_early(ds)
        else:
            title = "contact force: " + ", ".join(str(ds.attrs["case_name"]) for ds in runs)
    fig = Figure(figsize=(8, 4.8), dpi=120)
    ax = fig.subplots()
    draw_contact_force(ax, runs)
    ax.set_title(wrap_title(title), fontsize=10)
    legend = ax.get_legend()
    if len(runs) == 1 and legend is not None:
        # One run's legend (three entries) lies inside the axes wherever "best" puts it, so
        # it does not move the layout; left out of it, its place (a search over every
        # point of the curve) is not looked for twice more.
        legend.set_in_layout(False)
    # The layout of fig.tight_layout(), without the placeholder layout engine it leaves on
    # the figure, for which savefig would draw the whole figure once more before drawing
    # it (~0.06 s of the ~0.3 s); the picture is the same.
    TightLayoutEngine().execute(fig)
    png = Path(png)
    fig.savefig(png)
    return png
