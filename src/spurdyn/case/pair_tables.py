"""Read the gear, material, pair and mesh tables of a case file (TOML units in, SI out).

``docs/casefile.md`` lists every key with its unit and default. A gear needs only its
teeth, module (or pitch radius), face width and, unless 20 deg, pressure angle: the
heights and the cutter tip radius come from the basic rack (``basic_rack``, ISO 53
profile A by default) and the profile shift, the disk inertia from the blank. Every
problem is raised as an :class:`~spurdyn.errors.InputError` naming the key as written.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from spurdyn.case.files import read_text
from spurdyn.case.bearing_table import bearings_from_dict
from spurdyn.case.fault_tables import faults_from_dict
from spurdyn.errors import InputError
from spurdyn.geometry.fault import Fault
from spurdyn.fem.material import STEEL, Material, check_plausible
from spurdyn.iso6336 import materials as iso_materials
from spurdyn.iso6336 import safety as iso_safety
from spurdyn.geometry.blank import Blank
from spurdyn.geometry.gear import MAX_MODULE, MAX_TEETH, Gear
from spurdyn.geometry.pair import GearPair, default_centre_distance
from spurdyn.geometry.rack import ISO_53, BasicRack, default_rack
from spurdyn.mesh.tooth import DEFAULT_GRADING, DEFAULT_NX, DEFAULT_NY, DEFAULT_ROW_GRADING

GEAR_KEYS = {
    "teeth", "module", "pitch_radius", "tip_radius", "root_radius", "addendum", "dedendum",
    "pressure_angle_deg", "face_width", "disk_inertia", "cutter_tip_radius", "material",
    "tip_relief", "tip_relief_start_roll_deg", "tip_relief_start_radius", "tip_relief_shape",
    "profile_shift", "thickness_allowance", "basic_rack", "blank", "bearing",
}
RACK_KEYS = {"addendum", "dedendum", "fillet_radius"}
BLANK_KEYS = {"bore_radius", "hub_radius", "rim_radius", "web_width"}
#: Keys that only make sense with ``tip_relief`` in the same table.
RELIEF_KEYS = ("tip_relief_start_roll_deg", "tip_relief_start_radius", "tip_relief_shape")
MATERIAL_KEYS = {"young", "poisson", "density", "sigma_flim", "sigma_hlim", "sigma_fe",
                 "material_class", "grade", "hardness_hv", "hardness_hbw"}
#: The keys that give a material's ISO 6336-5 allowables as a class (the others as numbers).
CLASS_KEYS = ("material_class", "grade", "hardness_hv", "hardness_hbw")
PAIR_KEYS = {"centre_distance", "driver"}
MESH_KEYS = {"nx", "ny", "grading", "row_grading"}
TOP_KEYS = {"gear_a", "gear_b", "pair", "mesh", "run", "model", "fault", "crack"}

@dataclass(frozen=True)
class MeshedPair:
    """A gear pair and the mesh density to model it with."""

    pair: GearPair
    nx: int = DEFAULT_NX
    ny: int = DEFAULT_NY
    name: str = "pair"
    grading: float = DEFAULT_GRADING
    row_grading: float = DEFAULT_ROW_GRADING
    faults: tuple[Fault, ...] = ()
    bearings: tuple[Any, Any] | None = None


def check_keys(table: dict[str, Any], allowed: set[str], where: str) -> None:
    """Refuse a key of ``table`` that is not in ``allowed``.

    Parameters
    ----------
    table : dict
        One table of a case file.
    allowed : set of str
        The keys it may hold.
    where : str
        The table's name, prefixed to the key in the message ("" at the top level).

    Raises
    ------
    InputError
        Naming the first unknown key and the keys expected.
    """
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
    check_keys(table, MATERIAL_KEYS, where)
    values: dict[str, Any] = {k: _number(table, k, where) for k in ("young", "poisson", "density")}
    try:
        values.update(_allowables(table, where))
        material = Material(**values)
        check_plausible(material)
        return material
    except InputError as err:
        raise err.prefixed(where) from None
    except ValueError as err:
        raise InputError(where, str(err)) from None


def _bare_number(table: dict[str, Any], key: str) -> float:
    """``table[key]`` as a finite float; errors name the bare key."""
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(key, f"must be a finite number (got {value!r})")
    return float(value)


def _allowables(table: dict[str, Any], where: str) -> dict[str, Any]:
    """The ISO 6336-5 allowables of a material table (Pa), optional: either numbers
    (``sigma_hlim``, ``sigma_flim`` or ``sigma_fe = Y_ST sigma_flim``) or a class, grade
    and hardness. Errors name the bare key; the caller prefixes the table."""
    given = [k for k in CLASS_KEYS if k in table]
    numbers = [k for k in ("sigma_hlim", "sigma_flim", "sigma_fe") if k in table]
    if given and numbers:
        raise InputError(numbers[0], f"give either the allowable stress numbers or an ISO "
                         f"6336-5 material_class with grade and hardness, not both "
                         f"(found {', '.join(given)})")
    if "sigma_fe" in table and "sigma_flim" in table:
        raise InputError("sigma_fe", "give either sigma_flim or sigma_fe (= 2 sigma_flim), "
                         "not both")
    if not given:
        out = {}
        for key in numbers:
            value = _bare_number(table, key)
            iso_materials.check_allowable(key, value)
            out["sigma_flim" if key == "sigma_fe" else key] = \
                value / iso_safety.Y_ST if key == "sigma_fe" else value
        return out
    for key in ("material_class", "grade"):
        if key not in table:
            raise InputError(key, "is missing: an ISO 6336-5 class needs material_class, "
                             "grade and hardness, e.g. material_class = \"Eh\", grade = "
                             "\"MQ\", hardness_hv = 700")
    cls = iso_materials.material_class(table["material_class"])
    key = iso_materials.HARDNESS_KEYS[cls.scale]
    for other in iso_materials.HARDNESS_KEYS.values():
        if other != key and other in table:
            raise InputError(other, f"class {cls.name} is rated by its {cls.scale} hardness: "
                             f"give {key}")
    if key not in table:
        raise InputError(key, f"is missing: class {cls.name} needs its surface hardness in "
                         f"{cls.scale}")
    hardness = _bare_number(table, key)
    hlim, flim = iso_materials.allowable_stresses(cls.name, table["grade"], hardness)
    return {"sigma_hlim": hlim, "sigma_flim": flim,
            "iso_class": (cls.name, table["grade"], hardness)}


def gear_from_table(table: dict[str, Any], where: str) -> Gear:
    """Build a :class:`Gear` from a TOML table (see ``docs/casefile.md`` for the keys)."""
    if not isinstance(table, dict):
        raise InputError(where, "must be a table")
    check_keys(table, GEAR_KEYS, where)
    teeth = _integer(table, "teeth", where)
    if teeth < 1:
        raise InputError(f"{where}.teeth", f"must be a positive whole number (got {teeth})")
    if teeth > MAX_TEETH:  # before the radii, which a huge count would put out of reach
        raise InputError(f"{where}.teeth", f"must be at most {MAX_TEETH} (got {teeth})")
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
    top = _at_most_one(table, "addendum", "tip_radius", where)
    addendum = None if top is None else _number(table, top, where)
    if top == "tip_radius":
        if not math.isfinite(addendum) or addendum <= r_p:
            raise InputError(f"{where}.tip_radius", f"must be above the pitch radius {r_p:g} m "
                             f"(got {addendum!r})")
        if addendum - r_p > 2.0 * module:
            raise InputError(f"{where}.tip_radius", f"is more than two modules above the pitch "
                             f"radius; at most {r_p + 2.0 * module:g} m")
        addendum -= r_p
    elif top is not None and (not math.isfinite(addendum) or addendum <= 0.0):
        raise InputError(f"{where}.addendum", f"must be a positive number (got {addendum!r})")
    bottom = _at_most_one(table, "dedendum", "root_radius", where)
    dedendum = None if bottom is None else _number(table, bottom, where)
    if bottom == "root_radius":
        if not math.isfinite(dedendum) or dedendum <= 0.0:
            raise InputError(f"{where}.root_radius", f"must be a positive number (got {dedendum!r})")
        if dedendum >= r_p:
            raise InputError(f"{where}.root_radius", f"must be below the pitch radius {r_p:g} m")
        if "tip_radius" in table and dedendum >= table["tip_radius"]:
            raise InputError(f"{where}.tip_radius", "must be above root_radius")
        dedendum = r_p - dedendum
    elif bottom is not None and (not math.isfinite(dedendum) or dedendum <= 0.0):
        raise InputError(f"{where}.dedendum", f"must be a positive number (got {dedendum!r})")
    alpha = _number(table, "pressure_angle_deg", where, 20.0)
    if not 12.0 <= alpha <= 35.0:
        raise InputError(f"{where}.pressure_angle_deg", f"must lie between 12 and 35 (got {alpha:g})")
    material = material_from_table(table["material"], f"{where}.material") \
        if "material" in table else STEEL
    # Read outside the try below: their refusals already name the table.
    face_width = _number(table, "face_width", where)
    optional = {key: _number(table, key, where) for key in
                ("cutter_tip_radius", "disk_inertia", "profile_shift", "thickness_allowance")
                if key in table}
    base_radius = r_p * math.cos(math.radians(alpha))
    relief, start_key = _relief_from_table(table, where, base_radius)
    rack, blank = _rack_from_table(table, where), _blank_from_table(table, where)
    try:
        return Gear(
            teeth=teeth, module=module, pressure_angle=math.radians(alpha),
            face_width=face_width, addendum=addendum, dedendum=dedendum, material=material,
            basic_rack=rack, blank=blank,
            **optional, **relief,
        )
    except InputError as err:
        # Name the key the user wrote, not the one it was turned into.
        written = {"addendum": top, "dedendum": bottom, "module": size,
                   "pressure_angle": "pressure_angle_deg",
                   "tip_relief_start_roll": start_key}
        field = err.field.split(".")[0]
        if field in written and written[field] is not None and written[field] != field:
            raise InputError(f"{where}.{written[field]}", err.reason) from None
        if field in ("addendum", "dedendum", "cutter_tip_radius") and field not in table:
            # Made from the basic rack and the shift: point at what the user can change.
            key = "profile_shift" if "profile_shift" in table else "basic_rack"
            raise InputError(f"{where}.{key}", f"gives a {field.replace('_', ' ')} that "
                             f"{err.reason}") from None
        raise err.prefixed(where) from None


def _at_most_one(table: dict[str, Any], a: str, b: str, where: str) -> str | None:
    if a in table and b in table:
        raise InputError(f"{where}.{b}", f"give either {a} or {b}, not both")
    return a if a in table else b if b in table else None


def _rack_from_table(table: dict[str, Any], where: str) -> BasicRack | None:
    """``basic_rack``: an ISO 53 profile letter or a table of heights in modules."""
    if "basic_rack" not in table:
        return None
    value = table["basic_rack"]
    if isinstance(value, str):
        if value.upper() not in ISO_53:
            raise InputError(f"{where}.basic_rack", f"must be one of the ISO 53 profiles "
                             f"{', '.join(ISO_53)} or a table {{{', '.join(sorted(RACK_KEYS))}}} "
                             f"in modules (got {value!r})")
        return ISO_53[value.upper()]
    if not isinstance(value, dict):
        raise InputError(f"{where}.basic_rack", "must be \"A\", \"B\", \"C\", \"D\" or a table")
    check_keys(value, RACK_KEYS, f"{where}.basic_rack")
    a = ISO_53["A"]
    try:
        return BasicRack("custom", *(_number(value, k, f"{where}.basic_rack", getattr(a, k))
                                     for k in ("addendum", "dedendum", "fillet_radius")))
    except InputError as err:
        raise err.prefixed(where) from None


def _blank_from_table(table: dict[str, Any], where: str) -> Blank | None:
    """``blank``: the dimensions the disk inertia is computed from (m)."""
    if "blank" not in table:
        return None
    value = table["blank"]
    if not isinstance(value, dict):
        raise InputError(f"{where}.blank", "must be a table of radii and a web width (m)")
    check_keys(value, BLANK_KEYS, f"{where}.blank")
    if "disk_inertia" in table:
        raise InputError(f"{where}.blank", "give either disk_inertia or a blank, not both")
    dims = {k: _number(value, k, f"{where}.blank") for k in BLANK_KEYS if k in value}
    return Blank(**dims)


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


def pair_from_dict(data: dict[str, Any], name: str = "pair") -> MeshedPair:
    """Build a :class:`MeshedPair` from the parsed TOML document."""
    check_keys(data, TOP_KEYS, "")
    if "gear_a" not in data:
        raise InputError("gear_a", "table is missing")
    gear_a = gear_from_table(data["gear_a"], "gear_a")
    gear_b = gear_from_table(data["gear_b"], "gear_b") if "gear_b" in data else gear_a
    pair_table = data.get("pair", {})
    if not isinstance(pair_table, dict):
        raise InputError("pair", "must be a table")
    check_keys(pair_table, PAIR_KEYS, "pair")
    centre = None
    if "centre_distance" in pair_table:
        centre = _number(pair_table, "centre_distance", "pair")
        if not math.isfinite(centre) or centre <= 0.0:
            raise InputError("pair.centre_distance", f"must be a positive number (got {centre!r})")
    driver = pair_table.get("driver", "a")
    try:
        pair = GearPair(gear_a=gear_a, gear_b=gear_b, centre_distance=centre, driver=driver)
    except InputError as err:
        if err.field == "centre_distance" and centre is None:
            raise _no_clearance(data, gear_a, gear_b, err) from None
        if not err.field.startswith("gear_"):
            raise err.prefixed("pair") from None
        # GearPair names the gear's field; name the key written in the file instead.
        where, field = err.field.split(".", 1)
        table = data.get(where, data["gear_a"])
        written = {"pressure_angle": "pressure_angle_deg",
                   "module": "module" if "module" in table else "pitch_radius"}
        raise InputError(f"{where}.{written.get(field, field)}", err.reason) from None
    mesh_table = data.get("mesh", {})
    if not isinstance(mesh_table, dict):
        raise InputError("mesh", "must be a table")
    check_keys(mesh_table, MESH_KEYS, "mesh")
    nx, ny = _integer(mesh_table, "nx", "mesh", DEFAULT_NX), _integer(mesh_table, "ny", "mesh", DEFAULT_NY)
    grading = _number(mesh_table, "grading", "mesh", DEFAULT_GRADING)
    row_grading = _number(mesh_table, "row_grading", "mesh", DEFAULT_ROW_GRADING)
    return MeshedPair(pair=pair, nx=nx, ny=ny, name=name, grading=grading, row_grading=row_grading,
                      faults=faults_from_dict(data, pair), bearings=bearings_from_dict(data))


#: The keys of a gear table that set its root (its dedendum), in the order a refusal names them.
ROOT_KEYS = ("root_radius", "dedendum", "basic_rack", "profile_shift")


def _no_clearance(data: dict[str, Any], gear_a: Gear, gear_b: Gear,
                  err: InputError) -> InputError:
    """The refusal of a pair without a centre distance whose tip hits the other gear's root:
    the centre distance is the pair's own, so name the key that set the root (or the tip)."""
    a = default_centre_distance(gear_a, gear_b)
    hit_b = a <= gear_a.tip_radius + gear_b.root_radius      # A's tip on B's root
    root, tip = ("gear_b", "gear_a") if hit_b else ("gear_a", "gear_b")
    for where, keys in ((root, ROOT_KEYS), (tip, ("tip_radius", "addendum"))):
        table = data.get(where, data["gear_a"])
        key = next((k for k in keys if k in table), None)
        if key is None:
            continue
        if key == "basic_rack" and isinstance(table[key], dict):
            key = "basic_rack.dedendum" if "dedendum" in table[key] else "basic_rack.addendum"
        return InputError(f"{'gear_a' if where not in data else where}.{key}",
                          f"leaves no clearance: a tip would hit the other gear's root at the "
                          f"centre distance {a:.6g} m (the pair's own); a dedendum must exceed "
                          "the mating addendum")
    return err.prefixed("pair")


def load_pair(path: str | Path) -> MeshedPair:
    """Read a gear-pair TOML file."""
    path = Path(path)
    return pair_from_dict(read_toml(path), name=path.stem)


def read_toml(path: Path) -> dict[str, Any]:
    """The tables of a TOML file.

    Parameters
    ----------
    path : Path
        The file.

    Returns
    -------
    dict
        Its tables, as :mod:`tomllib` reads them.

    Raises
    ------
    InputError
        Naming the file, if it is missing, unreadable, too large (:func:`~spurdyn.case.files.read_text`)
        or not valid TOML.
    """
    text = read_text(path, str(path), "no such file; give a preset name or a TOML file")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(str(path), f"is not valid TOML ({err})") from None


def _allowables_to_dict(material: Material) -> dict[str, Any]:
    """The allowables as :func:`_allowables` reads them: the class if they came from one."""
    if material.iso_class is not None:
        name, grade, hardness = material.iso_class
        key = iso_materials.HARDNESS_KEYS[iso_materials.LINES[name].scale]
        return {"material_class": name, "grade": grade, key: hardness}
    return {k: getattr(material, k) for k in ("sigma_flim", "sigma_hlim")
            if getattr(material, k) is not None}


def gear_to_dict(gear: Gear) -> dict[str, Any]:
    """A gear as its case-file table, the inverse of :func:`gear_from_table`.

    Parameters
    ----------
    gear : Gear
        The gear.

    Returns
    -------
    dict
        The ``[gear_a]``/``[gear_b]`` table (relief, rack and blank keys only when used).
    """
    table: dict[str, Any] = {
        "teeth": gear.teeth, "module": gear.module, "addendum": gear.addendum,
        "dedendum": gear.dedendum, "pressure_angle_deg": math.degrees(gear.pressure_angle),
        "face_width": gear.face_width, "disk_inertia": gear.disk_inertia,
        "cutter_tip_radius": gear.cutter_tip_radius,
        "material": {"young": gear.material.young, "poisson": gear.material.poisson,
                     "density": gear.material.density,
                     **_allowables_to_dict(gear.material)},
    }
    if gear.tip_relief > 0.0 or gear.tip_relief_start_roll is not None:
        table["tip_relief"] = gear.tip_relief
        if gear.tip_relief_start_roll is not None:
            table["tip_relief_start_roll_deg"] = math.degrees(gear.tip_relief_start_roll)
        table["tip_relief_shape"] = gear.tip_relief_shape
    # Written only when used, so that older cases store the same description.
    for key in ("profile_shift", "thickness_allowance"):
        if getattr(gear, key) != 0.0:
            table[key] = getattr(gear, key)
    rack = gear.basic_rack
    if rack != default_rack(gear.pressure_angle):
        table["basic_rack"] = rack.name if ISO_53.get(rack.name) == rack else {
            k: getattr(rack, k) for k in sorted(RACK_KEYS)}
    if gear.blank is not None:
        del table["disk_inertia"]
        table["blank"] = {k: getattr(gear.blank, k) for k in sorted(BLANK_KEYS)
                          if getattr(gear.blank, k) is not None}
    return table


