"""Pictures of a grown root crack (``spurdyn crack``): its path on the cracked sector's
deformed mesh under the worst load, and an animation of its growth."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["draw_growth", "draw_path"]

#: The Q8 nodes in the order they run round the element (corners and mid-sides).
_ROUND = [0, 4, 1, 5, 2, 6, 3, 7]


def _near(nodes: NDArray[np.float64], elements: NDArray[np.intp], box: NDArray[np.float64]
          ) -> NDArray[np.intp]:
    """The elements with a corner inside ``box`` ``((x0, y0), (x1, y1))``."""
    c = nodes[elements[:, :4]]
    inside = np.all((c >= box[0]) & (c <= box[1]), axis=-1)
    return elements[inside.any(axis=1)]


def _box(cell_nodes: NDArray[np.float64]) -> NDArray[np.float64]:
    lo, hi = cell_nodes.min(axis=0), cell_nodes.max(axis=0)
    pad = 0.15 * (hi - lo)
    return np.array([lo - pad, hi + pad])


def draw_path(body: Any, u: NDArray[np.float64], cell_nodes: NDArray[np.float64],
              path: NDArray[np.float64], title: str, png: Path) -> float:
    """The cracked body's elements round the cracked cell, displaced by ``u`` magnified so
    that the largest displacement there is 4 % of the cell's height, and the crack's path
    (mm); returns the magnification."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    nodes, elements = body.mesh.nodes, body.mesh.elements
    box = _box(cell_nodes)
    shown = _near(nodes, elements, box)
    uu = np.asarray(u).reshape(-1, 2)
    peak = float(np.max(np.hypot(*uu[np.unique(shown)].T)))
    scale = 0.04 * float(np.ptp(cell_nodes[:, 1])) / peak if peak > 0.0 else 0.0
    moved = (nodes + scale * uu) * 1e3
    fig, ax = plt.subplots(figsize=(7, 8))
    ax.add_collection(PolyCollection(moved[shown[:, _ROUND]], facecolors="0.93",
                                     edgecolors="0.55", linewidths=0.2))
    ax.plot(path[:, 0] * 1e3, path[:, 1] * 1e3, "r.-", lw=1.2, ms=3, label="crack path (undeformed)")
    ax.set_xlim(box[0, 0] * 1e3, box[1, 0] * 1e3)
    ax.set_ylim(box[0, 1] * 1e3, box[1, 1] * 1e3)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"{title}\ndisplacements x {scale:.3g}", fontsize=9)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=130)
    plt.close(fig)
    return scale


def draw_growth(cell_nodes: NDArray[np.float64], outline: NDArray[np.float64],
                length: NDArray[np.float64], path: NDArray[np.float64], k_eq: NDArray[np.float64],
                title: str, target: Path) -> str:
    """An animation of the crack growing, one frame a tip (``length`` the tips' crack
    lengths, m; ``path`` the mouth then the tips): the cell's outline, the path so far,
    K_eq against the length beside it. A GIF through Pillow when it is there (returns
    ``"gif"``), else the frames side by side in one PNG (``"png"``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = length.size
    box = _box(cell_nodes) * 1e3
    loop = np.vstack([outline, outline[:1]]) * 1e3

    def frame(ax_path: Any, ax_k: Any, i: int) -> None:
        ax_path.clear()
        ax_k.clear()
        ax_path.plot(loop[:, 0], loop[:, 1], "k-", lw=0.6)
        upto = np.vstack([path[: len(path) - n + i + 1]]) * 1e3
        ax_path.plot(upto[:, 0], upto[:, 1], "r.-", lw=1.2, ms=3)
        ax_path.set_xlim(box[:, 0])
        ax_path.set_ylim(box[:, 1])
        ax_path.set_aspect("equal")
        ax_path.set_title(f"{title}: crack {length[i] * 1e3:.2f} mm", fontsize=8)
        ax_k.plot(length[: i + 1] * 1e3, k_eq[: i + 1] / 1e6, "b.-")
        ax_k.set_xlim(0.0, max(length[-1] * 1e3, 1e-3) * 1.05)
        ax_k.set_ylim(0.0, float(np.max(k_eq)) / 1e6 * 1.1)
        ax_k.set_xlabel("crack length (mm)")
        ax_k.set_ylabel("K_eq, worst load (MPa sqrt(m))")

    import importlib.util

    from matplotlib.animation import FuncAnimation, PillowWriter

    if importlib.util.find_spec("PIL") is None:
        fig, axes = plt.subplots(2, n, figsize=(2.2 * n, 5), squeeze=False)
        for i in range(n):
            frame(axes[0, i], axes[1, i], i)
        fig.tight_layout()
        fig.savefig(target.with_suffix(".png"), dpi=80)
        plt.close(fig)
        return "png"
    fig, (ax_path, ax_k) = plt.subplots(1, 2, figsize=(9, 4.5))
    anim = FuncAnimation(fig, lambda i: frame(ax_path, ax_k, i), frames=n, interval=400)
    anim.save(target.with_suffix(".gif"), writer=PillowWriter(fps=3))
    plt.close(fig)
    return "gif"
