"""The hubs on radial bearings (docs/sector.md, 6.12): each gear translates rigidly in the
fixed frame, ``(x, y)`` along the line of centres (away from the other gear) and across it
(the side the drive flanks' force on the gear points to), each gear's frame the other's
mirror image as the bodies' are. A bearing pulls its hub back by ``-k x - c x_dot``.

The translations are their own block of the step (decoupled from the bodies' modes, the
derivation's first model): per gear ``S_tt = (m + gamma' c + beta' k) I``, constant. A
contact's gap opens by ``n . x_g`` on each gear, ``n = (sin alpha_w, cos alpha_w)`` on a drive
flank and ``(sin alpha_w, -cos alpha_w)`` on a back flank: the rows' constant entries on the
four translations ``(x_A, y_A, x_B, y_B)`` (driver first), after both bodies' coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.sector.packs import BearingPack

#: Translations a run with bearings adds: ``(x, y)`` of each gear, the driver's first.
TRANSLATIONS = 4


@dataclass(frozen=True)
class HubBearings:
    """The run's bearings, driver first (:func:`hub_bearings`): ``rows`` ``(2, 4)`` a drive
    (0) and a back (1) contact's entries on the translations, per translation the gear's
    ``mass`` (kg), the bearing's ``k`` (N/m) and ``c`` (N s/m), and ``tinv`` the inverse of
    ``S_tt`` (0 on a hub held where only the other has a bearing)."""

    rows: NDArray[np.float64]
    mass: NDArray[np.float64]
    k: NDArray[np.float64]
    c: NDArray[np.float64]
    tinv: NDArray[np.float64]

    def of(self, sides: NDArray[np.intp]) -> NDArray[np.float64]:
        """``(p, 4)`` the translation entries of contacts on flanks ``sides``."""
        return self.rows[sides]

    def free(self, q: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        """``S_tt^-1 (-k x - c x_dot)``: the translations' accelerations without contacts."""
        return self.tinv * (-self.k * q - self.c * v)

    def force(self, q: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        """The force each bearing carries, ``k x + c x_dot`` (N; the hub's is its negative)."""
        return self.k * q + self.c * v

    def kinetic(self, v: NDArray[np.float64]) -> float:
        return 0.5 * float(self.mass @ (v * v))

    def strain(self, q: NDArray[np.float64]) -> float:
        return 0.5 * float(self.k @ (q * q))

    def static(self, total: float) -> NDArray[np.float64]:
        """The translations under drive contacts carrying ``total`` (N), ``n total / k``."""
        held = self.k > 0.0
        return np.where(held, self.rows[0] * total / np.where(held, self.k, 1.0), 0.0)

    def compiled(self) -> BearingPack:
        return BearingPack(self.rows.copy(), self.tinv.copy(), self.k.copy(), self.c.copy())


def bearing_pack(bearings: HubBearings | None) -> BearingPack:
    """The compiled implicit loop's pack of a run's bearings (no translations without)."""
    if bearings is None:
        return BearingPack(np.zeros((2, 0)), np.zeros(0), np.zeros(0), np.zeros(0))
    return bearings.compiled()


def gear_mass(block: Any) -> float:
    """The gear's translating mass (kg): the meshed body's lumped masses (its free nodes',
    and its hub circle's, held, from their share of ``J_body`` at the hub circle's radius)
    and the blank's inside the hub circle, full face width from the bore (the hub's
    inertia is not read: a case's ``disk_inertia`` may carry a shaft's beside the gear)."""
    gear = block.body.gear
    r_in = float(block.body.mesh.inner_radius)
    bore = gear.blank.bore_radius if gear.blank is not None else 0.0
    j_free = float(block.rot @ (block.mass * block.rot))
    held = max(block.body_inertia - j_free, 0.0) / r_in**2
    hub = gear.material.density * gear.face_width * math.pi * (r_in**2 - bore**2)
    return 0.5 * float(block.mass.sum()) + held + hub


def hub_bearings(bearings: Any, driver: str, alpha_w: float, blocks: Any, gamma_p: float, beta_p: float,
                 whole: bool) -> HubBearings | None:
    """The run's :class:`HubBearings` of ``bearings`` (gear A's and B's, the settings'), the
    driver's first; ``None`` without. A bearing needs whole gears (a sector's hub holds the
    teeth not meshed: its mass is not the gear's)."""
    if bearings is None:
        return None
    if not whole:
        raise InputError("gear_a.bearing" if bearings[0] is not None else "gear_b.bearing",
                         "a hub on a bearing needs whole gears: give cycles of 3 or more and no fewer "
                         "teeth than the gears have")
    own = bearings if driver == "a" else bearings[::-1]
    s, c = math.sin(alpha_w), math.cos(alpha_w)
    rows = np.array([[s, c, s, c], [s, -c, s, -c]])
    mass = np.repeat([gear_mass(b) for b in blocks], 2)
    k = np.repeat([b.stiffness if b is not None else 0.0 for b in own], 2)
    damp = np.repeat([b.damping if b is not None else 0.0 for b in own], 2)
    on = np.repeat([b is not None for b in own], 2)
    tinv = np.where(on, 1.0 / (mass + gamma_p * damp + beta_p * k), 0.0)
    return HubBearings(rows, mass, k, damp, tinv)


__all__ = ["HubBearings", "TRANSLATIONS", "gear_mass", "bearing_pack", "hub_bearings"]
