"""Constants of the contact search, shared by its NumPy and compiled versions.

Defined once here; the compiled kernels read them as globals, so the compiled-code gate
(:mod:`spurdyn.jit`) keys the disk cache on this file too. Nothing here imports spurdyn.
"""

from __future__ import annotations

import math
from collections import namedtuple
from typing import Any

#: Contact modes: flank to flank, A's tip corner on B's flank, B's tip corner on A's.
FLANK, CORNER_A, CORNER_B = 0, 1, 2

#: Golden-section ratio and the bracket width (flank coordinate) at which it stops.
GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)
GOLDEN_TOL = 1e-10
#: A point this close to a tip (flank coordinate) is that tip's corner.
EDGE = 1e-9
#: Newton's polish of the golden-section point is kept if it moved less than this.
POLISH = 1e-4
#: Half-step (flank coordinate, element units) of the central difference that gives the
#: slope of a contact row's point along its flank (``roll_entries``): 1e-3 of an element
#: (0.1-0.5 um). The points are ~5 cm from the disk's centre, so each carries ~1e-17 m of
#: round-off, 1e-14 of a unit of slope at this step (1e-5 left the two backends' rows
#: 3e-4 apart); the involute's curvature over the step is ~1e-9 of the slope.
ROLL_STEP = 1e-3

#: The columns of a flank's parameter row (:func:`flank_row`),
#: what the compiled search reads of a flank besides its node lists. ``ny`` is the
#: element rows along the flank, ``h`` the spacing of the spline data points, the last
#: four the tip relief (:func:`spurdyn.geometry.relief.relief_params`).
FLANK_COLUMNS: tuple[str, ...] = ('t0', 't1', 'r0', 'r_tip', 'base_radius', 'psi_base', 'ref_angle', 'ny', 'h', 'relief_amount', 'relief_start', 'relief_exponent', 'relief_tip')
#: Column indices by name: ``fpar[F.h]``.
F = namedtuple("FlankColumns", FLANK_COLUMNS)(*range(len(FLANK_COLUMNS)))


def flank_row(flank: Any) -> list[float]:
    """The parameter row of a :class:`spurdyn.model.flank.Flank`, in the order of
    :data:`FLANK_COLUMNS` (its ``relief`` tuple gives the last four)."""
    relief = dict(zip(FLANK_COLUMNS[-4:], flank.relief))
    return [float(relief[c]) if c in relief else float(getattr(flank, c)) for c in FLANK_COLUMNS]
