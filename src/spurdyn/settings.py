"""What to simulate: the run settings of a dynamic contact analysis (SI units).

The bottom floor of the solvers: it imports only the error type and the mesh defaults.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields, replace
from typing import Any

from spurdyn.errors import InputError
from spurdyn.history import TorqueHistory
from spurdyn.mesh.tooth import (DEFAULT_GRADING, DEFAULT_NX, DEFAULT_NY, DEFAULT_ROW_GRADING,
                               MAX_GRADING, MAX_ROW_GRADING)

#: The paper's time step (s).
PAPER_DT = 3e-8
#: The paper's tolerance on the displacement constraint errors (m).
PAPER_TOL = 1e-12

RPM = 2.0 * math.pi / 60.0

#: ``"paper"``: the paper's method (the constraint iteration of its Appendix B). The
#: ``"pinned"`` fallback for stalls of the point contact on fine meshes was retired when
#: the distributed contact carried every run it was made for (docs/solver.md, section 6).
METHODS = ("paper",)
#: What a case that still asks for the retired method is told.
RETIRED_METHODS = {"pinned": "was retired: the distributed contact (contact = \"hertz\") "
                             "carries the fine meshes it was for (docs/solver.md, section 6)"}
BACKENDS = ("numba", "numpy")
#: Contact models: ``"point"``, the paper's one point pair per tooth pair; ``"hertz"``, the
#: force spread over the Hertzian strip and the gap averaged over it (docs/solver.md,
#: section 11).
CONTACTS = ("point", "hertz")
#: Time integrators (:data:`spurdyn.solvers.loop.STEPPERS`): the paper's classical RK4, and
#: the implicit generalized-alpha scheme (docs/implicit.md).
INTEGRATORS = ("rk4", "implicit")
#: The models a case can ask for (``[model] kind``, ``--model``): the paper's one-tooth FE
#: model, the lumped two-disk model and the sector model of several teeth on their rims
#: (:data:`spurdyn.simulators.MODELS` holds their simulate functions, in this order).
MODEL_NAMES = ("fe", "lumped", "sector")
#: The model of a case file or a Python run that names none (``[model]`` left out, no
#: ``--model``, ``simulate(..., model=None)``): the sector model, whose several elastic teeth
#: on elastic rims carry the load sharing and the stresses an engineer asks for (issue 35).
DEFAULT_MODEL = "sector"
#: The model of the paper's presets (``paper-fig8`` ...), which reproduce the paper.
PAPER_MODEL = "fe"
#: Where the lumped model's mesh stiffness comes from: the paper model's root-clamped tooth
#: pair, or the sector model's quasi-static mesh cycle (docs/sector.md).
STIFFNESSES = ("tooth", "sector")
#: How the sector model steps its bodies: on their modes and the flanks' residual
#: flexibility (fast), or whole (the reference; docs/sector.md, section 6.6).
BODIES = ("modal", "full")
#: Why the sector stiffness needs a steady state (the one place that says it).
SECTOR_STIFFNESS_REASON = ("'sector' is a mesh cycle under constant torques: it needs a "
                           "steady-state run (cycles; --cycles N)")
#: Why the sector model (and the lumped model on its stiffness) refuses rows graded along
#: the tooth.
SECTOR_ROW_GRADING_REASON = ("the sector model meshes its teeth with rows even in radius: leave "
                             "it out (or 1); the FE model and the lumped model on the tooth's "
                             "stiffness take it")


def refuse_sector_row_grading(row_grading: float, key: str = "mesh.row_grading", why: str = "") -> None:
    """Refuse, in one line naming ``key``, rows graded along the tooth where the sector
    model's bodies are meshed (their rows are even in radius: docs/sector.md)."""
    if row_grading != 1.0:
        raise InputError(key, why + SECTOR_ROW_GRADING_REASON)
#: The generalized-alpha scheme's spectral radius at infinite frequency when the run gives
#: none: modes far above the step's resolution lose 20 % of their amplitude a step, the
#: pair's torsional mode a negligible part (docs/implicit.md, "The default").
DEFAULT_RHO_INF = 0.8

#: Largest ``accel_levels``: for the smallest ``eps_1`` the iteration admits (1e-12,
#: :func:`spurdyn.solvers.paper.iteration_numpy.accelerated_update`) the coefficient ``om_n`` of
#: Appendix B falls below the smallest double at ``n = 11`` and ``b_bar`` is infinite;
#: ``A_n e`` also costs ``2^(n-1) - 1`` products, 511 at 10.
MAX_ACCEL_LEVELS = 10
#: Largest ``max_iter``: a stage still iterating after this many iterations has stalled
#: (the paper's cases take tens); more would only spend hours on one step.
MAX_ITER = 100_000
#: Most flank spline points: 32 per element along the flank of the densest tooth mesh
#: (``ny`` <= 256, :func:`spurdyn.mesh.tooth.tooth_mesh`). Each element edge is a quadratic
#: fixed by its three nodes, so denser data describes nothing new.
MAX_SPLINE = 32 * 256 + 1


#: Why each capped whole-number setting stops where it does.
INTEGER_LIMITS = {
    "n_spline": "32 points per element along the densest flank describe each element edge "
                "fully",
    "max_iter": "a stage that needs more has stalled",
    "accel_levels": "beyond it the acceleration coefficients of Appendix B underflow",
}


#: ``(key, lowest, highest or None)`` of the whole-number settings.
INTEGER_BOUNDS = (("n_spline", 8, MAX_SPLINE), ("max_iter", 1, MAX_ITER),
                  ("accel_levels", 1, MAX_ACCEL_LEVELS), ("save_every", 1, None),
                  ("frames_every", 0, None))


#: Most mesh cycles of a steady-state run (20 settle a damped pair many times over).
MAX_CYCLES = 10_000
#: A steady-state run that gives no ``max_cycles`` goes on, if it has not settled after its
#: ``cycles``, up to this many times them: a run settles in time (its transient decays as
#: ``exp(-zeta omega_n t)``), and at high speed a mesh cycle is short (docs/sector.md, 6.5).
SETTLE_CYCLES_FACTOR = 4

#: How a steady-state run starts: ``"static"``, from the static equilibrium of the loaded
#: pair at the first position of a mesh cycle (no start-up oscillation); ``"rest"``, the
#: bodies undeformed at their nominal speeds and the torques ramped up from zero over
#: ``ramp_cycles`` mesh cycles.
STARTS = ("static", "rest")
#: Mesh cycles of the torques' ramp of a run from rest when the run gives none.
DEFAULT_RAMP_CYCLES = 1.0
#: The case keys of the Rayleigh damping (as a ratio at two frequencies, for both coefficients).
RAYLEIGH_RATIO_KEYS = ("run.rayleigh_ratio", "run.rayleigh_hz")
@dataclass(frozen=True)
class Bearing:
    """A hub's radial bearing, isotropic (docs/sector.md, 6.12): ``stiffness`` (N/m) and
    ``damping`` (N s/m) of the force ``-k x - c x_dot`` on the hub's translation ``x``."""

    stiffness: float
    damping: float = 0.0


#: The case keys of the hubs' bearings, gear A's and gear B's.
BEARING_KEYS = ("gear_a.bearing", "gear_b.bearing")


def check_bearings(bearings: Any) -> None:
    """Refuse bearings that are not two (gear A's, gear B's), each a :class:`Bearing` of a
    positive stiffness and a damping >= 0 (or ``None`` for none; both ``None`` is no bearing)."""
    if bearings is None:
        return
    if not isinstance(bearings, tuple) or len(bearings) != 2 or all(b is None for b in bearings):
        raise InputError("bearings", f"must be gear A's and gear B's Bearing, at least one (got {bearings!r})")
    for key, b in zip(BEARING_KEYS, bearings):
        if b is None:
            continue
        for name, lo in (("stiffness", 0.0), ("damping", None)):
            v = getattr(b, name, None)
            if (not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v)
                    or (v <= 0.0 if lo is not None else v < 0.0)):
                what = "a positive number of N/m" if lo is not None else "a number of N s/m >= 0"
                raise InputError(f"{key}.{name}", f"must be {what} (got {v!r})")


#: The case keys of a torque history.
HISTORY_KEYS = ("run.torque_history", "run.torque_history_periodic")


def _setting(default: Any, *models: str, keys: tuple[str, ...] | None = None) -> Any:
    """A :class:`RunSettings` field read by ``models`` (every model when none is named),
    given in a case file or on the command line as ``keys`` (``run.<name>`` by default):
    who reads each setting is declared once, here (:func:`settings_read_by`)."""
    return field(default=default, metadata={"models": models or MODEL_NAMES, "keys": keys})


@dataclass(frozen=True)
class RunSettings:
    """Settings of one run of the dynamic contact solver.

    The fields come in sections: what every model reads, then each model's own options.
    Which models read a field is declared once, beside it (:func:`settings_read_by`); a
    model's registry entry (:data:`spurdyn.simulators.MODELS`) refuses the others when
    they are given (docs/architecture.md, "Models that own their rules").

    Parameters
    ----------
    speed_a, speed_b
        Initial angular speeds (rad/s) of gears A and B, each positive along its own
        sense of rotation (A clockwise, B counter-clockwise).
    torque
        External torque ``tau_0`` on the driver (N m). The driven gear's load torque is
        ``tau_0 r_b,driven / r_b,driver``. Both follow the paper's Fig. 7 schedule.
    dt
        Time step (s).
    angle
        Rotation of gear A to simulate (rad), from the start of contact; ``None`` is the
        angle of action ``theta_s``.
    nx, ny
        Q8 elements across and along each tooth.
    grading
        How much thinner the outline columns of each tooth mesh are than its middle ones
        (1: even; :func:`spurdyn.mesh.tooth.thickness_spacing`).
    row_grading
        How much taller the fillet rows of each tooth mesh are than its flank rows (1: rows
        even in radius from the fillet cut to the tip; :func:`spurdyn.mesh.tooth.row_radii`).
        The FE model and the lumped model on the tooth's stiffness; the sector model refuses
        it (:data:`SECTOR_ROW_GRADING_REASON`).
    n_spline
        Data points of each flank spline.
    tol_disp
        Tolerance of the displacement stage (m); the velocity and acceleration stages use
        ``tol_disp / dt`` and ``tol_disp / dt**2``.
    max_iter
        Iteration cap of each stage in each step.
    accel_levels
        The integer ``n`` of the accelerated iteration (Appendix B).
    method
        ``"paper"``: the accelerated iteration of Appendix B with ``C = c G M^-1 G^T``
        (the one of :data:`METHODS`).
    backend
        ``"numba"`` (compiled, superposed) or ``"numpy"`` (the straightforward reference);
        the lumped model's steady right-hand side compiled or in Python.
    contact
        ``"hertz"`` (the distributed contact, the default: it holds at design loads and
        its stiffness converges with the mesh) or ``"point"`` (the paper's, which its
        presets use), one of :data:`CONTACTS`.
    integrator
        The time integrator, one of :data:`INTEGRATORS`.
    damping_ratio
        Viscous damping ratio of the pair's torsional mode, by a mesh damper along the
        line of action acting in contact. ``None`` (not given): the model's default, none
        for the FE and the lumped model (the paper's undamped pair), the sector model's
        :data:`spurdyn.sector.rules.MESH_DAMPING_RATIO`; give 0 for none. The FE model takes
        it with the implicit integrator only (:data:`spurdyn.simulators.FE_DAMPING_REASON`).
    rho_inf
        Spectral radius at infinite frequency of the implicit integrator (1: no
        numerical dissipation, 0: the most), :data:`DEFAULT_RHO_INF`.
    cycles
        Mesh cycles of a steady-state run under constant torques (``None``: the lumped
        model's one engagement with the paper's torque ramps; the sector model's
        :data:`spurdyn.sector.rules.DEFAULT_CYCLES`). The lumped and the sector model.
    max_cycles
        Most mesh cycles of a steady-state run: one that has not settled after ``cycles``
        goes on, cycle by cycle, until it settles or has run these (``None``: the model's
        default, :data:`SETTLE_CYCLES_FACTOR` times ``cycles``; equal to ``cycles`` for a run
        of exactly ``cycles``).
    stiffness
        The lumped model's mesh stiffness, one of :data:`STIFFNESSES`: ``"tooth"`` the
        paper model's root-clamped tooth pair (point or Hertzian per ``contact``),
        ``"sector"`` the sector model's quasi-static mesh cycle (needs ``cycles``).
    bodies
        The sector model's bodies, one of :data:`BODIES`: ``"modal"`` their modes and the
        flanks' residual flexibility, ``"full"`` the whole finite-element bodies.
    back_flanks
        Whether the sector model's back flanks are contacts too (backlash and rattle): ``None``
        where the pair has backlash (:func:`spurdyn.solvers.sector.run.back_flanks_on`).
    start
        How a steady-state run starts, one of :data:`STARTS`: from the static equilibrium
        of the loaded pair, or from rest with the torques ramped up.
    ramp_cycles
        Mesh cycles over which a run from rest ramps its torques up linearly (``None``:
        :data:`DEFAULT_RAMP_CYCLES`).
    torque_history
        The torques against time (:class:`TorqueHistory`) instead of constant ones; the run's
        ``torque`` stays the nominal one the static start, the mesh damper and the dynamic
        factor refer to. A run under a history lasts its ``cycles`` (no settled test).
    teeth
        The sector model's teeth per gear: ``None`` those the run meets and a neighbour on
        each side (:func:`spurdyn.sector.system.teeth_for`); the gear's number of
        teeth or more, the whole gear.
    start_state
        Where a steady-state run starts instead of the static compression: the
        transmission error ``delta`` (m) and its slope ``d delta / d phi_A`` (m/rad) at the
        start of a mesh cycle, as another run ended (``info["steady"]["end_state"]``); what a
        sweep with continuation passes from one speed to the next. The sector model's is its
        whole state per angle (:func:`spurdyn.sector.state.pack_state`,
        ``info["sector_end_state"]``).
    rayleigh_mass, rayleigh_stiffness
        Rayleigh damping ``C = a M + b K`` of the elastic teeth (``a`` in 1/s, ``b`` in
        s), acting on their deformation rate in the disk frame (implicit integrator).
        ``None`` (neither given): the model's default, none for the paper's model, the
        sector model's bodies' structural damping
        (:data:`spurdyn.solvers.sector.run.BODY_DAMPING_RATIO`); give 0 for none.
    save_every
        Keep every k-th step in the time history.
    frames_every
        Keep the tooth nodal displacements every m-th step (0: none).
    keep_theta_term
        Keep the second-order elastic torque ``-(dw/dtheta)^T K w`` on the disks.
    name
        A name for the run.
    faults
        The case's faults (:class:`spurdyn.geometry.fault.Fault`, its ``[[fault]]``
        tables): the sector model carries them on its whole gears (docs/faults.md, "Faults
        in motion").
    bearings
        The hubs' radial bearings, gear A's and gear B's (:class:`Bearing`, ``None`` for a
        hub whose centre is held), or ``None``: both centres held (docs/sector.md, 6.12).
    """

    # Every model reads these.
    speed_a: float = _setting(MISSING, keys=("run.speed_a_rpm",))
    speed_b: float = _setting(MISSING, keys=("run.speed_b_rpm",))
    torque: float = _setting(MISSING)
    nx: int = _setting(DEFAULT_NX, keys=("mesh.nx",))
    ny: int = _setting(DEFAULT_NY, keys=("mesh.ny",))
    grading: float = _setting(DEFAULT_GRADING, keys=("mesh.grading",))
    damping_ratio: float | None = _setting(None)
    name: str = _setting("run", keys=())
    # One engagement along a time step: the FE model, and the lumped model's.
    dt: float = _setting(PAPER_DT, "fe", "lumped")
    angle: float | None = _setting(None, "fe", "lumped", keys=("run.angle_deg",))
    row_grading: float = _setting(DEFAULT_ROW_GRADING, "fe", "lumped", keys=("mesh.row_grading",))
    n_spline: int = _setting(61, "fe", "lumped")
    contact: str = _setting("hertz", "fe", "lumped")
    save_every: int = _setting(1, "fe", "lumped")
    # The FE model's own: its constraint iteration, time integrator and tooth frames.
    tol_disp: float = _setting(PAPER_TOL, "fe")
    max_iter: int = _setting(500, "fe")
    accel_levels: int = _setting(3, "fe")
    method: str = _setting("paper", "fe")
    integrator: str = _setting("rk4", "fe")
    frames_every: int = _setting(100, "fe")
    keep_theta_term: bool = _setting(True, "fe")
    # Elastic bodies stepped by generalized-alpha: the FE model (implicit) and the sector model.
    backend: str = _setting("numba", "fe", "sector", "lumped")
    rho_inf: float = _setting(DEFAULT_RHO_INF, "fe", "sector")
    rayleigh_mass: float | None = _setting(None, "fe", "sector", keys=("run.rayleigh_mass", *RAYLEIGH_RATIO_KEYS))
    rayleigh_stiffness: float | None = _setting(None, "fe", "sector",
                                                keys=("run.rayleigh_stiffness", *RAYLEIGH_RATIO_KEYS))
    # Mesh cycles of a steady state: the lumped and the sector model.
    cycles: int | None = _setting(None, "lumped", "sector")
    max_cycles: int | None = _setting(None, "lumped", "sector")
    teeth: int | None = _setting(None, "lumped", "sector")
    start: str = _setting("static", "lumped", "sector")
    ramp_cycles: float | None = _setting(None, "lumped", "sector")
    torque_history: TorqueHistory | None = _setting(None, "lumped", "sector", keys=HISTORY_KEYS)
    start_state: tuple[float, ...] | None = _setting(None, "lumped", "sector", keys=())
    # The lumped model's own.
    stiffness: str = _setting("tooth", "lumped")
    # The sector model's own.
    bodies: str = _setting("modal", "sector")
    back_flanks: bool | None = _setting(None, "sector")
    faults: tuple[Any, ...] = _setting((), "sector", keys=("fault",))
    bearings: tuple[Bearing | None, Bearing | None] | None = _setting(None, "sector", keys=BEARING_KEYS)

    def __post_init__(self) -> None:
        """Refuse a setting out of its range, naming its key, in the order of the fields' checks."""
        self._check_numbers()
        self._check_cycles_and_stepper()
        self._check_steady_state()
        check_bearings(self.bearings)

    def _check_numbers(self) -> None:
        """Refuse a speed, step, torque, angle, whole number, grading or damping out of range."""
        for key in ("speed_a", "speed_b", "dt", "tol_disp"):
            v = getattr(self, key)
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) or v <= 0:
                raise InputError(key, f"must be a positive number (got {v!r})")
        if not isinstance(self.torque, (int, float)) or not math.isfinite(self.torque) or self.torque < 0:
            raise InputError("torque", f"must be a number >= 0 (got {self.torque!r})")
        if self.angle is not None and (not math.isfinite(self.angle) or self.angle <= 0):
            raise InputError("angle", f"must be a positive angle (got {self.angle!r})")
        for key, lo, hi in INTEGER_BOUNDS:
            v = getattr(self, key)
            if not isinstance(v, int) or isinstance(v, bool) or v < lo:
                raise InputError(key, f"must be a whole number >= {lo} (got {v!r})")
            if hi is not None and v > hi:
                raise InputError(key, f"must be at most {hi:,} (got {v:,}): {INTEGER_LIMITS[key]}")
        g = self.grading
        if (not isinstance(g, (int, float)) or isinstance(g, bool) or not math.isfinite(g)
                or not DEFAULT_GRADING <= g <= MAX_GRADING):
            raise InputError("grading", f"must be a number from 1 (even) to {MAX_GRADING:g} "
                             f"(got {g!r})")
        g = self.row_grading
        if (not isinstance(g, (int, float)) or isinstance(g, bool) or not math.isfinite(g)
                or not DEFAULT_ROW_GRADING <= g <= MAX_ROW_GRADING):
            raise InputError("row_grading", f"must be a number from 1 (even rows) to "
                             f"{MAX_ROW_GRADING:g} (got {g!r})")
        z = self.damping_ratio
        if z is not None and (not isinstance(z, (int, float)) or isinstance(z, bool) or not math.isfinite(z)
                or not 0.0 <= z < 1.0):
            raise InputError("damping_ratio", f"must be a number from 0 to below 1 (got {z!r})")
        for key in ("rayleigh_mass", "rayleigh_stiffness"):
            v = getattr(self, key)
            if v is None:
                continue
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) or v < 0:
                raise InputError(key, f"must be a number >= 0 (got {v!r})")

    def _check_cycles_and_stepper(self) -> None:
        """Refuse bad ``cycles``/``max_cycles`` and an unknown stepper, contact or backend."""
        n = self.cycles
        if n is not None and (not isinstance(n, int) or isinstance(n, bool) or not 1 <= n <= MAX_CYCLES):
            raise InputError("cycles", f"must be a whole number from 1 to {MAX_CYCLES:,} (got {n!r})")
        m = self.max_cycles
        if m is not None:
            if not isinstance(m, int) or isinstance(m, bool) or not 1 <= m <= MAX_CYCLES:
                raise InputError("max_cycles", f"must be a whole number from 1 to {MAX_CYCLES:,} (got {m!r})")
            if n is None:
                raise InputError("max_cycles", "bounds a steady-state run: give its cycles too (--cycles N)")
            if m < n:
                raise InputError("max_cycles", f"must be at least the run's cycles, {n} (got {m})")
        r = self.rho_inf
        if not isinstance(r, (int, float)) or isinstance(r, bool) or not 0.0 <= r <= 1.0:
            raise InputError("rho_inf", f"must be a number from 0 to 1 (got {r!r})")
        if self.method in RETIRED_METHODS:
            raise InputError("method", f"{self.method!r} {RETIRED_METHODS[self.method]}")
        if self.method not in METHODS:
            raise InputError("method", f"must be one of {', '.join(METHODS)} (got {self.method!r})")
        if self.backend not in BACKENDS:
            raise InputError("backend", f"must be one of {', '.join(BACKENDS)} (got {self.backend!r})")
        if self.contact not in CONTACTS:
            raise InputError("contact", f"must be one of {', '.join(CONTACTS)} (got {self.contact!r})")
        if self.integrator not in INTEGRATORS:
            raise InputError("integrator", f"must be one of {', '.join(INTEGRATORS)} "
                             f"(got {self.integrator!r})")
        if self.back_flanks is not None and not isinstance(self.back_flanks, bool):
            raise InputError("back_flanks", f"must be true or false (got {self.back_flanks!r})")

    def _check_steady_state(self) -> None:
        """Refuse a start, ramp, torque history, body or stiffness model the run cannot take."""
        k = self.teeth
        if k is not None and (not isinstance(k, int) or isinstance(k, bool) or k < 1):
            raise InputError("teeth", f"must be a whole number >= 1 (got {k!r})")
        if self.start not in STARTS:
            raise InputError("start", f"must be one of {', '.join(STARTS)} (got {self.start!r})")
        rc = self.ramp_cycles
        if rc is not None:
            if not isinstance(rc, (int, float)) or isinstance(rc, bool) or not math.isfinite(rc) or rc <= 0:
                raise InputError("ramp_cycles", f"must be a positive number of mesh cycles (got {rc!r})")
            if self.start != "rest":
                raise InputError("ramp_cycles", "ramps the torques of a run from rest: give start = "
                                 "\"rest\" too (--start rest), or leave it out")
        for key, given in (("start", self.start != "static"), ("torque_history", self.torque_history is not None)):
            if given and self.cycles is None:
                raise InputError(key, "is for a run of mesh cycles (the sector and the lumped model): "
                                 "give its cycles too (--cycles N)")
        if self.torque_history is not None:
            if not isinstance(self.torque_history, TorqueHistory):
                raise InputError("torque_history", f"must be a TorqueHistory (got {self.torque_history!r})"[:200])
            if self.max_cycles is not None and self.max_cycles != self.cycles:
                raise InputError("max_cycles", "a run under a torque history lasts its cycles: the "
                                 "settled test is for constant torques; leave max_cycles out")
        if self.bodies not in BODIES:
            raise InputError("bodies", f"must be one of {', '.join(BODIES)} (got {self.bodies!r})")
        if self.stiffness not in STIFFNESSES:
            raise InputError("stiffness", f"must be one of {', '.join(STIFFNESSES)} "
                             f"(got {self.stiffness!r})")
        s = self.start_state
        if s is not None and (len(s) < 2 or not all(isinstance(v, float) and math.isfinite(v) for v in s)):
            raise InputError("start_state", f"must be finite numbers, two for the lumped model (got {s!r})"[:200])
        if self.stiffness == "sector" and self.cycles is None:
            raise InputError("stiffness", SECTOR_STIFFNESS_REASON)

    @property
    def cycles_limit(self) -> int | None:
        """Most mesh cycles the run may go on to if it has not settled: ``max_cycles``, or
        :data:`SETTLE_CYCLES_FACTOR` times ``cycles`` (``None`` without ``cycles``); under a
        torque history, its ``cycles``."""
        if self.cycles is None:
            return None
        if self.max_cycles is not None or self.torque_history is not None:
            return self.max_cycles or self.cycles
        return min(SETTLE_CYCLES_FACTOR * self.cycles, MAX_CYCLES)

    @property
    def damped(self) -> bool:
        """Whether any damping is asked for (the mesh damper or Rayleigh's)."""
        return self.mesh_damping > 0.0 or any(v > 0.0 for v in self.rayleigh)

    @property
    def mesh_damping(self) -> float:
        """The mesh damper's ratio as given, 0 if not given (the FE and the lumped model's
        default; the sector model's is :func:`spurdyn.sector.rules.mesh_damping`)."""
        return self.damping_ratio or 0.0

    @property
    def rayleigh(self) -> tuple[float, float]:
        """Rayleigh's ``(a, b)`` as given, 0 for one not given (the paper model's default)."""
        return (self.rayleigh_mass or 0.0, self.rayleigh_stiffness or 0.0)

    @property
    def tol_vel(self) -> float:
        return self.tol_disp / self.dt

    @property
    def tol_acc(self) -> float:
        return self.tol_disp / self.dt**2

    def with_(self, **changes: Any) -> "RunSettings":
        """A copy with some settings changed."""
        return replace(self, **changes)


def settings_read_by(model: str) -> tuple[str, ...]:
    """The :class:`RunSettings` fields ``model`` (one of :data:`MODEL_NAMES`) reads, in
    their order of declaration."""
    return tuple(f.name for f in fields(RunSettings) if model in f.metadata["models"])


def setting_keys(name: str) -> tuple[str, ...]:
    """The case keys (``run.dt``, ``mesh.nx``, ...) a setting is given as, the first its
    own; none for one no case gives (``name``, ``start_state``)."""
    meta = next(f.metadata for f in fields(RunSettings) if f.name == name)
    return (f"run.{name}",) if meta["keys"] is None else meta["keys"]
