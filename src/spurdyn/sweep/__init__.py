"""Speed sweeps: the dynamic factor against speed, on one machine or a Dask cluster.

``spurdyn sweep`` (:mod:`spurdyn.cli.sweep`) and, from Python::

    from pathlib import Path
    from spurdyn.case import preset_case
    from spurdyn.sweep import SerialBackend, SweepPlan, local_backend, parse_speeds, run_sweep

    plan = SweepPlan(case=preset_case("paper-fig8"), model="lumped",
                     rpms=parse_speeds("1000:20000/40"), torques=None, out=Path("out/sweep"))
    with local_backend(jobs=2) as backend:        # or SerialBackend(): this process
        report = run_sweep(plan, backend)
    report.dataset["dynamic_factor"]

The modules: :mod:`~spurdyn.sweep.spec` (grids, point keys, settings hash),
:mod:`~spurdyn.sweep.point` (one point: run and figures), :mod:`~spurdyn.sweep.backends`
(this process or Dask), :mod:`~spurdyn.sweep.scheduler` (an existing cluster, over TCP or
TLS), :mod:`~spurdyn.sweep.store` (point files, ``sweep.nc``),
:mod:`~spurdyn.sweep.runner` (resumable runs), :mod:`~spurdyn.sweep.resonance` (the
natural-frequency estimate), :mod:`~spurdyn.sweep.plot` (``dynamic_factor.png``),
:mod:`~spurdyn.sweep.faults` (a fault's sizes, its points' signals) and
:mod:`~spurdyn.sweep.fault_store` (``fault_sweep.nc``).
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from (imported when first asked for, so that
#: ``spurdyn --help`` does not pay for xarray and Matplotlib).
_EXPORTS = {
    "DaskBackend": "backends", "SerialBackend": "backends", "local_backend": "backends",
    "scheduler_backend": "scheduler",
    "FIGURES": "point", "PointOutcome": "point", "PointTask": "point", "run_point": "point",
    "ResonanceEstimate": "resonance", "resonance_estimate": "resonance",
    "SweepReport": "runner", "run_sweep": "runner", "points_to_compute": "runner",
    "MODELS": "spec", "PointKey": "spec", "SweepPlan": "spec", "parse_speeds": "spec",
    "parse_torques": "spec", "point_case": "spec", "settings_hash": "spec",
    "STATUS_CODES": "store", "load_dataset": "store",
    "FaultAxis": "faults", "fault_axis": "faults", "fault_dataset": "fault_store",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
