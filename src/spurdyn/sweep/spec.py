"""What a speed sweep is: the speed and torque grids, the points and their keys.

A sweep runs one case (a preset or a TOML file) at every speed of a grid, and optionally
at every torque of a second grid, each run covering the whole engagement. A point is
identified by its :class:`PointKey`: the model, the speed of gear A, the torque and the
hash of every other setting of the case (:func:`settings_hash`), so a point computed once
is found again whatever command asked for it.

Every function here is pure; refusals are :class:`~spurdyn.errors.InputError` naming the
option.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from spurdyn.case.file import Case, case_to_dict
from spurdyn.errors import InputError
from spurdyn.simulators import MODELS as _MODELS
from spurdyn.settings import RPM
from spurdyn.solvers.limits import MAX_BYTES
from spurdyn.sweep.faults import FaultAxis, fault_case, size_text

#: Models a sweep can run.
MODELS = tuple(_MODELS)

#: Bytes a point of a sweep takes: in the sweep's own process (its key, case, task, cost
#: and record: 4.4 kB) and in its folder (its point file and its row of the results:
#: 4.1 kB), measured on 2,000 and 20,000 points (docs/performance_sweep.md, "Many points").
BYTES_PER_POINT = 8_500
#: Most points one sweep may hold (and so one grid): the memory guard of a run's results
#: (:data:`~spurdyn.solvers.limits.MAX_BYTES`, 1 GiB) over :data:`BYTES_PER_POINT`.
MAX_POINTS = MAX_BYTES // BYTES_PER_POINT

#: Speeds and torques are rounded to this many decimals (so keys do not depend on the
#: last bit of a floating-point step).
DECIMALS = 6


def _number(text: str, field: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(field, f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise InputError(field, f"{text!r} is not a finite number")
    return value


def parse_grid(text: str, field: str, *, positive: bool = True,
               decimals: int = DECIMALS) -> tuple[float, ...]:
    """Read a grid: ``START:STOP:STEP``, ``START:STOP/N`` or a list ``A,B,C``.

    Parameters
    ----------
    text
        ``START:STOP:STEP`` runs from START by STEP up to STOP (STOP included when the
        steps land on it, to a millionth of a step); ``START:STOP/N`` is N evenly spaced
        values, both ends included; ``A,B,C`` (or a single value) lists the values.
    field
        The option name used in refusals (``--rpm``).
    positive
        Refuse zero (else only negative values are refused).
    decimals
        Decimals the values are rounded to (a fault's size in metres takes nine).

    Returns
    -------
    tuple of float
        Sorted, distinct values rounded to ``decimals`` decimals.

    Raises
    ------
    InputError
        A malformed grid, a negative (or zero) value, ``STOP < START``, a step that is
        not positive, more than :data:`MAX_POINTS` values.
    """
    text = text.strip()
    syntax = "must be START:STOP:STEP, START:STOP/N or a list A,B,C"
    if not text:
        raise InputError(field, f"is empty; it {syntax}")
    if ":" in text:
        parts = text.split(":")
        if len(parts) == 2 and "/" in parts[1]:
            stop_text, n_text = parts[1].split("/", 1)
            start, stop = _number(parts[0], field), _number(stop_text, field)
            try:
                n = int(n_text)
            except ValueError:
                raise InputError(field, f"N in START:STOP/N must be a whole number (got "
                                 f"{n_text!r})") from None
            if n < 1:
                raise InputError(field, f"N in START:STOP/N must be at least 1 (got {n})")
            if n > MAX_POINTS:
                raise InputError(field, f"{n:,} values; at most {MAX_POINTS:,}")
            if n > 1 and stop <= start:
                raise InputError(field, f"STOP {stop:g} must be above START {start:g}")
            values = [start] if n == 1 else [start + (stop - start) * i / (n - 1)
                                             for i in range(n)]
        elif len(parts) == 3:
            start, stop, step = (_number(p, field) for p in parts)
            if step <= 0:
                raise InputError(field, f"STEP must be positive (got {step:g})")
            if stop < start:
                raise InputError(field, f"STOP {stop:g} is below START {start:g}")
            span = (stop - start) / step      # inf for a step far below the range
            if not span < MAX_POINTS:
                many = f"{span + 1:,.0f}" if span < 1e15 else "more than 1e15"
                raise InputError(field, f"{many} values; at most {MAX_POINTS:,}")
            count = math.floor(span + 1e-6) + 1
            values = [start + i * step for i in range(count)]
        else:
            raise InputError(field, f"{text!r}: {syntax}")
    else:
        values = [_number(p, field) for p in text.split(",")]
        if len(values) > MAX_POINTS:
            raise InputError(field, f"{len(values):,} values; at most {MAX_POINTS:,}")
    for v in values:  # checked as stored: rounded to ``decimals`` decimals
        if v < 0 or (positive and round(v, decimals) == 0):
            kind = "positive" if positive else "zero or positive"
            raise InputError(field, f"values must be {kind} to {decimals} decimals (got {v:g})")
        if v != 0 and round(v, decimals) == 0:      # would be stored as a zero it is not
            raise InputError(field, f"{v:g} is zero to {decimals} decimals: give 0 or at least "
                             f"{10.0 ** -decimals:g}")
    return tuple(sorted({round(v, decimals) + 0.0 for v in values}))


def check_count(rpms: tuple[float, ...], torques: tuple[float, ...] | None, sizes: int = 1,
                per_point: int = BYTES_PER_POINT) -> None:
    """Refuse a sweep of more than the points the memory guard holds (speeds times torques
    times a fault sweep's ``sizes``, each of ``per_point`` bytes: :data:`MAX_POINTS` for a
    healthy sweep), before any point is made.

    Raises
    ------
    InputError
        Naming ``--fault-size`` or ``--torque`` (the grid that multiplies the speeds), or
        ``--rpm``.
    """
    n = len(rpms) * (len(torques) if torques is not None else 1) * sizes
    most = MAX_BYTES // per_point
    if n > most:
        field = "--fault-size" if sizes > 1 else "--torque" if torques is not None else "--rpm"
        grids = f"{len(rpms):,} speeds x {len(torques):,} torques = " if torques else ""
        if sizes > 1:
            grids = f"{grids or f'{len(rpms):,} speeds = '}".removesuffix(" = ") + f" x {sizes:,} sizes = "
        raise InputError(field, f"{grids}{n:,} points; at most {most:,} (each holds "
                         f"about {per_point / 1e3:.1f} kB in memory and on disk, within "
                         f"the {MAX_BYTES / 2**30:g} GiB guard of a run's results)")


def parse_speeds(text: str, field: str = "--rpm") -> tuple[float, ...]:
    """The speeds of gear A (rpm) of ``--rpm``; see :func:`parse_grid`."""
    return parse_grid(text, field, positive=True)


def parse_torques(text: str, field: str = "--torque") -> tuple[float, ...]:
    """The torques (N m, zero allowed) of ``--torque``; see :func:`parse_grid`."""
    return parse_grid(text, field, positive=False)


def speed_ratio(case: Case) -> float:
    """``speed_b / speed_a`` of the case: kept at every speed of a sweep.

    The meshing ratio ``z_a / z_b`` (equal pitch-line speeds) unless the case starts B
    faster or slower (``paper-fig10``: 1.01).
    """
    return float(case.run.speed_b / case.run.speed_a)


def settings_dict(case: Case) -> dict[str, Any]:
    """Every setting of the case that a point depends on, apart from speed and torque.

    The case in the TOML layout (:func:`spurdyn.case.file.case_to_dict`) with the speeds
    replaced by their ratio ``run.speed_ratio`` and without ``run.torque`` (both are part
    of the point's key) and ``run.frames_every`` (which changes what is kept, not what is
    computed).
    """
    data = case_to_dict(case)
    run = dict(data["run"])
    for key in ("speed_a_rpm", "speed_b_rpm", "torque", "frames_every"):
        run.pop(key, None)
    run["speed_ratio"] = round(speed_ratio(case), 12)
    data["run"] = run
    return data


#: Orders of a continuation sweep (:attr:`SweepPlan.continuation`).
CONTINUATIONS = ("up", "down")


def settings_hash(case: Case, continuation: str | None = None, model: str | None = None,
                  faults: FaultAxis | None = None) -> str:
    """Twelve hex digits of the SHA-256 of :func:`settings_dict` (canonical JSON), with the
    sweep's ``continuation`` when it has one (its points start from another's end), a fault
    sweep's axis (``faults``: the fault but its size, which each point's key holds, and the
    samples of its signals' averages), and what
    a steady-state run takes by default where the case gives nothing (the most cycles it may
    go on to; for the sector ``model``, by default the case's, the bodies' damping) and the sector model's revision,
    so that points of a version before those defaults are not taken for its."""
    data = settings_dict(case if faults is None else faults.hashed_case(case))
    if continuation is not None:
        data["sweep"] = {"continuation": continuation}
    if faults is not None:
        data["sweep"] = {**data.get("sweep", {}), "fault_axis": faults.hash_dict()}
    data["run"].update(_MODELS[model or case.model].hash_extras(case.run))
    text = json.dumps(data, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:12]


def _num_text(x: float) -> str:
    return f"{x:.{DECIMALS}f}".rstrip("0").rstrip(".")


@dataclass(frozen=True, order=True)
class PointKey:
    """What identifies one point of a sweep.

    Attributes
    ----------
    model
        ``"fe"`` or ``"lumped"``.
    rpm
        Initial speed of gear A (rpm).
    torque
        External torque on the driver (N m).
    settings
        :func:`settings_hash` of the case.
    size
        A fault sweep's size of the fault (m; 0 the healthy pair), ``None`` in other sweeps
        (:mod:`spurdyn.sweep.faults`).
    """

    model: str
    rpm: float
    torque: float
    settings: str
    size: float | None = None

    @property
    def stem(self) -> str:
        """File-name stem, e.g. ``fe_rpm4000_tq22.25_0123456789ab`` (a fault sweep's with
        the size, ``sector_rpm1000_tq22.25_size0.0005_0123456789ab``)."""
        size = "" if self.size is None else f"_size{size_text(self.size)}"
        return f"{self.model}_rpm{_num_text(self.rpm)}_tq{_num_text(self.torque)}{size}_{self.settings}"

    def as_dict(self) -> dict[str, Any]:
        out = {"model": self.model, "rpm": self.rpm, "torque": self.torque,
               "settings_hash": self.settings}
        if self.size is not None:
            out["fault_size"] = self.size
        return out


@dataclass(frozen=True)
class SweepPlan:
    """One sweep: the case, the model, the grids and where the results go.

    Attributes
    ----------
    case
        The case; its speed and torque are replaced at each point (the speed ratio of
        B to A is kept).
    model
        ``"fe"`` or ``"lumped"``.
    rpms
        Speeds of gear A (rpm), increasing.
    torques
        Torques (N m), increasing; ``None``: the case's torque only, and the results have
        no ``torque`` dimension.
    out
        The sweep folder.
    keep_runs
        Also keep each point's whole run folder under ``out/runs/``.
    force
        Recompute the points already in ``out``.
    continuation
        ``None``: every point starts on its own (from the static compression); ``"up"`` or
        ``"down"``: the speeds run in that order, one after the other in this process, each
        point of a steady-state sweep starting from the previous speed's end state, so that
        the jumps of the nonlinear response show.
    run_pictures
        With ``keep_runs``: also draw each run folder's pictures (``spurdyn report`` keeps
        only the numbers: drawn in the sweep's process, they cost seconds a point).
    faults
        A fault sweep's axis of the case's one fault (:class:`~spurdyn.sweep.faults.FaultAxis`:
        its sizes, and the signals' samples a revolution), ``None`` for a healthy sweep.
    """

    case: Case
    model: str
    rpms: tuple[float, ...]
    torques: tuple[float, ...] | None
    out: Path
    keep_runs: bool = False
    force: bool = False
    continuation: str | None = None
    run_pictures: bool = True
    faults: FaultAxis | None = None

    @property
    def torque_values(self) -> tuple[float, ...]:
        return self.torques if self.torques is not None else (float(self.case.run.torque),)

    @property
    def sizes(self) -> tuple[float | None, ...]:
        """The fault's sizes (m) of a fault sweep, ``(None,)`` in another."""
        return (None,) if self.faults is None else self.faults.sizes

    @property
    def settings(self) -> str:
        return settings_hash(self.case, self.continuation, self.model, self.faults)

    def keys(self) -> list[PointKey]:
        """Every point, speed-major (then torque, then the fault's size)."""
        h = self.settings
        return [PointKey(self.model, rpm, tq, h, size) for rpm in self.rpms
                for tq in self.torque_values for size in self.sizes]

    def point_case(self, key: PointKey) -> Case:
        """The case of one point (see :func:`point_case`; a fault sweep's at the key's size,
        :func:`~spurdyn.sweep.faults.fault_case`)."""
        case = self.case if self.faults is None else fault_case(self.case, self.faults, key.size)
        return point_case(case, key.rpm, key.torque, keep_frames=self.keep_runs)


def point_case(case: Case, rpm: float, torque: float, keep_frames: bool = False) -> Case:
    """The case at speed ``rpm`` of gear A and torque ``torque``.

    Gear B starts at ``rpm * speed_ratio(case)``. Tooth frames are kept only when
    ``keep_frames`` (a point's figures do not need them).
    """
    run = case.run.with_(
        speed_a=rpm * RPM, speed_b=rpm * RPM * speed_ratio(case), torque=float(torque),
        frames_every=case.run.frames_every if keep_frames else 0,
        name=f"{case.name} {_num_text(rpm)} rpm {_num_text(torque)} N m")
    return replace(case, name=f"{case.name}@{_num_text(rpm)}rpm_{_num_text(torque)}Nm", run=run)


def expected_steps(case: Case) -> int:
    """Time steps the run of ``case`` needs (its cost, for ordering and time left)."""
    from spurdyn.solvers.limits import engagement_steps

    return engagement_steps(case)


def check_plan(plan: SweepPlan) -> None:
    """Refuse points that cannot run: more than :data:`MAX_POINTS` (:func:`check_count`), an
    angle shorter than one step at the top speed.

    Raises
    ------
    InputError
        Naming ``--angle``.
    """
    if plan.model not in MODELS:
        raise InputError("--model", f"must be one of {', '.join(MODELS)} (got {plan.model!r})")
    check_count(plan.rpms, plan.torques, len(plan.sizes),
                BYTES_PER_POINT + (0 if plan.faults is None else plan.faults.signal_bytes))
    top = point_case(plan.case, max(plan.rpms), plan.torque_values[0])
    if top.run.angle is not None and top.run.angle < top.run.speed_a * top.run.dt:
        raise InputError("--angle", f"{math.degrees(top.run.angle):g} deg is shorter than one "
                         f"time step at {max(plan.rpms):,g} rpm "
                         f"({math.degrees(top.run.speed_a * top.run.dt):.3g} deg)")
