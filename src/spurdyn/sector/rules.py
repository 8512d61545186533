"""The sector model's run rules (docs/sector.md, 6.3-6.7): its step, the bodies' default
damping, how many cycles a run may go on to, and whether the back flanks are contacts; the
constants :func:`spurdyn.solvers.sector.run.simulate_sector` and the sweep's settings hash
read."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from spurdyn.geometry.pair import GearPair
from spurdyn.model.alpha import KEEP_FREQUENCY, STEPS_PER_KEPT_PERIOD
from spurdyn.sector.system import WHOLE_FROM_CYCLES
from spurdyn.settings import RunSettings

# The sector model keeps what the paper model's implicit step keeps (docs/implicit.md,
# section 4): the modal bodies every mode below KEEP_FREQUENCY (150 kHz: the teeth's
# first modes on their rims, near 95 kHz, whose phase times the impacts after a separation),
# and the default step resolves it with STEPS_PER_KEPT_PERIOD steps a period. The
# pair's torsional mode (~5-6 kHz) and the mesh frequency's first harmonics lie well below;
# what the residual flexibility carries above it acts without inertia. Until revision 5 the
# step resolved only 50 kHz (2 us): near the resonance the impacts after the mesh separated
# came up to 2.6 us late against RK4 (docs/sector_rk4_validation.md).

#: Fewest steps per mesh cycle: the contact point crosses each element along the flank in
#: several steps.
STEPS_PER_MESH_PERIOD = 200
#: Positions of the quasi-static cycle the run reads its mean stiffness and its largest
#: quasi-static pair force from.
CYCLE_POSITIONS = 21
#: Bumped when a change of the model makes a run of the same settings differ (a sweep's
#: settings hash carries it, so that its stored points are not taken for the new model's):
#: 2, the mesh damper following the cycle's stiffness; 3, the back flanks contacts by default
#: where the pair has backlash; 4, a continuation point's common rotation set to its speed;
#: 5, the default step resolving :data:`KEEP_FREQUENCY` (150 kHz, was 50 kHz).
SECTOR_REVISION = 5
#: The bodies' structural damping when the run gives no Rayleigh damping: stiffness
#: proportional, this ratio at :data:`BODY_DAMPING_FREQUENCY` (a tenth of it at 5 kHz, where the pair's
#: torsional mode lies). Without any, the bodies' own modes (the teeth on their rims, which
#: the mesh damper does not reach) ring for ever and a run never settles (docs/sector.md,
#: 6.5). An ASSUMPTION of typical magnitude, not a measured property of a gear; give
#: ``rayleigh_mass``/``rayleigh_stiffness`` (0 for none) to set another.
BODY_DAMPING_RATIO = 0.02
#: The frequency (Hz) at which the bodies' default damping has :data:`BODY_DAMPING_RATIO`.
BODY_DAMPING_FREQUENCY = 50e3
#: The mesh damper's ratio when the run gives none (``damping_ratio`` left out): the middle
#: of the ratios measured on spur pairs and used in practice (docs/sector.md, "The defaults
#: an engineer gets"); give ``damping_ratio`` (0 for none) to set another.
MESH_DAMPING_RATIO = 0.05
#: Mesh cycles of a run that gives none (``cycles`` left out): enough for a damped pair
#: started from its static equilibrium to settle (it goes on, if not, to
#: :data:`~spurdyn.settings.SETTLE_CYCLES_FACTOR` times them).
DEFAULT_CYCLES = 5


def mesh_damping(settings: RunSettings) -> tuple[float, str]:
    """The mesh damper's ratio of a sector run and where it came from: the run's, or if it
    gives none :data:`MESH_DAMPING_RATIO` (``"model default"``)."""
    if settings.damping_ratio is None:
        return MESH_DAMPING_RATIO, "model default"
    return float(settings.damping_ratio), "run"


def with_defaults(settings: RunSettings) -> RunSettings:
    """``settings`` with the sector model's :data:`DEFAULT_CYCLES` where it gives no ``cycles``."""
    return settings if settings.cycles is not None else settings.with_(cycles=DEFAULT_CYCLES)


def body_rayleigh(settings: RunSettings) -> tuple[float, float]:
    """Rayleigh's ``(a, b)`` of the sector model's bodies: the run's, or if it gives none,
    :data:`BODY_DAMPING_RATIO` at :data:`BODY_DAMPING_FREQUENCY` on the stiffness alone."""
    if settings.rayleigh_mass is None and settings.rayleigh_stiffness is None:
        return 0.0, 2.0 * BODY_DAMPING_RATIO / (2.0 * math.pi * BODY_DAMPING_FREQUENCY)
    return settings.rayleigh


#: Normal backlash (m) from which the back flanks are contacts when the run does not say
#: (``RunSettings.back_flanks`` None): a pair with less is taken as the nominal tight pair
#: whose back flanks are not modelled (docs/sector.md, 6.7).
BACKLASH_FLOOR = 1e-9


def back_flanks_on(pair: GearPair, settings: RunSettings) -> bool:
    """Whether the run's back flanks are contacts: as ``settings.back_flanks`` says, or by
    default where the pair has backlash (more than :data:`BACKLASH_FLOOR`)."""
    if settings.back_flanks is not None:
        return bool(settings.back_flanks)
    return pair.backlash_normal > BACKLASH_FLOOR


def cycles_limit(settings: RunSettings) -> int:
    """Most mesh cycles a sector run may go on to if it has not settled (``max_cycles``; by
    default :data:`~spurdyn.settings.SETTLE_CYCLES_FACTOR` times its cycles on whole gears,
    and on a sector of teeth, which covers only the cycles asked, those)."""
    settings = with_defaults(settings)
    cycles = int(settings.cycles)
    if settings.max_cycles is None and cycles < WHOLE_FROM_CYCLES:
        return cycles
    return int(settings.cycles_limit or cycles)


def cover_cycles(settings: RunSettings, most: int | None = None) -> int:
    """The mesh cycles' worth of teeth a sector run carries contacts for: its
    :func:`cycles_limit` (or ``most`` where the run goes further: a faulty pair's whole
    revolutions), and under a torque history half as many more (at least 2), as the gears
    may run ahead of their nominal speed (docs/sector.md, 6.8)."""
    most = cycles_limit(settings) if most is None else most
    return most if settings.torque_history is None else most + max(2, -(-most // 2))


def full_coordinates(pair: GearPair, settings: RunSettings) -> int:
    """The coordinates of a run's whole finite-element bodies (``bodies = "full"``): the free
    DOFs of both gears' meshed teeth and rims, as the run meshes them (the teeth it carries:
    :func:`~spurdyn.sector.system.teeth_for`), and the two hubs' rotations. Meshed, not
    assembled: 0.1-0.3 s for the paper's whole gears."""
    from spurdyn.sector.body import sector_body
    from spurdyn.sector.statics import driving_pair
    from spurdyn.sector.system import teeth_for

    settings = with_defaults(settings)
    dp = driving_pair(pair)
    teeth = teeth_for(dp, cover_cycles(settings), back_flanks_on(dp, settings), settings.teeth)
    return 2 + sum(sector_body(gear, min(count, gear.teeth), settings.nx, settings.ny,
                               first=first, grading=settings.grading).free_dofs.size
                   for gear, (first, count) in zip((dp.gear_a, dp.gear_b), teeth))


#: Samples per mesh cycle of the coordinates the teeth's root stress is recovered from
#: (docs/sector.md, 6.11): the sampled peak of a tooth's stress, a corner at the end of its
#: single contact, lies below the true one by at most the stress's rise over a sample's
#: interval, measured below 0.2 % at this many.
STRESS_SAMPLES = 100


def stress_steps(per_cycle: int, n_steps: int) -> NDArray[np.intp]:
    """The steps of a run of ``n_steps`` (a whole number of cycles of ``per_cycle`` steps)
    whose coordinates are kept: :data:`STRESS_SAMPLES` a cycle (every step of a coarser
    cycle), the nearest steps to evenly spaced phases, the same in every cycle."""
    n = min(STRESS_SAMPLES, per_cycle)
    rows = np.arange(n_steps * n // per_cycle + 1)
    cycle, j = np.divmod(rows, n)
    # the nearest step to phase j / n, halves up, in whole numbers: the same every cycle
    return (cycle * per_cycle + (2 * j * per_cycle + n) // (2 * n)).astype(np.intp)


def steps_per_cycle(speed: float, teeth: int, dt: float | None = None) -> int:
    """Steps per mesh cycle ``2 pi / (z omega)``: a whole number, so that every cycle is
    sampled at the same phases, giving a step no longer than ``dt`` (by default the
    smaller of a tenth of the period of :data:`KEEP_FREQUENCY` and 1/:data:`STEPS_PER_MESH_PERIOD`
    of the cycle)."""
    period = 2.0 * math.pi / (teeth * abs(speed))
    if dt is None:
        dt = min(1.0 / (STEPS_PER_KEPT_PERIOD * KEEP_FREQUENCY), period / STEPS_PER_MESH_PERIOD)
    return max(int(math.ceil(period / dt - 1e-9)), 1)


__all__ = ["BACKLASH_FLOOR", "BODY_DAMPING_FREQUENCY", "BODY_DAMPING_RATIO", "CYCLE_POSITIONS", "DEFAULT_CYCLES",
           "KEEP_FREQUENCY", "MESH_DAMPING_RATIO", "SECTOR_REVISION", "STEPS_PER_KEPT_PERIOD", "STEPS_PER_MESH_PERIOD",
           "STRESS_SAMPLES", "back_flanks_on", "body_rayleigh", "cover_cycles", "cycles_limit", "mesh_damping",
           "steps_per_cycle", "stress_steps", "with_defaults"]
