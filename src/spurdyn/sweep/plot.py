"""The dynamic factor against speed (Matplotlib, no screen needed).

One curve per model in the folder (FE solid blue with dots, lumped dashed orange; with
several torques, one colour per torque) of the dynamic factor of the 10-us-averaged
contact force (:mod:`spurdyn.results.headline`). A run stopped early has no factor: a gap
in its curve and a hollow mark along the bottom; failed and missing points are left out
of the curves and ticked along the bottom. The top axis is the tooth mesh frequency; the speed at which
the mesh frequency equals the estimated torsional natural frequency ``f_n`` is marked
(and, lighter, the speed at which twice the mesh frequency does).
"""

from __future__ import annotations

import json

from pathlib import Path
from typing import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from spurdyn.results.headline import AVERAGING_WINDOW_S  # noqa: E402
from spurdyn.sweep.resonance import ResonanceEstimate  # noqa: E402
from spurdyn.sweep.store import STATUS_CODES, model_datasets  # noqa: E402

_STYLE = {"fe": {"ls": "-", "marker": "o", "label": "FE contact model", "colour": "C0"},
          "lumped": {"ls": "--", "marker": "s", "label": "lumped (two disks, mesh spring)",
                     "colour": "C1"}}


def line_colour(model: str, torque_index: int, n_torques: int) -> str:
    """One colour per model for a single torque; one per torque for several."""
    if n_torques > 1:
        return f"C{(torque_index + 2) % 10}" if torque_index >= 1 else "C0"
    return str(_STYLE.get(model, {}).get("colour", "C2"))


def _per_torque(ds: xr.Dataset) -> list[tuple[float, xr.Dataset]]:
    if "torque" in ds.dims:
        return [(float(t), ds.sel(torque=t)) for t in ds["torque"].values]
    return [(float(ds["torque"].values), ds)]


def _stiffness_note(ds: xr.Dataset) -> str:
    """``", sector stiffness"`` when the sweep's lumped model took the sector model's."""
    try:
        stiffness = json.loads(ds.attrs.get("settings", "{}"))["run"].get("stiffness")
    except (ValueError, KeyError, TypeError, AttributeError):
        return ""
    return ", sector stiffness" if stiffness == "sector" else ""


def draw_dynamic_factor(ax: plt.Axes, datasets: Mapping[str, xr.Dataset],
                        resonance: ResonanceEstimate | None) -> None:
    """Draw each model's dynamic factor against the speed of A on ``ax``."""
    torques = sorted({t for ds in datasets.values() for t, _ in _per_torque(ds)})
    lo, hi = np.inf, -np.inf
    for model, ds in datasets.items():
        style = _STYLE.get(model, {"ls": "-.", "marker": "^", "label": model, "colour": "C2"})
        for torque, part in _per_torque(ds):
            rpm = part["rpm"].values.astype(float)
            if rpm.size:
                lo, hi = min(lo, rpm.min()), max(hi, rpm.max())
            status = part["status"].values
            ok = status == STATUS_CODES["complete"]
            partial = status == STATUS_CODES["incomplete"]
            # a run stopped early has no factor: a gap in the curve, a hollow mark below
            factor = np.where(ok, part["dynamic_factor"].values.astype(float), np.nan)
            shown = ok | partial
            label = (style["label"] + _stiffness_note(ds)
                     + (f", {torque:g} N m" if len(torques) > 1 else ""))
            colour = line_colour(model, torques.index(torque), len(torques))
            ax.plot(rpm[shown], factor[shown], ls=style["ls"], color=colour, lw=1.4,
                    marker=style["marker"], ms=3.5 if rpm.size <= 60 else 1.5, label=label)
            if partial.any():
                ax.plot(rpm[partial], np.zeros(int(partial.sum())), ls="none",
                        marker=style["marker"], ms=7, mfc="white", mec=colour, clip_on=False,
                        transform=ax.get_xaxis_transform(),
                        label=f"{model}: run stopped early (no factor)")
            if "settled" in part:
                # a steady-state point whose last cycles still changed: hollow
                loose = ok & (part["settled"].values == 0)
                if loose.any():
                    ax.plot(rpm[loose], factor[loose], ls="none", marker=style["marker"], ms=6,
                            mfc="white", mec=colour, label=f"{model}: not settled (the last "
                            "cycles still changed)")
            lost = (status == STATUS_CODES["failed"]) | (status == STATUS_CODES["not_run"])
            if lost.any():
                ax.plot(rpm[lost], np.zeros(int(lost.sum())), ls="none", marker="x",
                        color="red", ms=7, clip_on=False, transform=ax.get_xaxis_transform(),
                        label=f"{model}: failed or not run")
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    if resonance is not None and np.isfinite(lo) and resonance.iso_resonance_rpm is not None:
        grid = np.linspace(lo, hi, 400) if hi > lo else np.array([lo])
        ax.plot(grid, resonance.iso_kv(grid), color="0.35", lw=1.3, ls="--",
                label=f"ISO 6336-1 K_v (method B; n_E1 = {resonance.iso_resonance_rpm:,.0f} rpm)")
    if resonance is not None and np.isfinite(lo):
        n_res = resonance.resonance_rpm
        span = hi - lo if hi > lo else max(hi, 1.0)
        for n, text, alpha in ((n_res, f"mesh frequency = f_n = {resonance.natural_frequency_hz / 1e3:.2f} kHz"
                                f"\n{n_res:,.0f} rpm", 0.9),
                               (n_res / 2, f"2 x mesh frequency = f_n\n{n_res / 2:,.0f} rpm", 0.45)):
            if lo - 0.05 * span <= n <= hi + 0.05 * span:
                ax.axvline(n, color="C3", lw=1.2, ls="-." if alpha > 0.5 else ":", alpha=alpha)
                ax.annotate(text, xy=(n, 0.98), xycoords=("data", "axes fraction"),
                            xytext=(4, -4), textcoords="offset points", ha="left", va="top",
                            fontsize=7.5, color="C3", alpha=min(1.0, alpha + 0.1))
    ax.set_xlabel("speed of gear A (rpm)")
    ax.set_ylabel(f"dynamic factor  (peak of the {AVERAGING_WINDOW_S * 1e6:g}-µs average of the"
                  "\ncontact force / static force)")
    ax.grid(True, lw=0.4, alpha=0.5)
    if resonance is not None:
        z = resonance.teeth_a
        top = ax.secondary_xaxis("top", functions=(lambda n: z * n / 60e3, lambda f: f * 60e3 / z))
        top.set_xlabel("tooth mesh frequency (kHz)")
    handles, labels = ax.get_legend_handles_labels()
    seen: dict[str, object] = {}
    for h, lab in zip(handles, labels):
        seen.setdefault(lab, h)
    # below the axes: inside, the legend hid the resonance lines' labels and the curves' peaks
    ax.legend(list(seen.values()), list(seen), fontsize=8, loc="upper center",
              bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)


def plot_dynamic_factor(datasets: Mapping[str, xr.Dataset], png: str | Path,
                        resonance: ResonanceEstimate | None = None, title: str = "") -> Path:
    """Write the picture of :func:`draw_dynamic_factor` to ``png``; return the path."""
    fig, ax = plt.subplots(figsize=(9, 5.2), layout="constrained")
    try:
        draw_dynamic_factor(ax, datasets, resonance)
        if title:
            ax.set_title(title, fontsize=10)
        png = Path(png)
        tmp = png.with_name(f".{png.stem}.tmp{png.suffix}")
        fig.savefig(tmp, dpi=130)
        tmp.replace(png)
    finally:
        plt.close(fig)
    return png


def plot_sweep_folder(out: Path, png: Path, resonance: ResonanceEstimate | None) -> Path:
    """Draw every model's sweep found in the folder ``out`` (``sweep_<model>.nc``)."""
    datasets = model_datasets(out)
    names = sorted({str(ds.attrs.get("case_name", "")) for ds in datasets.values()})
    cycles, exact = set(), True
    for ds in datasets.values():
        try:
            run = json.loads(ds.attrs.get("settings", "{}"))["run"]
        except (ValueError, KeyError, TypeError):
            cycles.add(None)
            continue
        cycles.add(run.get("cycles"))
        # a steady state goes on until it settles unless max_cycles is its cycles
        exact &= run.get("cycles") is None or run.get("max_cycles") == run.get("cycles")
    each = ("one engagement per point" if cycles == {None} else
            f"steady state over {', '.join(str(c) for c in sorted(c for c in cycles if c))} "
            f"mesh cycles per point{'' if exact else ', more until settled'} (last cycles)")
    title = f"{', '.join(names)}: dynamic factor against speed, {each}"
    if len({ds.attrs.get("settings_hash") for ds in datasets.values()}) > 1:
        title += "\n(the models' sweeps in this folder have different settings)"
    return plot_dynamic_factor(datasets, png, resonance, title)
