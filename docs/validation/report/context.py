"""What the sections share: the runs with the pair's figures (:class:`Ctx`), and the
tables of contact episodes and of a run's cost."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .helpers import contact_episodes, moving_average, n0, on_common_grid, rms, table, zone_masks
from .runs import Run
from .spurdyn_api import PAPER_TORQUE, paper_pair


class Ctx:
    """The runs and the pair's figures shared by the sections."""

    def __init__(self, runs: dict[str, Run]) -> None:
        self.runs = runs
        self.pair = paper_pair()
        self.tau0 = PAPER_TORQUE
        self.rb = self.pair.gear_a.base_radius
        self.static = self.tau0 / self.rb
        self.theta_s = self.pair.theta_s
        self.theta_2 = self.pair.theta_2
        self.zone_deg = (math.degrees(self.theta_2), math.degrees(self.theta_s - self.theta_2))
        self._avg: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        self.figures: dict[str, Any] = {}

    def avg(self, name: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(t, f)`` of the 10-us moving average of a run's contact force."""
        if name not in self._avg:
            r = self.runs[name]
            f, t = moving_average(r["time"], r["contact_force"])
            self._avg[name] = (t, f)
        return self._avg[name]

    def avg_angle(self, name: str) -> NDArray[np.float64]:
        """Rotation of A (deg) at the centres of the averaging windows of a run."""
        r = self.runs[name]
        t, _ = self.avg(name)
        return np.degrees(np.interp(t, r["time"], r["angle"]))

    def single(self, name: str) -> NDArray[np.bool_]:
        """Mask of a run's samples in the single-contact zone."""
        r = self.runs[name]
        return zone_masks(r["angle"], self.theta_2, self.theta_s)["single"]

    def peak_avg(self, name: str) -> float:
        """Peak of the 10-us moving average of a run's contact force."""
        return float(self.avg(name)[1].max())

    def rms_avg(self, a: str, b: str) -> float:
        """RMS of the difference of two runs' averaged forces on a common 0.1-us grid."""
        _, (x, y) = on_common_grid([self.avg(a), self.avg(b)], 1e-7)
        return rms(x - y)

    def impacts(self, name: str, min_duration: float = 10e-6) -> list[dict[str, float]]:
        """Contact episodes lasting at least ``min_duration`` (brief touches left out)."""
        r = self.runs[name]
        return [e for e in contact_episodes(r["time"], r["angle"], r["contact_force"])
                if e["t_off"] - e["t_on"] >= min_duration]


def episodes_table(ctx: Ctx, name: str) -> str:
    """A markdown table of every contact episode of a run."""
    r = ctx.runs[name]
    eps = contact_episodes(r["time"], r["angle"], r["contact_force"])
    rows = []
    for i, e in enumerate(eps, 1):
        dur = (e["t_off"] - e["t_on"]) * 1e6
        rows.append([i, f"{math.degrees(e['angle_on']):.2f}° / {e['t_on'] * 1e6:.1f} µs",
                     f"{math.degrees(e['angle_off']):.2f}° / {e['t_off'] * 1e6:.1f} µs"
                     + (" (end of run)" if e["open_end"] else ""),
                     f"{dur:.1f}", n0(e["peak"]), f"{math.degrees(e['angle_peak']):.2f}°",
                     "impact" if dur >= 10 else "brief touch"])
    return table(["#", "contact made (A's rotation / time)", "contact lost", "duration (µs)",
                  "peak (N)", "at", "kind"], rows)


def run_cost(ctx: Ctx, name: str) -> str:
    """Steps and wall time of a run, and where it stopped if it did not finish."""
    r = ctx.runs[name]
    m = r.meta
    cost = f"{m['steps']:,} steps, {m['wall_s']:.1f} s"
    if m.get("status", "complete") != "complete":
        cost += f" (**stopped at {math.degrees(float(r['angle'][-1])):.2f}°**)"
    return cost

