"""Contact between the deformed flanks: the search for the contact pair and its kinematics.

Twins in mirrored files: :mod:`spurdyn.contact.search_numpy` (SciPy splines, the plain
version) and :mod:`spurdyn.contact.search_compiled` (Numba), with their shared constants,
contact modes and flank parameter columns in :mod:`spurdyn.contact.constants`. The flank
itself (a data description) is :class:`spurdyn.model.flank.Flank`.
"""
