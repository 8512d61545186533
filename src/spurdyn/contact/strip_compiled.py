"""The distributed contact's strip, compiled with Numba: the twin of :mod:`spurdyn.contact.strip_numpy`.

A strip is written into the contact rows ``cn``, ``cw`` (one half per gear, as
:func:`spurdyn.contact.search_compiled.contact_rows` lays them out) and comes with its
``delta_bar``; :func:`virtual_point` then evaluates the strip-averaged point as
:func:`~spurdyn.contact.search_compiled.material_point` evaluates a material point.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.contact.constants import F, ROLL_STEP
from spurdyn.contact.hertz import STRIP_POINTS, strip_quadrature
from spurdyn.contact.search_compiled import (
    pair_rates, delta_at, edge_shape, exact_at, material_point, spline_eval, weighted_point,
)
from spurdyn.jit import njit

#: The strip quadrature (points in units of ``b``, weights summing to 1), read as constants.
STRIP_X, STRIP_W = strip_quadrature(STRIP_POINTS)


@njit
def involute_curvature(r, rb):
    """The radius of curvature (m) of an involute of base radius ``rb`` at radius ``r``: the
    compiled home of :func:`spurdyn.contact.hertz.involute_curvature_radius`."""
    return math.sqrt(max(r * r - rb * rb, 0.0))


@njit
def hertz_half_width(load, rho_a, rho_b, estar, face):
    """Hertz half-width (m) under ``|load|`` between radii of curvature ``rho_a``, ``rho_b``:
    the one compiled home of :func:`spurdyn.contact.hertz.half_width` (the paper's strip and
    the sector model's loops read it)."""
    if load == 0.0 or rho_a <= 0.0 or rho_b <= 0.0:
        return 0.0
    r_star = rho_a * rho_b / (rho_a + rho_b)
    return math.sqrt(4.0 * abs(load) * r_star / (math.pi * estar * face))


@njit
def radius_of_curvature(fpar, t):
    """The involute's radius of curvature (m) at flank coordinate ``t``."""
    r = fpar[F.r0] + (fpar[F.r_tip] - fpar[F.r0]) * t / fpar[F.ny]
    return involute_curvature(r, fpar[F.base_radius])


@njit
def strip_half_width(P, a, b, load, estar, face):
    """Hertz half-width (m) at the pair ``(a, b)`` under ``|load|`` (twin of
    :func:`spurdyn.contact.search_numpy.strip_half_width`)."""
    return hertz_half_width(load, radius_of_curvature(P.fpar[0], a), radius_of_curvature(P.fpar[1], b),
                            estar, face)


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


@njit
def strip_gap(P, cn, cw, ns, dax, day, dbx, dby, theta, u, nx, ny):
    """The gap ``n . (x_bar_A - x_bar_B)`` the strip rows ``cn``, ``cw`` (A's half, then B's,
    ``ns`` slots each) with offsets ``delta_bar`` hold at ``(theta, u)``."""
    xa, ya = virtual_point(P, np.int64(0), cn, cw, np.int64(0), ns, dax, day, theta[0], u,
                           np.int64(0), 0.0, 0.0)
    xb, yb = virtual_point(P, np.int64(1), cn, cw, ns, ns, dbx, dby, theta[1], u,
                           np.int64(0), 0.0, 0.0)
    return nx * (xa - xb) + ny * (ya - yb)


@njit
def row_point(P, g, t, hw, th, u, cn, cw):
    """Position of the point the contact rows of gear ``g`` read at flank coordinate ``t``:
    the strip of half-width ``hw`` (written into the scratch rows ``cn``, ``cw``, one
    flank's outline long) or, with ``hw = 0``, the material point (twin of
    :func:`spurdyn.contact.search_numpy.row_point`)."""
    if hw > 0.0:
        dx, dy, _ = strip_rows(P, g, t, hw, cn, cw, np.int64(0), cn.size)
        return virtual_point(P, g, cn, cw, np.int64(0), cn.size, dx, dy, th, u, np.int64(0), 0.0, 0.0)
    return material_point(P, g, t, th, u, np.int64(0), 0.0, 0.0)


@njit
def _turned(P, g, e, out):
    """The value and two derivatives (``out``, 6) of the velocity spline of gear ``g``'s
    rigid flank for a unit turn of its disk, from its position spline's (``e``)."""
    sg = P.sense[g]
    out[0] = -sg * (e[1] - P.centre[g, 1])
    out[1] = sg * (e[0] - P.centre[g, 0])
    out[2], out[3] = -sg * e[3], sg * e[2]
    out[4], out[5] = -sg * e[5], sg * e[4]


@njit
def roll_entries(P, theta, u, a, b, mode, nx, ny, va, vb, Ma, Mb, hw, da, db):
    """``(roll_A, roll_B, row_A, row_B)`` of a pair located on the rigidly turned flanks
    (``va`` ... ``Mb`` their splines, as :func:`~spurdyn.contact.search_compiled.search`
    left them), its rows the strip of ``hw`` (0: the material points) with offsets ``da``,
    ``db``: the twin of :func:`spurdyn.contact.search_numpy.roll_entries`."""
    ea = np.empty(6)
    eb = np.empty(6)
    fa = np.zeros(6)
    fb = np.zeros(6)
    spline_eval(va, Ma, P.fpar[0, F.t0], P.fpar[0, F.h], a, ea)
    spline_eval(vb, Mb, P.fpar[1, F.t0], P.fpar[1, F.h], b, eb)
    # A unit turn moves the rigid flank's data points by s Jz (x - c), so its velocity
    # spline is s Jz (position spline - c): no spline to fit.
    _turned(P, np.int64(0), ea, fa)
    da_a, db_a = pair_rates(ea, eb, fa, fb, mode)
    fa[:] = 0.0
    _turned(P, np.int64(1), eb, fb)
    da_b, db_b = pair_rates(ea, eb, fa, fb, mode)
    nside = P.side.shape[1]
    cn = np.empty(nside, dtype=np.int64)
    cw = np.empty(nside)
    slope = np.zeros(2)
    for g in range(2):
        t = a if g == 0 else b
        moves = (da_a != 0.0 or da_b != 0.0) if g == 0 else (db_a != 0.0 or db_b != 0.0)
        if not moves:               # a tip corner: the point does not roll
            continue
        lo = max(t - ROLL_STEP, P.fpar[g, F.t0])
        hi = min(t + ROLL_STEP, P.fpar[g, F.t1])
        xh, yh = row_point(P, np.int64(g), hi, hw, theta[g], u, cn, cw)
        xl, yl = row_point(P, np.int64(g), lo, hw, theta[g], u, cn, cw)
        slope[g] = (nx * (xh - xl) + ny * (yh - yl)) / (hi - lo)
    roll_a = slope[0] * da_a - slope[1] * db_a
    roll_b = slope[0] * da_b - slope[1] * db_b
    # the turn of the offsets R delta: n . (s R Jz delta) per gear, B's with minus
    turn = np.empty(2)
    for g in range(2):
        dx, dy = (da[0], da[1]) if g == 0 else (db[0], db[1])
        sg = P.sense[g]
        c, s = math.cos(sg * theta[g]), math.sin(sg * theta[g])
        rx, ry = c * dx - s * dy, s * dx + c * dy
        turn[g] = sg * (-nx * ry + ny * rx) * (1.0 if g == 0 else -1.0)
    return roll_a, roll_b, roll_a + turn[0], roll_b + turn[1]


@njit
def point_offsets(P, a, b, d):
    """The material points' involute offsets ``delta`` at ``(a, b)`` into ``d`` (4,)."""
    d[0], d[1] = delta_at(P.fpar[0], P.sideY[0], a)
    d[2], d[3] = delta_at(P.fpar[1], P.sideY[1], b)
