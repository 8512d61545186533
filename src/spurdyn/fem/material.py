"""Linear-elastic isotropic material and its plane-stress constitutive matrix."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError

__all__ = ["Material", "STEEL", "plane_stress_matrix"]


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
