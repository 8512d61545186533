"""The external torques on the two disks: the paper's Fig. 7 schedule, and the hubs'
torques of a run of mesh cycles (constant, a torque history, a ramp from rest: :func:`hub_torques`).

The model carries one tooth per gear, but real pairs share the load between two tooth
pairs over the double-contact zones. Lee & Jang account for this by ramping the
external torques: on each gear the torque rises linearly from 0 to its full value over
the first ``theta_2`` of that gear's rotation after the start of contact, holds, and
falls linearly back to 0 over the last ``theta_2`` before the end of contact at
``theta_s`` (the rest is carried by the teeth that are not modelled).

Each gear uses its own angles: ``theta_s^g = path / r_b^g`` and
``theta_2^g = theta_s^g - 2 pi / z_g``. The two double-contact zones have the same
length ``path - p_b`` on the line of action, so under rigid kinematics the ramps of the
two gears coincide in time.

Signs follow each gear's own sense of rotation (A clockwise, B counter-clockwise): the
driver's torque is positive (along its rotation), the driven gear's load torque is
negative (against its rotation). The driven torque is scaled by the base radii,
``tau_0 r_b,driven / r_b,driver``, so that the two torques balance through the same
static tooth force ``tau_0 / r_b,driver``.

All functions are pure and vectorised over the angles; SI units (rad, N m).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.settings import DEFAULT_RAMP_CYCLES, RPM, RunSettings, TorqueHistory


def torque_schedule(phi: ArrayLike, theta_s: float, theta_2: float) -> NDArray[np.float64]:
    """Fraction of the full torque at a gear rotation ``phi`` since the start of contact.

    The trapezoid of the paper's Fig. 7::

        f(phi) = clip(min(phi, theta_s - phi) / theta_2, 0, 1)

    that is 0 before the start (``phi <= 0``), a linear rise to 1 at ``phi = theta_2``,
    1 over the single-contact zone, a linear fall to 0 at ``phi = theta_s`` and 0 after.
    If ``theta_2 > theta_s / 2`` (contact ratio above 2) the plateau vanishes and the
    trapezoid becomes a triangle of height ``theta_s / (2 theta_2)``.

    Parameters
    ----------
    phi
        Rotation of the gear since the start of contact (rad), along its own sense.
    theta_s
        Angle of action of that gear (rad).
    theta_2
        Double-contact angle of that gear (rad), ``> 0``.

    Returns
    -------
    numpy.ndarray
        The fraction, in ``[0, 1]``, with the shape of ``phi`` (0-d for a scalar).
    """
    if not theta_s > 0.0 or not theta_2 > 0.0:
        raise ValueError(f"theta_s and theta_2 must be positive (got {theta_s!r}, {theta_2!r})")
    phi = np.asarray(phi, dtype=float)
    return np.clip(np.minimum(phi, theta_s - phi) / theta_2, 0.0, 1.0)


def torque_fraction(phi: float, theta_s: float, theta_2: float) -> float:
    """Scalar :func:`torque_schedule` in plain Python (for ODE right-hand sides)."""
    return min(1.0, max(0.0, min(phi, theta_s - phi) / theta_2))


def gear_angles(pair: GearPair) -> tuple[tuple[float, float], tuple[float, float]]:
    """Angle of action and double-contact angle of each gear.

    Returns
    -------
    ((theta_s_a, theta_2_a), (theta_s_b, theta_2_b))
        ``theta_s^g = path / r_b^g``, ``theta_2^g = theta_s^g - 2 pi / z_g`` (rad).
    """
    path = pair.path_of_contact
    out = []
    for gear in (pair.gear_a, pair.gear_b):
        ts = path / gear.base_radius
        out.append((ts, ts - 2.0 * math.pi / gear.teeth))
    return out[0], out[1]


def torque_amplitudes(pair: GearPair, tau0: float) -> tuple[float, float]:
    """Signed full torques ``(T_a, T_b)`` along each gear's sense of rotation (N m).

    ``tau0`` acts on the driver (positive, along its rotation); the driven gear carries
    ``-tau0 r_b,driven / r_b,driver`` (against its rotation).
    """
    ra, rb = pair.gear_a.base_radius, pair.gear_b.base_radius
    if pair.driver == "a":
        return tau0, -tau0 * rb / ra
    return -tau0 * ra / rb, tau0


def gear_torques(
    pair: GearPair, tau0: float, phi_a: ArrayLike, phi_b: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """External torques on disks A and B at their rotations since the start of contact.

    Parameters
    ----------
    pair
        The gear pair; ``pair.driver`` says which gear ``tau0`` drives.
    tau0
        Full external torque on the driver (N m), ``>= 0``.
    phi_a, phi_b
        Rotations of A and B since the start of contact (rad), each along its own sense
        (A clockwise, B counter-clockwise). Broadcast against each other.

    Returns
    -------
    tau_a, tau_b
        Torques (N m) along each gear's sense of rotation. For ``driver == "a"``:
        ``tau_a = +tau0 f_A(phi_a)``, ``tau_b = -tau0 (r_bB / r_bA) f_B(phi_b)``; for
        ``driver == "b"`` the roles swap. ``f_g`` is :func:`torque_schedule` with the
        gear's own ``theta_s`` and ``theta_2`` (:func:`gear_angles`).
    """
    (tsa, t2a), (tsb, t2b) = gear_angles(pair)
    amp_a, amp_b = torque_amplitudes(pair, tau0)
    fa = torque_schedule(phi_a, tsa, t2a)
    fb = torque_schedule(phi_b, tsb, t2b)
    fa, fb = np.broadcast_arrays(fa, fb)
    return amp_a * fa, amp_b * fb


def static_force(pair: GearPair, torque: float) -> float:
    """Quasi-static tooth force (N) of the driver's torque ``tau_0``: ``tau_0 / r_b`` of the
    driving gear, the one home of this figure."""
    driver = pair.gear_a if pair.driver == "a" else pair.gear_b
    return torque / driver.base_radius


def history_at(history: TorqueHistory, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """The driver's and the load torque of a :class:`~spurdyn.settings.TorqueHistory` at the
    run's times ``t`` (s; the history's first time is the run's 0): linear between samples,
    repeated with its period past its end if it is periodic, else held at its last value
    (a run the history does not cover is refused before it starts). ``None`` for a history
    without a load column."""
    time = np.asarray(history.time) - history.time[0]
    t = np.asarray(t, dtype=float)
    if history.periodic:
        t = np.mod(t, history.duration)
    driver = np.interp(t, time, np.asarray(history.driver))
    load = None if history.load is None else np.interp(t, time, np.asarray(history.load))
    return driver, load


def hub_torques(pair: GearPair, settings: RunSettings, t: ArrayLike) -> NDArray[np.float64]:
    """The signed torques ``(T_a, T_b)`` on the hubs of a run of mesh cycles at its times
    ``t`` (s), along each gear's sense of rotation, shape ``t.shape + (2,)``: the constant
    ones of :func:`torque_amplitudes`, or the run's torque history (its load column, or the
    nominal load), times the ramp of a run from rest (linear from 0 at ``t = 0`` to 1 after
    ``ramp_cycles`` mesh cycles at the driver's nominal speed; not where it starts from another
    run's end, a continuation's ``start_state``)."""
    t = np.asarray(t, dtype=float)
    amp_a, amp_b = torque_amplitudes(pair, settings.torque)
    out = np.empty(t.shape + (2,))
    out[..., 0], out[..., 1] = amp_a, amp_b
    history = settings.torque_history
    if history is not None:
        driver, load = history_at(history, t)
        drv, drn = (0, 1) if pair.driver == "a" else (1, 0)
        out[..., drv] = driver
        if load is not None:
            out[..., drn] = -load
    if settings.start == "rest" and settings.start_state is None:     # not a continuation's
        gear = pair.gear_a if pair.driver == "a" else pair.gear_b
        speed = settings.speed_a if pair.driver == "a" else settings.speed_b
        cycles = settings.ramp_cycles or DEFAULT_RAMP_CYCLES
        t_ramp = cycles * 2.0 * math.pi / (gear.teeth * speed)
        out *= np.clip(t / t_ramp, 0.0, 1.0)[..., None]
    return out


def check_history(pair: GearPair, settings: RunSettings) -> None:
    """Refuse a torque history that is not periodic and ends before the run does (its
    ``cycles`` mesh cycles at the driver's nominal speed).

    Raises
    ------
    InputError
        ``torque_history``, with the two durations and the ways out.
    """
    history = settings.torque_history
    if history is None or history.periodic:
        return
    gear = pair.gear_a if pair.driver == "a" else pair.gear_b
    speed = settings.speed_a if pair.driver == "a" else settings.speed_b
    cycles = settings.cycles_limit or settings.cycles or 1
    lasts = cycles * 2.0 * math.pi / (gear.teeth * speed)
    if history.duration < lasts * (1.0 - 1e-9):
        raise InputError("torque_history", f"covers {history.duration:.4g} s and the run lasts "
                         f"{lasts:.4g} s ({cycles} mesh cycles at {speed / RPM:,.0f} rpm): give a "
                         "longer history, fewer cycles, or periodic = true to repeat it")
