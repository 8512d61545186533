"""A fault sweep: the case's one fault over its sizes, and what a point keeps of the
sensors' signals (docs/sweep.md, "Fault datasets").

``spurdyn sweep CASE --fault-size 0:2e-3/6`` runs the case's fault (a crack's length, a
spall's depth) at each size, at every speed and torque of the sweep. Size 0 is the healthy
pair: the healthy model runs it (a crack of no length has no mesh), over the whole
revolutions of the faulty gear a faulty run takes (:func:`fault_case`). A point keeps, per
sensor signal (:data:`SIGNALS`), the condition indicators of
:func:`spurdyn.results.vibration.signal_indicators` and the time-synchronous average over a
revolution of the faulty gear on :attr:`FaultAxis.samples` angles (:func:`signal_figures`);
:mod:`spurdyn.sweep.fault_store` assembles them into one data set.

This module imports no other of the sweep's (``spec`` imports it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault

#: Fault kinds that have a size (what the size axis scales: a crack's length, a spall's
#: depth, a chip's height; all held in ``Fault.depth``).
SIZED_KINDS = ("crack", "spall", "chip")
#: The sensors' signals a point keeps (``result.nc``'s, :mod:`spurdyn.results.vibration`).
SIGNALS = ("mesh_force", "hub_acceleration_a", "hub_acceleration_b", "bearing_force_separating",
           "bearing_force_transverse")
#: Their units.
SIGNAL_UNITS = {"mesh_force": "N", "hub_acceleration_a": "rad s-2", "hub_acceleration_b": "rad s-2",
                "bearing_force_separating": "N", "bearing_force_transverse": "N"}
#: The indicators a point keeps per signal: name -> (units, ``None`` the signal's), long name.
INDICATORS: dict[str, tuple[str | None, str]] = {
    "rms": (None, "root mean square about the mean over the window's samples"),
    "kurtosis": ("1", "kurtosis about the mean over the window's samples"),
    "crest_factor": ("1", "peak over RMS about the mean over the window's samples"),
    "fm0": ("1", "FM0 of the time-synchronous average: its peak-to-peak over the sum of its mesh harmonics"),
    "fm4": ("1", "FM4: the kurtosis of the average's difference signal"),
    "na4": ("1", "NA4: the residual signal's kurtosis over its variance averaged over the revolutions"),
    "sideband_energy_ratio": ("1", "six shaft orders either side of the mesh order over the mesh order, "
                                   "on the average's orders"),
}
#: Shaft orders a tooth the dataset's averages keep: its angle samples are the power of two
#: at or above twice this times the faulty gear's teeth (16 mesh harmonics and their
#: sidebands; 1,024 samples on a 28-tooth gear).
ORDERS_PER_TOOTH = 16
#: Bytes of one value of a kept average: a Python float in a record's list (8 B of pointer,
#: 24 B of object) and some 20 B of its JSON text in the point file.
BYTES_PER_SAMPLE = 52


def size_of(fault: Fault) -> float | None:
    """The size the axis scales: a crack's length, a spall's depth or a chip's height (m);
    ``None`` for a missing tooth."""
    return float(fault.depth) if fault.kind in SIZED_KINDS else None


def size_text(size: float) -> str:
    """A size (m) as a file name writes it, to the nanometre: ``0.0005``."""
    return f"{size:.9f}".rstrip("0").rstrip(".")


def angle_samples(teeth: int) -> int:
    """Angle samples a revolution of the dataset's averages (:data:`ORDERS_PER_TOOTH`)."""
    return int(2 ** math.ceil(math.log2(2 * ORDERS_PER_TOOTH * teeth)))


@dataclass(frozen=True)
class FaultAxis:
    """A fault sweep's axis.

    Attributes
    ----------
    fault
        The case's one fault (at the case's size).
    sizes
        Its sizes (m, increasing; 0 the healthy pair); ``(None,)`` for a missing tooth.
    teeth
        Teeth of the faulty gear (a revolution is that many mesh cycles).
    samples
        Angle samples of a revolution of the kept averages (:func:`angle_samples`).
    """

    fault: Fault
    sizes: tuple[float | None, ...]
    teeth: int
    samples: int

    @property
    def signal_bytes(self) -> int:
        """Bytes a point's averages take in the sweep's process and folder, beyond a speed
        sweep's point (:data:`spurdyn.sweep.spec.BYTES_PER_POINT`)."""
        return len(SIGNALS) * self.samples * BYTES_PER_SAMPLE

    def hashed_case(self, case: Any) -> Any:
        """The case as a fault sweep's settings hash reads it: the fault's size left out
        (each point's key holds it)."""
        if size_of(self.fault) is None:
            return case
        return replace(case, run=case.run.with_(faults=(replace(self.fault, depth=0.0),)))

    def hash_dict(self) -> dict[str, Any]:
        """What else a fault sweep's points depend on: the averages' samples."""
        return {"angle_samples": self.samples}


def fault_axis(case: Any, sizes: tuple[float, ...] | None) -> FaultAxis | None:
    """The fault sweep of ``case`` over ``sizes`` (m, from ``--fault-size``; ``None``: the
    case's own size), ``None`` for a healthy case without sizes. (A model that carries no
    faults has refused the case's already: the registry's rule, ``ModelEntry.refuse``.)

    Raises
    ------
    InputError
        Naming ``--fault-size``: sizes without a fault, for a missing tooth, for several
        faults, one the fault's checks refuse (a spall deeper than 1 mm, a crack leaving its
        tooth); naming ``fault``: several faults without sizes.
    """
    faults = tuple(case.run.faults)
    if not faults:
        if sizes is not None:
            raise InputError("--fault-size", "needs a fault to size: give the case a [[fault]] table or "
                             "--fault gear=a,tooth=5,kind=crack,depth=1e-3")
        return None
    if len(faults) > 1:
        raise InputError("--fault-size" if sizes is not None else "fault",
                         f"a fault sweep follows one fault; the case has {len(faults)}: keep one "
                         "(several faults at once are a case for `spurdyn run`)")
    fault = faults[0]
    if sizes is not None and size_of(fault) is None:
        raise InputError("--fault-size", f"a {fault.kind} tooth has no size: give a crack, a spall or a chip, "
                         "or leave out --fault-size")
    if sizes is None:
        sizes = (size_of(fault),) if size_of(fault) is not None else (None,)   # type: ignore[assignment]
    for size in sizes:
        if size:
            _check_size(case, fault, size)
    teeth = (case.pair.gear_a if fault.gear == "a" else case.pair.gear_b).teeth
    return FaultAxis(fault, tuple(sizes), int(teeth), angle_samples(int(teeth)))


def _check_size(case: Any, fault: Fault, size: float) -> None:
    """Refuse a size the fault's own checks refuse (those of its ``[[fault]]`` table)."""
    from spurdyn.case.fault_tables import fault_from_table, fault_to_table

    try:
        fault_from_table(fault_to_table(replace(fault, depth=size)), "fault", case.pair)
    except InputError as err:
        raise InputError("--fault-size", f"{size:g} m: {err.field.removeprefix('fault.')} "
                         f"{err.reason}") from None


def fault_case(case: Any, axis: FaultAxis, size: float | None) -> Any:
    """The case of the fault at ``size`` (m): the case itself for ``None``; else the run
    over whole revolutions of the faulty gear (:func:`spurdyn.sector.model.whole_periods`:
    at least two, and as many at most), the faulty run's as the model takes them, and for 0
    the healthy pair over the same (each point's figures then read its last revolution,
    :func:`last_revolution`)."""
    if size is None:
        return case
    from spurdyn.sector.model import whole_periods
    from spurdyn.sector.rules import cycles_limit, with_defaults

    run = case.run
    cycles = int(with_defaults(run).cycles)
    cycles, most = whole_periods(cycles, cycles_limit(run), axis.teeth, run.max_cycles is None)
    if size > 0.0:      # the cycles the faulty model itself takes, said in its case
        faulty = run.with_(faults=(replace(axis.fault, depth=float(size)),), cycles=cycles,
                           max_cycles=most)
        return replace(case, name=f"{case.name}_{axis.fault.kind}{size_text(size)}", run=faulty)
    healthy = run.with_(faults=(), cycles=cycles, max_cycles=most)
    return replace(case, name=f"{case.name}_healthy", run=healthy)


def orders_resampled(tsa: NDArray[np.float64], samples: int, start: float = 0.0) -> NDArray[np.float64]:
    """A revolution's average on ``samples`` points of the gear's angle ``2 pi j / samples``:
    its shaft orders below half of both its points and ``samples`` kept, the others dropped,
    each turned by the average's ``start`` angle (rad: its point 0 is at that angle of the
    gear). The average is one period, so this is its band-limited interpolation, exact for an
    average of those orders at any start (the orders at either count's half, whose sine part
    a sampling loses, are dropped)."""
    y = np.fft.rfft(np.asarray(tsa, float))
    n = min(samples // 2, (tsa.size + 1) // 2)
    keep = np.zeros(samples // 2 + 1, complex)
    keep[:n] = y[:n] * np.exp(-1j * np.arange(n) * start)
    return np.fft.irfft(keep, samples) * (samples / tsa.size)


def last_revolution(f: Any) -> Any:
    """The followed gear's window (:class:`~spurdyn.results.vibration.Followed`) cut to its
    last whole revolution: every point of a sweep reads the same length of signal, whatever
    number of revolutions its run took to settle."""
    keep = np.flatnonzero(np.abs(f.angle - f.angle[-1]) >= 2.0 * math.pi)
    if keep.size == 0:
        return f
    first = int(keep[-1])
    sel = f.sel.copy()
    sel[np.flatnonzero(f.sel)[:first]] = False
    angle, time = f.angle[first:], f.time[first:]
    f_shaft = abs(angle[-1] - angle[0]) / (time[-1] - time[0]) / (2.0 * math.pi)
    return f._replace(sel=sel, angle=angle, time=time, f_shaft=f_shaft)


def signal_figures(ds: Any, info: dict[str, Any], teeth: tuple[int, int], gear: str,
                   samples: int) -> dict[str, Any]:
    """What a fault sweep's point keeps of its run's data set ``ds``: per signal of
    :data:`SIGNALS` the :data:`INDICATORS` and the average over a revolution of ``gear``
    on ``samples`` angles, over :func:`spurdyn.results.vibration.followed`'s window (the
    same as ``summary.json``'s ``vibration``, following ``gear`` on the healthy pair too);
    only a ``reason`` where the run holds no whole revolution there."""
    from spurdyn.diagnostics import synchronous_average
    from spurdyn.results.vibration import average_indicators, followed, tsa_points

    f = followed(ds, {**info, "fault_gear": gear}, teeth)
    if f is None:
        return {"reason": f"no whole revolution of gear {gear} after the first one's last mesh cycle"}
    f = last_revolution(f)
    points = tsa_points(f.angle, f.teeth)
    out: dict[str, Any] = {"window_s": [float(f.time[0]), float(f.time[-1])], "shaft_frequency_Hz": f.f_shaft}
    for name in SIGNALS:
        x = ds[name].values.astype(float)[f.sel]
        tsa = synchronous_average(x, f.angle - f.angle[0], points)    # one average for both
        figures = average_indicators(x, tsa, f.teeth)
        out["revolutions"] = figures.pop("revolutions")
        start = float(f.angle[0]) % (2.0 * math.pi)
        out[name] = {**figures, "tsa": orders_resampled(tsa.signal, samples, start).tolist()}
    return out


__all__ = ["BYTES_PER_SAMPLE", "INDICATORS", "ORDERS_PER_TOOTH", "SIGNALS", "SIGNAL_UNITS", "SIZED_KINDS",
           "FaultAxis", "angle_samples", "fault_axis", "fault_case", "last_revolution", "orders_resampled",
           "signal_figures",
           "size_of", "size_text"]
