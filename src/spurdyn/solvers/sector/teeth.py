"""What a sector run's record gives tooth by tooth (docs/sector.md, 6.11): every contact's
Hertzian pressure and half-width at every step, and the root stress of every tooth of both
gears at the sampled steps, from the kept coordinates through the fillets' linear maps
(:class:`spurdyn.sector.fillets.GearFillets`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from spurdyn.contact.hertz import peak_pressure
from spurdyn.model.root import peaks
from spurdyn.result import ToothStress
from spurdyn.sector.fault_bodies import pit_shares
from spurdyn.sector.fillets import GearFillets
from spurdyn.sector.rules import STRESS_SAMPLES, stress_steps
from spurdyn.sector.system import half_widths_at

#: Bytes the pairs' rows of the samples formed at once may take: on modal bodies a pair's
#: flank loads, ``f`` numbers on each gear (58 on the paper's pair; their modal rows, ``f x m``
#: numbers, are not formed: :meth:`GearFillets.stress_many`).
ROWS_BYTES = 8 * 2**20
#: Most samples formed at once (whole bodies, which gather nothing).
MOST_SAMPLES = 256
#: Why a run whose pit over part of the face width split a contact has no largest pressure.
SPLIT_PRESSURE_NOTE = ("none: a pit over part of the face width split a contact into two strips, "
                       "whose own forces (and pressures, the intact strip's the run's highest) are "
                       "not recorded; so no contact pressure maximum and no model contact safety "
                       "factor (docs/faults.md, section 8)")

if TYPE_CHECKING:  # annotations only
    from spurdyn.sector.model import SectorModel
    from spurdyn.solvers.sector.stepper import SectorRecord


def contact_pressures(model: SectorModel, theta_a: NDArray[np.float64], force: NDArray[np.float64],
                      offset: int = 0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(p_max, b)`` ``(n, C)``: Hertz's peak pressure (Pa) and half-width (m) of every
    contact of ``model.c_teeth`` at the driver's turns ``theta_a`` ``(n,)`` under its forces
    ``force`` ``(n, C)``, at the contact radii and curvatures the run's strips had (the gap
    table's, tip corners' included); NaN where a contact carries no force or is off its path,
    and where a pit over part of the face width splits it (its strips' own forces, which
    set theirs, are not recorded; docs/faults.md, section 8). ``offset`` the driver's body
    tooth of pair 0."""
    rolls = model.roll_0 + theta_a[:, None] + model.c_teeth[None, :] * model.pitch
    rolls = np.where(model.c_side[None, :] == 1, model.sigma - rolls, rolls)
    on = (rolls >= model.roll_0 - model.reach) & (rolls <= model.roll_1 + model.reach) \
        & np.isfinite(force) & (np.nan_to_num(force) > 0.0)
    if model.splits:
        at = model.flank_places(model.c_teeth + offset, model.c_side)
        on &= pit_shares(model.faults, at, model.c_side, rolls)[0] == 0.0
    p, b = np.full(force.shape, np.nan), np.full(force.shape, np.nan)
    if on.any():
        _, _, r_a, r_b = model.table.at(rolls[on])
        b[on] = half_widths_at(model.dp, (r_a, r_b), force[on], model.estar, model.width)
        p[on] = peak_pressure(force[on], b[on], model.width)
    return p, b


def split_anywhere(model: SectorModel, theta_a: NDArray[np.float64], force: NDArray[np.float64],
                   offset: int = 0) -> bool:
    """Whether a pit over part of the face width splits a loaded contact at any of the
    driver's turns ``theta_a`` (:func:`contact_pressures`' arguments)."""
    if not model.splits:
        return False
    rolls = model.roll_0 + theta_a[:, None] + model.c_teeth[None, :] * model.pitch
    rolls = np.where(model.c_side[None, :] == 1, model.sigma - rolls, rolls)
    at = model.flank_places(model.c_teeth + offset, model.c_side)
    loaded = np.isfinite(force) & (np.nan_to_num(force) > 0.0)
    return bool((loaded & (pit_shares(model.faults, at, model.c_side, rolls)[0] > 0.0)).any())


def pair_pressures(model: SectorModel, theta_a: NDArray[np.float64], force: NDArray[np.float64],
                   keep: NDArray[np.bool_] | None, offset: int = 0) -> dict[str, NDArray[np.float64]]:
    """The :class:`~spurdyn.result.Result` fields of the contacts' pressure: per drive pair
    (those of ``keep``, all if ``None``) ``pair_contact_pressure`` and
    ``pair_contact_half_width``, and at each step the largest over every contact, the back
    flanks' too (``contact_pressure_max``, ``contact_half_width``; NaN with none, and NaN
    throughout a run where a pit over part of the face width splits a contact at any step:
    the split pair's strips are not recorded, and its intact strip is the run's highest
    pressure, so no step's or run's largest is known; docs/faults.md, section 8)."""
    pressure, half = contact_pressures(model, theta_a, force, offset)
    drive = (slice(None), slice(0, model.teeth.size))
    pair_p, pair_b = pressure[drive], half[drive]
    if keep is not None:
        pair_p, pair_b = pair_p[:, keep], pair_b[:, keep]
    any_on = np.isfinite(pressure).any(axis=1) & (not split_anywhere(model, theta_a, force, offset))
    p_max = np.where(any_on, np.nanmax(np.where(any_on[:, None], pressure, 0.0), axis=1), np.nan)
    b_max = np.where(any_on, np.nanmax(np.where(any_on[:, None], half, 0.0), axis=1), np.nan)
    return {"pair_contact_pressure": pair_p, "pair_contact_half_width": pair_b,
            "contact_pressure_max": p_max, "contact_half_width": b_max}


def pair_budget(model: SectorModel) -> int:
    """The pairs whose rows may be formed at once (:data:`ROWS_BYTES`; on whole bodies
    :data:`MOST_SAMPLES` samples' worth of every contact)."""
    if not model.modes:
        return MOST_SAMPLES * model.c_teeth.size
    # a flank load's 2 (2 ny + 1) numbers (BodyBlock.flank_loads) on each gear
    per_pair = 8 * sum(2 * (2 * blk.body.flank.ny + 1) for blk in model.blocks)
    return max(ROWS_BYTES // per_pair, 1)


def sample_runs(pairs: NDArray[np.intp], budget: int) -> list[slice]:
    """Runs of consecutive samples, each of at most ``budget`` of their ``pairs`` (one
    sample a run if it has more) and :data:`MOST_SAMPLES` samples."""
    out, lo, total = [], 0, 0
    for i, count in enumerate(pairs.tolist()):
        if i > lo and (total + count > budget or i - lo == MOST_SAMPLES):
            out.append(slice(lo, i))
            lo, total = i, 0
        total += count
    return out + [slice(lo, len(pairs))] if len(pairs) else out


def fillet_stress(model: SectorModel, fillets: list[GearFillets], states: NDArray[np.float64],
                  force: NDArray[np.float64], offset: int = 0) -> list[NDArray[np.float64]]:
    """Per gear ``(S, K, n)`` the stress along every tooth's fillets (its ``fillets``) in the
    states ``states`` ``(S, n_q)`` under the contacts' forces ``force`` ``(S, C)``: the
    pairs' rows of all of them at once (:meth:`SectorModel.rows_many`) through the
    fillets' maps (:meth:`GearFillets.stress_many`)."""
    found = model.rows_many(states[:, 0], force, offset, full=False)
    sample, rows = found if found is not None else (None, None)
    f_on = force[sample, rows.on] if rows is not None else None
    return [f.stress_many(states[:, model.parts[g]], sample, rows.sides[g][1] if rows is not None else None, f_on)
            for g, f in enumerate(fillets)]


def root_stress(model: SectorModel, record: SectorRecord, n_kept: int, offset: int = 0) -> ToothStress | None:
    """The root stress of every tooth of the driver and the driven gear (``model.dp``'s
    order) at the run's sampled steps below ``n_kept``: per sample and tooth the largest
    stress along both fillets, its radius, the smallest and its radius; ``None`` where no
    sampled step was kept."""
    steps = stress_steps(model.per_cycle, record.gap.size - 1)
    keep = (steps < n_kept) & np.isfinite(record.states[:steps.size, 0])
    steps, states = steps[keep], record.states[:steps.size][keep]
    if not steps.size:
        return None
    fillets = [GearFillets(g) for g in model.gears]
    stress = [np.empty((steps.size,) + (f.teeth.size, f.radius.size)) for f in fillets]
    # BLAS on one thread, as in the run's steps: the products are small and another process
    # may hold the other core (two threads then wait on each other: several times slower)
    with threadpool_limits(limits=1, user_api="blas"):
        for at in sample_runs(model.near_many(states[:, 0], offset), pair_budget(model)):
            for g, sig in enumerate(fillet_stress(model, fillets, states[at], record.force[steps[at]], offset)):
                stress[g][at] = sig
    values = []
    for f, sig in zip(fillets, stress):
        flat = peaks(sig.reshape(-1, f.radius.size), f.radius)
        values.append(np.array([v.reshape(steps.size, f.teeth.size) for v in flat]))
    return ToothStress(time=steps * model.h, teeth=(fillets[0].teeth.copy(), fillets[1].teeth.copy()),
                       values=(values[0], values[1]), per_cycle=min(STRESS_SAMPLES, model.per_cycle))


__all__ = ["SPLIT_PRESSURE_NOTE", "contact_pressures", "split_anywhere", "fillet_stress", "pair_budget", "pair_pressures", "root_stress", "sample_runs"]
