"""Mesh stiffness by the potential-energy (energy) method, for a healthy or a cracked tooth.

The literature's reference for a faulty tooth's mesh stiffness: each tooth a non-uniform
cantilever on its base circle (bending, shear, axial compression; Yang & Lin 1987, Tian
2004), the fillet foundation of Sainsot, Velex & Duverger (2004), the constant
line-contact Hertzian stiffness, and a straight root crack that cuts the sections above
it (Tian 2004; Wu, Zuo & Parey 2008; Chen & Shao 2011). Geometry only, from
:mod:`spurdyn.geometry`; the derivation, assumptions and figures are in
``docs/faults_energy.md``. Not yet read by the command line or case files.
"""

from spurdyn.energy.crack import DEFAULT_CRACK_ANGLE, Crack
from spurdyn.energy.foundation import SAINSOT_COEFFICIENTS, foundation_compliance
from spurdyn.energy.pair import (MeshCycle, PairCompliance, hertz_compliance,
                                 mean_mesh_stiffness, mesh_cycle, pair_compliance)
from spurdyn.energy.tooth import ToothCompliance, tooth_compliance

__all__ = ["DEFAULT_CRACK_ANGLE", "SAINSOT_COEFFICIENTS", "Crack", "MeshCycle",
           "PairCompliance", "ToothCompliance", "foundation_compliance", "hertz_compliance",
           "mean_mesh_stiffness", "mesh_cycle", "pair_compliance", "tooth_compliance"]
