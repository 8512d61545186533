"""The pictures of ``spurdyn stiffness``: mesh stiffness, static transmission error and load
share over one mesh cycle, one line per torque; and a faulty pair's over its revolution."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from spurdyn.sector.faulty import Revolution
from spurdyn.sector.statics import MeshCycle


def draw_mesh_cycle(cycles: Sequence[MeshCycle], title: str, png: Path,
                    iso: Sequence[tuple[float, float] | None] = ()) -> None:
    """Three panels against the driver's roll angle of pair 0 (deg): the mesh stiffness
    ``k`` with each pair's single-pair stiffness thin, the loaded static transmission error,
    and each pair's load share; ``iso[i]`` = ``(c' b, c_gamma_alpha b)`` (N/m) of torque
    ``i``, dashed and dotted in its colour on the first."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for i, mc in enumerate(cycles):
        colour = f"C{i}"
        deg = np.degrees(mc.roll)
        label = f"{mc.torque:g} N m (W = {mc.load:,.0f} N)"
        axes[0].plot(deg, mc.stiffness / 1e6, color=colour, label=label)
        for j in range(mc.single_pair.shape[1]):
            axes[0].plot(deg, mc.single_pair[:, j] / 1e6, color=colour, lw=0.6, ls=":",
                         label="single pairs" if i == 0 and j == 0 else None)
        if i < len(iso) and iso[i] is not None:
            axes[0].axhline(iso[i][1] / 1e6, color=colour, ls="--", lw=1,
                            label="ISO 6336-1 c_γα b" if i == 0 else None)
            axes[0].axhline(iso[i][0] / 1e6, color=colour, ls="-.", lw=1,
                            label="ISO 6336-1 c′ b" if i == 0 else None)
        axes[1].plot(deg, mc.transmission_error * 1e6, color=colour, label=label)
        for j in range(mc.force.shape[1]):
            on = mc.single_pair[:, j] == mc.single_pair[:, j]
            axes[2].plot(deg[on], mc.share[on, j], color=colour, ls=("-", "--", ":")[j % 3],
                         label=f"pair {j}" if i == 0 else None)
    axes[0].set_ylabel("mesh stiffness (N/µm)")
    axes[1].set_ylabel("loaded static TE (µm)\nalong the line of action")
    axes[2].set_ylabel("load share")
    axes[2].set_xlabel("driver's roll angle of pair 0 (deg)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_title(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def draw_revolution(revs: Sequence[Revolution], title: str, png: Path) -> None:
    """Mesh stiffness and static transmission error over the revolution, the healthy pair's
    stiffness dashed, the cycles holding a fault shaded."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
    for i, rev in enumerate(revs):
        deg, colour = np.degrees(rev.angle), f"C{i}"
        axes[0].plot(deg, rev.stiffness / 1e6, color=colour, lw=1, label=f"{rev.torque:g} N m")
        axes[0].plot(deg, rev.healthy_stiffness / 1e6, color=colour, lw=0.8, ls="--",
                     label="healthy" if i == 0 else None)
        axes[1].plot(deg, rev.transmission_error * 1e6, color=colour, lw=1)
    rev = revs[0]
    for c in rev.faulty:
        span = np.degrees(rev.angle[rev.cycle == c])
        for ax in axes:
            ax.axvspan(span.min(), span.max() + (span[1] - span[0]), color="0.9", zorder=0)
    axes[0].set_ylabel("mesh stiffness (N/µm)")
    axes[1].set_ylabel("loaded static TE (µm)\n(gap: no pair carries)")
    axes[1].set_xlabel(f"turn of gear {rev.gear} (deg); shaded: cycles with the fault in the mesh")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[0].set_title(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


__all__ = ["draw_mesh_cycle", "draw_revolution"]
