"""One point of a sweep: run the model on one case and reduce the run to its figures.

:func:`run_point` is what the workers execute (by reference: the workers need spurdyn
installed). It never raises for a run that goes wrong: an exception becomes a
``"failed"`` outcome with the exception as its reason, and a run the solver stops early
(non-convergence, NaN) is ``"incomplete"`` with the solver's reason, like ``spurdyn run``.
"""

from __future__ import annotations

import json
import math
import os
import socket
import time
import traceback
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from spurdyn.case.file import Case
from spurdyn.result import Result
from spurdyn.results.headline import AVERAGING_WINDOW_S
from spurdyn.sweep.spec import PointKey

#: Outcomes of a point, in the order of their codes in ``sweep.nc`` (see
#: :data:`spurdyn.sweep.store.STATUS_CODES`).
COMPLETE, INCOMPLETE, FAILED = "complete", "incomplete", "failed"

_WINDOW = f"{AVERAGING_WINDOW_S * 1e6:g} us"

#: Figures of a point: name -> (units, long name). All come from
#: :func:`spurdyn.results.io.summarize` of the run, as ``spurdyn run`` writes them,
#: except ``rms_force`` (computed here, from the same data set).
FIGURES: dict[str, tuple[str, str]] = {
    "peak_force": ("N", "peak of the contact force averaged over a centred moving window "
                   f"of {_WINDOW} (the ripple of local tooth modes taken out)"),
    "peak_angle_deg": ("degree", "rotation of A at the centre of the window of peak_force"),
    "dynamic_factor": ("1", "peak_force over the quasi-static force torque / r_b (NaN for "
                       "a run stopped early: see status)"),
    "peak_force_raw": ("N", "largest saved contact force of the engagement (not converged: "
                       "carries the ripple of local tooth modes)"),
    "dynamic_factor_raw": ("1", "peak_force_raw over the quasi-static force (NaN for a run "
                           "stopped early)"),
    "mean_force_single_zone": ("N", "mean contact force in the single-contact zone (one "
                               "engagement; NaN for a steady-state run)"),
    "rms_force": ("N", "root mean square of the contact force over the saved steps of the "
                  "engagement (contact-free steps count as zero)"),
    "separations": ("1", "times contact was lost after first being made and the gap opened "
                    "beyond 10 nm (the tip leaving at the end not counted)"),
    "static_force": ("N", "quasi-static tooth force torque / r_b of the driver"),
    "root_stress_max_a": ("Pa", "largest root stress (tension) of gear A's teeth, over the "
                          "cycles of the dynamic factor (the sector model's fillets; NaN for a "
                          "run stopped early and where a sweep does not compute it)"),
    "root_stress_max_b": ("Pa", "largest root stress (tension) of gear B's teeth, over the "
                          "cycles of the dynamic factor (the sector model's fillets; NaN for a "
                          "run stopped early and where a sweep does not compute it)"),
    "angle_reached_deg": ("degree", "rotation of A the run reached"),
    "steps": ("1", "time steps (FE) or integrator steps (lumped) taken"),
    "wall_s": ("s", "wall-clock time of the point on its worker"),
    "settled": ("1", "steady-state runs (cycles): 1 if the cycle-to-cycle change of the peak "
                "mesh force and of the transmission error's RMS fell below the tolerance, "
                "else 0; NaN for a one-engagement run"),
    "cycles_done": ("1", "steady-state runs: the mesh cycles run (more than asked where the "
                    "run went on to settle, up to max_cycles; NaN for a one-engagement run)"),
    "transmission_error_rms": ("m", "steady-state runs: RMS of the transmission error about "
                               "its mean over the last cycles (NaN otherwise)"),
    "transmission_error_pp": ("m", "steady-state runs: peak-to-peak of the transmission "
                              "error over the last cycles (NaN otherwise)"),
    "end_transmission_error": ("m", "steady-state runs: the transmission error at the end of "
                               "the last cycle (where a continuation's next speed starts)"),
    "end_transmission_error_slope": ("m/rad", "steady-state runs: its slope d delta / d phi_A "
                                     "at the end of the last cycle"),
}


@dataclass(frozen=True)
class PointTask:
    """What a worker needs to compute one point.

    Attributes
    ----------
    key
        The point.
    case
        Its case (speed and torque set, see :meth:`SweepPlan.point_case`).
    keep_result
        Return the whole :class:`Result` too (for ``--keep-runs``).
    follow
        A fault sweep's faulty gear (``"a"`` or ``"b"``): the point also keeps its sensor
        signals' indicators and averages over that gear's revolution
        (:func:`spurdyn.sweep.faults.signal_figures`, under the figure ``"signals"``);
        ``None`` in other sweeps.
    samples
        The averages' angle samples a revolution (with ``follow``).
    """

    key: PointKey
    case: Case
    keep_result: bool = False
    follow: str | None = None
    samples: int = 0


@dataclass(frozen=True)
class PointOutcome:
    """What became of one point.

    Attributes
    ----------
    key
        The point.
    status
        ``"complete"``, ``"incomplete"`` (the run stopped early: ``reason``) or
        ``"failed"`` (an error: ``reason``).
    reason
        Why the point is not complete ("" when it is).
    figures
        :data:`FIGURES` (``None`` where a figure does not exist, e.g. no single-contact
        zone reached); empty for a failed point.
    worker
        ``host:pid`` of the process that computed it.
    finished
        Unix time at which it finished.
    result
        The run itself when asked for (``keep_result``), else ``None``.
    """

    key: PointKey
    status: str
    reason: str = ""
    figures: dict[str, Any] = field(default_factory=dict)
    worker: str = ""
    finished: float = 0.0
    result: Result | None = None


def _worker_name() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def simulate_model(model: str, case: Case) -> Result:
    """Run ``model`` (:data:`spurdyn.simulators.MODELS`) on ``case``; no progress reports.

    The lumped model keeps its FE stiffness table per pair and mesh in the process, so
    the points of a sweep share it.
    """
    from spurdyn.simulators import MODELS

    if model not in MODELS:
        raise ValueError(f"unknown model {model!r}")
    return MODELS[model](case.pair, case.run)


def point_figures(result: Result, case: Case, ds: Any = None) -> dict[str, Any]:
    """The figures (:data:`FIGURES`) of a run, through the run folder's own summary.

    Computed from :func:`spurdyn.results.io.result_to_dataset` (or its data set ``ds``
    where the caller has it) and :func:`~spurdyn.results.io.summarize`, so a point agrees
    with ``spurdyn run`` of the same case.
    """
    from spurdyn.results.io import result_to_dataset, summarize

    ds = result_to_dataset(result, case) if ds is None else ds
    s = summarize(ds)
    end = (result.info.get("steady") or {}).get("end_state") or (None, None)
    force = np.asarray(ds["contact_force"].values, float)
    finite = force[np.isfinite(force)]
    rms = float(np.sqrt(np.mean(finite * finite))) if finite.size else None
    # a run stopped early has none, as it has no dynamic factor: its largest stress may be
    # the spike that stopped it
    stress = (s.get("root_stress_max_Pa") if s.get("status") == "complete" else None) or (None, None)
    return {
        "peak_force": s["peak_force_N"],
        "peak_angle_deg": s["peak_angle_deg"],
        "dynamic_factor": s["dynamic_factor"],
        "peak_force_raw": s["peak_force_raw_N"],
        "dynamic_factor_raw": s["dynamic_factor_raw"],
        "mean_force_single_zone": s.get("mean_force_single_zone_N"),   # one engagement's
        "rms_force": rms,
        "separations": s["separations"],
        "static_force": s["static_force_N"],
        "root_stress_max_a": stress[0],
        "root_stress_max_b": stress[1],
        "angle_reached_deg": s["angle_deg"],
        "steps": s["steps"],
        "wall_s": s["wall_s"],
        "settled": None if "settled" not in s else float(s["settled"]),
        "cycles_done": s.get("cycles_done"),
        "transmission_error_rms": s.get("transmission_error_rms_m"),
        "transmission_error_pp": s.get("transmission_error_pp_m"),
        "end_transmission_error": end[0],
        "end_transmission_error_slope": end[1],
        # the sector model's whole end state, kept in memory for a continuation's next speed
        # (not a figure: not stored)
        "end_state": result.info.get("sector_end_state"),
    }


def _figures(result: Result, task: PointTask) -> dict[str, Any]:
    """:func:`point_figures`, and a fault sweep's signals (``task.follow``)."""
    if task.follow is None:
        return point_figures(result, task.case)
    from spurdyn.results.io import result_to_dataset
    from spurdyn.sweep.faults import signal_figures

    t0 = time.perf_counter()
    ds = result_to_dataset(result, task.case)
    figures = point_figures(result, task.case, ds)
    teeth = (task.case.pair.gear_a.teeth, task.case.pair.gear_b.teeth)
    info = json.loads(ds.attrs.get("info", "{}") or "{}")     # as the run's summary reads it
    # the build's and the figures' seconds: where a point's time goes (benchmarks/bench_fault_sweep.py)
    figures["signals"] = {**signal_figures(ds, info, teeth, task.follow, task.samples),
                          "build_s": result.info.get("build_s"), "figures_s": time.perf_counter() - t0}
    return figures


def run_point(task: PointTask) -> PointOutcome:
    """Compute one point: run the model, reduce the run to its figures.

    Never raises an ``Exception``: an error is a ``"failed"`` outcome whose reason is the
    exception (type, message and the line it came from). ``KeyboardInterrupt`` and other
    ``BaseException`` pass through.
    """
    t0 = time.perf_counter()
    try:
        result = simulate_model(task.key.model, task.case)
        if not result.wall_s:
            result.wall_s = time.perf_counter() - t0
        figures = _figures(result, task)
    except Exception as err:  # noqa: BLE001 - recorded, the sweep goes on
        where = traceback.extract_tb(err.__traceback__)[-1] if err.__traceback__ else None
        at = f" ({os.path.basename(where.filename)}:{where.lineno})" if where else ""
        return PointOutcome(key=task.key, status=FAILED,
                            reason=f"{type(err).__name__}: {err}{at}",
                            figures={"wall_s": time.perf_counter() - t0},
                            worker=_worker_name(), finished=time.time())
    if "signals" in figures:   # a fault sweep's point: its whole time on the worker (wall_s is the run's)
        figures["signals"]["point_s"] = time.perf_counter() - t0
    status = COMPLETE if result.status == "complete" else INCOMPLETE
    reason = "" if status == COMPLETE else (result.reason or "stopped early")
    if status == COMPLETE:
        peak = figures.get("peak_force")
        if peak is None or not math.isfinite(peak):
            status, reason = INCOMPLETE, "no finite contact force"
    return PointOutcome(key=task.key, status=status, reason=reason, figures=figures,
                        worker=_worker_name(), finished=time.time(),
                        result=result if task.keep_result else None)
