"""Fracture mechanics on the Q8 meshes (docs/fracture.md): stress intensity factors at a
crack tip by the interaction integral (:mod:`~spurdyn.fracture.integral`, on the auxiliary
fields of :mod:`~spurdyn.fracture.williams`) and by displacement correlation on quarter-point
elements (:mod:`~spurdyn.fracture.correlation`), the direction of growth
(:mod:`~spurdyn.fracture.direction`), the handbook's cracked strips and plates they are
checked on (:mod:`~spurdyn.fracture.plate`, :mod:`~spurdyn.fracture.handbook`), a crack
grown by increments to a verdict (:mod:`~spurdyn.fracture.growth`, the model's K given as a
function) and its life by Paris's law (:mod:`~spurdyn.fracture.life`)."""

from spurdyn.fracture.correlation import displacement_correlation, quarter_points
from spurdyn.fracture.direction import equivalent_k, growth_angle, tangential_stress
from spurdyn.fracture.integral import DEFAULT_RINGS, TipFactors, element_rings, stress_intensity
from spurdyn.fracture.plate import (
    CrackedPlate, centre_crack_plate, edge_crack_strip, end_load, solve,
)

__all__ = ["DEFAULT_RINGS", "CrackedPlate", "TipFactors", "centre_crack_plate",
           "displacement_correlation", "edge_crack_strip", "element_rings", "end_load",
           "equivalent_k", "growth_angle", "quarter_points", "solve", "stress_intensity",
           "tangential_stress"]
