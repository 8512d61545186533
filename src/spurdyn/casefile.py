"""Read gear-pair descriptions from TOML files (stdlib ``tomllib``).

A file holds the tables ``[gear_a]``, ``[gear_b]`` (optional: a copy of gear A),
``[pair]`` (optional) and ``[mesh]`` (optional); ``examples/paper_pair.toml`` shows every
key. Lengths are in metres, angles in degrees (keys ending ``_deg``), inertia in kg m^2,
moduli in Pa, density in kg/m^3. Every problem is raised as an
:class:`~spurdyn.errors.InputError` naming the key.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from spurdyn.errors import InputError
from spurdyn.fem.material import Material
from spurdyn.geometry.gear import DEFAULT_CUTTER_TIP_RADIUS, Gear, GearPair
from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY

GEAR_KEYS = {
    "teeth", "module", "pitch_radius", "tip_radius", "root_radius", "addendum", "dedendum",
    "pressure_angle_deg", "face_width", "disk_inertia", "cutter_tip_radius", "material",
}
MATERIAL_KEYS = {"young", "poisson", "density"}
PAIR_KEYS = {"centre_distance", "driver"}
MESH_KEYS = {"nx", "ny"}
TOP_KEYS = {"gear_a", "gear_b", "pair", "mesh"}


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
    r_p = module * teeth / 2.0
    top = _one_of(table, "addendum", "tip_radius", where)
    addendum = _number(table, top, where)
    if top == "tip_radius":
        if addendum <= r_p:
            raise InputError(f"{where}.tip_radius", f"must be above the pitch radius {r_p:g} m")
        addendum -= r_p
    bottom = _one_of(table, "dedendum", "root_radius", where)
    dedendum = _number(table, bottom, where)
    if bottom == "root_radius":
        if dedendum >= r_p:
            raise InputError(f"{where}.root_radius", f"must be below the pitch radius {r_p:g} m")
        if "tip_radius" in table and dedendum >= table["tip_radius"]:
            raise InputError(f"{where}.tip_radius", "must be above root_radius")
        dedendum = r_p - dedendum
    alpha = _number(table, "pressure_angle_deg", where, 20.0)
    if not 12.0 <= alpha <= 35.0:
        raise InputError(f"{where}.pressure_angle_deg", f"must lie between 12 and 35 (got {alpha:g})")
    material = material_from_table(table["material"], f"{where}.material") \
        if "material" in table else Material(210e9, 0.3, 7800.0)
    try:
        return Gear(
            teeth=teeth, module=module, pressure_angle=math.radians(alpha),
            face_width=_number(table, "face_width", where),
            addendum=addendum, dedendum=dedendum,
            cutter_tip_radius=_number(table, "cutter_tip_radius", where,
                                      DEFAULT_CUTTER_TIP_RADIUS * module),
            disk_inertia=_number(table, "disk_inertia", where),
            material=material,
        )
    except InputError as err:
        raise err.prefixed(where) from None


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
    centre = _number(pair_table, "centre_distance", "pair", 0.0) or None
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
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(str(path), "no such file; give a preset name or a TOML file") from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as err:
        raise InputError(str(path), f"cannot be read ({type(err).__name__})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(str(path), f"is not valid TOML ({err})") from None
    return pair_from_dict(data, name=path.stem)
