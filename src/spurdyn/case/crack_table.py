"""The ``[crack]`` table of a case file: the growth constants of ``spurdyn crack``
(docs/casefile.md, docs/fracture.md section 9), in SI units."""

from __future__ import annotations

import math
from typing import Any

from spurdyn.case.pair_tables import check_keys
from spurdyn.errors import InputError

__all__ = ["CRACK_KEYS", "crack_constants"]

#: Keys of the ``[crack]`` table: Paris's ``C`` (m per cycle at 1 Pa sqrt(m)), ``m``, and the
#: threshold range ``dK_th`` (Pa sqrt(m)).
CRACK_KEYS = {"paris_c", "paris_m", "threshold"}


def crack_constants(data: dict[str, Any]) -> dict[str, float]:
    """The ``[crack]`` table's constants (none if there is no table), each a finite number,
    refused naming ``crack.<key>``; whether they are enough for a life is the command's
    check."""
    table = data.get("crack")
    if table is None:
        return {}
    if not isinstance(table, dict):
        raise InputError("crack", "must be a table")
    check_keys(table, CRACK_KEYS, "crack")
    out = {}
    for key, value in table.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError(f"crack.{key}", f"must be a number (got {value!r})")
        out[key] = float(value)
    return out
