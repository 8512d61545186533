"""Where each run setting of a case comes from: a command-line override or the case file's
table, read and refused in one line naming the key or option written (:class:`RunSource`,
for :mod:`spurdyn.case.file`)."""

from __future__ import annotations

import math
from typing import Any, Mapping

from spurdyn.errors import InputError


class RunSource:
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

    def choice(self, key: str, default: str, allowed: tuple[str, ...],
               retired: Mapping[str, str] | None = None) -> str:
        found, value, name = self.get(key)
        if not found:
            return default
        if retired and isinstance(value, str) and value in retired:
            raise InputError(name, f"{value!r} {retired[value]}")
        if value not in allowed:
            raise InputError(name, f"must be one of {', '.join(allowed)} (got {value!r})")
        return str(value)

    def boolean(self, key: str, default: bool | None) -> bool | None:
        found, value, name = self.get(key)
        if not found:
            return default
        if not isinstance(value, bool):
            raise InputError(name, f"must be true or false (got {value!r})")
        return value


__all__ = ["RunSource"]
