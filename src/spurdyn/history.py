"""A run's torques against time (:class:`TorqueHistory`), read from a file or a table.

On the settings' floor (it imports only the error type); :mod:`spurdyn.settings` re-exports
it beside the run settings that hold it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from spurdyn.errors import InputError

#: Most points of a torque history (a million: a measured signal at 1 MHz for a second).
MAX_HISTORY_POINTS = 1_000_000


@dataclass(frozen=True)
class TorqueHistory:
    """The torques of a run against time, read from a file or a table (N m, s).

    Parameters
    ----------
    time
        Sample times (s), strictly increasing; the run's time 0 is the first.
    driver
        The driver's torque at each time (N m, along its rotation: positive drives).
    load
        The driven gear's load torque at each time (N m, against its rotation: positive
        resists); ``None``, the nominal load of the run's ``torque`` throughout.
    periodic
        Repeat the history with the period ``time[-1] - time[0]`` past its end; otherwise
        a run longer than the history is refused.
    source
        Where it came from (a file's name), for the reports.

    Between samples the torques are linear in time (:func:`spurdyn.model.loading.history_at`).
    """

    time: tuple[float, ...]
    driver: tuple[float, ...]
    load: tuple[float, ...] | None = None
    periodic: bool = False
    source: str = ""

    def __post_init__(self) -> None:
        t = self.time
        if len(t) < 2:
            raise InputError("torque_history", f"needs at least two samples (got {len(t)})")
        if len(t) > MAX_HISTORY_POINTS:
            raise InputError("torque_history", f"holds {len(t):,} samples, more than "
                             f"{MAX_HISTORY_POINTS:,}: resample it")
        for name, col in (("time", t), ("driver", self.driver), ("load", self.load)):
            if col is None:
                continue
            if len(col) != len(t):
                raise InputError("torque_history", f"{name} has {len(col)} values for {len(t)} times")
            bad = [v for v in col if not isinstance(v, float) or not math.isfinite(v)]
            if bad:
                raise InputError("torque_history", f"{name} must be finite numbers (got {bad[0]!r})")
        steps = [b - a for a, b in zip(t[:-1], t[1:])]
        if min(steps) <= 0.0:
            i = steps.index(min(steps))
            raise InputError("torque_history", f"times must increase: {t[i + 1]!r} s follows {t[i]!r} s")
        if not isinstance(self.periodic, bool):
            raise InputError("torque_history", f"periodic must be true or false (got {self.periodic!r})")

    @property
    def duration(self) -> float:
        """The time the history covers (s): its last time less its first (its period when
        ``periodic``)."""
        return self.time[-1] - self.time[0]
