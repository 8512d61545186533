"""Contact between the deformed flanks: the search for the contact pair and its kinematics
(for the Hertzian strip the pair of the rigidly turned flanks, docs/solver.md 11.2).

Twins in mirrored files: :mod:`spurdyn.contact.search_numpy` (SciPy splines, the plain
version) and :mod:`spurdyn.contact.search_compiled` (Numba), with their shared constants,
contact modes and flank parameter columns in :mod:`spurdyn.contact.constants`. The flank
itself (a data description) is :class:`spurdyn.model.flank.Flank`.
"""
