"""Gear geometry: involute flanks, trochoidal fillets, pairs and their derived figures."""

from spurdyn.geometry.gear import DEFAULT_CUTTER_TIP_RADIUS, DEFAULT_FILLET_CUT_ANGLE, Gear, GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, paper_gear, paper_pair

__all__ = ["DEFAULT_CUTTER_TIP_RADIUS", "DEFAULT_FILLET_CUT_ANGLE", "Gear", "GearPair",
           "PAPER_TORQUE", "paper_gear", "paper_pair"]
