"""The models a run or a sweep can use, by name, and the rules each owns:
``MODELS = {"fe": ..., "lumped": ..., "sector": ...}`` (SciPy's ``METHODS``, a name to an
object with its capabilities).

Each entry is a :class:`ModelEntry`: called as ``MODELS[name](pair, settings, progress)`` it
refuses what it cannot run and simulates; it says which settings it reads (declared once,
beside each field of :class:`~spurdyn.settings.RunSettings`) and refuses the others in
one line naming the key, and gives its default step, its size estimate, what a sweep's
settings hash carries for it, and its capabilities (tooth frames, a steady state). Nothing
outside this module asks a model's name what it can do. The solvers are imported when
first called, so importing this registry stays cheap; the entries pickle by reference
(worker processes take them).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field, fields
from typing import Any, Callable, Mapping, Protocol

from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.lumped.sources import sector_cycle, tooth_table
from spurdyn.result import Result
from spurdyn.settings import (MODEL_NAMES, SECTOR_ROW_GRADING_REASON, RunSettings, refuse_sector_row_grading,
                              setting_keys, settings_read_by)
from spurdyn.solvers.limits import Size, estimate

Progress = Callable[[int, float, float], None]
#: The case keys given on the command line -> how to name them (``{"run.dt": "--dt"}``);
#: ``None`` for settings built in Python, where a setting is given when it is not its default.
Labels = Mapping[str, str] | None


class Simulate(Protocol):
    def __call__(self, pair: GearPair, settings: RunSettings,
                 progress: Progress | None = None) -> Result: ...


#: Each setting's default (what a run that does not give it has).
DEFAULTS = {f.name: f.default for f in fields(RunSettings)}

#: Why the FE model refuses the sector stiffness.
FE_STIFFNESS_REASON = ("is the lumped model's: the FE model's stiffness is its own teeth's "
                       "(use --model lumped)")
#: Why the FE model refuses ``cycles``.
FE_CYCLES_REASON = ("needs a model that meshes for more than one engagement: the paper's "
                    "one-tooth FE model covers one (use --model sector or --model lumped)")
#: Why the FE solver's RK4 refuses damping.
FE_DAMPING_REASON = ("needs the implicit integrator in the FE model: the paper's RK4 is "
                     "undamped (use --integrator implicit, --model lumped, or no damping)")
#: Why the lumped model's steady state refuses an angle.
LUMPED_ANGLE_REASON = ("is one engagement's rotation; a steady state runs its mesh cycles "
                       "(--cycles): leave out one of them")
#: Why a model without several teeth refuses ``teeth``.
TEETH_REASON = ("sets the sector model's teeth per gear (--model sector, or the lumped model's "
                "--stiffness sector); {model} would not read it")
#: Why the sector model refuses a time step, another integrator or another contact.
SECTOR_DT_REASON = ("the sector model sets its own step of accuracy (docs/sector.md, 6.3); "
                    "leave it out")
SECTOR_INTEGRATOR_REASON = "the sector model steps by generalized-alpha only; leave it out or give implicit"
SECTOR_TORQUE_REASON = ("must be above zero for the sector model: its run starts from the loaded "
                        "static mesh cycle and its steady state is measured against it (a torque "
                        "history's mean torque); an unloaded pair runs with --model lumped")
SECTOR_CONTACT_REASON = "the sector model's contact is the Hertzian strip; leave it out or give hertz"


def label(name: str, labels: Labels) -> str:
    """How to name setting ``name`` in a refusal: the option or key the user wrote, else its
    own case key (the field's name for settings built in Python)."""
    if labels is None:
        return name
    keys = setting_keys(name)
    return next((labels[k] for k in keys if k in labels), keys[0] if keys else name)


def given(name: str, settings: RunSettings, labels: Labels) -> bool:
    """Whether the user gave setting ``name``: on the command line (``labels``), or for
    settings built in Python (``labels`` None), a value other than its default."""
    if labels is None:
        return bool(getattr(settings, name) != DEFAULTS[name])
    return any(k in labels for k in setting_keys(name))


@dataclass(frozen=True)
class ModelEntry:
    """A model of the registry: its solver and the rules it owns.

    Attributes
    ----------
    name
        Its name (one of :data:`~spurdyn.settings.MODEL_NAMES`).
    solver
        ``"module:function"`` of its simulate function, imported when first called.
    title
        How refusals name it ("the sector model").
    reasons
        Why it refuses a setting it does not read, by field (a plain reason for the others),
        in the order it checks them (before the others).
    fixed
        Settings it does not read because it fixes them: the value it fixes is no refusal.
    strict
        Settings it does not read that are refused wherever they were given (a case file
        too), not only on the command line.
    keeps_frames
        Whether its runs keep tooth frames (``--vtu``, the size of a run).
    """

    name: str
    solver: str
    title: str
    reasons: Mapping[str, str] = field(default_factory=dict)
    fixed: Mapping[str, Any] = field(default_factory=dict)
    strict: tuple[str, ...] = ()
    keeps_frames: bool = False

    @property
    def reads(self) -> tuple[str, ...]:
        """The settings it reads (:func:`~spurdyn.settings.settings_read_by`)."""
        return settings_read_by(self.name)

    @property
    def unread(self) -> tuple[str, ...]:
        """The settings it does not read: each refused when given."""
        reads = set(self.reads)
        return tuple(f.name for f in fields(RunSettings) if f.name not in reads)

    def __call__(self, pair: GearPair, settings: RunSettings, progress: Progress | None = None) -> Result:
        """Refuse what the model cannot run, wherever it was given; run it with its defaults."""
        self.refuse(settings, {}, pair)
        module, name = self.solver.split(":")
        return getattr(importlib.import_module(module), name)(pair, self.with_defaults(settings), progress)

    def with_defaults(self, settings: RunSettings) -> RunSettings:
        """``settings`` with the model's own defaults where the run gives none (none here)."""
        return settings

    def refuse(self, settings: RunSettings, labels: Labels = None, pair: GearPair | None = None) -> None:
        """Refuse, in one line naming the key the user wrote (``labels``) and the fix, a
        setting it does not read that was given, and what it cannot do with the others
        (:meth:`check`; given the ``pair``, what depends on it)."""
        # those it gives a reason for first, in its order (the refusals' order of before)
        for name in (*self.reasons, *(n for n in self.unread if n not in self.reasons)):
            value = getattr(settings, name)
            if name in self.fixed and value == self.fixed[name]:
                continue
            wherever = labels is None or name in self.strict
            if (value == DEFAULTS[name]) if wherever else not given(name, settings, labels):
                continue
            readers = [m for m in MODEL_NAMES if name in settings_read_by(m)]
            raise InputError(label(name, labels), self.reasons.get(name) or
                             f"the {self.title} does not read it: leave it out, or run a model "
                             f"that does (--model {'|'.join(readers)})")
        self.check(settings, labels, pair)

    def check(self, settings: RunSettings, labels: Labels, pair: GearPair | None) -> None:
        """What the model cannot do with settings it reads (none by default)."""

    def default_step(self, settings: RunSettings, pair: GearPair) -> float:
        """The time step (s) of a run that gives none."""
        from spurdyn.solvers.check import default_step

        return default_step(settings, pair)

    def size(self, case: Any) -> Size:
        """What a case will cost (:func:`spurdyn.solvers.limits.check_size` refuses too
        much): one engagement along its ``dt``."""
        return estimate(case, frames=self.keeps_frames, steps_capped=False)

    def hash_extras(self, settings: RunSettings) -> dict[str, Any]:
        """What a sweep's settings hash carries beside the case's settings: the defaults a
        run takes where the case gives nothing (a steady state's most cycles)."""
        if settings.cycles is not None and settings.max_cycles is None:
            return {"cycles_limit": settings.cycles_limit}
        return {}

    def steady(self, settings: RunSettings) -> bool:
        """Whether the run is a steady state of mesh cycles (else one engagement)."""
        return settings.cycles is not None

    def sector_stiffness(self, settings: RunSettings) -> bool:
        """Whether the run's mesh stiffness is the sector model's mesh cycle."""
        return settings.stiffness == "sector"

    def refuse_continuation(self, case: Any) -> None:
        """Refuse, naming ``--continuation``, a case a continuation sweep cannot carry."""

    def compiles(self, settings: RunSettings) -> bool:
        """Whether a first run would compile the solver first (worth a word beforehand)."""
        return False

    def compile_seconds(self, settings: RunSettings) -> float:
        """About how long that compiling takes (seconds, measured on this project's machine)."""
        return 0.0


@dataclass(frozen=True)
class FEEntry(ModelEntry):
    """The paper's FE contact model: one tooth pair over one engagement
    (:func:`spurdyn.solvers.loop.simulate`)."""

    def check(self, settings: RunSettings, labels: Labels, pair: GearPair | None) -> None:
        """Damping the explicit integrator does not carry; a load lost in the rounding of
        the teeth's positions (zero is a load: an unloaded run, its dynamic factor none)."""
        if pair is not None and settings.torque > 0.0:
            _refuse_rounding_torque(pair, settings.torque, label("torque", labels),
                                    unloaded="; or 0 for an unloaded run")
        if settings.damped and settings.integrator == "rk4":
            name = ("damping_ratio" if settings.mesh_damping > 0.0 else "rayleigh_mass"
                    if settings.rayleigh[0] > 0.0 else "rayleigh_stiffness")
            raise InputError(label(name, labels), FE_DAMPING_REASON)

    def size(self, case: Any) -> Size:
        return estimate(case, frames=True, steps_capped=True)

    def compiles(self, settings: RunSettings) -> bool:
        if settings.backend != "numba":
            return False
        from spurdyn.solvers.warmup import needs_compiling

        return bool(needs_compiling(settings))

    def compile_seconds(self, settings: RunSettings) -> float:
        from spurdyn.solvers.warmup import compile_seconds

        return compile_seconds(settings)


@dataclass(frozen=True)
class LumpedEntry(ModelEntry):
    """Two disks on a mesh spring, damped by the run's ``damping_ratio``
    (:func:`simulate_lumped`)."""

    def check(self, settings: RunSettings, labels: Labels, pair: GearPair | None) -> None:
        if settings.cycles is not None and settings.angle is not None:
            raise InputError(label("angle", labels), LUMPED_ANGLE_REASON)
        if settings.stiffness == "sector":
            refuse_sector_row_grading(settings.row_grading, label("row_grading", labels),
                                      "with the sector stiffness (stiffness = \"sector\"), ")
        if settings.teeth is None:
            return
        if settings.stiffness != "sector":
            raise InputError(label("teeth", labels),
                             TEETH_REASON.format(model="the lumped model with the tooth's stiffness"))
        if pair is not None:
            from spurdyn.sector.statics import driving_pair, pairs_in_path

            need = pairs_in_path(driving_pair(pair))
            if settings.teeth < need:
                raise InputError(label("teeth", labels), f"must be at least the {need} teeth "
                                 f"that carry load together (got {settings.teeth})")


    def size(self, case: Any) -> Size:
        """One engagement along its ``dt``; a steady state, the samples of the most cycles it
        may go on to (:func:`spurdyn.lumped.steady.samples_per_cycle`)."""
        if case.run.cycles is None:
            return super().size(case)
        from spurdyn.lumped.steady import samples_per_cycle
        from spurdyn.sector.rules import DEFAULT_CYCLES

        run = case.run
        period = 2.0 * math.pi / (case.pair.gear_a.teeth * run.speed_a)
        most = max(run.cycles_limit or run.cycles, run.cycles)
        default = run.with_(cycles=DEFAULT_CYCLES, max_cycles=None).cycles_limit
        return cycles_size(case, samples_per_cycle(period), most, default, LUMPED_STEPS_PER_S)


#: Steps a second of the sector model, for the time a refusal of a long run estimates: on
#: whole modal gears, compiled (docs/sector.md: 70-120 us a step on the paper's pair), and on
#: a sector of teeth, in the NumPy loop (measured: 64,284 steps in 128 s, the paper's pair at
#: 1 rpm, build included, this project's 2-core machine).
SECTOR_STEPS_PER_S = 10_000
SECTOR_TEETH_STEPS_PER_S = 500
#: Samples a second of the lumped model's steady state, whose size counts samples (its
#: integrator takes about seven steps a sample; measured: paper-fig8 at 4,000 rpm, 200 cycles,
#: 107,201 samples in 21 s).
LUMPED_STEPS_PER_S = 5_000


#: Seconds a step of the sector model's whole bodies takes per coordinate (the NumPy loop,
#: whose solve of the whole stiffness grows with them; the modal bodies' does not): measured
#: by the difference of two runs' steps, 24.5 ms a step on 2 x 8 teeth over one cycle
#: (25,474 coordinates, 0.96 us each) and 45.0 ms on the paper's whole gears (55,554, 0.81 us);
#: the larger, so that a refusal does not promise less time than a run takes
#: (docs/cli.md, "Limits").
FULL_STEP_S_PER_COORDINATE = 0.96e-6


def full_bodies_size(case: Any, size: Size) -> Size:
    """``size`` of a sector run on whole bodies: its steps at the rate their coordinates
    allow (:data:`FULL_STEP_S_PER_COORDINATE`, the model's rate at most), bounded by the time
    :data:`~spurdyn.solvers.limits.MAX_SECONDS` rather than the step count, blaming
    ``bodies``."""
    from dataclasses import replace

    from spurdyn.sector.rules import full_coordinates
    from spurdyn.solvers.limits import MAX_SECONDS

    n = full_coordinates(case.pair, case.run)
    rate = min(size.steps_per_s, 1.0 / (FULL_STEP_S_PER_COORDINATE * n))
    return replace(size, steps_per_s=rate, most_steps=int(MAX_SECONDS * rate), blame="bodies",
                   remedy=f"a step of the whole bodies ({n:,} coordinates) takes about "
                   f"{1e3 / rate:.2g} ms: give modal bodies (bodies = \"modal\", the default)")


def cycles_size(case: Any, per_cycle: int, most: int, default_most: int, rate: float) -> Size:
    """The :class:`~spurdyn.solvers.limits.Size` of a steady state of ``per_cycle`` steps a mesh
    cycle over the ``most`` cycles it may go on to, one sample a step: too many steps blame the
    cycles (``max_cycles`` where given) when the model's default cycles (``default_most`` at
    most) would keep it within the limit, else the speed."""
    from spurdyn.solvers.limits import BYTES_PER_SAMPLE, MAX_STEPS

    steps = per_cycle * most
    cycles_key = "max_cycles" if case.run.max_cycles is not None else "cycles"
    blame = cycles_key if per_cycle * default_most <= MAX_STEPS else "speed_a_rpm"
    return Size(steps, (steps + 1) * BYTES_PER_SAMPLE, sampling=cycles_key, steps_capped=True,
                blame=blame, steps_per_s=rate, remedy="raise the speed, give fewer cycles")


@dataclass(frozen=True)
class SectorEntry(ModelEntry):
    """Several elastic teeth on elastic rims, hubs with inertia, under constant torques
    for ``settings.cycles`` mesh cycles (:func:`spurdyn.solvers.sector.run.simulate_sector`)."""

    def check(self, settings: RunSettings, labels: Labels, pair: GearPair | None) -> None:
        """A mode store the environment describes wrongly (:func:`spurdyn.store.check`);
        given the ``pair``, fewer ``teeth`` than the run meets."""
        from spurdyn import store

        if not settings.torque > 0.0:
            raise InputError(label("torque", labels), SECTOR_TORQUE_REASON)
        if pair is not None:
            _refuse_rounding_torque(pair, settings.torque, label("torque", labels))
        store.check()
        if pair is None or settings.teeth is None:
            return
        from spurdyn.sector.rules import back_flanks_on, cover_cycles
        from spurdyn.sector.statics import driving_pair
        from spurdyn.sector.system import teeth_for

        dp = driving_pair(pair)
        try:
            teeth_for(dp, cover_cycles(settings), back_flanks_on(dp, settings), settings.teeth)
        except InputError as err:
            raise InputError(label("teeth", labels), err.reason) from None

    def with_defaults(self, settings: RunSettings) -> RunSettings:
        """Its mesh cycles where the run gives none (:func:`~spurdyn.sector.rules.with_defaults`)."""
        from spurdyn.sector.rules import with_defaults

        return with_defaults(settings)

    def default_step(self, settings: RunSettings, pair: GearPair) -> float:
        """Its own step of accuracy: a whole number of steps per mesh cycle of the driver
        (:func:`~spurdyn.sector.rules.steps_per_cycle`)."""
        from spurdyn.sector.rules import steps_per_cycle

        speed, teeth = self._driver(settings, pair)
        return 2.0 * math.pi / (teeth * speed) / steps_per_cycle(speed, teeth)

    def size(self, case: Any) -> Size:
        """Every step of the most cycles it may go on to, one sample each, at its own step
        (whatever ``dt`` says)."""
        from spurdyn.sector.rules import DEFAULT_CYCLES, cycles_limit, steps_per_cycle
        from spurdyn.sector.system import WHOLE_FROM_CYCLES

        speed, teeth = self._driver(case.run, case.pair)
        most = cycles_limit(case.run)
        rate = SECTOR_STEPS_PER_S if most >= WHOLE_FROM_CYCLES else SECTOR_TEETH_STEPS_PER_S
        default = case.run.with_(cycles=DEFAULT_CYCLES, max_cycles=None)
        size = cycles_size(case, steps_per_cycle(speed, teeth), most, cycles_limit(default), rate)
        return full_bodies_size(case, size) if case.run.bodies == "full" else size

    def hash_extras(self, settings: RunSettings) -> dict[str, Any]:
        """Its revision, and its defaults where the case gives nothing: the bodies' damping,
        the mesh damper's, the cycles and the most cycles."""
        from spurdyn.sector.rules import SECTOR_REVISION, body_rayleigh, cycles_limit, mesh_damping, with_defaults

        extras: dict[str, Any] = {"sector_revision": SECTOR_REVISION}
        if settings.rayleigh_mass is None and settings.rayleigh_stiffness is None:
            extras["sector_body_rayleigh"] = list(body_rayleigh(settings))
        if settings.damping_ratio is None:
            extras["sector_mesh_damping"] = mesh_damping(settings)[0]
        if settings.cycles is None:
            extras["sector_cycles"] = with_defaults(settings).cycles
        if settings.max_cycles is None:
            extras["cycles_limit"] = cycles_limit(settings)
        return extras

    def steady(self, settings: RunSettings) -> bool:
        return True          # one mesh cycle at least

    def sector_stiffness(self, settings: RunSettings) -> bool:
        return True

    def refuse_continuation(self, case: Any) -> None:
        """Its continuation carries whole gears from one speed to the next."""
        from spurdyn.sector.system import WHOLE_FROM_CYCLES

        if case.run.cycles < WHOLE_FROM_CYCLES:
            raise InputError("--continuation", "carries the sector model's whole gears from one "
                             f"speed to the next: give --cycles {WHOLE_FROM_CYCLES} or more")
        most = max(case.pair.gear_a.teeth, case.pair.gear_b.teeth)
        if case.run.teeth is not None and case.run.teeth < most:
            raise InputError("--continuation", "carries the sector model's whole gears from one "
                             f"speed to the next: leave out --teeth or give {most}")
        if case.run.bearings is not None:   # the model's own start refuses it too, at the second speed
            raise InputError("--continuation", "carries the gears' modal state from one speed to the "
                             "next, not their hubs' translations on bearings: leave out the case's "
                             "[gear_a.bearing] and [gear_b.bearing] tables, or --continuation")

    @staticmethod
    def _driver(settings: RunSettings, pair: GearPair) -> tuple[float, int]:
        """The driver's speed (rad/s) and teeth."""
        driver = pair.gear_a if pair.driver == "a" else pair.gear_b
        return float(settings.speed_a if pair.driver == "a" else settings.speed_b), driver.teeth


def _refuse_rounding_torque(pair: GearPair, torque: float, name: str, unloaded: str = "") -> None:
    """Refuse a torque whose static tooth deflection is lost in the rounding of positions
    (the sector and FE models; ``unloaded`` ends the refusal, where a model runs unloaded).

    The deflection ``F / k`` is above ``F / (E b)`` (a tooth is far softer than a block of
    its face width, ``k ~ E b / 10``); below :data:`~spurdyn.solvers.limits.TOL_MIN_ROUNDINGS`
    times machine epsilon times the centre distance (2e-15 m on the paper's pair, the
    smallest ``tol_disp``) the contact forces are rounding (measured on the paper's pair:
    1e-9 N m ran to a dynamic factor of 0.000, 1e-4 N m to 1.40 as at 1 N m; the FE model's
    Fig. 8 run to 1.35e18 at 1e-20 N m, its peak force the unloaded run's: docs/cli.md, "Limits").
    """
    import sys

    from spurdyn.solvers.limits import TOL_MIN_ROUNDINGS

    driver = pair.gear_a if pair.driver == "a" else pair.gear_b
    floor = TOL_MIN_ROUNDINGS * sys.float_info.epsilon * pair.centre_distance
    least = floor * driver.material.young * driver.face_width * driver.base_radius
    if torque < least:
        raise InputError(name, f"{torque:g} N m deflects the teeth by less than the rounding of "
                         f"positions ({floor:.2g} m); at least {least:.2g} N m{unloaded}")


def simulate_lumped(pair: GearPair, settings: RunSettings,
                    progress: Progress | None = None) -> Result:
    """The lumped model (:func:`spurdyn.lumped.simulate_lumped`), damped by the run's
    ``damping_ratio``.

    The progress callback is called once, at the end (a lumped run takes a fraction of a
    second); a stop signal it raises there is left for the caller, who has the result.
    """
    from spurdyn.lumped import simulate_lumped as lumped

    stiffness = (sector_cycle(pair, settings) if settings.stiffness == "sector"
                 else tooth_table(pair, settings))
    if settings.cycles is not None:
        from spurdyn.lumped.steady import simulate_steady

        result = simulate_steady(pair, settings, stiffness, settings.mesh_damping, settings.cycles)
    else:        # one engagement: the tooth's table (the sector stiffness needs cycles)
        result = lumped(pair, settings, table=stiffness, damping_ratio=settings.mesh_damping)
    if progress is not None and len(result.angle):
        try:
            progress(result.steps, float(result.angle[-1]), float(result.angle[-1]))
        except KeyboardInterrupt:  # the run is done: keep it
            pass
    return result


#: Why the FE and the lumped model refuse a case's faults.
FAULTS_REASON = ("the sector model carries faults (--model sector); `spurdyn stiffness` follows a faulty "
                 "gear over its revolution")

#: Why the FE and the lumped model refuse the hubs' bearings.
BEARINGS_REASON = "the sector model carries the hubs' bearings (--model sector); this model holds the hubs' centres"

#: Model name -> its entry, in the order of :data:`~spurdyn.settings.MODEL_NAMES`.
MODELS: dict[str, ModelEntry] = {
    "fe": FEEntry("fe", "spurdyn.solvers.loop:simulate", "paper's FE model",
                  reasons={"faults": FAULTS_REASON, "stiffness": FE_STIFFNESS_REASON, "cycles": FE_CYCLES_REASON,
                           "teeth": TEETH_REASON.format(model="the paper's FE model"), "bearings": BEARINGS_REASON},
                  strict=("cycles", "teeth", "stiffness", "faults", "bearings"), keeps_frames=True),
    "lumped": LumpedEntry("lumped", "spurdyn.simulators:simulate_lumped", "lumped model",
                          reasons={"faults": FAULTS_REASON, "bearings": BEARINGS_REASON},
                          strict=("faults", "bearings")),
    "sector": SectorEntry("sector", "spurdyn.solvers.sector.run:simulate_sector", "sector model",
                          reasons={"dt": SECTOR_DT_REASON, "integrator": SECTOR_INTEGRATOR_REASON,
                                   "contact": SECTOR_CONTACT_REASON,
                                   "row_grading": SECTOR_ROW_GRADING_REASON},
                          fixed={"integrator": "implicit", "contact": "hertz", "row_grading": 1.0},
                          strict=("row_grading",)),
}


__all__ = ["DEFAULTS", "FE_CYCLES_REASON", "FE_DAMPING_REASON", "FE_STIFFNESS_REASON", "MODELS", "ModelEntry",
           "Progress", "Simulate", "TEETH_REASON", "given", "label", "sector_cycle", "simulate_lumped",
           "tooth_table"]
