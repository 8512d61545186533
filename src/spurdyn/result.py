"""The outcome of a run as a plain object: time histories, frames and a status."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: Names of the three stages of a step, in order.
STAGES = ("displacement", "velocity", "acceleration")


@dataclass(frozen=True)
class ToothStress:
    """The root stress of every tooth of both gears of a model of whole teeth on their rims,
    at sampled times (SI units).

    Attributes
    ----------
    time
        ``(S,)`` the sampled times (s).
    teeth
        The tooth numbers of the driver's and the driven gear's bodies, ``(K_0,)`` and
        ``(K_1,)`` (the model's own numbering).
    values
        Per gear (as ``teeth``) ``(4, S, K)``: the largest stress along both fillets of the
        tooth (tension positive), the distance of its point from the gear centre, the
        smallest (compression negative) and its distance.
    per_cycle
        Samples a mesh cycle.
    """

    time: NDArray[np.float64]
    teeth: tuple[NDArray[np.intp], NDArray[np.intp]]
    values: tuple[NDArray[np.float64], NDArray[np.float64]]
    per_cycle: int


@dataclass
class Result:
    """Time history of a simulated engagement (SI units; angles in rad unless named _deg).

    Every per-step array has the length of ``time`` (the saved steps, the initial state
    first). Gear quantities are stacked as ``(n, 2)``: column 0 is gear A, column 1 gear B.

    Attributes
    ----------
    time
        Time since the start of contact (s).
    angle
        Rotation of gear A since the start of contact (rad).
    contact_force
        Contact force (N), compression positive, 0 when the teeth are apart.
    gap
        Normal gap between the contact points (m): positive apart, negative penetration.
    roll
        Roll angles (rad) of the contact point on each tooth's involute ``(n, 2)``.
    theta, omega
        Rotation since the start (rad) and angular speed (rad/s) of each disk ``(n, 2)``,
        each along its own sense of rotation.
    torque
        External torques on the disks (N m) ``(n, 2)``, along each disk's sense.
    frame_time, frame_theta, frame_u
        Tooth frames: times ``(k,)``, rotations ``(k, 2)`` and absolute nodal
        displacements of both teeth ``(k, n_u)`` (A's DOFs first).
    status
        ``"complete"`` or ``"incomplete"``.
    reason
        Why an incomplete run stopped.
    steps
        Time steps taken.
    wall_s
        Wall-clock time of the run (s).
    info
        Anything else worth keeping (case description, model sizes, ...).
    contact_half_width, contact_pressure_max
        Half-width (m) and peak pressure (Pa) of Hertz's strip for the contact force at
        the contact point's radii of curvature (:mod:`spurdyn.contact.hertz`); ``None``
        for a model without a contact point.
    pair_force, pair_roll
        ``(n, P)`` normal force (N) of each tooth pair a model of several teeth holds, and
        the driver's roll angle of its contact point (rad; NaN off the path of contact);
        ``None`` for a model of one pair.
    back_force
        ``(n, B)`` normal force (N) of each pair of back flanks (the driver's tooth
        ``info["back_pair_teeth"][i]`` on the driven gear's ``-k + 1``, along the back line of
        action); ``None`` where the back flanks are not contacts.
    pair_contact_pressure, pair_contact_half_width
        ``(n, P)`` Hertz's peak pressure (Pa) and half-width (m) of each pair of
        ``pair_force`` (NaN where it carries no force); ``None`` for a model of one pair.
    tooth_stress
        The root stress of every tooth at sampled times, gear A's first
        (:class:`ToothStress`); ``None`` for a model that does not compute it per tooth.
    transmission_error
        ``(n,)`` ``r_b,driver theta_driver - r_b,driven theta_driven`` (m) less its rigid
        kinematic value: positive where the driver runs ahead; ``None`` where not computed.
    residual, iterations
        Final constraint error (max norm: m, m/s, m/s^2) and iterations ``(n, k)`` of each
        of the integrator's ``k`` stages, the first ``k`` of :data:`STAGES` (the paper's
        RK4: all three; the implicit integrator: its Newton iteration, one); ``None`` for a
        model without a constraint iteration (the lumped and the sector model).
    hub_translation
        The hubs' translations on their bearings ``(n, 8)``: gear A's and gear B's
        ``(x, y)``, then their rates (m, m/s), each in its gear's own frame, ``x`` along the
        line of centres away from the other gear, ``y`` across it (the side the drive flanks'
        force on the gear points to); ``None`` where the hubs' centres are held.
    corner
        Contact at a tip corner: 0 flank to flank, 1 A's tip corner, 2 B's tip corner;
        ``None`` for a model without a contact point.
    """

    time: NDArray[np.float64]
    angle: NDArray[np.float64]
    contact_force: NDArray[np.float64]
    gap: NDArray[np.float64]
    roll: NDArray[np.float64]
    theta: NDArray[np.float64]
    omega: NDArray[np.float64]
    torque: NDArray[np.float64]
    frame_time: NDArray[np.float64]
    frame_theta: NDArray[np.float64]
    frame_u: NDArray[np.float64]
    status: str = "complete"
    reason: str = ""
    steps: int = 0
    wall_s: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)
    contact_half_width: NDArray[np.float64] | None = None
    contact_pressure_max: NDArray[np.float64] | None = None
    pair_force: NDArray[np.float64] | None = None
    pair_roll: NDArray[np.float64] | None = None
    back_force: NDArray[np.float64] | None = None
    transmission_error: NDArray[np.float64] | None = None
    residual: NDArray[np.float64] | None = None
    iterations: NDArray[np.int64] | None = None
    corner: NDArray[np.int8] | None = None
    pair_contact_pressure: NDArray[np.float64] | None = None
    pair_contact_half_width: NDArray[np.float64] | None = None
    tooth_stress: ToothStress | None = None
    hub_translation: NDArray[np.float64] | None = None

    @property
    def angle_deg(self) -> NDArray[np.float64]:
        return np.degrees(self.angle)

    @property
    def complete(self) -> bool:
        return self.status == "complete"
