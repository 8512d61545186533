"""The tooth pairs' stiffnesses over one mesh cycle, for the lumped model's steady state.

Under constant torques the tooth pair that entered ``r`` pitches before the start of the
current mesh cycle (row ``r``) carries ``F_r = k_r(phase) delta`` at the phase
``phase = phi mod p`` of A's rotation ``phi`` (``p = 2 pi / z_A``). Two sources:

- :class:`TableCycle`: the paper model's single-pair table ``k_s(rho)``
  (:class:`~spurdyn.lumped.model.MeshStiffnessTable`), the pairs as independent springs in
  parallel, ``k_r = k_s(rho(phase + r p))``;
- :class:`SectorCycle`: the sector model's loaded tooth contact analysis
  (:func:`spurdyn.sector.statics.mesh_cycle`), where the rim couples the pairs: each pair's
  effective stiffness is its share of the mesh stiffness, ``k_r = (F_r / W) k``, so that
  ``k_r delta`` is the analysis' pair force at the static compression ``W / k``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.geometry.pair import GearPair
from spurdyn.lumped.model import MeshStiffnessTable, contact_roll_a


#: Samples per cycle of :meth:`SectorCycle.at`'s dense table (linear between them, as
#: between the analysis' positions, so that the table adds no error of its own beyond
#: 1/DENSE_SAMPLES of a cycle at a position's corner).
DENSE_SAMPLES = 4000


def pair_rolls(pair: GearPair, phi_a: ArrayLike, j: ArrayLike) -> NDArray[np.float64]:
    """Roll angles on A of the pairs that entered at ``j`` pitches (rows) at A's rotations
    ``phi_a`` (columns)."""
    p = 2.0 * math.pi / pair.gear_a.teeth
    phi = np.asarray(phi_a, dtype=float)[None, :] - p * np.asarray(j, dtype=float)[:, None]
    return contact_roll_a(pair, phi)


def rows_in_path(pair: GearPair) -> int:
    """Rows of a cycle: the pairs the path holds, ``ceil(theta_s / p)`` before and the new one."""
    return int(math.ceil(pair.theta_s / (2.0 * math.pi / pair.gear_a.teeth))) + 1


@dataclass(frozen=True)
class TableCycle:
    """Independent pairs in parallel, each with the single-pair table (module docstring)."""

    pair: GearPair
    table: MeshStiffnessTable

    @property
    def pitch(self) -> float:
        return 2.0 * math.pi / self.pair.gear_a.teeth

    @property
    def rows(self) -> int:
        return rows_in_path(self.pair)

    @property
    def k_max(self) -> float:
        """The largest single-pair stiffness (N/m)."""
        return float(self.table.k_max)

    def at(self, phase: float) -> list[float]:
        """``k_r`` (N/m) of rows ``r = 0 .. rows-1`` at one phase (rad)."""
        roll0, droll, offsets, scalar = self._consts
        return [scalar(roll0 + droll * (phase + o)) for o in offsets]

    @cached_property
    def _consts(self) -> tuple[float, float, list[float], Any]:
        # the pair's geometry is recomputed on every access: once here, not per call of at()
        roll0 = self.pair.start_roll_a if self.pair.driver == "a" else self.pair.end_roll_a
        droll = 1.0 if self.pair.driver == "a" else -1.0
        return roll0, droll, [r * self.pitch for r in range(self.rows)], self.table.scalar

    def tables(self) -> tuple[NDArray[np.float64], NDArray[np.float64], float, float, float]:
        """What :func:`~spurdyn.lumped.steady_compiled.stiffness_at` reads for :meth:`at`:
        the table's pieces ``(pieces, order)``, its breaks ``(1, n)``, ``h = 0``, the start
        roll and its sense."""
        roll0, droll, _, _ = self._consts
        table = self.table
        return (np.array(table.piece_coefficients, dtype=float), np.array([table.breaks], dtype=float),
                0.0, roll0, droll)

    def grid(self, phase: ArrayLike) -> NDArray[np.float64]:
        """``(rows, n)`` ``k_r`` at the phases ``phase``."""
        phase = np.asarray(phase, dtype=float)
        return np.asarray(self.table(pair_rolls(self.pair, phase, -np.arange(self.rows)))).reshape(self.rows, -1)

    def describe(self) -> dict[str, Any]:
        return {"source": "the paper model's single-pair table, pairs in parallel",
                "mesh_stiffness_table": self.table.as_dict()}


@dataclass(frozen=True)
class SectorCycle:
    """The sector model's mesh cycle (module docstring). ``phase`` (rad, from the start of
    the path) and ``k`` (``(n, rows)``, N/m) are the analysis' positions and effective pair
    stiffnesses; ``on`` marks the positions where each row is on the path; ``bounds`` are
    the phases ``[lo, hi]`` between which each row is on the path, exactly."""

    phase: NDArray[np.float64]
    k: NDArray[np.float64]
    on: NDArray[np.bool_]
    bounds: NDArray[np.float64]
    pitch: float
    info: dict[str, Any]

    @classmethod
    def from_mesh_cycle(cls, pair: GearPair, mc: Any) -> "SectorCycle":
        from spurdyn.sector.statics import driving_pair

        dp = driving_pair(pair)
        p_drv = 2.0 * math.pi / dp.gear_a.teeth
        # the analysis runs on the driver's roll; the steady state on A's rotation, whose
        # pitch spans the same mesh cycle
        scale = (2.0 * math.pi / pair.gear_a.teeth) / p_drv
        pitch = p_drv * scale
        phase = (mc.roll - dp.start_roll_a) * scale
        on = np.isfinite(mc.single_pair)
        k = mc.effective(mc.roll - dp.start_roll_a).T
        rows = k.shape[1]
        r = np.arange(rows)
        bounds = scale * np.column_stack([np.maximum(-r * p_drv, 0.0),
                                          np.minimum(dp.end_roll_a - dp.start_roll_a - r * p_drv, p_drv)])
        info = {"source": "the sector model's quasi-static mesh cycle (docs/sector.md)"} | {
            key: v for key, v in mc.summary().items()
            if key in ("teeth_per_gear", "rim_inner_radius_m", "n_dof", "positions",
                       "mesh_stiffness_mean_N_per_m", "single_pair_stiffness_max_N_per_m")}
        return cls(phase=phase, k=k, on=on, bounds=bounds, pitch=pitch, info=info)

    @property
    def rows(self) -> int:
        return int(self.k.shape[1])

    @property
    def k_max(self) -> float:
        return float(self.k.sum(axis=1).max())

    def grid(self, phase: ArrayLike) -> NDArray[np.float64]:
        phase = np.atleast_1d(np.asarray(phase, dtype=float))
        out = np.zeros((self.rows, phase.size))
        for r in range(self.rows):
            lo, hi = self.bounds[r]
            inside = (phase >= lo) & (phase <= hi)
            if inside.any() and self.on[:, r].any():
                out[r, inside] = np.interp(phase[inside], self.phase[self.on[:, r]], self.k[self.on[:, r], r])
        return out

    def at(self, phase: float) -> list[float]:
        """``k_r`` of every row at one phase: scalar arithmetic on a dense table of
        :meth:`grid` (the integrator calls this a dozen times a step)."""
        dense, bounds, h = self._dense
        x = phase / h
        i = min(max(int(x), 0), len(dense[0]) - 2)
        w = x - i
        return [(row[i] + w * (row[i + 1] - row[i])) if lo <= phase <= hi else 0.0
                for row, (lo, hi) in zip(dense, bounds)]

    def tables(self) -> tuple[NDArray[np.float64], NDArray[np.float64], float, float, float]:
        """What :func:`~spurdyn.lumped.steady_compiled.stiffness_at` reads for :meth:`at`:
        the dense rows, their bounds ``(rows, 2)``, the spacing ``h``, and two unused zeros."""
        dense, bounds, h = self._dense
        return np.array(dense, dtype=float), np.array(bounds, dtype=float), h, 0.0, 0.0

    @cached_property
    def _dense(self) -> tuple[list[list[float]], list[tuple[float, float]], float]:
        n = DENSE_SAMPLES
        h = self.pitch / n
        return (self.grid_inside(np.arange(n + 1) * h).tolist(),
                [(float(lo), float(hi)) for lo, hi in self.bounds], h)

    def grid_inside(self, phase: ArrayLike) -> NDArray[np.float64]:
        """As :meth:`grid`, but each row interpolated over the whole cycle (held constant
        beyond its samples), for :meth:`at` to cut at the exact bounds."""
        phase = np.atleast_1d(np.asarray(phase, dtype=float))
        out = np.zeros((self.rows, phase.size))
        for r in range(self.rows):
            if self.on[:, r].any():
                out[r] = np.interp(phase, self.phase[self.on[:, r]], self.k[self.on[:, r], r])
        return out

    def describe(self) -> dict[str, Any]:
        return dict(self.info)


__all__ = ["SectorCycle", "TableCycle", "pair_rolls", "rows_in_path"]
