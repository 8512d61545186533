"""The vibration of a sector run as a diagnostics study sees it: ``vibration.png``
(:mod:`spurdyn.results.vibration`): the mesh force's time-synchronous average over a
revolution of the faulty gear (the driver's on a healthy pair) and the spectra of the mesh
force and of that gear's hub acceleration, the mesh harmonics and the gear's shaft
sidebands marked. Drawn where the settled window holds a whole revolution."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from spurdyn import diagnostics as dg
from spurdyn.results.vibration import followed, synchronous

VIBRATION_PNG = "vibration.png"
#: Mesh harmonics the spectra show.
HARMONICS = 3
#: Shaft sidebands marked each side of a mesh harmonic.
SIDEBANDS = 3


def plot_vibration(ds: xr.Dataset, png: str | Path) -> Path | None:
    """Draw ``vibration.png`` (module docstring) to ``png``; ``None`` (nothing drawn) where
    the run's window holds no whole revolution."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    info = json.loads(ds.attrs.get("info", "{}") or "{}")
    case = json.loads(ds.attrs["case"])
    teeth = (int(case["gear_a"]["teeth"]), int(case["gear_b"]["teeth"]))
    f = followed(ds, info, teeth)
    if f is None:
        return None
    gear, f_shaft, z, sel, angle = f.gear, f.f_shaft, f.teeth, f.sel, f.angle
    dt = float(np.median(np.diff(f.time)))
    fig, axes = plt.subplots(3, 1, figsize=(9, 9), constrained_layout=True)
    mesh = ds["mesh_force"].values.astype(float)[sel]
    tsa = synchronous(mesh, angle, z)
    axes[0].plot(np.degrees(tsa.angle), tsa.signal, lw=0.8)
    axes[0].set(xlabel=f"turn of gear {gear.upper()} (deg)", ylabel="mesh force (N)",
                title=f"time-synchronous average over {tsa.revolutions} revolution(s) of gear {gear.upper()}")
    # the mesh harmonics and the sidebands of this gear's shaft (its marks as gear "a")
    marks = dg.mesh_marks(f_shaft, f_shaft, z, HARMONICS, SIDEBANDS)
    kind = np.asarray(marks.kind)
    for ax, name, label in ((axes[1], "mesh_force", "mesh force (N)"),
                            (axes[2], f"hub_acceleration_{gear}", f"hub {gear.upper()} acceleration (rad/s^2)")):
        x = ds[name].values.astype(float)[sel]
        spec = dg.spectrum(x - x.mean(), dt)
        top = (HARMONICS + 0.5) * z * f_shaft
        keep = spec.frequency <= top
        amp = spec.amplitude[keep]
        floor = 1e-6 * float(np.max(amp)) if np.max(amp) > 0 else 1.0    # six decades at most
        ax.semilogy(spec.frequency[keep], np.maximum(amp, floor), lw=0.7)
        mesh_f = marks.frequency[kind == "mesh"]
        for f in mesh_f:
            ax.axvline(f, color="tab:red", lw=0.6, ls="--")
        side = kind == "sideband_a"
        ax.plot(marks.frequency[side], np.maximum(dg.read_marks(spec, marks)[side], floor), "o", ms=3,
                color="tab:orange",
                label=f"shaft sidebands ({f_shaft:.1f} Hz)")
        ax.set(xlabel="frequency (Hz)", ylabel=label, xlim=(0, top))
        ax.legend(loc="upper right", fontsize=8)
    settled = bool(info["steady"].get("settled")) and ds.attrs.get("status") == "complete"
    fig.suptitle(f"{ds.attrs.get('case_name', '')}: mesh frequency {z * f_shaft:.1f} Hz (red)"
                 + ("" if settled else "\nNOT SETTLED: the last revolutions still differ"), fontsize=10)
    png = Path(png)
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


__all__ = ["VIBRATION_PNG", "plot_vibration"]
