"""The lumped models beside the finite-element one: two rigid disks on a mesh spring.

:func:`simulate_lumped` runs the classic two-disk, one-spring model with the FE model's
static stiffness (:func:`mesh_stiffness_table`) and torque schedule; it returns the same
:class:`~spurdyn.result.Result` as the FE solver (docs/lumped.md).
:mod:`~spurdyn.lumped.steady` runs the pair under constant torques over many mesh cycles,
every tooth pair in contact a spring, with the pairs' stiffnesses over a mesh cycle from
:mod:`~spurdyn.lumped.cycle` (the single-pair table, or the sector model's mesh cycle).
"""

from spurdyn.lumped.model import (
    MeshStiffnessTable, equivalent_mass, mesh_stiffness_table, simulate_lumped,
    torsional_natural_frequency,
)

__all__ = ["MeshStiffnessTable", "equivalent_mass", "mesh_stiffness_table", "simulate_lumped",
           "torsional_natural_frequency"]
