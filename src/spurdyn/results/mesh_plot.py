"""The picture of a run of several tooth pairs (the sector model): ``mesh.png``.

Three panels against the rotation of gear A: each pair's force with the mesh force (and, where
the back flanks are contacts, their forces below zero), each pair's share of the load, and the
transmission error; the settled window of a steady-state run shaded; an incomplete run says so
in the title.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from spurdyn.results.frames import speeds_label

MESH_PNG = "mesh.png"


def plot_mesh(ds: xr.Dataset, png: str | Path) -> Path:
    """Draw ``ds``'s pair forces, load shares and transmission error into ``png``.

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
    for j in range(force.shape[1]):
        if np.nanmax(force[:, j], initial=0.0) > 0.0:
            ax_f.plot(angle, force[:, j], lw=0.8, label=f"pair {int(teeth[j])}")
            ax_s.plot(angle, share[:, j], lw=0.8)
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
    ax_f.legend(fontsize=7, ncol=4, loc="best", framealpha=0.8)
    ax_s.set_ylabel("load share")
    ax_s.set_ylim(-0.05, 1.05)
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
    title = f"{ds.attrs['case_name']}: tooth pairs, {speeds_label(ds)}"
    if steady:
        title += f", last {steady['last_cycles']} of {steady['cycles']} cycles shaded"
    from spurdyn.results.plots import stopped_early, wrap_title

    title += stopped_early(ds)

    ax_f.set_title(wrap_title(title), fontsize=10)
    fig.tight_layout()
    png = Path(png)
    fig.savefig(png)
    return png


__all__ = ["MESH_PNG", "plot_mesh"]
