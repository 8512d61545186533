"""A case file's ``[[fault]]`` tables and the ``--fault`` option (docs/casefile.md, "Faults").

Each table names a gear, a tooth on it and a kind; a spall adds the stretch of the flank
it covers (``roll_deg``, the gear's own roll angles, inside its active profile), its
``depth`` (m) and ``width_fraction`` (of the face width, default 1); a chip its ``height``
below the tip circle and ``width`` along the top land (m). Every problem is
refused naming the key as written: ``fault[2].depth`` for the third table of a file,
``--fault`` for the option.
"""

from __future__ import annotations

import math
from typing import Any

from spurdyn.errors import InputError
from spurdyn.geometry.fault import KINDS, PLANNED_KINDS, Fault, active_rolls
from spurdyn.geometry.pair import GearPair

FAULT_KEYS = {"gear", "tooth", "kind", "roll_deg", "depth", "width_fraction", "angle_deg", "start_radius",
              "height", "width"}
#: The keys each kind reads beyond ``gear``, ``tooth`` and ``kind``.
KIND_KEYS = {"missing": set(), "spall": {"roll_deg", "depth", "width_fraction"},
             "crack": {"depth", "angle_deg", "start_radius"}, "chip": {"height", "width"}}
#: Deepest spall (m): beyond it a pit is a broken tooth (``kind = "missing"``).
MAX_SPALL_DEPTH = 1e-3
#: Steepest crack below the horizontal (deg): a crack along the tooth is not a root crack.
MAX_CRACK_ANGLE_DEG = 80.0


def _value(table: dict[str, Any], key: str, where: str) -> Any:
    if key not in table:
        raise InputError(f"{where}.{key}", "is missing")
    return table[key]


def _positive(table: dict[str, Any], key: str, where: str, default: float | None,
              top: float) -> float:
    value = table.get(key, default) if default is not None else _value(table, key, where)
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or not 0.0 < value <= top:
        raise InputError(f"{where}.{key}", f"must be a number above 0 and at most {top:g} "
                         f"(got {value!r})")
    return float(value)


def _spall_roll(table: dict[str, Any], where: str, pair: GearPair, gear: str) -> tuple[float, float]:
    value = _value(table, "roll_deg", where)
    lo, hi = active_rolls(pair, gear)
    span = f"{math.degrees(lo):.4g} to {math.degrees(hi):.4g} deg"
    if not isinstance(value, list) or len(value) != 2 or any(
            isinstance(v, bool) or not isinstance(v, (int, float)) for v in value):
        raise InputError(f"{where}.roll_deg", f"must be two roll angles in degrees, e.g. [{span.split(' to ')[0]}, "
                         f"{math.degrees(0.5 * (lo + hi)):.4g}] (got {value!r})")
    a, b = (math.radians(float(v)) for v in value)
    if not (lo - 1e-12 <= a < b <= hi + 1e-12):
        raise InputError(f"{where}.roll_deg", f"must rise and lie on the active flank of gear_{gear}, "
                         f"{span} of its roll (got {value!r})")
    return a, b


def fault_from_table(table: Any, where: str, pair: GearPair) -> Fault:
    """One fault from its table (``where`` its name in messages), checked against ``pair``."""
    if not isinstance(table, dict):
        raise InputError(where, "must be a table, e.g. [[fault]] gear = \"a\" tooth = 5 kind = \"missing\"")
    unknown = sorted(set(table) - FAULT_KEYS)
    if unknown:
        raise InputError(f"{where}.{unknown[0]}", f"unknown key; expected one of: {', '.join(sorted(FAULT_KEYS))}")
    gear = _value(table, "gear", where)
    if gear not in ("a", "b"):
        raise InputError(f"{where}.gear", f"must be \"a\" or \"b\" (got {gear!r})")
    teeth = (pair.gear_a if gear == "a" else pair.gear_b).teeth
    tooth = _value(table, "tooth", where)
    if isinstance(tooth, bool) or not isinstance(tooth, int) or not 0 <= tooth < teeth:
        raise InputError(f"{where}.tooth", f"must be a tooth of gear_{gear}, 0 to {teeth - 1} (got {tooth!r})")
    kind = _value(table, "kind", where)
    if kind in PLANNED_KINDS:
        raise InputError(f"{where}.kind", f"{kind!r} is not computed yet; the kinds computed are "
                         f"{', '.join(KINDS)}")
    if kind not in KINDS:
        raise InputError(f"{where}.kind", f"must be one of {', '.join(KINDS)} (got {kind!r})")
    extra = sorted(set(table) - {"gear", "tooth", "kind"} - KIND_KEYS[kind])
    if extra:
        raise InputError(f"{where}.{extra[0]}", f"is not read for kind = {kind!r}")
    if kind == "missing":
        return Fault(gear=gear, tooth=tooth, kind=kind)
    if kind == "crack":
        return _crack(table, where, pair, gear, tooth)
    if kind == "chip":
        return _chip(table, where, pair, gear, tooth)
    return Fault(gear=gear, tooth=tooth, kind=kind, roll=_spall_roll(table, where, pair, gear),
                 depth=_positive(table, "depth", where, None, MAX_SPALL_DEPTH),
                 width_fraction=_positive(table, "width_fraction", where, 1.0, 1.0))


def _crack(table: dict[str, Any], where: str, pair: GearPair, gear: str, tooth: int) -> Fault:
    """A crack's fault; its path checked against its tooth's cell on the default mesh by
    the mesher (which refuses a mouth off the fillet or a tip outside the cell, named as
    written here); the run checks it again on its own mesh."""
    from spurdyn.mesh.cracked import crack_path
    from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY, tooth_mesh
    from spurdyn.sector.body import body_cell

    depth = _positive(table, "depth", where, None, (pair.gear_a if gear == "a" else pair.gear_b).tip_radius)
    angle = None
    if "angle_deg" in table:
        value = table["angle_deg"]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 <= value <= MAX_CRACK_ANGLE_DEG:
            raise InputError(f"{where}.angle_deg", f"must be a number from 0 to {MAX_CRACK_ANGLE_DEG:g} "
                             f"(got {value!r})")
        angle = math.radians(float(value))
    start = _positive(table, "start_radius", where, None, math.inf) if "start_radius" in table else None
    g = pair.gear_a if gear == "a" else pair.gear_b
    written = {"fault.depth": "depth", "fault.start": "start_radius", "fault.angle": "angle_deg"}
    try:
        crack_path(g, tooth_mesh(g, DEFAULT_NX, DEFAULT_NY), "right", depth, angle, start,
                   region=body_cell(g, DEFAULT_NX, DEFAULT_NY))
    except InputError as err:
        raise InputError(f"{where}.{written.get(err.field, 'depth')}", err.reason) from None
    return Fault(gear=gear, tooth=tooth, kind="crack", depth=depth, angle=angle, start=start)


def _chip(table: dict[str, Any], where: str, pair: GearPair, gear: str, tooth: int) -> Fault:
    """A chip's fault: its cut must leave the loaded flank above the lowest point of its
    active profile (the mating tip's reach) and meet the top land short of its far corner."""
    g = pair.gear_a if gear == "a" else pair.gear_b
    low = g.base_radius * math.hypot(1.0, active_rolls(pair, gear)[0])
    height = _positive(table, "height", where, None, math.inf)
    if not g.tip_radius - height > low:
        raise InputError(f"{where}.height", f"must leave the cut on the active flank of gear_{gear}: "
                         f"below {(g.tip_radius - low) * 1e3:.4g} mm (the tip radius "
                         f"{g.tip_radius * 1e3:.4g} mm less the lowest contact radius "
                         f"{low * 1e3:.4g} mm; got {height * 1e3:.4g} mm)")
    land = g.tip_thickness
    width = _positive(table, "width", where, None, math.inf)
    if not width < land:
        raise InputError(f"{where}.width", f"must be less than the top land of gear_{gear}, "
                         f"{land * 1e3:.4g} mm along the tip circle (got {width * 1e3:.4g} mm)")
    return Fault(gear=gear, tooth=tooth, kind="chip", depth=height, width=width)


def fault_to_table(fault: Fault) -> dict[str, Any]:
    """The ``[[fault]]`` table :func:`fault_from_table` reads back as ``fault`` (a stored
    case's, which stands on its own)."""
    table: dict[str, Any] = {"gear": fault.gear, "tooth": fault.tooth, "kind": fault.kind}
    if fault.kind == "spall":
        table.update(roll_deg=[math.degrees(r) for r in fault.roll], depth=fault.depth,
                     width_fraction=fault.width_fraction)
    elif fault.kind == "crack":
        table["depth"] = fault.depth
        if fault.angle is not None:
            table["angle_deg"] = math.degrees(fault.angle)
        if fault.start is not None:
            table["start_radius"] = fault.start
    elif fault.kind == "chip":
        table.update(height=fault.depth, width=fault.width)
    return table


def faults_from_dict(data: dict[str, Any], pair: GearPair) -> tuple[Fault, ...]:
    """The case file's ``[[fault]]`` tables; a tooth with two faults of one kind refused."""
    tables = data.get("fault", [])
    if not isinstance(tables, list):
        raise InputError("fault", "must be an array of tables: [[fault]] gear = \"a\" tooth = 5 ...")
    faults = tuple(fault_from_table(t, f"fault[{i}]", pair) for i, t in enumerate(tables))
    check_faults(faults, [f"fault[{i}].tooth" for i in range(len(faults))])
    return faults


def check_faults(faults: tuple[Fault, ...], keys: list[str]) -> None:
    """Refuse, naming fault ``i``'s ``keys[i]``, a tooth missing twice, a missing tooth with
    another fault, or a tooth cracked or chipped twice or both (each meshes the tooth's cell
    again; spalls may be several on a flank)."""
    seen: dict[tuple[str, int], set[str]] = {}
    for f, key in zip(faults, keys):
        kinds = seen.setdefault((f.gear, f.tooth), set())
        if "missing" in kinds or (f.kind == "missing" and kinds):
            raise InputError(key, f"tooth {f.tooth} of gear_{f.gear} is missing: it takes no other fault")
        if f.kind == "crack" and "crack" in kinds:
            raise InputError(key, f"tooth {f.tooth} of gear_{f.gear} is already cracked: one crack a tooth")
        if f.kind in ("crack", "chip") and kinds & {"crack", "chip"}:
            raise InputError(key, f"tooth {f.tooth} of gear_{f.gear} is already cracked or chipped: one "
                             "crack or one chip a tooth")
        kinds.add(f.kind)


def parse_fault_option(text: str, pair: GearPair) -> Fault:
    """``--fault gear=a,tooth=5,kind=spall,roll_deg=20:24,depth=2e-5``: one fault, the
    keys of a ``[[fault]]`` table (a roll range as ``A:B``)."""
    table: dict[str, Any] = {}
    for item in str(text).split(","):
        key, sep, raw = item.partition("=")
        key, raw = key.strip(), raw.strip()
        if not sep or not key:
            raise InputError("--fault", f"must be key=value pairs separated by commas, e.g. "
                             f"gear=a,tooth=5,kind=missing (got {text!r})")
        table[key] = _option_value(key, raw)
    try:
        return fault_from_table(table, "fault", pair)
    except InputError as err:
        raise InputError("--fault", f"{err.field.removeprefix('fault.')} {err.reason}") from None


def _option_value(key: str, raw: str) -> Any:
    if key in ("gear", "kind"):
        return raw
    try:
        if key == "roll_deg":
            return [float(v) for v in raw.split(":")]
        return int(raw) if key == "tooth" and raw.lstrip("-").isdigit() else float(raw)
    except ValueError:
        raise InputError("--fault", f"{key} must be a number (got {raw!r})") from None


__all__ = ["FAULT_KEYS", "MAX_SPALL_DEPTH", "check_faults", "fault_from_table", "fault_to_table", "faults_from_dict",
           "parse_fault_option"]
