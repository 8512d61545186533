"""Read gear-pair and run descriptions from TOML files (stdlib ``tomllib``).

A file holds the tables ``[gear_a]``, ``[gear_b]`` (optional: a copy of gear A),
``[pair]`` (optional), ``[mesh]`` (optional) and ``[run]`` (the run settings, needed by
``spurdyn run``); ``examples/paper_pair.toml`` shows every pair key and
``examples/paper_fig8.toml`` every run key. Lengths are in metres, angles in degrees (keys
ending ``_deg``), speeds in rpm (keys ending ``_rpm``), torque in N m, time in s, inertia
in kg m^2, moduli in Pa, density in kg/m^3. A gear table may hold a tip relief:
``tip_relief`` (m), ``tip_relief_start_roll_deg`` (deg) or ``tip_relief_start_radius`` (m),
``tip_relief_shape`` (``"linear"``/``"parabolic"``). Every problem is raised as an
:class:`~spurdyn.errors.InputError` naming the key.

A :class:`Case` (pair + :class:`~spurdyn.solver.case.RunCase`) turns back into the same
dictionary with :func:`case_to_dict`, so a run can store its whole description and be
rebuilt from it (:func:`case_from_dict`).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, Mapping

from spurdyn.errors import InputError
from spurdyn.fem.material import Material
from spurdyn.geometry.gear import DEFAULT_CUTTER_TIP_RADIUS, MAX_MODULE, Gear, GearPair
from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY
from spurdyn.solver.case import BACKENDS, METHODS, RPM, RunCase

GEAR_KEYS = {
    "teeth", "module", "pitch_radius", "tip_radius", "root_radius", "addendum", "dedendum",
    "pressure_angle_deg", "face_width", "disk_inertia", "cutter_tip_radius", "material",
    "tip_relief", "tip_relief_start_roll_deg", "tip_relief_start_radius", "tip_relief_shape",
}
#: Keys that only make sense with ``tip_relief`` in the same table.
RELIEF_KEYS = ("tip_relief_start_roll_deg", "tip_relief_start_radius", "tip_relief_shape")
MATERIAL_KEYS = {"young", "poisson", "density"}
PAIR_KEYS = {"centre_distance", "driver"}
MESH_KEYS = {"nx", "ny"}
RUN_KEYS = {
    "speed_a_rpm", "speed_b_rpm", "torque", "dt", "angle_deg", "n_spline", "tol_disp",
    "max_iter", "accel_levels", "method", "backend", "save_every", "frames_every",
    "keep_theta_term",
}
TOP_KEYS = {"gear_a", "gear_b", "pair", "mesh", "run"}

#: How far past the angle of action ``theta_s`` a run may go (fraction of ``theta_s``):
#: beyond it the tip of A has left B's flank for good and the modelled teeth no longer
#: describe the meshing (the next pair, not modelled, carries the load).
ANGLE_MARGIN = 0.02


@dataclass(frozen=True)
class PairCase:
    """A gear pair and the mesh density to model it with."""

    pair: GearPair
    nx: int = DEFAULT_NX
    ny: int = DEFAULT_NY
    name: str = "pair"


def _check_keys(table: dict[str, Any], allowed: set[str], where: str) -> None:
    for key in table:
        if key not in allowed:
            hint = ", ".join(sorted(allowed))
            raise InputError(f"{where}.{key}" if where else key,
                             f"unknown key; expected one of: {hint}")


def _number(table: dict[str, Any], key: str, where: str, default: float | None = None) -> float:
    if key not in table:
        if default is None:
            raise InputError(f"{where}.{key}", "is missing")
        return default
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}.{key}", f"must be a number (got {value!r})")
    return float(value)


def _integer(table: dict[str, Any], key: str, where: str, default: int | None = None) -> int:
    if key not in table:
        if default is None:
            raise InputError(f"{where}.{key}", "is missing")
        return default
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{where}.{key}", f"must be a whole number (got {value!r})")
    return value


def _one_of(table: dict[str, Any], a: str, b: str, where: str) -> str:
    if a in table and b in table:
        raise InputError(f"{where}.{b}", f"give either {a} or {b}, not both")
    if a not in table and b not in table:
        raise InputError(f"{where}.{a}", f"is missing (or give {b})")
    return a if a in table else b


def material_from_table(table: dict[str, Any], where: str) -> Material:
    """Build a :class:`Material` from a TOML table."""
    if not isinstance(table, dict):
        raise InputError(where, "must be a table with young, poisson and density")
    _check_keys(table, MATERIAL_KEYS, where)
    values = {k: _number(table, k, where) for k in ("young", "poisson", "density")}
    try:
        return Material(**values)
    except InputError as err:
        raise err.prefixed(where) from None
    except ValueError as err:
        raise InputError(where, str(err)) from None


def gear_from_table(table: dict[str, Any], where: str) -> Gear:
    """Build a :class:`Gear` from a TOML table (see the module docstring for units)."""
    if not isinstance(table, dict):
        raise InputError(where, "must be a table")
    _check_keys(table, GEAR_KEYS, where)
    teeth = _integer(table, "teeth", where)
    if teeth < 1:
        raise InputError(f"{where}.teeth", f"must be a positive whole number (got {teeth})")
    size = _one_of(table, "module", "pitch_radius", where)
    module = _number(table, size, where)
    if module <= 0 or not math.isfinite(module):
        raise InputError(f"{where}.{size}", f"must be a positive number (got {module!r})")
    if size == "pitch_radius":
        module = 2.0 * module / teeth
    if module > MAX_MODULE:  # the usual slip: millimetres
        raise InputError(f"{where}.{size}", f"{table[size]:g} m gives a module of {module:g} m, "
                         f"beyond any gear (at most {MAX_MODULE:g} m); lengths are in metres, "
                         "not millimetres")
    r_p = module * teeth / 2.0
    top = _one_of(table, "addendum", "tip_radius", where)
    addendum = _number(table, top, where)
    if top == "tip_radius":
        if not math.isfinite(addendum) or addendum <= r_p:
            raise InputError(f"{where}.tip_radius", f"must be above the pitch radius {r_p:g} m "
                             f"(got {addendum!r})")
        if addendum - r_p > 2.0 * module:
            raise InputError(f"{where}.tip_radius", f"is more than two modules above the pitch "
                             f"radius; at most {r_p + 2.0 * module:g} m")
        addendum -= r_p
    elif not math.isfinite(addendum) or addendum <= 0.0:
        raise InputError(f"{where}.addendum", f"must be a positive number (got {addendum!r})")
    bottom = _one_of(table, "dedendum", "root_radius", where)
    dedendum = _number(table, bottom, where)
    if bottom == "root_radius":
        if not math.isfinite(dedendum) or dedendum <= 0.0:
            raise InputError(f"{where}.root_radius", f"must be a positive number (got {dedendum!r})")
        if dedendum >= r_p:
            raise InputError(f"{where}.root_radius", f"must be below the pitch radius {r_p:g} m")
        if "tip_radius" in table and dedendum >= table["tip_radius"]:
            raise InputError(f"{where}.tip_radius", "must be above root_radius")
        dedendum = r_p - dedendum
    elif not math.isfinite(dedendum) or dedendum <= 0.0:
        raise InputError(f"{where}.dedendum", f"must be a positive number (got {dedendum!r})")
    alpha = _number(table, "pressure_angle_deg", where, 20.0)
    if not 12.0 <= alpha <= 35.0:
        raise InputError(f"{where}.pressure_angle_deg", f"must lie between 12 and 35 (got {alpha:g})")
    material = material_from_table(table["material"], f"{where}.material") \
        if "material" in table else Material(210e9, 0.3, 7800.0)
    # Read outside the try below: their refusals already name the table.
    face_width = _number(table, "face_width", where)
    cutter = _number(table, "cutter_tip_radius", where, DEFAULT_CUTTER_TIP_RADIUS * module)
    inertia = _number(table, "disk_inertia", where)
    base_radius = module * teeth / 2.0 * math.cos(math.radians(alpha))
    relief, start_key = _relief_from_table(table, where, base_radius)
    try:
        return Gear(
            teeth=teeth, module=module, pressure_angle=math.radians(alpha),
            face_width=face_width, addendum=addendum, dedendum=dedendum,
            cutter_tip_radius=cutter, disk_inertia=inertia, material=material, **relief,
        )
    except InputError as err:
        # Name the key the user wrote, not the one it was turned into.
        if err.field == "addendum" and top != "addendum":
            raise InputError(f"{where}.{top}", err.reason) from None
        if err.field == "dedendum" and bottom != "dedendum":
            raise InputError(f"{where}.{bottom}", err.reason) from None
        if err.field == "tip_relief_start_roll":
            raise InputError(f"{where}.{start_key}", err.reason) from None
        raise err.prefixed(where) from None


def _relief_from_table(table: dict[str, Any], where: str,
                       base_radius: float) -> tuple[dict[str, Any], str]:
    """The tip-relief arguments of :class:`Gear` from a gear table, and the start key used.

    ``tip_relief`` (m), ``tip_relief_start_roll_deg`` (deg) or ``tip_relief_start_radius``
    (m, the radius of the involute point where the relief begins), ``tip_relief_shape``.
    """
    if "tip_relief" not in table:
        for key in RELIEF_KEYS:
            if key in table:
                raise InputError(f"{where}.{key}", "needs tip_relief (the relief amount, m) "
                                 "in the same table")
        return {}, "tip_relief_start_roll_deg"
    amount = _number(table, "tip_relief", where)
    if not math.isfinite(amount) or amount < 0.0:
        raise InputError(f"{where}.tip_relief", f"must be zero or a positive number of metres "
                         f"(got {amount!r})")
    relief: dict[str, Any] = {"tip_relief": amount}
    start_key = "tip_relief_start_roll_deg"
    if "tip_relief_start_roll_deg" in table or "tip_relief_start_radius" in table:
        start_key = _one_of(table, "tip_relief_start_roll_deg", "tip_relief_start_radius", where)
        value = _number(table, start_key, where)
        if not math.isfinite(value):
            raise InputError(f"{where}.{start_key}", f"must be a finite number (got {value!r})")
        if start_key == "tip_relief_start_roll_deg":
            relief["tip_relief_start_roll"] = math.radians(value)
        else:
            if value <= base_radius:
                raise InputError(f"{where}.tip_relief_start_radius", f"must be above the base "
                                 f"radius {base_radius:g} m, on the involute (got {value!r})")
            relief["tip_relief_start_roll"] = math.sqrt(value * value - base_radius**2) / base_radius
    elif amount > 0.0:
        raise InputError(f"{where}.tip_relief_start_roll_deg", "is missing (or give "
                         "tip_relief_start_radius): a tip relief needs the point where it begins")
    if "tip_relief_shape" in table:
        shape = table["tip_relief_shape"]
        if not isinstance(shape, str):
            raise InputError(f"{where}.tip_relief_shape", f"must be \"linear\" or \"parabolic\" "
                             f"(got {shape!r})")
        relief["tip_relief_shape"] = shape
    return relief, start_key


def pair_from_dict(data: dict[str, Any], name: str = "pair") -> PairCase:
    """Build a :class:`PairCase` from the parsed TOML document."""
    _check_keys(data, TOP_KEYS, "")
    if "gear_a" not in data:
        raise InputError("gear_a", "table is missing")
    gear_a = gear_from_table(data["gear_a"], "gear_a")
    gear_b = gear_from_table(data["gear_b"], "gear_b") if "gear_b" in data else gear_a
    pair_table = data.get("pair", {})
    if not isinstance(pair_table, dict):
        raise InputError("pair", "must be a table")
    _check_keys(pair_table, PAIR_KEYS, "pair")
    centre = None
    if "centre_distance" in pair_table:
        centre = _number(pair_table, "centre_distance", "pair")
        if not math.isfinite(centre) or centre <= 0.0:
            raise InputError("pair.centre_distance", f"must be a positive number (got {centre!r})")
    driver = pair_table.get("driver", "a")
    try:
        pair = GearPair(gear_a=gear_a, gear_b=gear_b, centre_distance=centre, driver=driver)
    except InputError as err:
        raise err if err.field.startswith("gear_") else err.prefixed("pair") from None
    mesh_table = data.get("mesh", {})
    if not isinstance(mesh_table, dict):
        raise InputError("mesh", "must be a table")
    _check_keys(mesh_table, MESH_KEYS, "mesh")
    nx = _integer(mesh_table, "nx", "mesh", DEFAULT_NX)
    ny = _integer(mesh_table, "ny", "mesh", DEFAULT_NY)
    return PairCase(pair=pair, nx=nx, ny=ny, name=name)


def load_pair(path: str | Path) -> PairCase:
    """Read a gear-pair TOML file."""
    path = Path(path)
    return pair_from_dict(_read_toml(path), name=path.stem)


# -- runs ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Case:
    """Everything one run needs: the pair, the run settings (mesh included) and a name.

    Attributes
    ----------
    name
        Name of the case (preset name or TOML file stem); the default output folder.
    pair
        The gear pair.
    run
        Run settings in SI units; ``run.nx``, ``run.ny`` hold the mesh density.
    description
        One line saying what the case is for.
    """

    name: str
    pair: GearPair
    run: RunCase
    description: str = ""

    @property
    def pair_case(self) -> PairCase:
        """The pair and its mesh, as ``spurdyn info`` takes them."""
        return PairCase(pair=self.pair, nx=self.run.nx, ny=self.run.ny, name=self.name)

    @property
    def angle(self) -> float:
        """Rotation of A to simulate (rad): ``run.angle`` or the whole ``theta_s``."""
        return self.pair.theta_s if self.run.angle is None else self.run.angle

    @property
    def static_force(self) -> float:
        """Quasi-static tooth force (N): torque over the driver's base radius."""
        driver = self.pair.gear_a if self.pair.driver == "a" else self.pair.gear_b
        return self.run.torque / driver.base_radius


class _Source:
    """Where each run setting comes from: a command-line override or the ``[run]`` table.

    ``overrides`` and ``labels`` are keyed by dotted names (``run.dt``, ``mesh.nx``);
    a label (``--dt``) names the field in refusals of an overridden value.
    """

    def __init__(self, table: Mapping[str, Any], where: str,
                 overrides: Mapping[str, Any], labels: Mapping[str, str]) -> None:
        self.table, self.where, self.overrides, self.labels = table, where, overrides, labels

    def field(self, key: str) -> str:
        dotted = f"{self.where}.{key}"
        return self.labels.get(dotted, dotted) if dotted in self.overrides else dotted

    def get(self, key: str) -> tuple[bool, Any, str]:
        dotted = f"{self.where}.{key}"
        if dotted in self.overrides and self.overrides[dotted] is not None:
            return True, self.overrides[dotted], self.labels.get(dotted, dotted)
        if key in self.table and self.table[key] is not None:
            return True, self.table[key], dotted
        return False, None, dotted

    def number(self, key: str, default: float | None, *, positive: bool = True,
               required_hint: str = "") -> float | None:
        found, value, name = self.get(key)
        if not found:
            if default is None and required_hint:
                raise InputError(name, f"is missing; {required_hint}")
            return default
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(name, f"must be a number (got {value!r})")
        value = float(value)
        if not math.isfinite(value):
            raise InputError(name, f"must be a finite number (got {value!r})")
        if positive and value <= 0.0:
            raise InputError(name, f"must be positive (got {value:g})")
        if not positive and value < 0.0:
            raise InputError(name, f"must not be negative (got {value:g})")
        return value

    def integer(self, key: str, default: int, low: int) -> int:
        found, value, name = self.get(key)
        if not found:
            return default
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(name, f"must be a whole number (got {value!r})")
        if value < low:
            raise InputError(name, f"must be a whole number >= {low} (got {value})")
        return value

    def choice(self, key: str, default: str, allowed: tuple[str, ...]) -> str:
        found, value, name = self.get(key)
        if not found:
            return default
        if value not in allowed:
            raise InputError(name, f"must be one of {', '.join(allowed)} (got {value!r})")
        return str(value)

    def boolean(self, key: str, default: bool) -> bool:
        found, value, name = self.get(key)
        if not found:
            return default
        if not isinstance(value, bool):
            raise InputError(name, f"must be true or false (got {value!r})")
        return value


def _round_down(x: float, digits: int) -> float:
    """``x > 0`` rounded down to ``digits`` significant digits."""
    scale = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return math.floor(x / scale) * scale


_RUN_DEFAULTS = {f.name: f.default for f in fields(RunCase)}
#: The ``[run]`` key of a :class:`RunCase` field whose name differs.
_RUN_KEY_OF = {"speed_a": "speed_a_rpm", "speed_b": "speed_b_rpm", "angle": "angle_deg"}


def case_from_pair(pair_case: PairCase, run_table: Mapping[str, Any] | None, name: str,
                   overrides: Mapping[str, Any] | None = None,
                   labels: Mapping[str, str] | None = None, description: str = "",
                   check_step: bool = True) -> Case:
    """Build a :class:`Case` from a pair and its ``[run]`` table (TOML units).

    Parameters
    ----------
    pair_case
        The pair and the mesh density of its ``[mesh]`` table.
    run_table
        The ``[run]`` table (speeds in rpm, angle in degrees, the rest SI), or ``None``.
    name
        Name of the case.
    overrides
        Values that replace the table's, keyed ``run.<key>`` or ``mesh.nx``/``mesh.ny``
        (``None`` values are ignored): the command-line options.
    labels
        How to name an overridden field in a refusal, e.g. ``{"run.dt": "--dt"}``.
    description
        One line about the case.
    check_step
        Refuse a time step above the stable RK4 step of either tooth mesh (builds both
        tooth models, a fraction of a second) and refuse a bad mesh.

    Raises
    ------
    InputError
        Unknown keys, wrong types, non-physical values, a ``dt`` above the stable step,
        an angle beyond ``theta_s`` plus :data:`ANGLE_MARGIN`.
    """
    overrides = dict(overrides or {})
    labels = dict(labels or {})
    table = {} if run_table is None else run_table
    if not isinstance(table, dict):
        raise InputError("run", "must be a table")
    _check_keys(table, RUN_KEYS, "run")
    src = _Source(table, "run", overrides, labels)
    pair = pair_case.pair
    hint = "give it in the [run] table or on the command line"
    speed_a = src.number("speed_a_rpm", None, required_hint=hint)
    speed_b = src.number("speed_b_rpm", speed_a * pair.gear_a.teeth / pair.gear_b.teeth)
    torque = src.number("torque", None, positive=False, required_hint=hint)
    dt = src.number("dt", _RUN_DEFAULTS["dt"])
    angle_deg = src.number("angle_deg", None)
    mesh = _Source({"nx": pair_case.nx, "ny": pair_case.ny}, "mesh", overrides, labels)
    nx = mesh.integer("nx", pair_case.nx, 1)
    ny = mesh.integer("ny", pair_case.ny, 1)
    settings = dict(
        speed_a=speed_a * RPM, speed_b=speed_b * RPM, torque=torque, dt=dt,
        angle=None if angle_deg is None else math.radians(angle_deg), nx=nx, ny=ny,
        n_spline=src.integer("n_spline", _RUN_DEFAULTS["n_spline"], 8),
        tol_disp=src.number("tol_disp", _RUN_DEFAULTS["tol_disp"]),
        max_iter=src.integer("max_iter", _RUN_DEFAULTS["max_iter"], 1),
        accel_levels=src.integer("accel_levels", _RUN_DEFAULTS["accel_levels"], 1),
        method=src.choice("method", _RUN_DEFAULTS["method"], METHODS),
        backend=src.choice("backend", _RUN_DEFAULTS["backend"], BACKENDS),
        save_every=src.integer("save_every", _RUN_DEFAULTS["save_every"], 1),
        frames_every=src.integer("frames_every", _RUN_DEFAULTS["frames_every"], 0),
        keep_theta_term=src.boolean("keep_theta_term", _RUN_DEFAULTS["keep_theta_term"]),
        name=name,
    )
    try:
        run = RunCase(**settings)
    except InputError as err:  # the upper bounds are RunCase's own
        raise InputError(src.field(_RUN_KEY_OF.get(err.field, err.field)), err.reason) from None

    from spurdyn.limits import check_run_bounds, check_sampling

    check_run_bounds(pair, run, src.field)
    theta_s = pair.theta_s
    if run.angle is not None:
        limit = theta_s * (1.0 + ANGLE_MARGIN)
        field_ = src.field("angle_deg")
        if run.angle > limit:
            raise InputError(field_, f"{angle_deg:g} deg goes beyond the angle of action "
                             f"theta_s = {math.degrees(theta_s):.3f} deg (+{ANGLE_MARGIN:.0%}): "
                             "the teeth would leave the modelled region")
        if run.angle < run.speed_a * run.dt:
            raise InputError(field_, f"{angle_deg:g} deg is shorter than one time step "
                             f"({math.degrees(run.speed_a * run.dt):.3g} deg at this speed)")
    check_sampling(pair, run, src.field)
    if check_step:
        from spurdyn.model.tooth import build_tooth

        stable = []
        for gear in (pair.gear_a, pair.gear_b):
            try:
                stable.append(build_tooth(gear, nx, ny).stable_step().dt_rk4)
            except InputError as err:
                if "mesh.nx" in overrides and err.field.startswith("mesh."):
                    label = labels.get("mesh.nx", "mesh")
                    raise InputError(label, f"{err.field[5:]} {err.reason}") from None
                raise
        dt_max = min(stable)
        if run.dt > dt_max:
            field_ = src.field("dt")
            if "run.dt" not in overrides and "mesh.nx" in overrides:
                field_ = labels.get("mesh.nx", "mesh")
            safe = _round_down(dt_max, 3)
            raise InputError(field_, f"dt {run.dt:g} s is above the stable RK4 step "
                             f"{dt_max:.4g} s of the {nx}x{ny} tooth mesh; use a dt of at most "
                             f"{safe:g} s or a coarser mesh")
    return Case(name=name, pair=pair, run=run, description=description)


def case_from_dict(data: dict[str, Any], name: str = "case",
                   overrides: Mapping[str, Any] | None = None,
                   labels: Mapping[str, str] | None = None,
                   check_step: bool = True) -> Case:
    """Build a :class:`Case` from a parsed TOML document (or :func:`case_to_dict`)."""
    if not isinstance(data, dict):
        raise InputError("case", "must be a table")
    pair_case = pair_from_dict(data, name=name)
    return case_from_pair(pair_case, data.get("run"), name, overrides, labels,
                          check_step=check_step)


def _read_toml(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(str(path), "no such file; give a preset name or a TOML file") from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as err:
        raise InputError(str(path), f"cannot be read ({type(err).__name__})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(str(path), f"is not valid TOML ({err})") from None


def load_case(path: str | Path, overrides: Mapping[str, Any] | None = None,
              labels: Mapping[str, str] | None = None, check_step: bool = True) -> Case:
    """Read a case TOML file: the pair tables and the ``[run]`` table."""
    path = Path(path)
    return case_from_dict(_read_toml(path), name=path.stem, overrides=overrides,
                          labels=labels, check_step=check_step)


def _gear_to_dict(gear: Gear) -> dict[str, Any]:
    table: dict[str, Any] = {
        "teeth": gear.teeth, "module": gear.module, "addendum": gear.addendum,
        "dedendum": gear.dedendum, "pressure_angle_deg": math.degrees(gear.pressure_angle),
        "face_width": gear.face_width, "disk_inertia": gear.disk_inertia,
        "cutter_tip_radius": gear.cutter_tip_radius,
        "material": {"young": gear.material.young, "poisson": gear.material.poisson,
                     "density": gear.material.density},
    }
    if gear.tip_relief > 0.0 or gear.tip_relief_start_roll is not None:
        table["tip_relief"] = gear.tip_relief
        if gear.tip_relief_start_roll is not None:
            table["tip_relief_start_roll_deg"] = math.degrees(gear.tip_relief_start_roll)
        table["tip_relief_shape"] = gear.tip_relief_shape
    return table


def case_to_dict(case: Case) -> dict[str, Any]:
    """The case as a TOML-shaped dictionary (TOML units) that :func:`case_from_dict` reads.

    ``run.angle_deg`` is left out when the run covers the whole angle of action.
    """
    run = case.run
    run_table: dict[str, Any] = {
        "speed_a_rpm": run.speed_a / RPM, "speed_b_rpm": run.speed_b / RPM,
        "torque": float(run.torque), "dt": run.dt,
    }
    if run.angle is not None:
        run_table["angle_deg"] = math.degrees(run.angle)
    run_table.update({k: getattr(run, k) for k in (
        "n_spline", "tol_disp", "max_iter", "accel_levels", "method", "backend",
        "save_every", "frames_every", "keep_theta_term")})
    return {
        "gear_a": _gear_to_dict(case.pair.gear_a),
        "gear_b": _gear_to_dict(case.pair.gear_b),
        "pair": {"centre_distance": case.pair.centre_distance, "driver": case.pair.driver},
        "mesh": {"nx": run.nx, "ny": run.ny},
        "run": run_table,
    }
