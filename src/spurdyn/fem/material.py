"""Linear-elastic isotropic material and its plane-stress constitutive matrix."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError

__all__ = ["Material", "STEEL", "bursting_speed", "check_plausible", "plane_stress_matrix"]

#: Bounds that catch a value in the wrong unit (docs/casefile.md, "Plausibility"). The
#: softest gear plastics (PE-UHMW, some 0.7 GPa) and the stiffest solids (diamond,
#: 1.1 TPa) bound Young's modulus; a modulus in MPa (210000 for steel) falls far below.
YOUNG_RANGE = (1e8, 1.2e12)
#: Lightest plastic (some 900 kg/m^3) to densest metal (osmium, 22600 kg/m^3), with room;
#: a density in g/cm^3 (7.8 for steel) falls far below.
DENSITY_RANGE = (500.0, 25e3)
#: Generous bound on the strength of a gear material as a fraction of its Young's modulus
#: (2.1 GPa for steel, above the strongest gear steels): the bursting speed is reckoned
#: from it, so any speed refused is beyond what the material can carry.
STRENGTH_OVER_YOUNG = 0.01


@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material.

    Parameters
    ----------
    young : float
        Young's modulus E [Pa]; must be finite and > 0.
    poisson : float
        Poisson's ratio nu [-]; must lie in (-1, 0.5) for a positive-definite
        plane-stress matrix.
    density : float
        Mass density rho [kg/m^3]; must be finite and > 0.
    sigma_flim, sigma_hlim : float or None
        Optional allowable stress numbers of ISO 6336-5 [Pa]: bending ``sigma_Flim`` and
        contact ``sigma_Hlim``; when given, a run reports the safety factors S_F and S_H.
    iso_class : tuple of (str, str, float) or None
        The ISO 6336-5 material class, quality grade and surface hardness (in the class's
        scale, HV or HBW) the allowable stress numbers were read from, kept so that a
        stored case names them; ``None`` when they were given as numbers. Checked by the
        case file (:mod:`spurdyn.iso6336.materials`), not here.

    Raises
    ------
    InputError
        If a field is not a number or out of range. ``field`` is the bare field name
        (``young``, ``poisson``, ``density``) so that a reader can prefix it with where
        the material came from (``gear_a.material``). ``InputError`` is a ``ValueError``.
    """

    young: float
    poisson: float
    density: float
    sigma_flim: float | None = None
    sigma_hlim: float | None = None
    iso_class: tuple[str, str, float] | None = None

    def __post_init__(self) -> None:
        for name in ("young", "poisson", "density"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise InputError(name, f"must be a number (got {value!r})")
        for name in ("young", "density"):
            value = getattr(self, name)
            # `not (x > 0)` also rejects NaN, which `x <= 0` would let through.
            if not value > 0:
                raise InputError(name, f"must be > 0 (got {value})")
            if not math.isfinite(value):
                raise InputError(name, f"must be finite (got {value})")
        nu = self.poisson
        if not -1.0 < nu < 0.5:
            raise InputError("poisson", f"must be in (-1, 0.5) (got {nu})")
        for name in ("sigma_flim", "sigma_hlim"):
            value = getattr(self, name)
            if value is None:
                continue
            if (isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer))
                    or not math.isfinite(value) or not 1e6 <= value <= 1e10):
                raise InputError(name, f"must be an allowable stress in Pa, 1e6 to 1e10 "
                                 f"(got {value!r}; a value in MPa is refused)")


def check_plausible(material: Material) -> None:
    """Refuse constants that are almost certainly in the wrong unit (MPa, g/cm^3).

    Kept apart from :class:`Material`, which accepts any physical numbers (unit tests use
    ``E = 200``); the case file calls it on what a user wrote. Errors name the field.
    """
    lo, hi = YOUNG_RANGE
    if not lo <= material.young <= hi:
        raise InputError("young", f"{material.young:g} Pa is outside any gear material "
                         f"({lo:g} to {hi:g} Pa); it is in Pa, not MPa or GPa "
                         f"(steel: 210e9)")
    lo, hi = DENSITY_RANGE
    if not lo <= material.density <= hi:
        raise InputError("density", f"{material.density:g} kg/m^3 is outside any gear material "
                         f"({lo:g} to {hi:g}); it is in kg/m^3, not g/cm^3 (steel: 7800)")


def bursting_speed(material: Material, outer_radius: float) -> float:
    """Angular speed (rad/s) at which a solid disk of this material would burst.

    The hoop stress at the centre of a spinning solid disk is ``(3 + nu) rho w^2 R^2 / 8``
    (thin-disk plane stress); it reaches the bound :data:`STRENGTH_OVER_YOUNG` ``E`` at
    ``w = sqrt(8 s / ((3 + nu) rho)) / R``. Some 800 m/s at the rim for steel: a speed
    above it is a unit slip, not a gear.
    """
    strength = STRENGTH_OVER_YOUNG * material.young
    return math.sqrt(8.0 * strength / ((3.0 + material.poisson) * material.density)) / outer_radius


STEEL = Material(young=210e9, poisson=0.3, density=7800.0)
"""Generic structural steel: E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3."""


def plane_stress_matrix(material: Material) -> NDArray[np.float64]:
    """Plane-stress constitutive matrix.

    Parameters
    ----------
    material : Material
        Elastic constants.

    Returns
    -------
    ndarray, shape (3, 3)
        ``D`` with ``[sxx, syy, txy] = D @ [exx, eyy, gxy]`` where ``gxy`` is
        the engineering shear strain ``du/dy + dv/dx`` [Pa].
    """
    e, nu = material.young, material.poisson
    c = e / (1.0 - nu**2)
    return c * np.array(
        [
            [1.0, nu, 0.0],
            [nu, 1.0, 0.0],
            [0.0, 0.0, 0.5 * (1.0 - nu)],
        ]
    )
