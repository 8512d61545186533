"""``spurdyn stiffness`` of a faulty pair: its figures over the faulty gear's revolution
(docs/faults.md) and the ``--csv`` table of ``k(theta)`` a lumped model reads."""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from spurdyn.sector.faulty import Revolution
from spurdyn.sector.statics import MeshCycle

#: Columns of the ``--csv`` table.
CSV_COLUMNS = ("torque_Nm", "angle_deg", "mesh_stiffness_N_per_m", "transmission_error_m",
               "healthy_mesh_stiffness_N_per_m")


def _none_nan(values: np.ndarray) -> list[float | None]:
    return [None if not math.isfinite(v) else float(v) for v in values]


def revolution_row(rev: Revolution) -> dict[str, Any]:
    """One torque's figures and arrays of ``--json``."""
    return rev.summary() | {
        "angle_deg": np.degrees(rev.angle).tolist(),
        "mesh_stiffness_N_per_m": rev.stiffness.tolist(),
        "healthy_mesh_stiffness_N_per_m": rev.healthy_stiffness.tolist(),
        "transmission_error_m": _none_nan(rev.transmission_error),
        "pair_force_N": rev.force.tolist(),
    }


def write_csv(path: Path, runs: Sequence[Revolution | MeshCycle]) -> None:
    """``k(theta)`` by torque: a revolution's positions, or a healthy cycle's (its angle
    the driver's roll from the start of the path, its healthy stiffness its own)."""
    with open(path, "w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(CSV_COLUMNS)
        for run in runs:
            if isinstance(run, Revolution):
                angle, healthy = run.angle, run.healthy_stiffness
            else:
                angle, healthy = run.roll - run.roll[0], run.stiffness
            for a, k, e, h in zip(np.degrees(angle), run.stiffness, run.transmission_error, healthy):
                out.writerow([f"{run.torque:.9g}", f"{a:.9g}", f"{k:.9g}",
                              f"{e:.9g}" if math.isfinite(e) else "", f"{h:.9g}"])


__all__ = ["CSV_COLUMNS", "revolution_row", "write_csv"]
