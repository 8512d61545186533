"""The time loop: from a pair and run settings to a :class:`~spurdyn.result.Result`.

The loop owns the run (history, frames, progress, stopping); a stepper
(:class:`~spurdyn.solvers.base.Stepper`) owns the method. :data:`STEPPERS` maps a time
integrator and a backend to the stepper that computes it: the paper's RK4 in NumPy
(:class:`~spurdyn.solvers.paper.stepper_numpy.NumpyStepper`, re-integrates every
iterate) and compiled (:class:`~spurdyn.solvers.paper.stepper_compiled.CompiledStepper`,
superposes the response to the forces), and the implicit integrator in both
(:mod:`spurdyn.solvers.implicit.stepper`). The run is checked first
(:mod:`spurdyn.solvers.check`, with the bounds of :mod:`spurdyn.solvers.limits`); the
commands ask :mod:`spurdyn.solvers.warmup` beforehand whether the compiled stepper will
compile. A run that cannot go on (a stage that does not converge, a NaN, Ctrl-C) returns
what it has with ``status = "incomplete"``.
"""

from __future__ import annotations

import importlib
import time
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.contact.hertz import half_width, peak_pressure
from spurdyn.geometry.pair import GearPair
from spurdyn.model.loading import static_force
from spurdyn.model.system import PairSystem, build_system, solver_pair
from spurdyn.result import STAGES, Result
from spurdyn.settings import RunSettings
from spurdyn.solvers.base import Frames, Stepper
from spurdyn.solvers.check import check_run
from spurdyn.solvers.layout import FAIL_ACC, FAIL_DISP, FAIL_NEWTON, FAIL_VEL, HISTORY, NCOL, OK
from spurdyn.solvers.paper.dynamics_numpy import strip_law

Progress = Callable[[int, float, float], None]

#: ``(integrator, backend) -> "module:class"`` of the stepper, imported when first used.
STEPPERS: dict[tuple[str, str], str] = {
    ("rk4", "numba"): "spurdyn.solvers.paper.stepper_compiled:CompiledStepper",
    ("rk4", "numpy"): "spurdyn.solvers.paper.stepper_numpy:NumpyStepper",
    ("implicit", "numba"): "spurdyn.solvers.implicit.stepper:CompiledImplicitStepper",
    ("implicit", "numpy"): "spurdyn.solvers.implicit.stepper:ImplicitStepper",
}


def make_stepper(system: PairSystem, settings: RunSettings) -> Stepper:
    """The stepper of ``settings.integrator`` on ``settings.backend``."""
    module, name = STEPPERS[(settings.integrator, settings.backend)].split(":")
    return getattr(importlib.import_module(module), name)(system, settings)


def simulate(pair: GearPair, settings: RunSettings, progress: Progress | None = None,
             chunk: int = 500) -> Result:
    """Simulate one tooth engagement of ``pair`` with the run settings ``settings``.

    Parameters
    ----------
    pair
        The gear pair (gear A drives).
    settings
        Run settings.
    progress
        Called as ``progress(step, angle_reached, angle_total)`` (rad) after each chunk.
    chunk
        Steps between calls of ``progress`` (and checks for Ctrl-C).

    Returns
    -------
    Result
        ``status`` is ``"incomplete"`` (with ``reason``) if the run stopped early.

    What the FE model cannot run (damping with RK4, mesh cycles) is refused by its registry
    entry (:data:`spurdyn.simulators.MODELS`), through which runs come.
    """
    if pair.driver == "b":
        return _simulate_driven_by_b(pair, settings, progress, chunk)
    wall0 = time.perf_counter()
    system = build_system(pair, settings)
    plan = check_run(pair, settings, system)
    angle = plan.angle
    stepper = make_stepper(system, settings)
    rows = np.empty(((plan.steps + 2) // settings.save_every + 8, NCOL))
    rows[0] = stepper.row()
    n_rows = 1
    frames: Frames = []
    if settings.frames_every:
        frames.append((stepper.t, stepper.theta.copy(), stepper.u.copy()))
    steps, status, reason = 0, "complete", ""
    loop0 = time.perf_counter()
    try:
        while stepper.theta_a < angle:
            if n_rows + chunk // settings.save_every + 2 > rows.shape[0]:
                rows = np.concatenate([rows, np.empty_like(rows)])
            done, written, stop = stepper.advance(chunk, angle, settings.save_every, rows[n_rows:],
                                                  settings.frames_every, frames)
            steps += done
            n_rows += written
            if progress is not None:
                progress(steps, stepper.theta_a, angle)
            if stop:
                status, reason = "incomplete", stop
                failed = stepper.failure.status if stepper.failure is not None else OK
                if (failed in (FAIL_DISP, FAIL_VEL, FAIL_ACC, FAIL_NEWTON) and settings.method == "paper"
                        and settings.contact == "point"):
                    reason += ("; the distributed contact (--contact hertz) may carry it "
                               "through (docs/solver.md, sections 6 and 11)")
                break
    except KeyboardInterrupt:
        status, reason = "incomplete", f"interrupted by the user at step {steps}"
    loop = time.perf_counter() - loop0
    return _to_result(pair, settings, system, rows[:n_rows], frames, status, reason, steps,
                      time.perf_counter() - wall0, loop)


def _simulate_driven_by_b(pair: GearPair, settings: RunSettings, progress: Progress | None,
                          chunk: int) -> Result:
    """Gear B drives: simulate the mirror image, in which B is the first gear and drives.

    With A turning clockwise and B counter-clockwise, a driving B pushes on the other
    flanks. Mirrored about the line between the centres, the pair is a pair whose first
    gear (B) drives clockwise on its right flank, which is what the solver models; every
    rotation, speed and torque keeps its sense relative to its own gear, so the results
    map back by swapping the gears' columns. Tooth frames are not mapped back (none kept).
    """
    inner_pair = solver_pair(pair)
    ratio = pair.gear_a.base_radius / pair.gear_b.base_radius   # theta_B / theta_A
    inner_settings = settings.with_(speed_a=settings.speed_b, speed_b=settings.speed_a,
                                    frames_every=0,
                                    angle=None if settings.angle is None
                                    else settings.angle * ratio)
    r = simulate(inner_pair, inner_settings, None if progress is None else
                 (lambda k, a, tot: progress(k, a / ratio, tot / ratio)), chunk)
    swap = (lambda a: a[:, ::-1].copy())
    corner = r.corner.copy()
    corner[r.corner == 1], corner[r.corner == 2] = 2, 1
    info = dict(r.info)
    info.update(theta_s=pair.theta_s, theta_2=pair.theta_2,
                single_zone=(pair.theta_2, pair.theta_s - pair.theta_2), driver="b",
                frames="not kept when gear B drives")
    theta = swap(r.theta)
    return Result(time=r.time, angle=theta[:, 0].copy(), contact_force=r.contact_force, gap=r.gap,
                  roll=swap(r.roll), theta=theta, omega=swap(r.omega), torque=swap(r.torque),
                  residual=r.residual, iterations=r.iterations, corner=corner,
                  frame_time=np.zeros(0), frame_theta=np.zeros((0, 2)),
                  frame_u=np.zeros((0, r.frame_u.shape[1])), status=r.status, reason=r.reason,
                  steps=r.steps, wall_s=r.wall_s, info=info,
                  # Hertz's strip is the same seen from either gear
                  contact_half_width=r.contact_half_width, contact_pressure_max=r.contact_pressure_max)


def _roll(system: PairSystem, g: int, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Roll angle (rad) of the involute point at flank coordinate ``t`` of gear ``g``'s
    flank in the (one) contact pair."""
    f = system.flanks(system.contacts[0])[g]
    r = f.r0 + (f.r_tip - f.r0) * np.asarray(t, dtype=float) / f.ny
    return np.sqrt(np.maximum(r * r - f.base_radius**2, 0.0)) / f.base_radius


def _to_result(pair: GearPair, settings: RunSettings, system: PairSystem, rows: NDArray[np.float64],
               frames: Frames, status: str, reason: str, steps: int, wall: float,
               loop: float) -> Result:
    col = {name: rows[:, i] for i, name in enumerate(HISTORY)}
    n_u = system.n_u
    if frames:
        ft = np.array([f[0] for f in frames])
        fth = np.array([f[1] for f in frames])
        fu = np.array([f[2] for f in frames])
    else:
        ft, fth, fu = np.zeros(0), np.zeros((0, 2)), np.zeros((0, n_u))
    single = pair.single_contact_roll_a
    roll = np.column_stack([_roll(system, 0, col["alpha"]), _roll(system, 1, col["beta"])])
    half, pressure = _hertz(system, -col["p"], roll)
    # the implicit integrator's one stage, its Newton iteration (its history's first columns)
    stages = 1 if settings.integrator == "implicit" else len(STAGES)
    return Result(
        time=col["t"].copy(),
        angle=col["theta_a"].copy(),
        contact_force=-col["p"],
        gap=-col["s"],
        roll=roll,
        theta=np.column_stack([col["theta_a"], col["theta_b"]]),
        omega=np.column_stack([col["omega_a"], col["omega_b"]]),
        torque=np.column_stack([col["tau_a"], col["tau_b"]]),
        residual=np.column_stack([col[f"res{j + 1}"] for j in range(stages)]),
        iterations=np.column_stack([col[f"it{j + 1}"] for j in range(stages)]).astype(np.int64),
        corner=col["mode"].astype(np.int8),
        frame_time=ft, frame_theta=fth, frame_u=fu,
        status=status, reason=reason, steps=steps, wall_s=wall,
        info={
            "model": "fe",
            "n_dof": system.n_dof,
            "n_x": system.n_x,
            "nodes": [g.mesh.n_nodes for g in system.gears],
            "theta_s": pair.theta_s,
            "theta_2": pair.theta_2,
            "static_force": static_force(pair, settings.torque),
            "single_zone": (single[0] - pair.start_roll_a, single[1] - pair.start_roll_a),
            "theta0": system.theta0,
            "method": settings.method,
            "backend": settings.backend,
            "contact": settings.contact,
            "loop_s": loop,       # wall time of the time loop alone (the rest: build, check)
        },
        contact_half_width=half, contact_pressure_max=pressure,
    )


def _hertz(system: PairSystem, force: NDArray[np.float64], roll: NDArray[np.float64]
           ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Hertz's half-width and peak pressure for the contact force at the contact point's
    radii of curvature ``r_b * roll`` (the strip the distributed contact spreads it over;
    for the point contact, the analytic strip of the same force)."""
    estar, face = strip_law(system)
    rho = roll * np.array([g.base_radius for g in system.gears])
    half = half_width(np.maximum(force, 0.0), rho[:, 0], rho[:, 1], estar, face)
    return half, peak_pressure(np.maximum(force, 0.0), half, face)
