"""The lumped models beside the finite-element one: two rigid disks on a mesh spring.

:func:`simulate_lumped` runs the classic two-disk, one-spring model with the FE model's
static stiffness (:func:`mesh_stiffness_table`) and torque schedule; it returns the same
:class:`~spurdyn.result.Result` as the FE solver (docs/lumped.md).
:mod:`~spurdyn.lumped.steady` runs the pair under constant torques over many mesh cycles,
every tooth pair in contact a spring, with the pairs' stiffnesses over a mesh cycle from
:mod:`~spurdyn.lumped.cycle` (the single-pair table, or the sector model's mesh cycle).

Its names are served lazily (:mod:`spurdyn.lazy`): the registry of models imports
:mod:`~spurdyn.lumped.sources` for every run, and :mod:`~spurdyn.lumped.model` brings
SciPy's ODE solvers and splines (``scipy.integrate``, ``scipy.interpolate``), which a run
of another model never needs.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from (imported when first asked for).
_EXPORTS = {name: "model" for name in ("MeshStiffnessTable", "equivalent_mass", "mesh_stiffness_table",
                                       "simulate_lumped", "torsional_natural_frequency")}

__all__ = sorted(_EXPORTS)

# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
