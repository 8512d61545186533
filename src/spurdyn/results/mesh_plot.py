"""The picture of a run of several tooth pairs (the sector model): ``mesh.png``.

Three panels against the rotation of gear A: each pair's force with the mesh force (and, where
the back flanks are contacts, their forces below zero), each pair's share of the load, and the
transmission error; the settled window of a steady-state run shaded; an incomplete run says so
in the title. The pairs are told apart by their teeth's numbers on the curves, not by a
legend entry each.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from numpy.typing import NDArray

from spurdyn.results.frames import speeds_label

MESH_PNG = "mesh.png"


#: Most tooth numbers written on the force curves; a longer run has every k-th numbered.
MAX_NUMBERS = 30


def _draw_pairs(ax_f: Axes, ax_s: Axes, angle: NDArray[np.float64], force: NDArray[np.float64],
                share: NDArray[np.float64], teeth: NDArray[np.int_]) -> None:
    """Each pair's force and share in its tooth's colour, the tooth's number above the
    middle of its contact (no legend entry a pair: a run of many cycles holds dozens)."""
    from spurdyn.results.cycle_plot import tooth_colour

    loaded = np.flatnonzero(np.nanmax(force, axis=0, initial=0.0) > 0.0)
    every = max(1, -(-loaded.size // MAX_NUMBERS))
    for n, j in enumerate(loaded):
        colour = tooth_colour(teeth[j])
        ax_f.plot(angle, force[:, j], lw=0.8, color=colour)
        ax_s.plot(angle, share[:, j], lw=0.8, color=colour)
        if n % every == 0:
            on = angle[force[:, j] > 0.0]
            # in a row above the curves (the mesh force would hide a number at the peak),
            # over the middle of the pair's contact
            ax_f.annotate(f"{int(teeth[j])}", (0.5 * (on[0] + on[-1]), 0.8), xycoords=("data", "axes fraction"),
                          ha="center", va="bottom", fontsize=6, color=colour)


def mesh_figure(ds: xr.Dataset) -> Figure:
    """``ds``'s pair forces, load shares and transmission error.

    Raises
    ------
    ValueError
        If the run has no pair forces (a model of one pair).
    """
    if "pair_force" not in ds:
        raise ValueError("the run has no tooth pairs' forces")
    angle = ds["angle_deg"].values
    force = ds["pair_force"].values
    share = ds["load_share"].values
    teeth = ds["pair"].values if "pair" in ds.coords else np.arange(force.shape[1])
    fig = Figure(figsize=(8, 8.5), dpi=110)
    ax_f, ax_s, ax_e = fig.subplots(3, 1, sharex=True)
    static = float(ds.attrs.get("static_force_N", np.nan))
    _draw_pairs(ax_f, ax_s, angle, force, share, teeth)
    ax_f.plot(angle, ds["mesh_force"].values, color="k", lw=1.2, label="mesh force")
    if "back_pair_force" in ds:     # the back flanks' forces, drawn below zero
        back = ds["back_pair_force"].values
        if np.nanmax(back, initial=0.0) > 0.0:
            ax_f.plot(angle, -ds["back_mesh_force"].values, color="C3", lw=1.0,
                      label="back flanks (drawn negative)")
            ax_f.axhline(0.0, color="0.5", lw=0.5)
    if np.isfinite(static):
        ax_f.axhline(static, color="k", ls="--", lw=0.8, label=f"T/r_b = {static:,.0f} N")
    ax_f.set_ylabel("normal force (N)")
    ax_f.set_ylim(top=1.3 * max(np.nanmax(ds["mesh_force"].values, initial=0.0), static if np.isfinite(static) else 0.0))
    ax_f.legend(fontsize=7, ncol=3, loc="upper right", framealpha=0.8)
    ax_s.set_ylabel("load share")
    ax_s.set_ylim(-0.05, 1.05)
    if "transmission_error" in ds:
        ax_e.plot(angle, ds["transmission_error"].values * 1e6, color="C3", lw=1.0)
    ax_e.set_ylabel("transmission error (µm)")
    ax_e.set_xlabel("rotation of gear A (deg)")
    info = json.loads(ds.attrs.get("info", "{}") or "{}")
    steady = info.get("steady")
    if steady and len(angle):
        lo = steady["window_s"][0]
        start = float(np.interp(lo, ds["time"].values, angle))
        for ax in (ax_f, ax_s, ax_e):
            ax.axvspan(start, angle[-1], color="0.9", zorder=0)
    from spurdyn.results.plots import stopped_early, wrap_title

    if steady:
        from spurdyn.results.cycle_plot import steady_title

        m = steady["last_cycles"]
        title = steady_title(ds, "tooth pairs (numbered: the driver's tooth of each)")
        title += "; the last " + (f"{m} cycles" if m > 1 else "cycle") + " shaded"
    else:
        title = f"{ds.attrs['case_name']}: tooth pairs, {speeds_label(ds)}" + stopped_early(ds)

    ax_f.set_title(wrap_title(title), fontsize=10)
    fig.tight_layout()
    return fig


def plot_mesh(ds: xr.Dataset, png: str | Path) -> Path:
    """Write :func:`mesh_figure` to ``png``."""
    png = Path(png)
    mesh_figure(ds).savefig(png)
    return png


def plot_pair_pictures(ds: xr.Dataset, directory: str | Path, part: int | None = None) -> list[Path]:
    """The pictures of a run of several tooth pairs written into ``directory``: ``mesh.png``
    (the whole run), and where the run holds what they draw ``mesh_cycle.png`` and
    ``transmission_error.png`` (the last settled mesh cycle,
    :mod:`spurdyn.results.cycle_plot`) and ``root_stress.png`` (each tooth's root stress,
    :mod:`spurdyn.results.teeth_stress_plot`) and ``vibration.png`` (a diagnostics study's
    view, :mod:`spurdyn.results.vibration_plot`). ``part`` 0 draws the root stress, the mesh
    cycle and the vibration alone, 1 the mesh and the transmission error (two parts about as long, drawn in
    two processes by :func:`spurdyn.results.io.write_run`), ``None`` all. Returns the
    files written."""
    from spurdyn.results.cycle_plot import MESH_CYCLE_PNG, TE_PNG, plot_mesh_cycle, plot_transmission_error
    from spurdyn.results.teeth_stress_plot import ROOT_STRESS_PNG, plot_teeth_stress
    from spurdyn.results.vibration_plot import VIBRATION_PNG, plot_vibration

    directory = Path(directory)
    parts = ({ROOT_STRESS_PNG: plot_teeth_stress, MESH_CYCLE_PNG: plot_mesh_cycle, VIBRATION_PNG: plot_vibration},
             {MESH_PNG: plot_mesh, TE_PNG: plot_transmission_error})
    draw = {**parts[0], **parts[1]} if part is None else parts[part]
    drawn = [plot(ds, directory / name) for name, plot in draw.items()]
    return [p for p in drawn if p is not None]


__all__ = ["MESH_PNG", "mesh_figure", "plot_mesh", "plot_pair_pictures"]
