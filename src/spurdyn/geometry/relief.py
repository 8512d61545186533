"""Tip relief: the single source of truth for the relief depth of a modified flank.

A tip relief removes material from the flank, normal to the involute, from a start roll
angle ``xi_s`` up to the tip. At the involute point of roll angle ``xi`` (rad) the depth
along the outward flank normal is

    depth(xi) = C_a * max(0, (xi - xi_s) / (xi_tip - xi_s)) ** k

with ``C_a`` the amount at the tip circle's roll angle ``xi_tip`` and ``k = 1`` (linear)
or ``2`` (parabolic). The roll angle of the involute point at radius ``r`` is
``xi = sqrt(r^2 - r_b^2) / r_b``. The formula is not clipped above ``xi_tip``: the
relieved flank meets the tip circle a few micrometres beyond the involute's tip point
(``docs/geometry.md``, section 7), where it is continued by the same formula.

:func:`relief_depth` is the formula; :func:`relief_params` gives its four numbers for a
gear (anything with the attributes of :class:`ReliefGear`), so compiled code can evaluate
the same depth as ``amount * max(0, (xi - start) / (tip - start)) ** exponent``;
:func:`check_relief` refuses a relief that is not a small, well-placed modification.
Numbers in, numbers out: this module does not import the gear.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError

#: Relief shapes and the exponent ``k`` of the depth formula.
RELIEF_SHAPES: dict[str, int] = {"linear": 1, "parabolic": 2}

#: Largest tilt (rad) a tip relief may give the flank: the largest slope of the depth
#: along the involute's arc length, ``k C_a r_b / ((L_a - L_s) L)`` with ``L = L_s``
#: (linear) or ``L_a`` (parabolic) (see ``docs/geometry.md``, section 7). A relief that
#: starts too close to the tip for its amount is refused.
MAX_RELIEF_TILT = 0.1

#: Largest tip relief as a fraction of the module (a second cap is a quarter of the tip
#: land of the unmodified tooth).
MAX_RELIEF_MODULES = 0.1


class ReliefGear(Protocol):
    """What :func:`relief_params` reads of a gear."""

    base_radius: float
    tip_radius: float
    tip_relief: float
    tip_relief_start_roll: float | None
    tip_relief_shape: str


def relief_depth(
    roll: ArrayLike, amount: float, start_roll: float, tip_roll: float, exponent: float
) -> NDArray[np.float64]:
    """Relief depth (m) along the outward flank normal at roll angles ``roll`` (rad).

    ``amount * max(0, (roll - start_roll) / (tip_roll - start_roll)) ** exponent``;
    zero everywhere if ``amount`` is zero. Vectorised over ``roll``.
    """
    xi = np.asarray(roll, dtype=float)
    if amount == 0.0:
        return np.zeros_like(xi)
    u = np.maximum((xi - start_roll) / (tip_roll - start_roll), 0.0)
    return amount * u**exponent


def relief_params(gear: ReliefGear) -> tuple[float, float, float, float]:
    """``(amount, start_roll, exponent, tip_roll)`` of a gear's tip relief, as floats.

    ``amount`` in m, the roll angles in rad (``tip_roll`` that of the tip circle,
    ``sqrt(r_a^2 - r_b^2) / r_b``), ``exponent`` 1.0 (linear) or 2.0 (parabolic). A gear
    without relief gives ``amount = 0.0`` (and ``start_roll = tip_roll``, exponent 1.0),
    for which the depth formula is zero everywhere; guard the division by
    ``amount > 0`` when evaluating it.
    """
    rb = gear.base_radius
    ra = gear.tip_radius
    tip_roll = math.sqrt(max(ra * ra - rb**2, 0.0)) / rb  # as Gear.roll_angle_at
    amount = float(gear.tip_relief)
    if amount == 0.0 or gear.tip_relief_start_roll is None:
        return 0.0, tip_roll, 1.0, tip_roll
    return (amount, float(gear.tip_relief_start_roll),
            float(RELIEF_SHAPES[gear.tip_relief_shape]), tip_roll)


def check_relief(amount: object, start: object, shape: object, *, form_roll: float,
                 tip_roll: float, base_radius: float, module: float,
                 tip_land: float) -> None:
    """Refuse a tip relief that is not a small, well-placed modification.

    ``form_roll`` and ``tip_roll`` are the roll angles (rad) of the form and tip radii,
    ``tip_land`` the unmodified tooth's land (m). Errors name the :class:`Gear` field.
    """
    if isinstance(amount, bool) or not isinstance(amount, (int, float)):
        raise InputError("tip_relief", f"must be a number (got {type(amount).__name__})")
    if not math.isfinite(amount) or amount < 0.0:
        raise InputError("tip_relief", f"must be zero or a positive number of metres "
                         f"(got {amount!r})")
    if not isinstance(shape, str) or shape not in RELIEF_SHAPES:
        raise InputError("tip_relief_shape", f"must be one of {', '.join(RELIEF_SHAPES)} "
                         f"(got {shape!r})")
    if start is None:
        if amount > 0.0:
            raise InputError("tip_relief_start_roll", "is missing: a tip relief needs the "
                             "roll angle where it begins")
        return
    if isinstance(start, bool) or not isinstance(start, (int, float)) or not math.isfinite(start):
        raise InputError("tip_relief_start_roll", f"must be a finite number (got {start!r})")
    lo, hi, rb = form_roll, tip_roll, base_radius
    if not lo - 1e-12 <= start < hi:
        r_lo, r_hi = rb * math.hypot(1.0, lo), rb * math.hypot(1.0, hi)
        raise InputError("tip_relief_start_roll", f"must lie on the involute, from the form "
                         f"radius' roll angle {math.degrees(lo):.4g} deg "
                         f"(r = {r_lo * 1e3:.5g} mm) up to below the tip's "
                         f"{math.degrees(hi):.4g} deg (r = {r_hi * 1e3:.5g} mm); "
                         f"got {math.degrees(start):.4g} deg")
    cap = min(MAX_RELIEF_MODULES * module, tip_land / 4.0)
    if amount > cap:
        raise InputError("tip_relief", f"{amount * 1e6:.4g} um is too large for this tooth "
                         f"(at most {cap * 1e6:.4g} um: 0.1 module and a quarter of the "
                         f"tip land)")
    if amount > 0.0:
        length_s, length_a = start * rb, hi * rb
        k = RELIEF_SHAPES[shape]
        # Largest slope of the depth along the involute's arc length s (ds = L dL / r_b):
        # at the start for a linear relief, at the tip for a parabolic one.
        length = length_s if k == 1 else length_a
        tilt = k * amount * rb / ((length_a - length_s) * max(length, 1e-12 * rb))
        if tilt > MAX_RELIEF_TILT:
            raise InputError("tip_relief_start_roll", f"starts too close to the tip (or "
                             f"the base circle) for a {amount * 1e6:.4g} um relief: it would "
                             f"tilt the flank by up to {tilt:.3g} rad (at most "
                             f"{MAX_RELIEF_TILT:g}); start lower or relieve less")
