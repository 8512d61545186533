"""The ``[gear_a.bearing]`` and ``[gear_b.bearing]`` tables: each hub on a radial bearing
(the sector model; docs/casefile.md, docs/sector.md 6.12)."""

from __future__ import annotations

from typing import Any

from spurdyn.errors import InputError
from spurdyn.settings import Bearing, check_bearings

#: The keys of a bearing table.
BEARING_TABLE_KEYS = ("stiffness", "damping")


def bearing_from_table(table: dict[str, Any], where: str) -> Bearing | None:
    """The bearing of a gear table ``where`` (``gear_a``, ``gear_b``): ``None`` without a
    ``bearing`` table; its stiffness (N/m, required) and damping (N s/m, 0 by default)
    refused in one line naming the key."""
    if "bearing" not in table:
        return None
    value = table["bearing"]
    key = f"{where}.bearing"
    if not isinstance(value, dict):
        raise InputError(key, "must be a table: stiffness = N/m, damping = N s/m")
    for k in value:
        if k not in BEARING_TABLE_KEYS:
            raise InputError(f"{key}.{k}", f"unknown key; expected one of: {', '.join(BEARING_TABLE_KEYS)}")
    if "stiffness" not in value:
        raise InputError(f"{key}.stiffness", "is missing: give the bearing's radial stiffness in N/m")
    bearing = Bearing(value["stiffness"], value.get("damping", 0.0))
    check_bearings((bearing, None) if where == "gear_a" else (None, bearing))
    return Bearing(float(bearing.stiffness), float(bearing.damping))


def bearings_from_dict(data: dict[str, Any]) -> tuple[Bearing | None, Bearing | None] | None:
    """Both hubs' bearings of a case document (gear B's table, when left out, is gear A's,
    its bearing too); ``None`` where neither gear has one."""
    a = bearing_from_table(data["gear_a"], "gear_a")
    b = bearing_from_table(data["gear_b"], "gear_b") if "gear_b" in data else a
    return None if a is None and b is None else (a, b)


def bearing_to_table(bearing: Bearing) -> dict[str, float]:
    """A bearing as its case table (the inverse of :func:`bearing_from_table`)."""
    return {"stiffness": bearing.stiffness, "damping": bearing.damping}


__all__ = ["BEARING_TABLE_KEYS", "bearing_from_table", "bearing_to_table", "bearings_from_dict"]
