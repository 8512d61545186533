"""Plotting shared by the sections: Matplotlib set up, the contact zones, saving a picture."""

from __future__ import annotations

import math
import sys
from typing import Any

from .context import Ctx
from .settings import FIGURES


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg backend with the report's style."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 8,
                         "axes.grid": True, "grid.color": "0.9", "lines.linewidth": 0.9})
    return plt


def shade_zones(ax: Any, ctx: Ctx, label: bool = True) -> None:
    """Grey double-contact zones, the quasi-static force and the angle axis on ``ax``."""
    z0, z1 = ctx.zone_deg
    ts = math.degrees(ctx.theta_s)
    ax.axvspan(0, z0, color="0.92", lw=0, label="double contact (one pair modelled)" if label else None)
    ax.axvspan(z1, ts, color="0.92", lw=0)
    ax.axhline(ctx.static, color="k", ls="--", lw=0.8,
               label=f"quasi-static τ0/r_b = {ctx.static:.1f} N" if label else None)
    ax.set_xlim(0, ts)
    ax.set_xlabel("rotation of gear A from the start of contact (deg)")


def save_figure(fig: Any, name: str) -> str:
    """Save ``fig`` as ``docs/figures/<name>``, close it; return its path relative to ``docs/``."""
    FIGURES.mkdir(parents=True, exist_ok=True)
    path = FIGURES / name
    fig.savefig(path, dpi=100, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    size = path.stat().st_size
    if size > 150_000:  # keep every picture well under 200 kB: 256-colour palette
        from PIL import Image

        with Image.open(path) as im:
            im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)
        size = path.stat().st_size
    if size > 200_000:
        print(f"warning: {path} is {size / 1e3:.0f} kB", file=sys.stderr)
    return f"figures/{name}"

