"""Models of the gear pair: the FE tooth, static pair stiffness, and (later) dynamics."""

from spurdyn.model.stiffness import (
    IsoStiffness,
    PairStiffness,
    ToothCompliance,
    iso_6336_stiffness,
    pair_stiffness,
    pitch_point_stiffness,
)
from spurdyn.model.tooth import ToothModel, build_tooth

__all__ = ["IsoStiffness", "iso_6336_stiffness", "PairStiffness", "ToothCompliance", "ToothModel", "build_tooth", "pair_stiffness",
           "pitch_point_stiffness"]
