"""Every name the report takes from ``spurdyn``, imported here and nowhere else.

The other modules import these names from this one, so that a move of a ``spurdyn``
module is one edit here.
"""

from __future__ import annotations

from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import (NASA_LIKE_TIP_RELIEF, PAPER_TORQUE, nasa_like_relief,
                                      paper_gear, paper_pair)
from spurdyn.lumped import (MeshStiffnessTable, mesh_stiffness_table, simulate_lumped,
                            torsional_natural_frequency)
from spurdyn.model.loading import gear_torques
from spurdyn.model.stiffness import (ToothCompliance, iso_6336_stiffness, pair_stiffness,
                                     pitch_point_stiffness)
from spurdyn.model.tooth import build_tooth
from spurdyn.results.balances import track
from spurdyn.results.headline import AVERAGING_WINDOW_S, window_means
from spurdyn.model.system import build_system
from spurdyn.settings import PAPER_DT, RunSettings
from spurdyn.solvers.check import stable_step
from spurdyn.solvers.loop import simulate
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper

__all__ = [
    "AVERAGING_WINDOW_S", "CompiledStepper", "GearPair", "MeshStiffnessTable", "NASA_LIKE_TIP_RELIEF", "PAPER_DT",
    "PAPER_TORQUE", "RunSettings", "ToothCompliance", "build_system", "build_tooth", "gear_torques",
    "iso_6336_stiffness", "mesh_stiffness_table", "nasa_like_relief", "pair_stiffness",
    "paper_gear", "paper_pair", "pitch_point_stiffness", "simulate", "simulate_lumped",
    "stable_step", "torsional_natural_frequency", "track", "window_means",
]
