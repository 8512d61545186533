"""Plane-stress finite elements: the Q8 element and its edge, material, assembly, stable step."""

from spurdyn.fem.assembly import (
    assemble_consistent_mass,
    assemble_lumped_mass,
    assemble_stiffness,
    centroid_stresses,
    element_mass,
    element_stiffness,
    element_stress,
    hrz_lump,
    jacobian_determinants,
    von_mises_plane_stress,
)
from spurdyn.fem.element import ElementQuadS2, gauss_2d
from spurdyn.fem.material import STEEL, Material, plane_stress_matrix
from spurdyn.fem.stable_step import (
    CENTRAL_DIFFERENCE_STABILITY_LIMIT, RK4_STABILITY_LIMIT, StableStep, stable_time_step,
)

__all__ = [
    "CENTRAL_DIFFERENCE_STABILITY_LIMIT",
    "RK4_STABILITY_LIMIT",
    "STEEL",
    "ElementQuadS2",
    "Material",
    "StableStep",
    "assemble_consistent_mass",
    "assemble_lumped_mass",
    "assemble_stiffness",
    "centroid_stresses",
    "element_mass",
    "element_stiffness",
    "element_stress",
    "gauss_2d",
    "hrz_lump",
    "jacobian_determinants",
    "plane_stress_matrix",
    "stable_time_step",
    "von_mises_plane_stress",
]
