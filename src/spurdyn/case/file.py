"""Read gear-pair and run descriptions from TOML files (stdlib ``tomllib``).

A file holds the tables ``[gear_a]``, ``[gear_b]`` (optional: a copy of gear A),
``[pair]`` (optional), ``[mesh]`` (optional) and ``[run]`` (the run settings, needed by
``spurdyn run``); ``docs/casefile.md`` lists every key, and :mod:`spurdyn.case.pair_tables`
reads the pair tables. Lengths are in metres, angles in degrees (keys
ending ``_deg``), speeds in rpm (keys ending ``_rpm``), torque in N m, time in s, inertia
in kg m^2, moduli in Pa, density in kg/m^3. A gear table may hold a tip relief:
``tip_relief`` (m), ``tip_relief_start_roll_deg`` (deg) or ``tip_relief_start_radius`` (m),
``tip_relief_shape`` (``"linear"``/``"parabolic"``). Every problem is raised as an
:class:`~spurdyn.errors.InputError` naming the key.

A :class:`Case` (pair + :class:`~spurdyn.settings.RunSettings`) turns back into the same
dictionary with :func:`case_to_dict`, so a run can store its whole description and be
rebuilt from it (:func:`case_from_dict`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any, Callable, Mapping

from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.case.pair_tables import TOP_KEYS, MeshedPair, check_keys, gear_to_dict, pair_from_dict, read_toml
from spurdyn.model.loading import check_history
from spurdyn.model.system import PairSystem, system_for
from spurdyn.mesh.tooth import DEFAULT_GRADING, DEFAULT_ROW_GRADING, MAX_GRADING, MAX_ROW_GRADING
from spurdyn.settings import (
    BACKENDS, BODIES, CONTACTS, DEFAULT_MODEL, INTEGRATORS, METHODS, MODEL_NAMES, PAPER_DT, RETIRED_METHODS, RPM, STARTS, STIFFNESSES,
    RunSettings, TorqueHistory,
)
from spurdyn.solvers.check import check_run, default_step
from spurdyn.solvers.implicit.damping import rayleigh_from_ratio
from spurdyn.case.source import RunSource
from spurdyn.case.torque import history_from_table, history_to_table, read_history_csv

RUN_KEYS = {
    "speed_a_rpm", "speed_b_rpm", "torque", "dt", "angle_deg", "n_spline", "tol_disp",
    "max_iter", "accel_levels", "method", "backend", "contact", "save_every", "frames_every",
    "keep_theta_term", "damping_ratio", "integrator", "rho_inf", "rayleigh_mass",
    "rayleigh_stiffness", "rayleigh_ratio", "rayleigh_hz", "cycles", "max_cycles", "stiffness", "bodies", "back_flanks",
    "teeth", "start", "ramp_cycles", "torque_history", "torque_history_periodic",
}



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
    model
        The model the file asks for (``[model] kind``, one of
        :data:`~spurdyn.settings.MODEL_NAMES`; ``--model`` overrides it).
    written
        The ``[run]`` keys the file wrote (``"run.dt"``, ...): a model that does not read
        one refuses it by that name (:meth:`labels`), as it refuses an option.
    """

    name: str
    pair: GearPair
    run: RunSettings
    description: str = ""
    model: str = DEFAULT_MODEL
    written: frozenset[str] = frozenset()

    def labels(self, options: Mapping[str, str]) -> dict[str, str]:
        """How a refusal names each setting given: the command line's ``options``
        (``{"run.dt": "--dt"}``), and the keys the file wrote by themselves."""
        return {**{key: key for key in self.written}, **options}

    @property
    def meshed_pair(self) -> MeshedPair:
        """The pair and its mesh, as ``spurdyn info`` takes them."""
        return MeshedPair(pair=self.pair, nx=self.run.nx, ny=self.run.ny, name=self.name,
                          grading=self.run.grading, row_grading=self.run.row_grading)

    @property
    def angle(self) -> float:
        """Rotation of A to simulate (rad): ``run.angle`` or the whole ``theta_s``; for a
        steady state, its mesh cycles of one angular pitch each."""
        if self.run.cycles is not None:
            return self.run.cycles * 2.0 * math.pi / self.pair.gear_a.teeth
        return self.pair.theta_s if self.run.angle is None else self.run.angle

    @property
    def static_force(self) -> float:
        """Quasi-static tooth force (N): torque over the driver's base radius."""
        from spurdyn.model.loading import static_force

        return static_force(self.pair, self.run.torque)


_RUN_DEFAULTS = {f.name: f.default for f in fields(RunSettings)}
#: A case file's contact model unless it says otherwise: the distributed contact, which
#: holds at design loads (the paper's presets say ``"point"``).
CASE_CONTACT = "hertz"
#: The ``[run]`` key of a :class:`RunSettings` field whose name differs.
_RUN_KEY_OF = {"speed_a": "speed_a_rpm", "speed_b": "speed_b_rpm", "angle": "angle_deg"}


def refuse_faults(meshed_pair: MeshedPair, reader: str) -> None:
    """Refuse a pair's ``[[fault]]`` tables where ``reader`` does not take them."""
    if meshed_pair.faults:
        raise InputError("fault", f"not read by {reader} yet; `spurdyn stiffness` follows a faulty "
                         "gear over its revolution")


def case_from_pair(meshed_pair: MeshedPair, run_table: Mapping[str, Any] | None, name: str,
                   overrides: Mapping[str, Any] | None = None,
                   labels: Mapping[str, str] | None = None, description: str = "",
                   check_step: bool = True, base: Path | None = None) -> Case:
    """Build a :class:`Case` from a pair and its ``[run]`` table (TOML units).

    Parameters
    ----------
    meshed_pair
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
    base
        The folder a ``torque_history`` file of the table is relative to (the case file's;
        one given on the command line is relative to the working folder).

    Raises
    ------
    InputError
        Unknown keys, wrong types, non-physical values, a ``dt`` above the stable step,
        an angle beyond ``theta_s`` plus :data:`spurdyn.solvers.check.ANGLE_MARGIN`.
    """
    overrides = dict(overrides or {})
    labels = dict(labels or {})
    faults = _option_faults(overrides.pop("fault", ()), meshed_pair)
    table = {} if run_table is None else run_table
    if not isinstance(table, dict):
        raise InputError("run", "must be a table")
    check_keys(table, RUN_KEYS, "run")
    src = RunSource(table, "run", overrides, labels)
    pair = meshed_pair.pair
    hint = "give it in the [run] table or on the command line"
    speed_a = src.number("speed_a_rpm", None, required_hint=hint)
    speed_b = src.number("speed_b_rpm", speed_a * pair.gear_a.teeth / pair.gear_b.teeth)
    scale_b = _speed_scale(table, overrides)
    speed_b *= scale_b
    torque = src.number("torque", None, positive=False, required_hint=hint)
    dt = src.number("dt", None)
    angle_deg = src.number("angle_deg", None)
    nx, ny, grading, row_grading = _mesh_density(meshed_pair, overrides, labels)
    settings = dict(
        # without a dt, the paper's until the system is built (the values are checked first)
        speed_a=speed_a * RPM, speed_b=speed_b * RPM, torque=torque,
        dt=PAPER_DT if dt is None else dt,
        angle=None if angle_deg is None else math.radians(angle_deg), nx=nx, ny=ny,
        grading=grading, row_grading=row_grading,
        **_run_options(src, base),
        name=name, faults=faults, bearings=meshed_pair.bearings,
    )
    try:
        run = RunSettings(**settings)
        check_history(pair, run)
    except InputError as err:  # the upper bounds are RunSettings's own
        raise InputError(src.field(_RUN_KEY_OF.get(err.field, err.field)), err.reason) from None
    system = None
    if check_step or dt is None:
        system = _system(pair, nx, ny, run.n_spline, grading, overrides, labels, row_grading)
    if dt is None:  # the FE model's default step (stored, and hashed by a sweep, for every model)
        run = run.with_(dt=default_step(run, pair, system))
    if system is not None:
        check_run(pair, run, system, _step_field(src, overrides, labels, scale_b))
    return Case(name=name, pair=pair, run=run, description=description,
                written=frozenset(f"run.{key}" for key in table))


def _option_faults(texts: Any, meshed_pair: MeshedPair) -> tuple[Any, ...]:
    """The case's faults and those of ``--fault`` options after them
    (:func:`~spurdyn.case.fault_tables.parse_fault_option`), checked together."""
    from spurdyn.case.fault_tables import check_faults, parse_fault_option

    given = tuple(parse_fault_option(text, meshed_pair.pair) for text in texts)
    if given:
        own = meshed_pair.faults
        check_faults(own + given, [f"fault[{i}].tooth" for i in range(len(own))] + ["--fault"] * len(given),
                     meshed_pair.pair)
    return meshed_pair.faults + given


def _mesh_density(meshed_pair: MeshedPair, overrides: Mapping[str, Any],
                  labels: Mapping[str, str]) -> tuple[int, int, float, float]:
    """``(nx, ny, grading, row_grading)`` of the ``[mesh]`` table as ``overrides`` change it,
    the gradings refused beyond their bounds."""
    mesh = RunSource({"nx": meshed_pair.nx, "ny": meshed_pair.ny, "grading": meshed_pair.grading,
                    "row_grading": meshed_pair.row_grading}, "mesh", overrides, labels)
    nx = mesh.integer("nx", meshed_pair.nx, 1)
    ny = mesh.integer("ny", meshed_pair.ny, 1)
    grading = mesh.number("grading", meshed_pair.grading)
    if not DEFAULT_GRADING <= grading <= MAX_GRADING:
        raise InputError(mesh.field("grading"), f"must be a number from 1 (even) to "
                         f"{MAX_GRADING:g} (got {grading:g})")
    row_grading = mesh.number("row_grading", meshed_pair.row_grading)
    if not DEFAULT_ROW_GRADING <= row_grading <= MAX_ROW_GRADING:
        raise InputError(mesh.field("row_grading"), f"must be a number from 1 (even rows) to "
                         f"{MAX_ROW_GRADING:g} (got {row_grading:g})")
    return nx, ny, grading, row_grading


def _run_options(src: RunSource, base: Path | None) -> dict[str, Any]:
    """The :class:`RunSettings` fields of the ``[run]`` table beyond the speeds, torque, step,
    angle and mesh, each checked (in this order, the order refusals come in)."""
    return dict(
        n_spline=src.integer("n_spline", _RUN_DEFAULTS["n_spline"], 8),
        tol_disp=src.number("tol_disp", _RUN_DEFAULTS["tol_disp"]),
        max_iter=src.integer("max_iter", _RUN_DEFAULTS["max_iter"], 1),
        accel_levels=src.integer("accel_levels", _RUN_DEFAULTS["accel_levels"], 1),
        method=src.choice("method", _RUN_DEFAULTS["method"], METHODS, RETIRED_METHODS),
        backend=src.choice("backend", _RUN_DEFAULTS["backend"], BACKENDS),
        contact=src.choice("contact", CASE_CONTACT, CONTACTS),
        save_every=src.integer("save_every", _RUN_DEFAULTS["save_every"], 1),
        frames_every=src.integer("frames_every", _RUN_DEFAULTS["frames_every"], 0),
        keep_theta_term=src.boolean("keep_theta_term", _RUN_DEFAULTS["keep_theta_term"]),
        damping_ratio=src.number("damping_ratio", _RUN_DEFAULTS["damping_ratio"], positive=False),
        integrator=src.choice("integrator", _RUN_DEFAULTS["integrator"], INTEGRATORS),
        rho_inf=src.number("rho_inf", _RUN_DEFAULTS["rho_inf"], positive=False),
        **_rayleigh(src),
        cycles=src.integer("cycles", None, 1),
        max_cycles=src.integer("max_cycles", None, 1),
        stiffness=src.choice("stiffness", "tooth", STIFFNESSES),
        bodies=src.choice("bodies", "modal", BODIES),
        back_flanks=src.boolean("back_flanks", None),
        teeth=src.integer("teeth", None, 1),
        start=src.choice("start", "static", STARTS),
        ramp_cycles=src.number("ramp_cycles", None),
        torque_history=_torque_history(src, base),
    )


def _step_field(src: RunSource, overrides: Mapping[str, Any], labels: Mapping[str, str],
                scale_b: float) -> Callable[[str], str]:
    """How the run check names a refused field: the key the user wrote, or what made it so."""
    def field(name: str) -> str:
        if name == "dt" and "run.dt" not in overrides:
            for key in ("mesh.grading", "mesh.row_grading", "mesh.nx"):  # the mesh made the step too large
                if key in overrides:
                    return labels.get(key, "mesh" if key == "mesh.nx" else key)
        if name == "speed_b_rpm" and (not src.get(name)[0] or scale_b != 1.0):
            return src.field("speed_a_rpm")          # B's speed comes from A's
        return src.field(name)

    return field


def _speed_scale(table: Mapping[str, Any], overrides: Mapping[str, Any]) -> float:
    """How much a speed of A given on the command line scales the case's own speed of B.

    ``--speed-a`` alone keeps the case's ratio of speeds, as a sweep does at each of its
    speeds (a preset's B at 4,000 rpm beside A at 18,000 would start a steady run with the
    gears 14,000 rpm apart). 1 where B's speed is given, or follows A's by default.
    """
    if "run.speed_a_rpm" not in overrides or "run.speed_b_rpm" in overrides:
        return 1.0
    own_a, own_b = table.get("speed_a_rpm"), table.get("speed_b_rpm")
    if own_b is None or isinstance(own_a, bool) or not isinstance(own_a, (int, float)) or own_a <= 0:
        return 1.0
    return float(overrides["run.speed_a_rpm"]) / float(own_a)


def _torque_history(src: RunSource, base: Path | None) -> TorqueHistory | None:
    """The ``torque_history``: a CSV file's name (relative to ``base``, or to the working
    folder where the command line gave it) or an inline table
    (:mod:`spurdyn.case.torque`), repeated if ``torque_history_periodic``."""
    periodic = src.boolean("torque_history_periodic", False)
    found, value, name = src.get("torque_history")
    if not found:
        if src.get("torque_history_periodic")[0]:
            raise InputError(src.field("torque_history_periodic"), "repeats a torque history: "
                             "give torque_history too (--torque-history FILE)")
        return None
    if isinstance(value, dict):
        return history_from_table(value, name, bool(periodic))
    if not isinstance(value, (str, Path)):
        raise InputError(name, f"must be a CSV file's name or a table (got {value!r})"[:200])
    path = Path(value)
    if not path.is_absolute() and base is not None and "run.torque_history" not in src.overrides:
        path = base / path
    return read_history_csv(path, name, bool(periodic))


def _rayleigh(src: RunSource) -> dict[str, float]:
    """Rayleigh's coefficients from ``rayleigh_mass`` and ``rayleigh_stiffness``, or from a
    damping ratio ``rayleigh_ratio`` at the two frequencies ``rayleigh_hz = [f1, f2]``;
    nothing if none of them is given (the model's default)."""
    a = src.number("rayleigh_mass", None, positive=False)
    b = src.number("rayleigh_stiffness", None, positive=False)
    zeta = src.number("rayleigh_ratio", None, positive=False)
    found, hz, name = src.get("rayleigh_hz")
    if zeta is None and not found:
        if a is None and b is None:
            return {}
        return {"rayleigh_mass": a or 0.0, "rayleigh_stiffness": b or 0.0}
    if a or b:
        raise InputError(src.field("rayleigh_ratio" if zeta is not None else "rayleigh_hz"),
                         "give Rayleigh damping either as rayleigh_mass and rayleigh_stiffness "
                         "or as rayleigh_ratio with rayleigh_hz, not both")
    if zeta is None or not found:
        missing = ("rayleigh_hz = [f1, f2] (--rayleigh-hz F1,F2)" if zeta is not None
                   else "rayleigh_ratio (--rayleigh-ratio Z)")
        raise InputError(src.field("rayleigh_ratio" if zeta is not None else "rayleigh_hz"),
                         f"needs {missing} beside it")
    if (not isinstance(hz, (list, tuple)) or len(hz) != 2
            or not all(isinstance(f, (int, float)) and not isinstance(f, bool)
                       and math.isfinite(f) and f > 0 for f in hz)):
        raise InputError(name, f"must be two positive frequencies in Hz, e.g. [5000, 50000] "
                         f"(got {hz!r})")
    a, b = rayleigh_from_ratio(zeta, float(hz[0]), float(hz[1]))
    if not (math.isfinite(a) and math.isfinite(b)):
        # name the key the user wrote: the frequencies, unless a ratio of 1 at them is finite
        ordinary = all(math.isfinite(c) for c in rayleigh_from_ratio(1.0, *map(float, hz)))
        raise InputError(src.field("rayleigh_ratio") if ordinary else name,
                         f"gives Rayleigh coefficients beyond any number (rayleigh_mass {a:g}, "
                         f"rayleigh_stiffness {b:g}): give a damping ratio below 1 at "
                         "frequencies in Hz")
    return {"rayleigh_mass": a, "rayleigh_stiffness": b}


def _system(pair: GearPair, nx: int, ny: int, n_spline: int, grading: float,
            overrides: Mapping[str, Any],
            labels: Mapping[str, str], row_grading: float = DEFAULT_ROW_GRADING) -> PairSystem:
    """The system the run will use (kept for it: built once); refuses a bad mesh."""
    try:
        return system_for(pair, nx, ny, n_spline, grading, row_grading)
    except InputError as err:
        if "mesh.nx" in overrides and err.field.startswith("mesh."):
            label = labels.get("mesh.nx", "mesh")
            raise InputError(label, f"{err.field[5:]} {err.reason}") from None
        raise


def case_from_dict(data: dict[str, Any], name: str = "case",
                   overrides: Mapping[str, Any] | None = None,
                   labels: Mapping[str, str] | None = None,
                   check_step: bool = True, base: Path | None = None) -> Case:
    """Build a :class:`Case` from a parsed TOML document (or :func:`case_to_dict`); ``base``
    the folder its files are relative to."""
    if not isinstance(data, dict):
        raise InputError("case", "must be a table")
    meshed_pair = pair_from_dict(data, name=name)
    model = _model_kind(data.get("model"), overrides or {}, labels or {})
    case = case_from_pair(meshed_pair, data.get("run"), name, overrides, labels,
                          check_step=check_step, base=base)
    return replace(case, model=model)


def _model_kind(table: Any, overrides: Mapping[str, Any], labels: Mapping[str, str]) -> str:
    """The ``[model]`` table's ``kind`` (:data:`~spurdyn.settings.DEFAULT_MODEL` without
    one); ``--model`` replaces it."""
    if "model.kind" in overrides:
        kind, name = overrides["model.kind"], labels.get("model.kind", "model.kind")
    else:
        if table is None:
            return DEFAULT_MODEL
        if not isinstance(table, dict):
            raise InputError("model", "must be a table, e.g. [model] kind = \"sector\"")
        check_keys(table, {"kind"}, "model")
        kind, name = table.get("kind", DEFAULT_MODEL), "model.kind"
    if kind not in MODEL_NAMES:
        raise InputError(name, f"must be one of {', '.join(MODEL_NAMES)} (got {kind!r})")
    return str(kind)


def load_case(path: str | Path, overrides: Mapping[str, Any] | None = None,
              labels: Mapping[str, str] | None = None, check_step: bool = True) -> Case:
    """Read a case TOML file: the pair tables and the ``[run]`` table."""
    path = Path(path)
    return case_from_dict(read_case_file(path), name=path.stem, overrides=overrides,
                          labels=labels, check_step=check_step, base=path.parent)


def read_case_file(path: str | Path) -> dict[str, Any]:
    """The tables of a case file, read as every command reads one: a file too large, not
    TOML, with an unknown table or key at the top or in ``[run]``, or whose ``run`` or
    ``model`` is not a table, refused naming the file or the key.

    The pair tables are read by :func:`~spurdyn.case.pair_tables.pair_from_dict`, the
    ``[run]`` table's values by :func:`case_from_pair` (``run``, ``sweep``) or
    :func:`file_torque` (``info``, ``stiffness``), with the same messages.
    """
    data = read_toml(Path(path))
    check_keys(data, TOP_KEYS, "")
    run = data.get("run")
    if run is not None:
        if not isinstance(run, dict):
            raise InputError("run", "must be a table")
        check_keys(run, RUN_KEYS, "run")
    _model_kind(data.get("model"), {}, {})
    return data


def file_torque(data: Mapping[str, Any]) -> float | None:
    """The ``[run]`` torque of a case file's tables (N m; ``None`` without one), refused as
    ``spurdyn run`` refuses it (``run.torque``)."""
    src = RunSource(data.get("run") or {}, "run", {}, {})
    return src.number("torque", None, positive=False)


#: ``[mesh]`` keys :func:`case_to_dict` writes only where they differ from these defaults (so
#: that the stored cases, and the sweep's hashes of them, of meshes without them stay as they were).
_MESH_WRITTEN_IF_GIVEN = (("row_grading", DEFAULT_ROW_GRADING),)
#: ``[run]`` keys :func:`case_to_dict` writes only where they differ from these defaults.
_WRITTEN_IF_GIVEN = (("cycles", None), ("max_cycles", None), ("stiffness", "tooth"), ("bodies", "modal"),
                     ("back_flanks", None), ("teeth", None), ("start", "static"), ("ramp_cycles", None))


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
        "n_spline", "tol_disp", "max_iter", "accel_levels", "method", "backend", "contact",
        "save_every", "frames_every", "keep_theta_term")})
    if run.damping_ratio is not None:   # 0 given is not the model's default
        run_table["damping_ratio"] = run.damping_ratio
    for key in ("rayleigh_mass", "rayleigh_stiffness"):
        if getattr(run, key) is not None:       # 0 given is not the model's default
            run_table[key] = getattr(run, key)
    if run.integrator != "rk4":
        run_table.update(integrator=run.integrator, rho_inf=run.rho_inf)
    # the keys written only where they differ from their default
    run_table.update({key: getattr(run, key) for key, default in _WRITTEN_IF_GIVEN
                      if getattr(run, key) != default})
    if run.torque_history is not None:   # inline: the stored case stands on its own
        run_table["torque_history"] = history_to_table(run.torque_history)
        run_table["torque_history_periodic"] = run.torque_history.periodic
    out = {
        "gear_a": gear_to_dict(case.pair.gear_a),
        "gear_b": gear_to_dict(case.pair.gear_b),
        "pair": {"centre_distance": case.pair.centre_distance, "driver": case.pair.driver},
        "mesh": {"nx": run.nx, "ny": run.ny, "grading": run.grading}
        | {key: getattr(run, key) for key, default in _MESH_WRITTEN_IF_GIVEN
           if getattr(run, key) != default},
        "run": run_table,
        "model": {"kind": case.model},
    }
    if run.bearings is not None:     # written only when given: the stored cases without stay as they were
        from spurdyn.case.bearing_table import bearing_to_table

        for name, b in zip(("gear_a", "gear_b"), run.bearings):
            if b is not None:
                out[name]["bearing"] = bearing_to_table(b)
    if run.faults:
        from spurdyn.case.fault_tables import fault_to_table

        out["fault"] = [fault_to_table(f) for f in run.faults]
    return out
