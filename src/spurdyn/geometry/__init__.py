"""Gear geometry: involute flanks, trochoidal fillets, basic racks, profile shift, tip
relief, blanks, pairs and their working geometry. Imports nothing above it."""

from spurdyn.geometry.blank import Blank
from spurdyn.geometry.gear import DEFAULT_CUTTER_TIP_RADIUS, DEFAULT_FILLET_CUT_ANGLE, Gear
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import (
    NASA_LIKE_TIP_RELIEF,
    PAPER_TORQUE,
    nasa_like_relief,
    paper_gear,
    paper_pair,
)
from spurdyn.geometry.rack import ISO_53, BasicRack, default_rack
from spurdyn.geometry.relief import RELIEF_SHAPES, relief_depth, relief_params

__all__ = ["DEFAULT_CUTTER_TIP_RADIUS", "DEFAULT_FILLET_CUT_ANGLE", "ISO_53", "BasicRack",
           "Blank", "Gear", "GearPair", "NASA_LIKE_TIP_RELIEF", "PAPER_TORQUE", "RELIEF_SHAPES",
           "default_rack", "nasa_like_relief", "paper_gear", "paper_pair", "relief_depth",
           "relief_params"]
