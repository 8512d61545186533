"""The one run check: stable time step, the default time step, angle of the run, step count.

Both the case file (refusing bad settings before anything is written, naming the key the
user wrote) and :func:`spurdyn.solvers.loop.simulate` call :func:`check_run` on the same
system (:func:`spurdyn.model.system.build_system` keeps the last ones it built), and the
stable step is eigen-solved once per system (:func:`stable_step` caches it on the system).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY
from spurdyn.model.alpha import accuracy_step
from spurdyn.model.system import PairSystem, system_for
from spurdyn.settings import DEFAULT_MODEL, RunSettings, settings_read_by
from spurdyn.solvers.limits import check_run_bounds, check_sampling, steps_for

#: How far beyond the angle of action ``theta_s`` (as a fraction of it) a run may go:
#: beyond it the tip of A has left B's flank for good and the modelled teeth no longer
#: describe the meshing (the next pair, not modelled, carries the load).
ANGLE_MARGIN = 0.02


@dataclass(frozen=True)
class RunPlan:
    """What a checked run will do: gear A's rotation (rad), the steps it takes, and the
    largest stable RK4 step of the mesh (s)."""

    angle: float
    steps: int
    stable_dt: float


def stable_step(system: PairSystem) -> float:
    """Largest stable RK4 step of either free tooth (s), eigen-solved once per system."""
    cached = system.__dict__.get("_stable_dt")
    if cached is None:
        from spurdyn.fem.stable_step import stable_time_step

        cached = min(stable_time_step(g.stiffness, g.mass).dt_rk4 for g in system.gears)
        object.__setattr__(system, "_stable_dt", cached)
    return cached


#: Fraction of the stable RK4 step of the mesh (the smaller of the two free teeth's) a
#: case run without a time step uses, rounded down to two significant digits: room for
#: the contact constraints, which stiffen the pair a little (docs/casefile.md, [run]).
DT_FRACTION = 0.8


def round_down(x: float, digits: int) -> float:
    """``x > 0`` rounded down to ``digits`` significant digits."""
    exponent = math.floor(math.log10(x)) - digits + 1
    if exponent < 0:  # divide by a power of ten held exactly: 15 / 1e9, not 15 * 1e-9
        scale = 10.0 ** -exponent
        return math.floor(x * scale) / scale
    scale = 10.0 ** exponent
    return math.floor(x / scale) * scale


def default_dt(stable_dt: float) -> float:
    """The time step (s) of a case that gives none: :data:`DT_FRACTION` of ``stable_dt``."""
    return round_down(DT_FRACTION * stable_dt, 2)


def default_step(settings: RunSettings, pair: GearPair, system: PairSystem | None = None) -> float:
    """The time step (s) of a one-engagement run that gives none (the FE model's, and the
    lumped model's samples): for the implicit integrator a step of accuracy
    (:func:`~spurdyn.model.alpha.accuracy_step`, two digits), else
    :func:`default_dt` of the stable step of the run's tooth meshes (``system`` if built)."""
    if settings.integrator == "implicit":   # a step of accuracy, not stability
        return round_down(accuracy_step(settings.speed_a, pair.gear_a.teeth), 2)
    if system is None:
        system = system_for(pair, settings.nx, settings.ny, settings.n_spline, settings.grading,
                            settings.row_grading)
    return default_dt(stable_step(system))


def run_settings(pair: GearPair, speed_a: float, torque: float, *,
                 speed_b: float | None = None, dt: float | None = None,
                 model: str = DEFAULT_MODEL, **kwargs: Any) -> RunSettings:
    """:class:`~spurdyn.settings.RunSettings` with the command line's defaults (SI units:
    rad/s, N m, s).

    ``speed_b`` defaults to the speed that meshes, ``speed_a z_a / z_b``; ``dt`` to
    :func:`default_dt` of the stable step of the ``nx`` x ``ny`` tooth meshes (built here,
    a fraction of a second, and kept for the run) when ``model`` reads a ``dt``
    (:func:`~spurdyn.settings.settings_read_by`; the sector model steps by its own rule and
    gets none). ``kwargs`` are the other fields of :class:`~spurdyn.settings.RunSettings`.
    """
    if speed_b is None:
        speed_b = speed_a * pair.gear_a.teeth / pair.gear_b.teeth
    if dt is None and "dt" in settings_read_by(model):
        system = system_for(pair, kwargs.get("nx", DEFAULT_NX), kwargs.get("ny", DEFAULT_NY),
                            kwargs.get("n_spline", RunSettings.n_spline),
                            kwargs.get("grading", RunSettings.grading),
                            kwargs.get("row_grading", RunSettings.row_grading))
        dt = default_dt(stable_step(system))
    if dt is not None:
        kwargs["dt"] = dt
    return RunSettings(speed_a=speed_a, speed_b=speed_b, torque=torque, **kwargs)


def check_run(pair: GearPair, settings: RunSettings, system: PairSystem,
              field: Callable[[str], str] = str) -> RunPlan:
    """Refuse settings the model cannot run; return what the run will do.

    Parameters
    ----------
    pair, settings, system
        The pair, the run settings and the system built from them.
    field
        Maps a ``[run]`` key (``"dt"``, ``"angle_deg"``, ...) to the key the user wrote
        (``"run.dt"``, ``"--dt"``), for the message.

    Raises
    ------
    InputError
        A setting beyond its meaning for the pair
        (:func:`~spurdyn.solvers.limits.check_run_bounds`), a ``dt`` above the stable RK4
        step of the mesh, an angle beyond ``theta_s`` plus :data:`ANGLE_MARGIN` or shorter
        than one step, a saving interval that keeps too few samples
        (:func:`~spurdyn.solvers.limits.check_sampling`).
    """
    s = settings
    check_run_bounds(pair, s, field)
    limit = stable_step(system)
    # the implicit integrator is stable at any step: its step is one of accuracy
    if s.dt > limit and s.integrator == "rk4":
        raise InputError(field("dt"), f"dt {s.dt:g} s is above the stable RK4 step {limit:.4g} s "
                         f"of the {s.nx}x{s.ny} tooth mesh"
                         + (f" graded {s.grading:g}" if s.grading != 1.0 else "")
                         + (f" with rows graded {s.row_grading:g}" if s.row_grading != 1.0 else "")
                         + f"; use a dt of at most {round_down(limit, 3):g} s or a coarser mesh"
                         + (" or less grading" if s.grading != 1.0 or s.row_grading != 1.0 else ""))
    theta_s = pair.theta_s
    angle = theta_s if s.angle is None else s.angle
    if angle > theta_s * (1.0 + ANGLE_MARGIN):
        raise InputError(field("angle_deg"), f"{math.degrees(angle):g} deg goes beyond the angle of "
                         f"action theta_s = {math.degrees(theta_s):.3f} deg (+{ANGLE_MARGIN:.0%}): "
                         "the teeth would leave the modelled region")
    if angle < s.speed_a * s.dt:
        raise InputError(field("angle_deg"), f"{math.degrees(angle):g} deg is shorter than one time "
                         f"step ({math.degrees(s.speed_a * s.dt):.3g} deg at this speed)")
    check_sampling(pair, s, field)
    return RunPlan(angle=angle, steps=steps_for(angle, s.speed_a, s.dt), stable_dt=limit)
