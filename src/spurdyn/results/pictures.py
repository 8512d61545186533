"""Pictures of the model (Matplotlib, no screen needed)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

from spurdyn.case.pair_tables import MeshedPair  # noqa: E402
from spurdyn.geometry.placement import line_of_action_point, mesh_angles, to_world_a, to_world_b  # noqa: E402
from spurdyn.mesh.tooth import ToothMesh, tooth_mesh  # noqa: E402

# Outline of a Q8 element through its mid-side nodes: corner, mid, corner, ...
_OUTLINE = [0, 4, 1, 5, 2, 6, 3, 7]


def _element_polygons(mesh: ToothMesh, world: np.ndarray) -> np.ndarray:
    return world[mesh.elements[:, _OUTLINE]]


def draw_mesh_position(case: MeshedPair, png: Path, roll_a: float | None = None) -> None:
    """Draw both teeth, meshed, touching at roll angle ``roll_a`` of A (default: pitch point)."""
    pair = case.pair
    roll = pair.pitch_roll_a if roll_a is None else roll_a
    theta_a, theta_b = mesh_angles(pair, roll)
    mesh_a = tooth_mesh(pair.gear_a, case.nx, case.ny, grading=case.grading,
                        row_grading=case.row_grading)
    mesh_b = tooth_mesh(pair.gear_b, case.nx, case.ny, grading=case.grading,
                        row_grading=case.row_grading)
    wa = to_world_a(mesh_a.nodes, theta_a)
    wb = to_world_b(mesh_b.nodes, theta_b, pair.centre_distance)

    fig, ax = plt.subplots(figsize=(7, 7), dpi=120)
    for mesh, world, colour, label in ((mesh_a, wa, "tab:blue", "gear A (driver)" if pair.driver == "a" else "gear A"),
                                       (mesh_b, wb, "tab:orange", "gear B" if pair.driver == "a" else "gear B (driver)")):
        polys = PolyCollection(_element_polygons(mesh, world) * 1e3, facecolor=colour, alpha=0.25,
                               edgecolor=colour, linewidth=0.6, label=label)
        ax.add_collection(polys)
        ax.plot(*(world[mesh.root_nodes] * 1e3).T, "k.", ms=3)
    ax.plot([], [], "k.", ms=3, label="root nodes (tied to the disk)")
    ends = np.array([line_of_action_point(pair, pair.start_roll_a),
                     line_of_action_point(pair, pair.end_roll_a)]) * 1e3
    ax.plot(*ends.T, "r-", lw=1.5, label="path of contact")
    q = line_of_action_point(pair, roll) * 1e3
    ax.plot(*q, "ro", ms=4)
    allpts = np.vstack([wa * 1e3, wb * 1e3, ends])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    pad = 0.05 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"{case.name}: {case.nx} x {case.ny} Q8 per tooth, contact at the pitch point")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)
