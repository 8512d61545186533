"""Contact between the two deformed flanks in NumPy/SciPy: the twin of :mod:`spurdyn.contact.search_compiled`.

Each flank is a not-a-knot cubic spline (SciPy's :class:`~scipy.interpolate.CubicSpline`)
through the current positions of its data points, parameterised by the flank
coordinate ``t`` (see :class:`~spurdyn.model.flank.Flank`). The contact pair is the
pair of points with the minimum normal distance: tangents parallel and the connecting
vector normal to both (docs/contact.md). Where that pair would lie beyond a tooth's tip,
the tip corner is projected onto the other flank instead ("corner contact"). The Hertzian
strip locates its pair on the rigidly turned flanks instead (``locate``; docs/solver.md 11.2).

The penetration (paper eq. 3) is measured between the *finite-element* material points
under the contact pair: ``s = n . (x_A - x_B)``, ``n`` the unit normal pointing from A
towards B, ``s > 0`` penetration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from spurdyn.contact.constants import CORNER_A, CORNER_B, EDGE, FLANK, GOLDEN, GOLDEN_TOL, POLISH, ROLL_STEP
from spurdyn.contact.hertz import half_width, involute_curvature_radius
from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.model.flank import Flank


def cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def outward_normal(tangent: NDArray[np.float64]) -> NDArray[np.float64]:
    """Outward unit normal of a right flank traversed root to tip: the tangent turned clockwise."""
    n = np.array([tangent[1], -tangent[0]])
    return n / np.hypot(*n)


def data_values(flank: Flank, nodal: NDArray[np.float64], mat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Surface values at the data points ``(n, 2)``: ``N nodal + mat delta``.

    ``nodal`` are nodal positions (or velocities, accelerations) ``(N, 2)``; ``mat`` is
    what the disk motion does to the involute offsets ``delta``: ``R`` for positions,
    ``sense omega R Jz`` for velocities, ``sense alpha R Jz - omega^2 R`` for accelerations.
    """
    return np.einsum("kj,kjd->kd", flank.data_weights, nodal[flank.data_nodes]) + flank.data_delta @ mat.T


def surface_point(flank: Flank, t: float, nodal: NDArray[np.float64], mat: NDArray[np.float64]) -> NDArray[np.float64]:
    """The surface value of the material point at flank coordinate ``t``."""
    nodes, w, _ = flank.locate(t)
    return w @ nodal[nodes] + mat @ flank.delta(t)


def flank_spline(flank: Flank, nodal: NDArray[np.float64], mat: NDArray[np.float64]) -> CubicSpline:
    """Not-a-knot cubic spline through the data-point values, in the flank coordinate."""
    t = np.linspace(flank.t0, flank.t1, flank.n_data)
    return CubicSpline(t, data_values(flank, nodal, mat), bc_type="not-a-knot")


@dataclass(frozen=True)
class ContactPair:
    """The contact pair found on the current flanks.

    Attributes
    ----------
    alpha, beta
        Flank coordinates of the contact points on A and B.
    mode
        :data:`FLANK`, :data:`CORNER_A` (A's tip corner on B's flank) or :data:`CORNER_B`.
    normal
        Unit contact normal, from A towards B.
    s
        Penetration (m) between the finite-element material points; negative is a gap.
    nodes_a, weights_a, nodes_b, weights_b
        Edge nodes and shape weights of the material points (the rows of ``N``).
    delta_a, delta_b
        The involute offsets ``delta`` of the material points (initial frame).
    half_width
        Half-width (m) of the Hertzian strip the rows average over (0: point contact;
        :mod:`spurdyn.contact.strip_numpy`).
    roll, theta_row
        For a pair located on the rigidly turned flanks (the strip's; None and zero for the
        point contact, the paper's): the rate of its gap per unit turn of each disk
        ``(theta_A, theta_B)`` as the pair rolls with them, and the contact row's entries on
        the disks, that roll plus the turn of the offsets ``R delta_bar``
        (:func:`roll_entries`, docs/solver.md section 11.3).
    """

    alpha: float
    beta: float
    mode: int
    normal: NDArray[np.float64]
    s: float
    nodes_a: NDArray[np.intp]
    weights_a: NDArray[np.float64]
    nodes_b: NDArray[np.intp]
    weights_b: NDArray[np.float64]
    delta_a: NDArray[np.float64]
    delta_b: NDArray[np.float64]
    half_width: float = 0.0
    roll: tuple[float, float] | None = None
    theta_row: tuple[float, float] = (0.0, 0.0)


def _newton_pair(pa: CubicSpline, pb: CubicSpline, a: float, b: float) -> tuple[float, float, bool]:
    """Solve ``P_A' x P_B' = 0`` and ``(P_A - P_B) . P_A' = 0`` for ``(alpha, beta)``."""
    for _ in range(30):
        xa, ta, ca = pa(a), pa(a, 1), pa(a, 2)
        xb, tb, cb = pb(b), pb(b, 1), pb(b, 2)
        d = xa - xb
        f = np.array([cross(ta, tb), d @ ta])
        jac = np.array([[cross(ca, tb), cross(ta, cb)],
                        [ta @ ta + d @ ca, -(tb @ ta)]])
        step = np.linalg.solve(jac, f)
        big = max(abs(step[0]), abs(step[1]))
        if big > 0.5:   # at most half an element at a time
            step = step * (0.5 / big)
        a, b = a - step[0], b - step[1]
        if abs(step[0]) + abs(step[1]) < 1e-11:
            return a, b, True
        if not (np.isfinite(a) and np.isfinite(b)):
            return a, b, False
    return a, b, False


def _project(point: NDArray[np.float64], p: CubicSpline, t: float, lo: float, hi: float) -> float:
    """Flank coordinate of the foot of the normal from ``point`` onto spline ``p``."""
    for _ in range(30):
        d = p(t) - point
        tan, cur = p(t, 1), p(t, 2)
        step = (d @ tan) / (tan @ tan + d @ cur)
        t = min(max(t - step, lo), hi)
        if abs(step) < 1e-11:
            break
    return t


def _gap(pa: CubicSpline, pb: CubicSpline, fb: Flank, a: float, b: float) -> tuple[float, float]:
    """Normal gap from A's point ``a`` to B (foot of the normal at ``b``, warm start) and ``b``."""
    p = pa(a)
    b = _project(p, pb, b, fb.t0, fb.t1)
    return float(outward_normal(pa(a, 1)) @ (pb(b) - p)), b


def _scan(pa: CubicSpline, pb: CubicSpline, fa: Flank, fb: Flank, b_guess: float) -> tuple[float, float]:
    """A global start: the data point of A whose normal gap to B is smallest (deepest)."""
    best, best_ab = np.inf, (fa.t0, fb.t0)
    b = min(max(b_guess, fb.t0), fb.t1)
    for a in np.linspace(fa.t0, fa.t1, fa.n_data):
        gap, b = _gap(pa, pb, fb, a, b)
        if gap < best:
            best, best_ab = gap, (float(a), float(b))
    return best_ab


def _deepest(pa: CubicSpline, pb: CubicSpline, fa: Flank, fb: Flank,
             a0: float, b0: float) -> tuple[float, float]:
    """The deepest point (smallest normal gap) of A within one data spacing of ``a0``.

    The safeguard for wavy flanks: where the flanks are nearly conforming the Newton
    iteration of :func:`_newton_pair` can cycle, but the gap along A is still a smooth
    function whose minimum is the contact pair; golden-section search finds it.
    """
    h = (fa.t1 - fa.t0) / (fa.n_data - 1)
    lo, hi = max(a0 - h, fa.t0), min(a0 + h, fa.t1)
    x1, x2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    g1, b1 = _gap(pa, pb, fb, x1, b0)
    g2, b2 = _gap(pa, pb, fb, x2, b0)
    while hi - lo > GOLDEN_TOL:
        if g1 <= g2:
            hi, x2, g2, b2 = x2, x1, g1, b1
            x1 = hi - GOLDEN * (hi - lo)
            g1, b1 = _gap(pa, pb, fb, x1, b2)
        else:
            lo, x1, g1, b1 = x1, x2, g2, b2
            x2 = lo + GOLDEN * (hi - lo)
            g2, b2 = _gap(pa, pb, fb, x2, b1)
    return (x1, b1) if g1 <= g2 else (x2, b2)


def _pair(pa: CubicSpline, pb: CubicSpline, fa: Flank, fb: Flank,
          guess: tuple[float, float]) -> tuple[float, float, int]:
    """``(alpha, beta, mode)`` of the contact pair (see :func:`find_contact`)."""
    a, b, ok = _newton_pair(pa, pb, *guess)
    near = guess
    if not ok or abs(a - guess[0]) + abs(b - guess[1]) > 1.0:
        # Lost or jumped more than an element (wavy flanks after an impact): start again
        # from the deepest data point of a scan along A; if Newton cycles there too, take
        # the deepest point near it by a bracketed search.
        near = _scan(pa, pb, fa, fb, guess[1])
        a, b, ok = _newton_pair(pa, pb, *near)
        if not ok or abs(a - near[0]) + abs(b - near[1]) > 1.0:
            a, b = _deepest(pa, pb, fa, fb, *near)
            near = (a, b)
            # A minimum is located only to ~sqrt(machine epsilon); Newton, started this
            # close, polishes it to round-off unless the flanks conform there.
            a2, b2, ok2 = _newton_pair(pa, pb, a, b)
            if ok2 and abs(a2 - a) + abs(b2 - b) < POLISH:
                a, b = a2, b2
            ok = a < fa.t1 - EDGE and b < fb.t1 - EDGE
    if ok and fa.t0 <= a <= fa.t1 and fb.t0 <= b <= fb.t1:
        return a, b, FLANK
    # The pair lies beyond a tooth's tip: that tip corner touches the other flank. Of the
    # corners whose foot lies on the other flank, keep the nearer.
    ga = min(max(a if ok else near[0], fa.t0), fa.t1)
    gb = min(max(b if ok else near[1], fb.t0), fb.t1)
    a_b = _project(pb(fb.t1), pa, ga, fa.t0, fa.t1)     # B's corner on A
    b_a = _project(pa(fa.t1), pb, gb, fb.t0, fb.t1)     # A's corner on B
    dist_b = np.hypot(*(pb(fb.t1) - pa(a_b))) if fa.t0 < a_b < fa.t1 else np.inf
    dist_a = np.hypot(*(pa(fa.t1) - pb(b_a))) if fb.t0 < b_a < fb.t1 else np.inf
    if dist_b <= dist_a and np.isfinite(dist_b):
        return a_b, fb.t1, CORNER_B
    if np.isfinite(dist_a):
        return fa.t1, b_a, CORNER_A
    return ga, gb, FLANK


def find_contact(fa: Flank, fb: Flank, xa: NDArray[np.float64], xb: NDArray[np.float64],
                 ra: NDArray[np.float64], rb: NDArray[np.float64], guess: tuple[float, float],
                 load: float = 0.0, law: tuple[float, float] | None = None,
                 locate: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None) -> ContactPair:
    """Contact pair of two flanks.

    ``xa``, ``xb`` are the current nodal positions ``(N, 2)``, ``ra``, ``rb`` the disks'
    rotation matrices ``R(sense theta)``, ``guess`` the last ``(alpha, beta)``. With a
    ``law`` ``(E*, face width)`` the rows and the gap are the averages over the Hertzian
    strip of the normal force ``load`` (N) at a flank-to-flank pair (a tip corner and a
    zero load keep the point). ``locate``: other nodal positions of the two teeth (the
    rigidly turned ones, for the strip: docs/solver.md, section 11.2) on which the pair,
    its mode and the normal are found; the gap is still that of ``xa``, ``xb`` there.
    """
    xa_at, xb_at = (xa, xb) if locate is None else locate
    pa, pb = flank_spline(fa, xa_at, ra), flank_spline(fb, xb_at, rb)
    a, b, mode = _pair(pa, pb, fa, fb, guess)
    if mode == CORNER_A:
        normal = -outward_normal(pb(b, 1))
    else:
        normal = outward_normal(pa(a, 1))
    if law is not None and load != 0.0 and mode == FLANK:
        hw = strip_half_width(fa, fb, a, b, load, law)
        na, wa, da = strip_rows(fa, a, hw)
        nb, wb, db = strip_rows(fb, b, hw)
        s = float(normal @ ((wa @ xa[na] + ra @ da) - (wb @ xb[nb] + rb @ db)))
        return ContactPair(alpha=float(a), beta=float(b), mode=mode, normal=normal, s=s,
                           nodes_a=na, weights_a=wa, nodes_b=nb, weights_b=wb,
                           delta_a=da, delta_b=db, half_width=hw)
    na, wa, _ = fa.locate(a)
    nb, wb, _ = fb.locate(b)
    s = float(normal @ (surface_point(fa, a, xa, ra) - surface_point(fb, b, xb, rb)))
    return ContactPair(alpha=float(a), beta=float(b), mode=mode, normal=normal, s=s,
                       nodes_a=na, weights_a=wa, nodes_b=nb, weights_b=wb,
                       delta_a=fa.delta(a), delta_b=fb.delta(b))


def strip_half_width(fa: Flank, fb: Flank, a: float, b: float, load: float,
                     law: tuple[float, float]) -> float:
    """Hertz half-width (m) of the pair at flank coordinates ``(a, b)`` under ``load`` (N),
    from the two involutes' radii of curvature there and the ``law`` ``(E*, face width)``."""
    rho_a = involute_curvature_radius(fa.r0 + (fa.r_tip - fa.r0) * a / fa.ny, fa.base_radius)
    rho_b = involute_curvature_radius(fb.r0 + (fb.r_tip - fb.r0) * b / fb.ny, fb.base_radius)
    return half_width(load, rho_a, rho_b, law[0], law[1])


def sliding_acceleration(fa: Flank, fb: Flank, xa: NDArray[np.float64], xb: NDArray[np.float64],
                         ra: NDArray[np.float64], rb: NDArray[np.float64],
                         va: NDArray[np.float64], vb: NDArray[np.float64],
                         ma: NDArray[np.float64], mb: NDArray[np.float64],
                         c: ContactPair,
                         rates_from: tuple[NDArray[np.float64], ...] | None = None,
                         ) -> tuple[float, float, float]:
    """The Appendix A terms of the relative normal acceleration, and ``d alpha/dt``, ``d beta/dt``.

    Returns ``(extra, alpha_dot, beta_dot)`` with ``extra`` to be added to
    ``n . (N_A a_A - N_B a_B)``: the Coriolis terms ``2 alpha' n . V_A,alpha`` and the
    curvature terms ``alpha'^2 n . P_A,alpha alpha`` (and minus the same for B).
    ``rates_from``: positions and velocities ``(xa, xb, va, vb)`` of the flanks the pair is
    located on (the rigidly turning ones, for the strip: docs/solver.md, section 11.2); the
    pair's rates are theirs, the terms those of the deformed flanks.
    """
    pa, pb = flank_spline(fa, xa, ra), flank_spline(fb, xb, rb)
    sa, sb = flank_spline(fa, va, ma), flank_spline(fb, vb, mb)
    n = c.normal
    ad, bd = pair_rates(c, pa, pb, sa, sb) if rates_from is None else pair_rates(
        c, *(flank_spline(f, x, m) for f, x, m in zip((fa, fb, fa, fb), rates_from, (ra, rb, ma, mb))))
    ca, cb = pa(c.alpha, 2), pb(c.beta, 2)
    dwa, dwb = sa(c.alpha, 1), sb(c.beta, 1)
    extra = 2.0 * ad * (n @ dwa) + ad * ad * (n @ ca) - 2.0 * bd * (n @ dwb) - bd * bd * (n @ cb)
    return float(extra), float(ad), float(bd)


def row_point(flank: Flank, t: float, half_width: float, x: NDArray[np.float64],
              r: NDArray[np.float64]) -> NDArray[np.float64]:
    """The point ``N_bar x + R delta_bar`` the contact rows of a pair at flank coordinate
    ``t`` read (the strip of ``half_width`` around it; 0: the material point), at nodal
    positions ``x`` and disk rotation ``r``."""
    nodes, w, d = strip_rows(flank, t, half_width)
    return w @ x[nodes] + r @ d


def roll_entries(fa: Flank, fb: Flank, c: ContactPair, xa: NDArray[np.float64],
                 xb: NDArray[np.float64], ra: NDArray[np.float64], rb: NDArray[np.float64],
                 rigid: tuple[NDArray[np.float64], ...]
                 ) -> tuple[tuple[float, float], tuple[float, float]]:
    """``(roll, theta_row)`` of a pair located on the rigidly turned flanks: the contact
    row's entries on ``(theta_A, theta_B)`` (docs/solver.md, section 11.3).

    The pair ``(alpha, beta)`` rolls with the disks' turns, and the gap its rows hold
    changes with it by ``n . P_A' d alpha - n . P_B' d beta`` (``roll``), ``P'`` the slope
    along the flank of the point the rows read (:func:`row_point`, by a central difference
    of ``ROLL_STEP``); the row's entries add the turn of the offsets,
    ``n . (s_A R_A Jz delta_A - s_B R_B Jz delta_B)``. ``rigid``: the rigid flanks' nodal
    positions ``(xa, xb)``, then their nodal velocities for a unit turn of each disk and
    the matrices ``s R Jz`` those turns apply to the offsets, ``(va, vb, ma, mb)``; the
    pair's rates per unit turn come from :func:`pair_rates` on them.
    """
    pa, pb = flank_spline(fa, rigid[0], ra), flank_spline(fb, rigid[1], rb)
    zero = np.zeros((2, 2))
    still_a = flank_spline(fa, np.zeros_like(rigid[2]), zero)
    still_b = flank_spline(fb, np.zeros_like(rigid[3]), zero)
    turn_a = flank_spline(fa, rigid[2], rigid[4])
    turn_b = flank_spline(fb, rigid[3], rigid[5])
    da_a, db_a = pair_rates(c, pa, pb, turn_a, still_b)
    da_b, db_b = pair_rates(c, pa, pb, still_a, turn_b)
    slopes = []
    for f, t, x, r, moves in ((fa, c.alpha, xa, ra, da_a != 0.0 or da_b != 0.0),
                              (fb, c.beta, xb, rb, db_a != 0.0 or db_b != 0.0)):
        if not moves:               # a tip corner: the point does not roll
            slopes.append(0.0)
            continue
        lo, hi = max(t - ROLL_STEP, f.t0), min(t + ROLL_STEP, f.t1)
        d = row_point(f, hi, c.half_width, x, r) - row_point(f, lo, c.half_width, x, r)
        slopes.append(float(c.normal @ d) / (hi - lo))
    roll = (slopes[0] * da_a - slopes[1] * db_a, slopes[0] * da_b - slopes[1] * db_b)
    turn = (float(c.normal @ (rigid[4] @ c.delta_a)), -float(c.normal @ (rigid[5] @ c.delta_b)))
    return roll, (roll[0] + turn[0], roll[1] + turn[1])


def pair_rates(c: ContactPair, pa: CubicSpline, pb: CubicSpline, sa: CubicSpline,
                sb: CubicSpline) -> tuple[float, float]:
    """``(d alpha/dt, d beta/dt)`` of the pair ``c`` on the flanks of positions ``pa``, ``pb``
    and velocities ``sa``, ``sb`` (Appendix A: equal tangential velocities, normals that stay
    aligned; a tip corner is a material point)."""
    ta, tb = pa(c.alpha, 1), pb(c.beta, 1)
    ca, cb = pa(c.alpha, 2), pb(c.beta, 2)
    wa, wb = sa(c.alpha), sb(c.beta)
    dwa, dwb = sa(c.alpha, 1), sb(c.beta, 1)
    if c.mode == FLANK:
        that = ta / np.hypot(*ta)
        lhs = np.array([[that @ ta, -(that @ tb)],
                        [cross(ta, ca) / (ta @ ta), -cross(tb, cb) / (tb @ tb)]])
        rhs = np.array([that @ (wb - wa), cross(tb, dwb) / (tb @ tb) - cross(ta, dwa) / (ta @ ta)])
        ad, bd = np.linalg.solve(lhs, rhs)
    elif c.mode == CORNER_A:
        ad, bd = 0.0, float(tb @ (wa - wb) / (tb @ tb))
    else:
        ad, bd = float(ta @ (wb - wa) / (ta @ ta)), 0.0
    return float(ad), float(bd)
