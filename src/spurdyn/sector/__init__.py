"""The sector model (issue 15): gears with several elastic teeth on an elastic rim, their
statics and the model of a dynamic run. Derivation: ``docs/sector.md``.

The quasi-static side:

``body``
    One gear's sector, its stiffness with the hub held and the loads a contact strip puts
    on a tooth's flank.
``statics``
    The loaded tooth contact analysis over a mesh cycle (the static transmission error, the
    mesh stiffness, the load share) that ``spurdyn stiffness`` reports; ``plot`` its picture.

The model of a dynamic run, built once and stepped by :mod:`spurdyn.solvers.sector` (which
holds only the stepping):

``model``
    :class:`~spurdyn.sector.model.SectorModel`: all of the pieces below for one run, from
    the pair and the run settings (:meth:`~spurdyn.sector.model.SectorModel.build`).
``system``, ``reduced``, ``bodies``
    The two bodies' matrices in the hubs' frames, the teeth they hold, a tooth pair's rigid
    gap and its strip; a body on its modes; a gear as the loops see it (whole or modal,
    behind one small interface, with its compiled twin's pack).
``state``, ``lcp``, ``damper``, ``cache``
    A continuation's start state; the pairs' complementarity problem; the mesh damper
    along the cycle; what the runs of one process share.
``rules``, ``packs``
    The run's rules (its step, the bodies' default damping, the cycles it may go on to,
    the back flanks, the model's revision); the typed packs the model fills for the
    compiled loops.

It sits below :mod:`spurdyn.solvers`: the generalized-alpha coefficients its bodies are
factorised for and the mesh damper's formula come from :mod:`spurdyn.model`.
The names below are served lazily (importing the package imports no model).
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for.
_HOMES = {
    "SectorBody": "body", "sector_body": "body",
    "MeshCycle": "statics", "mesh_cycle": "statics", "driving_pair": "statics",
    "SectorModel": "model", "Start": "model",
    "GearBlock": "system", "gear_block": "system", "GapTable": "system", "gap_table": "system",
    "teeth_for": "system",
    "ReducedGear": "reduced", "reduce_gear": "reduced",
    "FullBody": "bodies", "ModalBody": "bodies",
    "SectorState": "state", "pack_state": "state", "unpack_state": "state",
    "Rows": "lcp",
    "damper_at": "damper", "mesh_damper_table": "damper",
    "SECTOR_REVISION": "rules", "steps_per_cycle": "rules", "cycles_limit": "rules",
    "GapArrays": "packs", "ModalGear": "packs", "SectorConfig": "packs", "SectorContacts": "packs",
}

__all__ = sorted(_HOMES)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _HOMES, globals())
