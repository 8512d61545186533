"""Contact between the deformed flanks: the search for the contact pair and its kinematics
(for the Hertzian strip the pair of the rigidly turned flanks, docs/solver.md 11.2).

Twins in mirrored files: :mod:`spurdyn.contact.search_numpy` (SciPy splines, the plain
version) and :mod:`spurdyn.contact.search_compiled` (Numba), with their shared constants,
contact modes and flank parameter columns in :mod:`spurdyn.contact.constants`. The flank
itself (a data description) is :class:`spurdyn.model.flank.Flank`.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from, imported when first asked for
#: (the compiled search loads Numba's code only when used).
_EXPORTS = {
    "FLANK_COLUMNS": "constants", "flank_row": "constants", "effective_modulus": "hertz",
    "half_width": "hertz", "peak_pressure": "hertz", "strip_compliance": "hertz",
    "ContactPair": "search_numpy", "find_contact": "search_numpy",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
