"""How a crack's faces met in a dynamic run (docs/faults.md, "The crack's faces in motion").

The implicit step holds the faces as a unilateral contact and records per step their largest
force and their least and largest opening (:class:`~spurdyn.solvers.sector.stepper.SectorRecord`,
``faces``): the openings ``B^T u`` (:attr:`~spurdyn.sector.body.SectorBody.seam_loads`,
positive open) from the modes and the residual flexibility under the pairs' and the faces'
forces (:class:`~spurdyn.sector.faces.CrackFaces`). This gives them over the run's kept steps
for ``summary.json``'s ``crack_faces``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # annotations only
    from spurdyn.sector.model import SectorModel


def face_openings(model: SectorModel, record: Any, n_kept: int) -> dict[str, Any] | None:
    """The least and the largest opening (m) of the cracked gears' faces over the run's
    steps below ``n_kept``, when the least was, and their largest force (N, a node pair's)
    and when, and the share of the steps with a pair of faces closed; ``None`` for a run without a crack or without kept steps."""
    faces = record.faces[:n_kept]
    done = np.isfinite(faces[:, 1]) if faces.size else np.zeros(0, bool)
    if model.faces is None or not done.any():
        return None
    steps = np.flatnonzero(done)
    least, most, force = faces[steps, 1], faces[steps, 2], faces[steps, 0]
    return {"least_opening_m": float(least.min()), "largest_opening_m": float(most.max()),
            "least_at_s": float(steps[least.argmin()] * model.h),
            "largest_face_force_N": float(force.max()), "largest_force_at_s": float(steps[force.argmax()] * model.h),
            "closed_fraction": float(np.mean(force > 0.0))}


__all__ = ["face_openings"]
