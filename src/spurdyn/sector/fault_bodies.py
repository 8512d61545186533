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
roll on the path (the driver's roll angle of the contact point) for both gears; a spall over
part of it splits the contact there into the intact strip and the pit's
(:func:`spurdyn.solvers.sector.rows_compiled.rows_and_loads`); a chipped
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
from spurdyn.geometry.fault import Fault, chip_roll, faulty_cycles
from spurdyn.geometry.pair import GearPair
from spurdyn.sector.statics import driving_pair
from spurdyn.sector.system import WHOLE_FROM_CYCLES
from spurdyn.settings import RunSettings


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
        ``(z, 2, 4)`` per body tooth (from ``first``) and flank the contact's rolls ``(lo,
        hi)`` on its path where the gap is ``depth`` wider over the share ``width`` of the
        face width (1 across it); zeros elsewhere.
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
        pits = np.zeros((z, 2, 4))
        for f in (f for f in mine if f.kind == "spall"):
            at = body_tooth(f.tooth, g, first, z) - first
            if pits[at, 0, 3]:
                raise InputError("fault", f"a dynamic run takes one spall a flank (tooth {f.tooth} has two)")
            pits[at, 0] = (*_pit_rolls(dp, g, f), f.depth, f.width_fraction)
        gone = np.zeros(z, np.int64)
        gone[[k - first for k in missing]] = 1
        chips = tuple((body_tooth(f.tooth, g, first, z), f) for f in mine if f.kind == "chip")
        lost = no_lost(z)
        for k, f in chips:
            lost[k - first, 0] = _lost_rolls(dp, g, f)
        out.append(GearFaults(missing, cracks, pits, gone, chips, lost))
    _one_split(out, faults)
    return out[0], out[1]


def _one_split(gears: list[GearFaults], faults: tuple[Fault, ...]) -> None:
    """Refuse (``fault``) spalls over part of the face width on both gears: a pair splits
    into two rows, the intact strip and the pit's (docs/faults.md, section 8), not four."""
    if all(any_split((gf,)) for gf in gears):
        teeth = ", ".join(f"{f.gear}{f.tooth}" for f in faults if f.kind == "spall" and f.width_fraction < 1.0)
        raise InputError("fault", f"a dynamic run takes spalls over part of the face width on one gear only (got "
                         f"{teeth}): give width_fraction = 1 to those of one gear; `spurdyn stiffness` takes any")


def split_rows(faults: tuple[GearFaults, GearFaults], at: tuple[NDArray[np.intp], NDArray[np.intp]],
               sd: NDArray[np.intp], rolls: NDArray[np.float64], force: NDArray[np.float64],
               pit: NDArray[np.float64]) -> tuple[NDArray[Any], ...]:
    """The rows of the contacts at body teeth ``at`` (per gear), flanks ``sd`` and ``rolls``
    (docs/faults.md, section 8): one a contact, two where a pit over part of the face width
    splits it, the intact strip's and then the pit's. Per row ``(idx, kind, share, extra,
    held)``: its contact's place in the arguments, kind (0 whole, 1 the intact strip, 2 the
    pit's), share of the face width, extra gap (the pit's depth) and force of the step
    before, from the contacts' ``force`` and their pit strips' ``pit`` (-1 where a contact
    was whole: it enters the pit with its force in proportion to the shares). Twin of
    :func:`~spurdyn.solvers.sector.rows_compiled.split_rows`."""
    shares, depths = pit_shares(faults, at, sd, rolls)
    split = shares > 0.0
    idx = np.repeat(np.arange(rolls.size), np.where(split, 2, 1))
    second = np.concatenate([[False], idx[1:] == idx[:-1]])
    kind = np.where(second, 2, np.where(split[idx], 1, 0))
    w = shares[idx]
    share = np.where(kind == 1, 1.0 - w, np.where(kind == 2, w, 1.0))
    held = row_forces(kind, share, force[idx], pit[idx])
    return idx, kind, share, np.where(kind == 2, depths[idx], 0.0), held


def any_split(faults: tuple[GearFaults, ...] | None) -> bool:
    """Whether a spall over part of the face width splits pairs (docs/faults.md, section 8)."""
    return bool(faults) and any(bool(np.any((gf.pits[..., 3] > 0.0) & (gf.pits[..., 3] < 1.0))) for gf in faults)


def strip_excess(kind: NDArray[np.intp] | None, share: NDArray[np.float64] | None, c_h: float) -> Any:
    """The split rows' (:func:`split_rows`' ``kind``, ``share``) strip compliances
    ``c_H / s`` beyond the ``c_H`` of every row: a diagonal, 0 where no row is split."""
    if kind is None or not kind.any():
        return 0.0
    return np.diag(np.where(kind > 0, c_h / share - c_h, 0.0))


def pit_shares(faults: tuple[GearFaults, GearFaults], at: tuple[NDArray[np.intp], NDArray[np.intp]],
               sd: NDArray[np.intp], rolls: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per contact (:func:`split_rows`' arguments, any shape) the share of the face width a
    pit over part of it covers at its roll (0: none there) and the pit's depth."""
    shares, depths = np.zeros(rolls.shape), np.zeros(rolls.shape)
    for gf, a in zip(faults, at):
        lo, hi, depth, width = np.moveaxis(gf.pits[a, sd], -1, 0)
        inside = (0.0 < width) & (width < 1.0) & (lo <= rolls) & (rolls <= hi)
        shares, depths = np.where(inside, width, shares), np.where(inside, depth, depths)
    return shares, depths


def row_forces(kind: NDArray[np.intp], share: NDArray[np.float64], force: NDArray[np.float64],
               pit: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per row of :func:`split_rows` (its ``kind`` and ``share``) its force from its
    contact's ``force`` and pit strip's ``pit``: a whole contact's, the pit's, the rest the
    intact strip's; where the contact was whole (``pit`` -1), in proportion to the shares."""
    return np.where(kind == 0, force, np.where(pit >= 0.0, np.where(kind == 1, force - pit, pit), share * force))


def no_faults(count: int) -> GearFaults:
    """A healthy gear's (the compiled loops' packs of every run have the fields)."""
    return GearFaults(frozenset(), (), np.zeros((count, 2, 4)), np.zeros(count, np.int64), (), no_lost(count))


def run_faults(pair: GearPair, settings: RunSettings, bodies: tuple[tuple[int, int], tuple[int, int]]) -> Any:
    """The run's faults on its whole gears (:func:`gear_faults`), ``None``
    without faults; a faulty run on a sector of teeth refused (a fault comes round)."""
    if not settings.faults:
        return None
    dp = driving_pair(pair)
    if any(count < gear.teeth for (_, count), gear in zip(bodies, (dp.gear_a, dp.gear_b))):
        raise InputError("fault", f"a faulty gear runs whole: give cycles of {WHOLE_FROM_CYCLES} or more "
                         "and no fewer teeth than the gears have")
    if settings.bodies != "modal":
        raise InputError("fault", "a faulty gear runs on modal bodies: give bodies = \"modal\"")
    return gear_faults(dp, pair.driver, tuple(settings.faults), (bodies[0][0], bodies[1][0]))


def faulty_cycles_of(dp: GearPair, driver: str, faults: Any) -> int:
    """The mesh cycles after which a faulty pair repeats (the faulty gear's revolution, both
    gears' meeting again with faults on both); 1 for a healthy pair."""
    if not faults:
        return 1
    gears = {f.gear for f in faults}
    turning = dp.gear_a if gears == {driver} else dp.gear_b
    other = dp.gear_b if turning is dp.gear_a else dp.gear_a
    return faulty_cycles(turning.teeth, other.teeth, len(gears) == 2)


def check_cracked_flanks(blocks: tuple[Any, Any], faults: tuple[GearFaults, GearFaults],
                         low: tuple[float, float], half_width: float) -> None:
    """Refuse (``fault``) a cracked tooth whose mesh has no node where its contacts load its
    flank: the crack's mouth splits a fillet edge that reaches the lowest contact radius
    ``low`` of its gear (a strip of ``half_width`` there, ``(1 - w)^-1/2`` times wider on a
    tooth with a pit over the share ``w`` of the face width: its intact strip may carry the
    pair), on a coarse mesh or a high mouth."""
    from spurdyn.contact.strip_numpy import strip_weights

    for blk, gf, r in zip(blocks, faults, low):
        body = blk.body
        for k, fault in gf.cracks:
            absent = body.mesh.tooth_dofs(k).reshape(-1, 2)[body.flank.side_nodes][:, 0] < 0
            part = gf.pits[k - blk.first, :, 3]
            share = float(np.where(part < 1.0, part, 0.0).max())
            b = half_width / np.sqrt(1.0 - share)
            w = strip_weights(body.flank, body.flank_coordinate(np.array([r])), np.array([b]))[0]
            if np.any(w[absent] > 0.0):
                raise InputError("fault", f"the crack on tooth {fault.tooth} of gear {fault.gear} opens on the "
                                 f"flank's edge the contacts load ({r * 1e3:.4g} mm and up) on this mesh: give a "
                                 "finer mesh (--mesh) or a lower start_radius")


def cracked_meshes(dp: GearPair, faults: GearFaults, g: int, nx: int, ny: int, grading: float) -> dict[int, Any]:
    """The meshes of gear ``g``'s cracked and chipped body teeth."""
    from spurdyn.sector.faulty import fault_mesh

    gear = dp.gear_a if g == 0 else dp.gear_b
    return {k: fault_mesh(gear, f, nx, ny, grading) for k, f in faults.meshed}


__all__ = ["GearFaults", "body_tooth", "check_cracked_flanks", "cracked_meshes", "faulty_cycles_of", "gear_faults",
           "no_faults", "no_lost", "run_faults",
           "any_split", "pit_shares", "row_forces", "split_rows", "strip_excess"]
