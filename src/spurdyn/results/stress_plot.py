"""The stress history of a run: root stress of each tooth and contact pressure against the
rotation of gear A, ISO 6336's nominal stresses dashed beside them (``spurdyn plot DIR
--stress``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from spurdyn.errors import InputError
from spurdyn.results.frames import case_from_run, speeds_label
from spurdyn.results.plots import stopped_early, wrap_title
from spurdyn.results.stress import iso_figures

_COLOURS = ("tab:blue", "tab:orange")


def plot_stress_history(ds: xr.Dataset, png: str | Path) -> Path:
    """Write the stress history of the run ``ds`` to ``png``.

    Raises
    ------
    InputError
        If the run holds no root stress (no tooth frames: a lumped run, or
        ``frames_every = 0``).
    """
    if "root_stress" not in ds:
        raise InputError(str(ds.attrs.get("case_name", "run")),
                         "holds no root stress (run with tooth frames, frames_every > 0)")
    iso = iso_figures(case_from_run(ds))
    angle = np.degrees(ds["frame_theta_a"].values)
    fig = Figure(figsize=(8, 6.4), dpi=120)
    ax_r, ax_c = fig.subplots(2, 1, sharex=True)
    for g, name in enumerate(("A", "B")):
        c = _COLOURS[g]
        ax_r.plot(angle, ds["root_stress"].values[:, g] / 1e6, color=c, lw=1.2,
                  label=f"tooth {name}, tension")
        ax_r.plot(angle, ds["root_stress_compressive"].values[:, g] / 1e6, color=c, lw=0.8,
                  alpha=0.6, label=f"tooth {name}, compression")
        sigma_f0 = (iso["iso6336_sigma_F0_Pa"] or [None, None])[g]
        if sigma_f0 is not None:
            ax_r.axhline(sigma_f0 / 1e6, color=c, ls="--", lw=0.9,
                         label=f"ISO 6336-3 σ_F0 of {name}")
    ax_r.axhline(0.0, color="0.6", lw=0.5)
    ax_r.set_ylabel("stress along the fillet (MPa)")
    ax_r.legend(fontsize=7, ncol=2, loc="best")
    ax_r.grid(alpha=0.3)
    if "contact_pressure_max" in ds:
        ax_c.plot(ds["angle_deg"].values, ds["contact_pressure_max"].values / 1e6, color="tab:red",
                  lw=0.8, label="strip's peak Hertzian pressure")
    else:
        ax_c.text(0.5, 0.5, "no contact pressure: the point contact spreads no strip\n"
                  "(run with --contact hertz)", ha="center", va="center",
                  transform=ax_c.transAxes, fontsize=9, color="0.4")
    if iso["iso6336_sigma_H0_Pa"] is not None:
        ax_c.axhline(iso["iso6336_sigma_H0_Pa"] / 1e6, color="k", ls="--", lw=0.9,
                     label="ISO 6336-2 σ_H0")
    ax_c.set_ylabel("contact pressure (MPa)")
    ax_c.set_xlabel("rotation of gear A since the start of contact (deg)")
    ax_c.grid(alpha=0.3)
    if ax_c.get_legend_handles_labels()[0]:
        ax_c.legend(fontsize=7, loc="best")
    title = f"{ds.attrs['case_name']}: stresses, {speeds_label(ds)}, " \
            f"{json.loads(ds.attrs['case'])['run'].get('contact', 'point')} contact"
    title += stopped_early(ds)
    ax_r.set_title(wrap_title(title), fontsize=10)
    fig.tight_layout()
    png = Path(png)
    fig.savefig(png)
    return png


__all__ = ["plot_stress_history"]
