"""Where the lumped model's mesh stiffness comes from: the paper model's tooth pair
(:func:`tooth_table`, point or Hertzian contact) or the sector model's quasi-static mesh
cycle (:func:`sector_cycle`), each cached per process so that the points of a sweep share
them (moved here from :mod:`spurdyn.simulators`, whose lumped entry reads them)."""

from __future__ import annotations

from typing import Any

from spurdyn.geometry.pair import GearPair
from spurdyn.settings import RunSettings

#: Mesh-stiffness tables of the lumped model, per (pair, mesh, load), kept in the process so
#: that the points of a sweep share them.
_TABLES: dict[Any, Any] = {}


def tooth_table(pair: GearPair, settings: RunSettings) -> Any:
    """The paper model's single-pair stiffness table of the run's contact model (the strip's
    depends on the load), on the run's tooth meshes (rows graded by ``row_grading``; the
    point contact's table on even columns, as it always was), cached per process."""
    from spurdyn.lumped.model import mesh_stiffness_table

    hertz = settings.contact == "hertz" and settings.torque > 0
    key = (pair, settings.nx, settings.ny, settings.torque if hertz else None,
           settings.grading if hertz else None, settings.row_grading)
    try:
        table = _TABLES.get(key)
    except TypeError:  # an unhashable pair: no caching
        key, table = None, None
    if table is None:
        table = (hertz_table(pair, settings) if hertz
                 else mesh_stiffness_table(pair, settings.nx, settings.ny,
                                           row_grading=settings.row_grading))
        if key is not None:
            _TABLES[key] = table
    return table


def sector_cycle(pair: GearPair, settings: RunSettings) -> Any:
    """The sector model's mesh cycle of the run's pair, mesh, torque and teeth as the lumped
    model's stiffness (:class:`spurdyn.lumped.cycle.SectorCycle`), cached per process."""
    from spurdyn.lumped.cycle import SectorCycle
    from spurdyn.settings import refuse_sector_row_grading

    refuse_sector_row_grading(settings.row_grading)

    key = ("sector", pair, settings.nx, settings.ny, settings.grading, settings.torque, settings.teeth)
    try:
        cycle = _TABLES.get(key)
    except TypeError:  # an unhashable pair: no caching
        key, cycle = None, None
    if cycle is None:
        # K at or above a gear's teeth is the whole gear (the cycle takes one K for both)
        teeth = None if settings.teeth is None else min(settings.teeth, pair.gear_a.teeth, pair.gear_b.teeth)
        mc = quasi_static_cycle(pair, settings.torque, settings.nx, settings.ny, teeth,
                                settings.grading)
        cycle = SectorCycle.from_mesh_cycle(pair, mc)
        if key is not None:
            _TABLES[key] = cycle
    return cycle


def quasi_static_cycle(pair: GearPair, torque: float, nx: int, ny: int, teeth: int | None,
                       grading: float, positions: int | None = None) -> Any:
    """The sector model's quasi-static mesh cycle (:func:`spurdyn.sector.statics.mesh_cycle`,
    its default positions unless given), cached per process: the lumped model's stiffness
    and ``spurdyn stiffness`` (a report's page) share it. Its arrays are read, never
    written, by those who take it."""
    from spurdyn.sector.statics import DEFAULT_POSITIONS, mesh_cycle

    positions = DEFAULT_POSITIONS if positions is None else int(positions)
    key = ("mesh cycle", pair, float(torque), nx, ny, teeth, grading, positions)
    try:
        mc = _TABLES.get(key)
    except TypeError:  # an unhashable pair: no caching
        key, mc = None, None
    if mc is None:
        mc = mesh_cycle(pair, torque, nx, ny, teeth=teeth, positions=positions, grading=grading)
        if key is not None:
            _TABLES[key] = mc
    return mc


def hertz_table(pair: GearPair, settings: RunSettings) -> Any:
    """The lumped model's stiffness table with the Hertzian strip of the static force
    (:func:`spurdyn.solvers.paper.statics.static_stiffness`), over the path of contact."""
    import numpy as np

    from spurdyn.lumped.model import DEFAULT_TABLE_POINTS, MeshStiffnessTable
    from spurdyn.model.loading import static_force
    from spurdyn.model.system import system_for
    from spurdyn.solvers.paper.statics import static_stiffness

    system = system_for(pair, settings.nx, settings.ny, settings.n_spline, settings.grading,
                        settings.row_grading)
    spair = system.pair                      # the pair as the solver runs it (A driving)
    roll = np.linspace(spair.start_roll_a, spair.end_roll_a, DEFAULT_TABLE_POINTS)
    force = static_force(pair, settings.torque)
    k = np.array([static_stiffness(system, float(r), force, "hertz").stiffness for r in roll])
    if pair.driver != "a":
        # B drives: the solver's A is the pair's B; the table runs along the pair's A roll,
        # which is the solver's B roll there
        roll = np.asarray(spair.roll_b_from_roll_a(roll), dtype=float)
        order = np.argsort(roll)
        roll, k = roll[order], k[order]
    return MeshStiffnessTable(roll, k, "pchip")


__all__ = ["hertz_table", "quasi_static_cycle", "sector_cycle", "tooth_table"]
