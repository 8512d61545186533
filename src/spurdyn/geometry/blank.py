"""Gear blanks: the rigid body under the teeth and its moment of inertia.

A blank is a solid disk from the bore to the root circle, or a hub, a web and a rim.
Its inertia plus that of the teeth that are not modelled elastically is the rigid
disk's ``J``; the one elastic tooth brings its own mass through the finite elements, so
each tooth is counted once (``docs/geometry.md``, section 9). Numbers in, numbers out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from spurdyn.errors import InputError


@dataclass(frozen=True)
class Blank:
    """Dimensions of a gear blank (m); the face width and the root circle come from the gear.

    Parameters
    ----------
    bore_radius
        Radius of the shaft bore (0: none; the shaft is then not counted).
    hub_radius, rim_radius, web_width
        A webbed blank: full face width from the bore to ``hub_radius``, a web of axial
        width ``web_width`` from there to ``rim_radius``, full face width again from
        ``rim_radius`` to the root circle. All three or none.
    """

    bore_radius: float = 0.0
    hub_radius: float | None = None
    rim_radius: float | None = None
    web_width: float | None = None

    @property
    def webbed(self) -> bool:
        return self.web_width is not None

    def describe(self) -> str:
        """One line saying what was assumed."""
        bore = f", bore radius {self.bore_radius * 1e3:.4g} mm" if self.bore_radius else ""
        if not self.webbed:
            return f"solid disk to the root circle{bore}"
        return (f"hub to {self.hub_radius * 1e3:.4g} mm, web {self.web_width * 1e3:.4g} mm wide "
                f"to {self.rim_radius * 1e3:.4g} mm, rim to the root circle{bore}")


def check_blank(blank: Blank, root_radius: float, face_width: float) -> None:
    """Refuse a blank that does not fit under the teeth (errors name ``blank.<key>``)."""
    for key in ("bore_radius", "hub_radius", "rim_radius", "web_width"):
        v = getattr(blank, key)
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                              or not math.isfinite(v) or v < 0.0):
            raise InputError(f"blank.{key}", f"must be a number of metres >= 0 (got {v!r})")
    if blank.bore_radius >= root_radius:
        raise InputError("blank.bore_radius", f"must be below the root radius {root_radius:g} m")
    web = (blank.hub_radius, blank.rim_radius, blank.web_width)
    if any(v is None for v in web) and not all(v is None for v in web):
        raise InputError("blank.web_width", "a web needs hub_radius, rim_radius and web_width")
    if blank.webbed:
        if not blank.bore_radius <= blank.hub_radius < blank.rim_radius <= root_radius:
            raise InputError("blank.rim_radius", "needs bore_radius <= hub_radius < rim_radius "
                             f"<= the root radius {root_radius:g} m")
        if not 0.0 < blank.web_width <= face_width:
            raise InputError("blank.web_width", f"must lie in (0, face width {face_width:g} m]")


def ring_inertia(density: float, width: float, r_out: float, r_in: float) -> float:
    """Polar moment of inertia (kg m^2) of a ring: ``rho w pi (r_o^4 - r_i^4) / 2``."""
    return density * width * math.pi * (r_out**4 - r_in**4) / 2.0


def blank_inertia(blank: Blank, root_radius: float, face_width: float, density: float) -> float:
    """Polar moment of inertia (kg m^2) of the blank up to the root circle."""
    if not blank.webbed:
        return ring_inertia(density, face_width, root_radius, blank.bore_radius)
    return (ring_inertia(density, face_width, blank.hub_radius, blank.bore_radius)
            + ring_inertia(density, blank.web_width, blank.rim_radius, blank.hub_radius)
            + ring_inertia(density, face_width, root_radius, blank.rim_radius))


#: The range of a given ``disk_inertia`` in units of the gear's own solid disk (the default
#: blank's). Below: lighter than a thin rim under the teeth (a rim one module deep holds
#: about ``4 m / r = 8 / z`` of the solid disk, 0.008 at the most teeth). Above: what a shaft can
#: carry beside the gear, with a margin of a hundred (a flywheel of 0.3 kg m^2 beside the
#: paper's gear is 1,000 times it, a motor's rotor beside a 17-tooth pinion some 2,500).
#: Beyond either end the number is a slip of units (g mm^2, or 1e300), not a gear.
INERTIA_RATIOS = (1e-3, 1e6)


def check_disk_inertia(j: float, solid: float) -> None:
    """Refuse a given ``disk_inertia`` ``j`` (kg m^2) beyond :data:`INERTIA_RATIOS` times the
    gear's own solid disk's ``solid`` (the default blank's), naming ``disk_inertia``."""
    low, high = INERTIA_RATIOS
    if not low * solid <= j <= high * solid:
        raise InputError("disk_inertia", f"{j:g} kg m^2 is {j / solid:.3g} times the gear's own "
                         f"solid disk ({solid:.3g} kg m^2); give {low * solid:.3g} to "
                         f"{high * solid:.3g} kg m^2 (inertia is in kg m^2)")
