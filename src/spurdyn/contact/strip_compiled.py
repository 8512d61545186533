"""The distributed contact's strip, compiled with Numba: the twin of :mod:`spurdyn.contact.strip_numpy`.

A strip is written into the contact rows ``cn``, ``cw`` (one half per gear, as
:func:`spurdyn.contact.search_compiled.contact_rows` lays them out) and comes with its
``delta_bar``; :func:`virtual_point` then evaluates the strip-averaged point as
:func:`~spurdyn.contact.search_compiled.material_point` evaluates a material point.
"""

from __future__ import annotations

import math

from spurdyn.contact.constants import F
from spurdyn.contact.hertz import STRIP_POINTS, strip_quadrature
from spurdyn.contact.search_compiled import edge_shape, exact_at, weighted_point
from spurdyn.jit import njit

#: The strip quadrature (points in units of ``b``, weights summing to 1), read as constants.
STRIP_X, STRIP_W = strip_quadrature(STRIP_POINTS)


@njit
def radius_of_curvature(fpar, t):
    """The involute's radius of curvature (m) at flank coordinate ``t``."""
    r = fpar[F.r0] + (fpar[F.r_tip] - fpar[F.r0]) * t / fpar[F.ny]
    rb = fpar[F.base_radius]
    return math.sqrt(max(r * r - rb * rb, 0.0))


@njit
def strip_half_width(P, a, b, load, estar, face):
    """Hertz half-width (m) at the pair ``(a, b)`` under ``|load|`` (twin of
    :func:`spurdyn.contact.search_numpy.strip_half_width`)."""
    ra = radius_of_curvature(P.fpar[0], a)
    rb = radius_of_curvature(P.fpar[1], b)
    if load == 0.0 or ra <= 0.0 or rb <= 0.0:
        return 0.0
    r_star = ra * rb / (ra + rb)
    return math.sqrt(4.0 * abs(load) * r_star / (math.pi * estar * face))


@njit
def strip_rows(P, g, t_c, hw, cn, cw, off, ns):
    """Write the strip of gear ``g`` around ``t_c`` into ``cn[off:off + ns]``, ``cw[...]``.

    Returns ``(dx, dy, fits)``: ``delta_bar = Y_exact(t_c) - N_bar Y`` and whether the
    strip's nodes fit in the ``ns`` slots (unused slots get zero weight on the first node).
    """
    fp = P.fpar[g]
    ny = fp[F.ny]
    r0, r1, rb = fp[F.r0], fp[F.r_tip], fp[F.base_radius]
    slope = (r1 - r0) / ny
    r_c = r0 + slope * t_c
    nq = STRIP_X.size
    lo = 1 << 30
    hi = -1
    ts = STRIP_X.copy()
    for k in range(nq):
        r = math.sqrt(max(r_c * r_c + 2.0 * rb * hw * STRIP_X[k], 0.0))
        t = min(max((r - r0) / slope, 0.0), ny)
        ts[k] = t
        row = min(int(math.floor(t)), int(ny) - 1)
        lo = min(lo, row)
        hi = max(hi, row)
    first = P.side[g, 2 * lo]
    for j in range(ns):
        cn[off + j] = first
        cw[off + j] = 0.0
    nside = 2 * (hi - lo) + 3
    if nside > ns:
        return 0.0, 0.0, False
    for j in range(nside):
        cn[off + j] = P.side[g, 2 * lo + j]
    for k in range(nq):
        t = ts[k]
        row = min(int(math.floor(t)), int(ny) - 1)
        w0, w1, w2 = edge_shape(2.0 * (t - row) - 1.0)
        j = 2 * (row - lo)
        cw[off + j] += STRIP_W[k] * w0
        cw[off + j + 1] += STRIP_W[k] * w1
        cw[off + j + 2] += STRIP_W[k] * w2
    ex, ey = exact_at(fp, t_c)
    sy = P.sideY[g]
    for j in range(nside):
        ex -= cw[off + j] * sy[2 * lo + j, 0]
        ey -= cw[off + j] * sy[2 * lo + j, 1]
    return ex, ey, True


@njit
def virtual_point(P, g, cn, cw, off, ns, dx, dy, th, uget, kind, om, al):
    """Position (kind 0), velocity (1) or acceleration (2) of the strip-averaged point
    ``c + N_bar (Y + u) + R delta_bar`` of gear ``g`` (rows in ``cn[off:off + ns]``)."""
    return weighted_point(P, g, cn, cw, off, ns, dx, dy, th, uget, kind, om, al)
