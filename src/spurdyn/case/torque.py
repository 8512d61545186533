"""Read a torque history (:class:`~spurdyn.settings.TorqueHistory`) from a CSV file or a case
file's inline table (docs/casefile.md, "Torques that vary").

The CSV file has a header naming its columns and one sample a line, commas between values;
lines starting with ``#`` and blank lines are skipped::

    # an idle engine's torque: 2 N m with a fluctuation of 8 N m at 120 Hz
    time_s, driver_Nm, load_Nm
    0.0,    2.0,       2.0
    ...

``time_s`` (s, increasing) and ``driver_Nm`` (the driver's torque, N m, positive along its
rotation) are needed; ``load_Nm`` (the driven gear's load torque, positive against its
rotation) is optional: without it the load is the run's nominal one. Every problem is raised
as an :class:`~spurdyn.errors.InputError` naming the case key, the file and the line.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

from spurdyn.case.files import read_text
from spurdyn.errors import InputError
from spurdyn.settings import TorqueHistory

#: The columns of a history: needed, and optional.
NEEDED_COLUMNS = ("time_s", "driver_Nm")
OPTIONAL_COLUMNS = ("load_Nm",)


def read_history_csv(path: Path, key: str, periodic: bool = False) -> TorqueHistory:
    """The torque history in the CSV file ``path`` (module docstring); ``key`` names the case
    key or option that gave it, for the refusals."""
    text = read_text(path, key)
    header: list[str] | None = None
    columns: dict[str, list[float]] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.split(",")]
        where = f"{path.name} line {number}"
        if header is None:
            header = cells
            unknown = [c for c in cells if c not in NEEDED_COLUMNS + OPTIONAL_COLUMNS]
            missing = [c for c in NEEDED_COLUMNS if c not in cells]
            if unknown or missing or len(set(cells)) != len(cells):
                raise InputError(key, f"{where}: the header must name the columns "
                                 f"{', '.join(NEEDED_COLUMNS)} and optionally {', '.join(OPTIONAL_COLUMNS)}, "
                                 f"each once (got {line!r})"[:300])
            columns = {c: [] for c in cells}
            continue
        if len(cells) != len(header):
            raise InputError(key, f"{where}: {len(cells)} values for the {len(header)} columns "
                             f"{', '.join(header)}")
        for name, cell in zip(header, cells):
            try:
                value = float(cell)
            except ValueError:
                raise InputError(key, f"{where}: {cell!r} is not a number ({name})") from None
            if not math.isfinite(value):
                raise InputError(key, f"{where}: {cell!r} is not a finite number ({name})")
            columns[name].append(value)
    if header is None:
        raise InputError(key, f"{path.name} holds no header and no samples")
    return _history(columns, key, periodic, path.name)


def history_from_table(table: Mapping[str, Any], key: str, periodic: bool = False) -> TorqueHistory:
    """The torque history of an inline table ``{time_s = [...], driver_Nm = [...],
    load_Nm = [...]}`` (what :func:`history_to_table` writes)."""
    allowed = NEEDED_COLUMNS + OPTIONAL_COLUMNS
    for name in table:
        if name not in allowed:
            raise InputError(f"{key}.{name}", f"unknown key; expected one of: {', '.join(allowed)}")
    columns: dict[str, list[float]] = {}
    for name in allowed:
        if name not in table:
            if name in NEEDED_COLUMNS:
                raise InputError(f"{key}.{name}", "is missing")
            continue
        values = table[name]
        if (not isinstance(values, list)
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)):
            raise InputError(f"{key}.{name}", "must be a list of numbers")
        columns[name] = [float(v) for v in values]
    return _history(columns, key, periodic, "")


def _history(columns: Mapping[str, list[float]], key: str, periodic: bool, source: str) -> TorqueHistory:
    """The :class:`TorqueHistory` of the columns, its refusals named by ``key``."""
    load = columns.get("load_Nm")
    try:
        return TorqueHistory(time=tuple(columns["time_s"]), driver=tuple(columns["driver_Nm"]),
                             load=None if load is None else tuple(load), periodic=periodic,
                             source=source)
    except InputError as err:
        raise InputError(key, f"{source + ': ' if source else ''}{err.reason}") from None


def history_to_table(history: TorqueHistory) -> dict[str, list[float]]:
    """The inline table of a history, that :func:`history_from_table` reads back."""
    table = {"time_s": list(history.time), "driver_Nm": list(history.driver)}
    if history.load is not None:
        table["load_Nm"] = list(history.load)
    return table


__all__ = ["NEEDED_COLUMNS", "OPTIONAL_COLUMNS", "history_from_table", "history_to_table",
           "read_history_csv"]
