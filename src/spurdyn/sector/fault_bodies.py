"""Where a dynamic run's faults sit on its whole gears (docs/faults.md, "Faults in motion").

A dynamic run of the sector model carries the gears whole, body tooth ``k`` the one that
meets the contacts of the driver's tooth ``k`` (:class:`~spurdyn.sector.model.SectorModel`):
the driver's contact ``c`` is its body tooth ``c`` on the driven gear's body tooth ``-c``,
and contact ``c = -k`` enters the path ``k`` mesh cycles after the start. So a fault on
tooth ``k`` (numbered, as :mod:`spurdyn.geometry.fault` numbers them, in the order the
teeth enter the mesh) sits on the driver's body tooth ``-k`` and on the driven gear's body
tooth ``k``, each taken round its ring into the body's numbers ``first .. first + z - 1``.

A missing tooth's body has no tooth there and its contacts are not made; a cracked tooth's
body is meshed with the crack (:func:`spurdyn.sector.faulty.cracked_mesh`), its faces a
contact of their own (:mod:`spurdyn.sector.faces`); a spall over the whole face width widens
the gap of its flank's contact by its depth over the pit's rolls, written in the contact's
roll on the path (the driver's roll angle of the contact point) for both gears; a chipped
tooth's body is meshed with the corner cut off (:func:`spurdyn.sector.faulty.chipped_mesh`)
and its drive flank's contact is not made over the rolls beyond the cut (``lost``, in the
same rolls on the path).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault, chip_roll
from spurdyn.geometry.pair import GearPair


@dataclass(frozen=True)
class GearFaults:
    """One gear's faults in its whole body's numbers (module docstring).

    Attributes
    ----------
    missing
        The body teeth broken off.
    cracks
        ``(body tooth, fault)`` of each cracked tooth.
    pits
        ``(z, 2, 3)`` per body tooth (from ``first``) and flank the contact's rolls ``(lo,
        hi)`` on its path where the gap is ``depth`` wider; zeros elsewhere.
    gone
        ``(z,)`` 1 on a missing tooth.
    chips
        ``(body tooth, fault)`` of each chipped tooth.
    lost
        ``(z, 2, 2)`` per body tooth and flank the contact's rolls ``(lo, hi)`` on its path
        where the flank is gone (a chip's, beyond its cut): the contact is not made there;
        ``(inf, -inf)`` (none) elsewhere.
    """

    missing: frozenset[int]
    cracks: tuple[tuple[int, Fault], ...]
    pits: NDArray[np.float64]
    gone: NDArray[np.int64]
    chips: tuple[tuple[int, Fault], ...] = ()
    lost: NDArray[np.float64] | None = None

    @property
    def any(self) -> bool:
        return bool(self.missing or self.cracks or self.chips or np.any(self.pits[..., 2]))

    @property
    def meshed(self) -> tuple[tuple[int, Fault], ...]:
        """The teeth meshed again (cracked or chipped), ``(body tooth, fault)``."""
        return self.cracks + self.chips


def no_lost(z: int) -> NDArray[np.float64]:
    """``(z, 2, 2)`` :attr:`GearFaults.lost` of a gear without chips: no roll lost."""
    out = np.empty((z, 2, 2))
    out[..., 0], out[..., 1] = np.inf, -np.inf
    return out


def body_tooth(tooth: int, g: int, first: int, z: int) -> int:
    """The body tooth of gear ``g``'s (0 the driver) fault tooth ``tooth``, round its ring."""
    k = -tooth if g == 0 else tooth
    return first + (k - first) % z


def _pit_rolls(dp: GearPair, g: int, fault: Fault) -> tuple[float, float]:
    """A spall's rolls of its own flank as the driver's rolls of the contact point: the
    driven gear's run backwards along the path (``rho_B = (L - rho_A r_bA) / r_bB``)."""
    lo, hi = fault.roll
    if g == 0:
        return lo, hi
    ra, rb, length = dp.gear_a.base_radius, dp.gear_b.base_radius, dp.line_of_centres_length
    return (length - hi * rb) / ra, (length - lo * rb) / ra


def _lost_rolls(dp: GearPair, g: int, fault: Fault) -> tuple[float, float]:
    """A chip's lost stretch of its drive flank, beyond the cut toward its tip, as the
    driver's rolls of the contact point (the driven gear's run backwards, as a pit's)."""
    cut = chip_roll(dp.gear_a if g == 0 else dp.gear_b, fault)
    if g == 0:
        return cut, math.inf
    ra, rb, length = dp.gear_a.base_radius, dp.gear_b.base_radius, dp.line_of_centres_length
    return -math.inf, (length - cut * rb) / ra


def gear_faults(dp: GearPair, driver: str, faults: tuple[Fault, ...], firsts: tuple[int, int]) -> tuple[
        GearFaults, GearFaults]:
    """Each gear of the driving pair ``dp``'s faults (``driver`` the case's name of its
    driver, which the faults' ``gear`` names), its whole body from ``firsts``."""
    out = []
    for g, gear in enumerate((dp.gear_a, dp.gear_b)):
        z, first = gear.teeth, firsts[g]
        mine = [f for f in faults if (f.gear == driver) == (g == 0)]
        missing = frozenset(body_tooth(f.tooth, g, first, z) for f in mine if f.kind == "missing")
        cracks = tuple((body_tooth(f.tooth, g, first, z), f) for f in mine if f.kind == "crack")
        pits = np.zeros((z, 2, 3))
        for f in (f for f in mine if f.kind == "spall"):
            at = body_tooth(f.tooth, g, first, z) - first
            if f.width_fraction < 1.0:
                raise InputError("fault", f"a dynamic run takes a spall across the whole face width: give "
                                 f"width_fraction = 1 for tooth {f.tooth} (got {f.width_fraction:g}); "
                                 "`spurdyn stiffness` takes any")
            if pits[at, 0, 2]:
                raise InputError("fault", f"a dynamic run takes one spall a flank (tooth {f.tooth} has two)")
            pits[at, 0] = (*_pit_rolls(dp, g, f), f.depth)
        gone = np.zeros(z, np.int64)
        gone[[k - first for k in missing]] = 1
        chips = tuple((body_tooth(f.tooth, g, first, z), f) for f in mine if f.kind == "chip")
        lost = no_lost(z)
        for k, f in chips:
            lost[k - first, 0] = _lost_rolls(dp, g, f)
        out.append(GearFaults(missing, cracks, pits, gone, chips, lost))
    return out[0], out[1]


def check_cracked_flanks(blocks: tuple[Any, Any], faults: tuple[GearFaults, GearFaults],
                         low: tuple[float, float], half_width: float) -> None:
    """Refuse (``fault``) a cracked tooth whose mesh has no node where its contacts load its
    flank: the crack's mouth splits a fillet edge that reaches the lowest contact radius
    ``low`` of its gear (a strip of ``half_width`` there), on a coarse mesh or a high mouth."""
    from spurdyn.contact.strip_numpy import strip_weights

    for blk, gf, r in zip(blocks, faults, low):
        body = blk.body
        for k, fault in gf.cracks:
            absent = body.mesh.tooth_dofs(k).reshape(-1, 2)[body.flank.side_nodes][:, 0] < 0
            w = strip_weights(body.flank, body.flank_coordinate(np.array([r])), np.array([half_width]))[0]
            if np.any(w[absent] > 0.0):
                raise InputError("fault", f"the crack on tooth {fault.tooth} of gear {fault.gear} opens on the "
                                 f"flank's edge the contacts load ({r * 1e3:.4g} mm and up) on this mesh: give a "
                                 "finer mesh (--mesh) or a lower start_radius")


def cracked_meshes(dp: GearPair, faults: GearFaults, g: int, nx: int, ny: int, grading: float) -> dict[int, Any]:
    """The meshes of gear ``g``'s cracked and chipped body teeth."""
    from spurdyn.sector.faulty import fault_mesh

    gear = dp.gear_a if g == 0 else dp.gear_b
    return {k: fault_mesh(gear, f, nx, ny, grading) for k, f in faults.meshed}


__all__ = ["GearFaults", "body_tooth", "no_lost", "check_cracked_flanks", "cracked_meshes", "gear_faults"]
