"""The sector model (issue 15): gears with several elastic teeth on an elastic rim.

``body``: one gear's sector, its stiffness with the hub held and the loads a contact
strip puts on a tooth's flank. ``statics``: the loaded tooth contact analysis over a
mesh cycle (the static transmission error, the mesh stiffness, the load share) that
``spurdyn stiffness`` reports. ``plot``: its picture. Derivation: ``docs/sector.md``.
"""

from __future__ import annotations

__all__ = ["SectorBody", "MeshCycle", "mesh_cycle", "sector_body"]


def __getattr__(name: str):
    if name in ("SectorBody", "sector_body"):
        from spurdyn.sector import body
        return getattr(body, name)
    if name in ("MeshCycle", "mesh_cycle"):
        from spurdyn.sector import statics
        return getattr(statics, name)
    raise AttributeError(name)
