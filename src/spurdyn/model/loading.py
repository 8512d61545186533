"""The external torques on the two disks: the paper's Fig. 7 schedule.

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

from spurdyn.geometry.pair import GearPair


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
