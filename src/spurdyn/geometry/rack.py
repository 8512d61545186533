"""Basic rack profiles (ISO 53) and the fits of a cutter tip radius.

A basic rack gives, in multiples of the module, the gear's addendum ``h_aP``, its
dedendum ``h_fP`` (the cutter's addendum) and the root fillet radius ``rho_fP`` (the
cutter's tip radius). Numbers in, numbers out: nothing here knows a gear.
See ``docs/geometry.md``, section 8.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from spurdyn.errors import InputError


@dataclass(frozen=True)
class BasicRack:
    """A basic rack profile, in multiples of the module.

    Parameters
    ----------
    name
        ``"A"`` to ``"D"`` for the ISO 53 profiles, anything else for a custom rack.
    addendum
        ``h_aP / m``: the gear's addendum above the datum line.
    dedendum
        ``h_fP / m``: the gear's dedendum below the datum line (the cutter's addendum).
    fillet_radius
        ``rho_fP / m``: the root fillet radius (the cutter's tip radius).
    """

    name: str
    addendum: float
    dedendum: float
    fillet_radius: float

    def __post_init__(self) -> None:
        for key in ("addendum", "dedendum", "fillet_radius"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value) or value < 0.0 or (value == 0.0 and key != "fillet_radius"):
                raise InputError(f"basic_rack.{key}", f"must be a positive number of modules "
                                 f"(got {value!r})")
        if self.addendum > 2.0 or self.dedendum > 2.5:
            raise InputError("basic_rack", "heights are in modules: the addendum is at most 2 "
                             "and the dedendum at most 2.5")


#: ISO 53:1998 basic rack profiles for 20 deg gears: A (the common one, the paper's
#: 1 / 1.25 / 0.38), B and C (smaller fillets), D (deep, for finish grinding).
ISO_53: dict[str, BasicRack] = {
    "A": BasicRack("A", 1.0, 1.25, 0.38),
    "B": BasicRack("B", 1.0, 1.25, 0.30),
    "C": BasicRack("C", 1.0, 1.25, 0.25),
    "D": BasicRack("D", 1.0, 1.40, 0.39),
}


def full_round_radius(pressure_angle: float, dedendum: float) -> float:
    """Largest cutter tip radius (in modules) that fits the rack: the full-round tip.

    The rounding touches the cutter flank and the tip line; its centre lies
    ``pi/4 + h tan(alpha) + rho (1 - sin alpha) / cos alpha`` from the middle of the cut
    space and may not pass the cutter tooth's centre line at ``pi/2``, so
    ``rho <= (pi/4 - h tan alpha) cos alpha / (1 - sin alpha)`` with ``h`` the cutter's
    addendum in modules (``docs/geometry.md``, section 8).
    """
    sa, ca = math.sin(pressure_angle), math.cos(pressure_angle)
    return (math.pi / 4.0 - dedendum * sa / ca) * ca / (1.0 - sa)


def default_rack(pressure_angle: float) -> BasicRack:
    """The rack a gear of this pressure angle (rad) gets when none is named.

    ISO 53 profile A where its 0.38 m fillet fits (20 deg and below); for larger pressure
    angles the same heights with the full-round fillet rounded down to 0.01 m (0.31 m at
    25 deg), as cutters for those angles are made, so no standard gear is refused.
    """
    rack = ISO_53["A"]
    fits = math.floor(full_round_radius(pressure_angle, rack.dedendum) * 100.0) / 100.0
    if rack.fillet_radius <= fits:
        return rack
    return BasicRack(f"A ({math.degrees(pressure_angle):.4g} deg, full-round fillet)",
                     rack.addendum, rack.dedendum, max(fits, 0.0))
