"""A dynamic run of the sector model (docs/sector.md, section 6; varying torques, 6.8).

The run builds the :class:`~spurdyn.sector.model.SectorModel` of the pair and the
settings once (the bodies, the contacts, the mesh damper, the loading), starts from the
static equilibrium of the loaded pair at the first position of a mesh cycle (the
quasi-static analysis of :mod:`spurdyn.sector.statics` on the same bodies), or from rest, or
from another run's end, the hubs at their nominal speeds, and steps it by generalized-alpha
(:mod:`spurdyn.solvers.sector.implicit_numpy`, its compiled twin
:mod:`spurdyn.solvers.sector.step_compiled`) for ``cycles`` mesh cycles and on, one at a
time, until it settles (:func:`~spurdyn.solvers.sector.stepper.settle`). The stepper is the
registry's (:data:`~spurdyn.solvers.sector.stepper.STEPPERS`) for the settings' backend.
"""

from __future__ import annotations

import math
import time as _time
from typing import Any, Callable

import numpy as np
from threadpoolctl import threadpool_limits

from spurdyn.geometry.pair import GearPair
from spurdyn.result import Result
from spurdyn.sector.model import SectorModel
from spurdyn.sector.rules import (
    BACKLASH_FLOOR,
    BODY_DAMPING_FREQUENCY,
    BODY_DAMPING_RATIO,
    KEEP_FREQUENCY,
    SECTOR_REVISION,
    STEPS_PER_MESH_PERIOD,
    back_flanks_on,
    body_rayleigh,
    cycles_limit,
    steps_per_cycle,
)
from spurdyn.sector.state import SectorState, pack_state
from spurdyn.sector.system import REACH, back_teeth
from spurdyn.settings import RunSettings
from spurdyn.solvers.sector.output import sector_result
from spurdyn.solvers.sector.stepper import SectorRecord, SectorStepper, make_stepper, settle


def sector_backend(model: SectorModel, settings: RunSettings, energy: bool) -> str:
    """The backend a run steps on: the settings' ``numba`` (the default) is the compiled loop
    where it steps the model (modal bodies of whole gears, no energy record), and the NumPy
    loop elsewhere, said so in ``info["backend"]``; ``numpy`` is the NumPy loop."""
    compiled = settings.backend == "numba" and model.modes and not energy and model.whole
    return "numba" if compiled else "numpy"


def simulate_sector(pair: GearPair, settings: RunSettings,
                    progress: Callable[[int, float, float], None] | None = None, *,
                    dt: float | None = None, energy: bool = False,
                    modes: bool | float | None = None) -> Result:
    """Run the sector model of ``pair`` with ``settings`` (module docstring).

    Parameters
    ----------
    pair, settings
        The pair and the run: its ``torque`` (on the driver), speeds, ``cycles`` (1 if not
        given), mesh (``nx``, ``ny``, ``grading``), ``damping_ratio`` (the mesh damper),
        ``rayleigh_mass``/``rayleigh_stiffness`` (the bodies; :func:`body_rayleigh` if
        neither is given), ``rho_inf`` and ``backend`` (:func:`sector_backend`).
    progress
        Called as ``progress(step, angle_reached, angle_total)`` (rad) about a hundred times.
    dt
        The time step (s); by default the one of :func:`steps_per_cycle`. It is shortened
        to a whole number of steps per mesh cycle.
    energy
        Keep the energy balance per sample in ``info["energy"]`` (kinetic, strain,
        strip, the torques' work, J), and the hubs' momenta with the pairs' torques on
        them in ``info["momentum"]``.
    modes
        Reduce each body to its modes (:mod:`spurdyn.sector.reduced`): ``True``
        keeps those below :data:`KEEP_FREQUENCY`, a number those below it (Hz); ``False`` steps the whole
        finite-element bodies; ``None`` as ``settings.bodies`` says.

    Returns
    -------
    Result
        ``contact_force`` the most loaded pair's force, ``gap`` the smallest gap of a pair
        on the path, ``pair_force`` every pair's, ``transmission_error``
        ``r_bA theta_A - r_bB theta_B`` (the driver's), ``info["steady"]`` the settled test, ``info["build_s"]`` the seconds of the model's build.
    """
    wall0 = _time.perf_counter()
    model = SectorModel.build(pair, settings, dt=dt, modes=modes)
    build_s = _time.perf_counter() - wall0
    record = SectorRecord(model, model.per_cycle * model.cycles, energy)
    backend = sector_backend(model, settings, energy)
    stepper = make_stepper(model, record, "implicit", backend, energy)
    # BLAS on one thread: the products are small and another process may hold the other core
    # (as the implicit integrator's steps, docs/implicit.md)
    limit = threadpool_limits(limits=1, user_api="blas")
    try:
        status, reason, n_kept, target = settle(stepper, progress)
    finally:
        limit.restore_original_limits()
    result = _result(model, stepper, record, status, reason, n_kept, target, backend, _time.perf_counter() - wall0)
    result.info["build_s"] = build_s        # of the wall time: the model's build (a faulty gear's is long)
    return result


def _result(model: SectorModel, stepper: SectorStepper, record: SectorRecord, status: str, reason: str,
            n_kept: int, target: int, backend: str, wall: float) -> Result:
    """The run as a :class:`~spurdyn.result.Result` with its record complete: the pairs of
    the cycles run (those of the cycles it might have gone on to never came), and where a
    continuation of a complete run on whole gears starts."""
    settings, start, dp, pitch = model.settings, stepper.start_state, model.dp, model.pitch
    teeth, back_k = model.teeth, model.back_k
    keep = teeth >= -target - 1
    back_keep = back_k >= back_teeth(dp, target, REACH * pitch)[0] if model.back else np.zeros(0, bool)
    info: dict[str, Any] = {}
    if status == "complete" and model.whole:
        info["sector_end_state"] = end_state(model, stepper)
    info.update(tooth_offset=start.offset, common_rotation_reset=start.reset, rayleigh=list(model.rayleigh),
                # the bodies' damping was the model's default (BODY_DAMPING_RATIO), not the run's
                rayleigh_default=settings.rayleigh_mass is None and settings.rayleigh_stiffness is None,
                bodies="modal" if model.modes else "full",
                modes=[g.n - 1 for g in model.gears] if model.modes else None, coordinates=model.n,
                backend=backend)
    if settings.faults:     # the gear a diagnostics study follows: the faulty one (the driver's with both)
        gears = {f.gear for f in settings.faults}
        info["fault_gear"] = gears.pop() if len(gears) == 1 else model.pair.driver
    return sector_result(model, record, n_kept=n_kept, status=status, reason=reason, wall=wall, most=model.most,
                         keep=keep, back_keep=back_keep if model.back else None, info=info,
                         offset=start.offset)


def end_state(model: SectorModel, stepper: Any) -> tuple[float, ...]:
    """Where the next speed of a continuation starts: this end, the teeth N on (the pitches
    the driver turned: the cycles run, give or take its transmission error)."""
    st = stepper.state
    q, v, acc, qdd, force = st.q, st.v, st.acc, st.qdd, st.force
    speed, pitch, offset = model.speed, model.pitch, stepper.start_state.offset
    turned = int(round(q[0] / pitch))
    q_end = q.copy()
    q_end[0] -= turned * pitch
    q_end[model.na] -= turned * 2.0 * math.pi / model.dp.gear_b.teeth
    loaded = np.flatnonzero(force > 0.0)
    return pack_state(SectorState(offset - turned, q_end, v / speed, acc / speed**2, qdd / speed**2,
                                  model.c_teeth[loaded] + offset, force[loaded], model.c_side[loaded]))


__all__ = ["BACKLASH_FLOOR", "BODY_DAMPING_FREQUENCY", "BODY_DAMPING_RATIO", "KEEP_FREQUENCY", "SECTOR_REVISION",
           "STEPS_PER_MESH_PERIOD", "back_flanks_on", "body_rayleigh", "cycles_limit", "end_state", "sector_backend",
           "simulate_sector", "steps_per_cycle"]
