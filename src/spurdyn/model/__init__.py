"""What a run builds once from a pair: the system, flanks, loading, tooth models, stiffness,
and the numbers of its settings that the solvers and the sector model share.

- :mod:`~spurdyn.model.system`: gear bodies (a disk carrying teeth), the flank pairs, the
  placed pair (:func:`~spurdyn.model.system.build_system`, built once per run);
- :mod:`~spurdyn.model.flank`: the active flank as the contact search sees it;
- :mod:`~spurdyn.model.loading`: the torque schedule and the static force;
- :mod:`~spurdyn.model.tooth`, :mod:`~spurdyn.model.stiffness`: one tooth's FE model and
  the static pair stiffness along the path of contact;
- :mod:`~spurdyn.model.alpha`: the generalized-alpha coefficients and the implicit
  integrator's default step; :mod:`~spurdyn.model.damper`: the mesh damper's coefficient
  (both read by :mod:`spurdyn.solvers.implicit` and :mod:`spurdyn.sector`).

The names below are served lazily (stiffness needs SciPy's optimisers, slow to import).
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

_HOMES = {
    "IsoStiffness": "stiffness", "PairStiffness": "stiffness", "ToothCompliance": "stiffness",
    "iso_6336_stiffness": "stiffness", "pair_stiffness": "stiffness",
    "pitch_point_stiffness": "stiffness", "ToothModel": "tooth", "build_tooth": "tooth",
}

__all__ = sorted(_HOMES)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _HOMES, globals())
