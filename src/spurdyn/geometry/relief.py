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
:class:`~spurdyn.geometry.gear.Gear`, so compiled code can evaluate the same depth as
``amount * max(0, (xi - start) / (tip - start)) ** exponent``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:  # pragma: no cover - imports for annotations only
    from spurdyn.geometry.gear import Gear

#: Relief shapes and the exponent ``k`` of the depth formula.
RELIEF_SHAPES: dict[str, int] = {"linear": 1, "parabolic": 2}


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


def relief_params(gear: "Gear") -> tuple[float, float, float, float]:
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
