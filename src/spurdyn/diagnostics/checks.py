"""Checks of the arguments the diagnostics take, each refusal naming the argument.

A bad argument raises :class:`spurdyn.errors.InputError` with the argument's name as its
field and the fix in its reason, as everywhere in spurdyn.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError


def as_signal(values: ArrayLike, key: str, least: int = 2) -> NDArray[np.float64]:
    """``values`` as a 1-D array of at least ``least`` finite floats, else refused naming ``key``."""
    try:
        x = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise InputError(key, f"is not an array of numbers ({err})") from None
    if x.ndim != 1:
        raise InputError(key, f"must be one-dimensional (one value per sample), got shape {x.shape}")
    if x.size < least:
        raise InputError(key, f"has {x.size} samples, at least {least} are needed")
    if not np.all(np.isfinite(x)):
        raise InputError(key, f"holds {int(np.sum(~np.isfinite(x)))} values that are NaN or infinite")
    return x


def positive(value: float, key: str) -> float:
    """``value`` as a finite float > 0, else refused naming ``key``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(key, f"must be a number, got {value!r}")
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise InputError(key, f"must be finite and > 0, got {v!r}")
    return v


def count(value: int, key: str, least: int) -> int:
    """``value`` as an integer >= ``least``, else refused naming ``key``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(key, f"must be a whole number, got {value!r}")
    if int(value) < least:
        raise InputError(key, f"must be at least {least}, got {int(value)}")
    return int(value)
