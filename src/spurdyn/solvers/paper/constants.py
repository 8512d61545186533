"""Constants of the paper's method, shared by its NumPy and compiled steps.

The contact force moves to the contact pair found by an iterate when the pair has moved
by more than :data:`RELOCATE` (flank coordinate, i.e. elements) from where the force
acts, at most :data:`MAX_RELOCATE` times a step. Smooth meshing moves the pair ~1e-4
element a step and never triggers it; after an impact, waves on the flanks can make the
pair jump a large part of an element within a step, and a force left behind cannot close
the gap there. Nothing here imports spurdyn (the compiled step reads these globals).
"""

RELOCATE = 0.05
MAX_RELOCATE = 4

#: The smallest margin (a fraction of the displacement tolerance) by which the
#: displacement stage aims inside the tolerance band (docs/solver.md, section 7, "Where
#: the displacement stage aims"): ten times the round-off of a gap between 6-cm
#: coordinates (1e-17 m) at the paper's tolerance, a ten-thousandth of the band.
BAND_MARGIN = 1e-4
