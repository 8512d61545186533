"""Where the run settings stop meaning anything, and how big a run may get unasked.

Two kinds of checks, both naming the key the user wrote:

- :func:`check_run_bounds` and :func:`check_sampling`, for every run (the run check,
  :func:`spurdyn.solvers.check.check_run`, calls them): settings measured against the pair (the
  displacement tolerance against the module and the rounding of positions, the time
  step against the engagement, the speeds against the bursting speed, the saving
  interval against the run, the torque against the teeth's elastic range);
- :func:`check_size`, for ``spurdyn run`` and ``spurdyn sweep``: a run of more than
  :data:`MAX_STEPS` steps or :data:`MAX_BYTES` of results is refused unless asked for
  (``--allow-large``), with the estimate in the message.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from spurdyn.errors import InputError
from spurdyn.fem.material import bursting_speed
from spurdyn.settings import PAPER_DT, RPM


def steps_for(angle: float, speed: float, dt: float) -> int:
    """Time steps for gear A to turn ``angle`` (rad) at ``speed`` (rad/s) with step ``dt``."""
    return int(math.ceil(angle / (speed * dt)))

#: Fewest steps over the angle of action: fewer cannot follow the contact (the contact
#: point crosses each of the ~14 elements along a flank in a few steps).
MIN_STEPS_PER_ENGAGEMENT = 100
#: Fewest saved steps after the start: a peak needs a sample on either side of it (with
#: fewer, ``save_every`` keeps little more than the start and the summary says nothing).
MIN_SAMPLES = 3
#: Largest ``tol_disp`` as a fraction of the module: a micrometre-deflecting tooth pair
#: whose gap may be off by more passes through itself unnoticed.
TOL_MAX_PER_MODULE = 1e-6
#: Smallest ``tol_disp`` in units of the rounding of positions (machine epsilon times the
#: centre distance): below it no iteration can meet the tolerance.
TOL_MIN_ROUNDINGS = 100.0
#: Largest quasi-static strain ``F / (E b m)`` of a tooth: the linear elastic model ends
#: long before (steels yield near 0.2 %); this only refuses torques without meaning.
MAX_STRAIN = 0.01

#: Steps a run may take unasked (a full engagement of the paper's pair at ~60 rpm, about
#: ten minutes of the compiled solver on one core).
MAX_STEPS = 2_000_000
#: Steps per second of the compiled solver on the default mesh, for the time estimate of
#: a refusal (measured: paper-fig8, 29,251 steps in 6.4 s on one shared core).
STEPS_PER_S = 4000
#: Seconds of work a run may take unasked: what :data:`MAX_STEPS` take at the FE model's
#: :data:`STEPS_PER_S` (500 s), the bound of a model whose step costs more than the step
#: count says (the sector model's whole bodies: :attr:`Size.most_steps`).
MAX_SECONDS = MAX_STEPS / STEPS_PER_S
#: Bytes of results a run may hold unasked (in memory and in ``result.nc``).
MAX_BYTES = 1 << 30
#: Bytes per saved step: the solver's history row (18 numbers) and the dataset's
#: variables (21 numbers), 8 bytes each.
BYTES_PER_SAMPLE = (18 + 21) * 8


def engagement_steps(case: Any) -> int:
    """Steps a case takes over the angle it simulates (its angle or ``theta_s``)."""
    return engagement_steps_of(case.pair, case.run)


def check_run_bounds(pair: Any, run: Any, field: Callable[[str], str]) -> None:
    """Refuse run settings beyond their meaning for ``pair``.

    ``field("dt")`` gives the name to use for the ``[run]`` key ``dt`` (the option when
    it was given on the command line).
    """
    for key, speed, gear in (("speed_a_rpm", run.speed_a, pair.gear_a),
                             ("speed_b_rpm", run.speed_b, pair.gear_b)):
        limit = bursting_speed(gear.material, gear.tip_radius)
        if speed > limit:   # a unit slip, not a gear (docs/casefile.md): said first
            raise InputError(field(key), f"{speed / RPM:g} rpm is above the bursting speed "
                             f"{limit / RPM:.3g} rpm of gear {key[6].upper()}; speeds are in rpm, "
                             "not rad/s or rad/min")
    driver = pair.gear_a if pair.driver == "a" else pair.gear_b
    per_step = run.speed_a * run.dt
    if pair.theta_s / per_step < MIN_STEPS_PER_ENGAGEMENT:
        # Blame the time step when the paper's would give enough steps at this speed.
        dt_blamed = pair.theta_s / (run.speed_a * PAPER_DT) >= MIN_STEPS_PER_ENGAGEMENT
        raise InputError(field("dt" if dt_blamed else "speed_a_rpm"),
                         f"{run.speed_a / RPM:.4g} rpm with dt = {run.dt:g} s turns "
                         f"gear A {math.degrees(per_step):.3g} deg per step, fewer than "
                         f"{MIN_STEPS_PER_ENGAGEMENT} steps over the angle of action "
                         f"({math.degrees(pair.theta_s):.3f} deg); give a "
                         f"{'smaller dt' if dt_blamed else 'lower speed'}")
    tol_max = TOL_MAX_PER_MODULE * driver.module
    tol_min = TOL_MIN_ROUNDINGS * sys.float_info.epsilon * pair.centre_distance
    if not tol_min <= run.tol_disp <= tol_max:
        raise InputError(field("tol_disp"), f"must lie between {tol_min:.2g} m (rounding of "
                         f"positions) and {tol_max:.2g} m (a millionth of the module) "
                         f"(got {run.tol_disp:g}); the paper uses 1e-12")
    check_torque(pair, run.torque, field("torque"))
    if run.torque_history is not None:
        check_history_torques(pair, run.torque_history, field("torque_history"))


def check_torque(pair: Any, torque: float, field: str, driven: bool = False,
                 what: str = "") -> None:
    """Refuse a torque (N m) whose quasi-static tooth force ``|T| / r_b`` strains the tooth
    of the gear it acts on by more than :data:`MAX_STRAIN` (``F / (E b m)``): the driver's,
    or with ``driven`` the driven gear's (a load torque). ``what`` says where the torque was
    found (a torque history's sample), before the figures."""
    gear = pair.gear_a if (pair.driver == "a") != driven else pair.gear_b
    force = abs(torque) / gear.base_radius
    strain = force / (gear.material.young * gear.face_width * gear.module)
    if strain > MAX_STRAIN:
        top = MAX_STRAIN * gear.material.young * gear.face_width * gear.module * gear.base_radius
        raise InputError(field, f"{what}{torque:g} N m strains the {'driven' if driven else 'driver'}"
                         f"'s tooth by about {strain:.2g}, beyond any elastic tooth; at most "
                         f"{top:.4g} N m")


def check_history_torques(pair: Any, history: Any, field: str) -> None:
    """:func:`check_torque` on the largest driver's and load torque of a torque history
    (:class:`~spurdyn.settings.TorqueHistory`), naming the sample's time."""
    for column, driven in (("driver", False), ("load", True)):
        values = getattr(history, column)
        if values is None:
            continue
        i = max(range(len(values)), key=lambda j: abs(values[j]))
        check_torque(pair, values[i], field, driven,
                     f"its {column} torque at {history.time[i]:g} s, ")


def check_sampling(pair: Any, run: Any, field: Callable[[str], str]) -> None:
    """Refuse a saving interval that keeps fewer than :data:`MIN_SAMPLES` samples of the
    run (or fewer than its steps, for a run shorter than that).

    A frame interval longer than the run is left alone: it keeps the start frame, and
    a case file's interval is often meant for the whole engagement, not a short --angle.
    """
    steps = engagement_steps_of(pair, run)
    if steps // run.save_every < min(MIN_SAMPLES, steps):
        raise InputError(field("save_every"), f"{run.save_every:,} keeps fewer than "
                         f"{min(MIN_SAMPLES, steps)} samples of this {steps:,}-step run; at "
                         f"most {max(1, steps // MIN_SAMPLES):,}")


def engagement_steps_of(pair: Any, run: Any) -> int:
    """:func:`engagement_steps` from a pair and its run settings."""
    return steps_for(pair.theta_s if run.angle is None else run.angle, run.speed_a, run.dt)


@dataclass(frozen=True)
class Size:
    """What a run will cost: its steps and the bytes of results it keeps.

    Attributes
    ----------
    steps
        Time steps of the run.
    bytes
        Bytes of results it keeps (the history, and the tooth frames).
    frame_bytes
        The part of ``bytes`` that the tooth frames take.
    steps_capped
        Whether the steps themselves are limited (:data:`MAX_STEPS`): the FE model's cost is
        per step; the others' steps are cheap.
    sampling
        The ``[run]`` key that sets how many samples are kept (blamed for too many bytes).
    blame
        The ``[run]`` key blamed for too many steps; ``None``: the time step, where the
        paper's would keep the run within the limit, else the speed (the FE model's rule).
    steps_per_s
        The model's steps a second, for the time a refusal estimates.
    remedy
        What would shorten the run, for the refusal.
    most_steps
        The steps a run may take unasked: :data:`MAX_STEPS`, or fewer where a step costs
        more than the model's usual (:data:`MAX_SECONDS` at ``steps_per_s``).
    """

    steps: int
    bytes: int
    frame_bytes: int = 0
    steps_capped: bool = False
    sampling: str = "save_every"
    blame: str | None = None
    steps_per_s: float = STEPS_PER_S
    remedy: str = "raise the speed, shorten --angle"
    most_steps: int = MAX_STEPS


def estimate(case: Any, frames: bool = True, steps_capped: bool = True) -> Size:
    """The :class:`Size` of a case stepped by its ``dt`` over the angle it simulates: its
    history samples, and with ``frames`` its tooth frames."""
    steps = engagement_steps(case)
    size = (steps // case.run.save_every + 1) * BYTES_PER_SAMPLE
    frame_bytes = 0
    if frames and case.run.frames_every:
        from spurdyn.mesh.tooth import tooth_mesh

        n_u = sum(tooth_mesh(g, case.run.nx, case.run.ny).n_dof
                  for g in (case.pair.gear_a, case.pair.gear_b))
        frame_bytes = (steps // case.run.frames_every + 1) * n_u * 8
    return Size(steps, size + frame_bytes, frame_bytes, steps_capped)


def _label(labels: Mapping[str, str], key: str) -> str:
    return labels.get(f"run.{key}", f"run.{key}")


def check_size(case: Any, labels: Mapping[str, str], size: Size, *,
               flag: str = "--allow-large", speed_field: str | None = None) -> None:
    """Refuse a run beyond :data:`MAX_STEPS` or :data:`MAX_BYTES` (``flag`` allows it), of
    the ``size`` its model estimates (:meth:`spurdyn.simulators.ModelEntry.size`).

    The refusal names the time step when the paper's would keep the run within the limit,
    else the speed (``speed_field`` if given); for the size, the tooth frames or the saving
    interval (the speed instead, when ``speed_field`` is given and the interval is not an
    option the user gave).
    """
    steps = size.steps
    if size.steps_capped and steps > size.most_steps:
        if size.blame is None:  # the time step, when the paper's would keep the run within the limit
            blame = "dt" if steps * case.run.dt / PAPER_DT <= MAX_STEPS else "speed_a_rpm"
        else:
            blame = size.blame
        key = speed_field or _label(labels, blame) if blame == "speed_a_rpm" else _label(labels, blame)
        raise InputError(key, f"{case.name} would take {steps:,} steps (limit {size.most_steps:,}; "
                         f"about {steps / size.steps_per_s / 60:,.0f} min at {size.steps_per_s:,.0f} "
                         f"steps/s); {size.remedy}, or give {flag} to run it anyway")
    if size.bytes > MAX_BYTES:
        frames = size.frame_bytes > size.bytes / 2
        what = "frames_every" if frames else size.sampling
        # The saving interval, unless the speed was what the user wrote for it (a sweep).
        key = _label(labels, what) if frames or f"run.{what}" in labels or not speed_field \
            else speed_field
        raise InputError(key, f"{case.name} would keep about {size.bytes / 2**30:,.1f} GiB of results "
                         f"(limit {MAX_BYTES / 2**30:g} GiB); keep fewer "
                         f"{'tooth frames' if frames else 'steps'} or give {flag} to run it anyway")


__all__ = ["MAX_BYTES", "MAX_SECONDS", "MAX_STEPS", "Size", "check_history_torques", "check_run_bounds", "check_sampling",
           "check_size", "check_torque", "engagement_steps", "estimate"]
