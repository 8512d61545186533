"""Gear geometry: involute flanks, trochoidal fillets, tip relief, pairs and their figures."""

from spurdyn.geometry.gear import DEFAULT_CUTTER_TIP_RADIUS, DEFAULT_FILLET_CUT_ANGLE, Gear, GearPair
from spurdyn.geometry.presets import (
    NASA_LIKE_TIP_RELIEF,
    PAPER_TORQUE,
    nasa_like_relief,
    paper_gear,
    paper_pair,
)
from spurdyn.geometry.relief import RELIEF_SHAPES, relief_depth, relief_params

__all__ = ["DEFAULT_CUTTER_TIP_RADIUS", "DEFAULT_FILLET_CUT_ANGLE", "Gear", "GearPair",
           "NASA_LIKE_TIP_RELIEF", "PAPER_TORQUE", "RELIEF_SHAPES", "nasa_like_relief",
           "paper_gear", "paper_pair", "relief_depth", "relief_params"]
