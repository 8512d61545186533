"""A crack growing by increments in the direction of the maximum tangential stress until it
reaches a boundary of the region it runs in (docs/fracture.md, section 8).

The crack is a polyline, mouth first. At each tip the caller's ``evaluate(path)`` gives K_I,
K_II and K_eq under the worst load (the model's business: a gear's mesh cycle,
:mod:`spurdyn.sector.crack_tip`); the crack turns by Erdogan & Sih's ``theta_c``
(:func:`~spurdyn.fracture.direction.growth_angle`) and runs on by the increment. The region
(:class:`Region`) is a cracked cell's outline, each stretch a free surface or the rim's
inner boundary (a held circle, or a cut to the neighbouring cells below the root circle);
when the crack's next increment would come within reach of the outline, the ray along its
new direction decides where it comes out: through a free surface the tooth breaks off
(``"tooth"``), through the rim's inner boundary the rim breaks (``"rim"``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fracture.direction import growth_angle
from spurdyn.mesh import outline as ol
from spurdyn.mesh.tooth import ToothMesh

__all__ = ["DECIDE_REACH", "Growth", "GrowthStopped", "Region", "Step", "TipState", "cell_region", "grow",
           "junction_band", "path_length"]

#: The crack is decided when the ray along its new direction meets the outline within this
#: many increments of its tip, or the tip comes within :data:`DECIDE_NEAR` increments of
#: the outline: the next tip would leave no room for the elements and domains at it.
DECIDE_REACH = 1.5
DECIDE_NEAR = 0.75
#: A next tip above the rim's inner circle (a web's junction) by less than this many tip
#: sizes decides a rim fracture: the tip's own elements and the ring round them (q = 1 on
#: their nodes in the 2-ring domain) reach 8.4-10.0 tip sizes from the tip in the cracked
#: cell's graded mesh (docs/fracture.md, 8.5), so a tip solved further up keeps them all in
#: the rim's width, only the domains' outer rings cut by ``widths=``.
JUNCTION_TIPS = 10.0
#: ... and by no more than this share of the rim's thickness below the root circle (a tip
#: size from a long first crack must not take a thin rim's ligament away).
JUNCTION_SHARE = 0.25
#: Most increments a crack may take before the loop stops undecided.
MAX_STEPS = 400


@dataclass(frozen=True)
class TipState:
    """What a crack's tip sees under its worst load: K_I, K_II, K_eq (Pa sqrt(m)) and the
    load's position (the model's, e.g. the driver's roll angle, rad)."""

    k_i: float
    k_ii: float
    k_eq: float
    position: float


@dataclass(frozen=True)
class Step:
    """One tip of the growing crack: its length along the path (m), the tip ``(2,)``, its
    :class:`TipState` and the turn ``theta_c`` (rad, counter-clockwise) of the next piece."""

    length: float
    tip: NDArray[np.float64]
    state: TipState
    turn: float


@dataclass(frozen=True)
class Growth:
    """A grown crack.

    Attributes
    ----------
    path
        ``(k, 2)`` the crack, mouth first, its last point the last tip solved.
    steps
        Every tip solved, in order.
    verdict
        ``"tooth"``, ``"rim"``, or ``None`` (undecided: :attr:`reason`).
    length
        The crack's length when it reaches the boundary (m): the path's, and the straight
        run from the last tip to the outline along the last direction; ``None`` undecided.
    exit
        ``(2,)`` where it reaches the outline; ``None`` undecided.
    reason
        In words, how the loop ended.
    """

    path: NDArray[np.float64]
    steps: tuple[Step, ...]
    verdict: str | None
    length: float | None
    exit: NDArray[np.float64] | None
    reason: str


@dataclass(frozen=True)
class Region:
    """A closed outline, each of its points labelled: what the crack breaks if it comes out
    at the stretch that starts there.

    Attributes
    ----------
    polygon
        ``(P, 2)`` the outline, closed on its first point (m).
    kind
        ``(P,)`` ``"tooth"`` on a free surface, ``"rim"`` on the rim's inner boundary.
    inner_radius
        Below this radius (the rim's: a web's junction, or the held hub) the crack is
        through the rim (m).
    """

    polygon: NDArray[np.float64]
    kind: NDArray[np.str_]
    inner_radius: float

    def ray(self, p: NDArray[np.float64], d: NDArray[np.float64]) -> tuple[float, str, NDArray[np.float64]]:
        """Where the ray from ``p`` along the unit ``d`` first meets the outline: its
        distance (m; ``inf`` if never), the stretch's kind, the point."""
        a, b = self.polygon, np.roll(self.polygon, -1, axis=0)
        e = b - a
        den = d[0] * e[:, 1] - d[1] * e[:, 0]
        w = a - p
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / den
            s = (w[:, 0] * d[1] - w[:, 1] * d[0]) / den
        hit = (np.abs(den) > 0.0) & (t > 0.0) & (s >= 0.0) & (s <= 1.0)
        if not hit.any():
            return math.inf, "", p
        k = int(np.flatnonzero(hit)[np.argmin(t[hit])])
        return float(t[k]), str(self.kind[k]), p + t[k] * d

    def nearest(self, p: NDArray[np.float64]) -> tuple[str, NDArray[np.float64]]:
        """The outline's point nearest ``p`` and its stretch's kind."""
        a, b = self.polygon, np.roll(self.polygon, -1, axis=0)
        e = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, e) / np.maximum(np.einsum("ij,ij->i", e, e), 1e-300),
                    0.0, 1.0)
        q = a + t[:, None] * e
        k = int(np.argmin(np.hypot(*(q - p).T)))
        return str(self.kind[k]), q[k]

    def clearance(self, p: NDArray[np.float64]) -> float:
        """The least distance from ``p`` to the outline (m)."""
        return ol.distance(self.polygon, p)


def cell_region(cell: ToothMesh, half_pitch: float, inner_radius: float,
                rim_radius: float | None = None) -> Region:
    """The region of a cracked cell (:func:`spurdyn.mesh.sector.cell_mesh`): the hub's arc
    (radius ``inner_radius``) and the radial cuts to the neighbouring cells (angle
    ``half_pitch`` from the centre line) the rim's inner boundary, the rest free surface;
    ``rim_radius`` a web's junction below which the crack is through the rim (default the
    hub's)."""
    edges = ol.outline_edges(cell)
    poly = ol.polygon(cell.nodes, edges)
    per = poly.shape[0] // edges.shape[0]
    mid = cell.nodes[edges[:, 1]]                  # each edge's mid-side node
    r = np.hypot(*mid.T)
    chi = np.abs(np.arctan2(mid[:, 0], mid[:, 1]))
    held = (np.abs(r - inner_radius) <= 1e-6 * inner_radius) | (chi >= half_pitch * (1.0 - 1e-6))
    kind = np.repeat(np.where(held, "rim", "tooth"), per)
    return Region(polygon=poly, kind=kind,
                  inner_radius=inner_radius if rim_radius is None else float(rim_radius))


class GrowthStopped(Exception):
    """Raised by a growth's ``evaluate`` that cannot solve a tip (its mesh refused): the
    growth ends there, undecided, with the message as its reason (at the first tip the
    caller's refusal stands)."""


def path_length(path: NDArray[np.float64]) -> float:
    """The polyline's length (m)."""
    return float(np.sum(np.hypot(*np.diff(path, axis=0).T)))


def _turned(d: NDArray[np.float64], angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    out = np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
    return out / np.hypot(*out)


def _below_rim(region: Region, tip: NDArray[np.float64], d: NDArray[np.float64]) -> float:
    """Distance (m) along ``d`` from ``tip`` to the circle ``region.inner_radius`` (``inf`` if
    the ray does not cross it inward)."""
    b = float(tip @ d)
    c = float(tip @ tip) - region.inner_radius ** 2
    disc = b * b - c
    if c <= 0.0:
        return 0.0                                   # the tip is below it already
    if disc < 0.0 or b >= 0.0:
        return math.inf
    return -b - math.sqrt(disc)


def junction_band(tip_size: float, rim_thickness: float) -> float:
    """How far above the rim's inner circle (m) a next tip decides a rim fracture:
    :data:`JUNCTION_TIPS` tip sizes ``tip_size`` (m), at most :data:`JUNCTION_SHARE` of the
    rim's ``rim_thickness`` below the root circle (m)."""
    return min(JUNCTION_TIPS * tip_size, JUNCTION_SHARE * rim_thickness)


def _decide(region: Region, tip: NDArray[np.float64], d: NDArray[np.float64], increment: float,
            band: float = 0.0) -> tuple[float, str, NDArray[np.float64]] | None:
    """``(distance, kind, point)`` if the crack at ``tip`` running along ``d`` is to be decided
    now (module constants), else ``None``: the nearest of the outline ahead (within reach,
    or the next tip near it: then the outline's point nearest that tip) and the rim's
    inner circle within an increment (or the next tip above it by less than ``band`` (m,
    :func:`junction_band`): then the circle's point nearest that tip)."""
    found: list[tuple[float, str, NDArray[np.float64]]] = []
    dist, kind, point = region.ray(tip, d)
    if dist <= DECIDE_REACH * increment:
        found.append((dist, kind, point))
    nxt = tip + increment * d
    if region.clearance(nxt) < DECIDE_NEAR * increment:
        kind_n, point_n = region.nearest(nxt)
        found.append((float(np.hypot(*(point_n - tip))), kind_n, point_n))
    down = _below_rim(region, tip, d)
    if down <= increment:
        found.append((down, "rim", tip + down * d))
    r_next = float(np.hypot(*nxt))
    if region.inner_radius <= r_next < region.inner_radius + band:
        # the next tip just above the junction: the rim's ligament is gone (and a tip's
        # elements there would reach the junction: no domain of one width)
        point = nxt * (region.inner_radius / r_next)
        found.append((float(np.hypot(*(point - tip))), "rim", point))
    return min(found, key=lambda f: f[0]) if found else None


def grow(path: NDArray[np.float64], increment: float, evaluate: Callable[[NDArray[np.float64]], TipState],
         region: Region, max_steps: int = MAX_STEPS,
         progress: Callable[[Step], None] | None = None, band: float = 0.0) -> Growth:
    """Grow the crack ``path`` (``(k, 2)``, mouth first) by ``increment`` (m) a step until
    it reaches ``region``'s outline (module docstring), at most ``max_steps`` increments;
    a next tip less than ``band`` (m, :func:`junction_band`; default none) above the rim's
    inner circle decides a rim fracture.

    Raises
    ------
    InputError
        ``increment`` not a positive length.
    """
    if isinstance(increment, bool) or not isinstance(increment, (int, float)) or \
            not math.isfinite(increment) or not increment > 0.0:
        raise InputError("increment", f"must be a positive length in m (got {increment!r})")
    path = np.asarray(path, dtype=float)
    steps: list[Step] = []
    for _ in range(max_steps + 1):
        try:
            state = evaluate(path)
        except GrowthStopped as stop:
            if not steps:
                raise
            return Growth(path[:-1], tuple(steps), None, None, None, str(stop))
        tip, ahead = path[-1], path[-1] - path[-2]
        ahead = ahead / np.hypot(*ahead)
        if not state.k_eq > 0.0:
            steps.append(Step(path_length(path), tip, state, math.nan))
            return Growth(path, tuple(steps), None, None, None,
                          "the tip is closed (K_I <= 0) under every load position")
        turn = growth_angle(state.k_i, state.k_ii)
        step = Step(path_length(path), tip, state, turn)
        steps.append(step)
        if progress is not None:
            progress(step)
        d = _turned(ahead, turn)
        decided = _decide(region, tip, d, increment, band)
        if decided is not None:
            dist, kind, point = decided
            return Growth(path, tuple(steps), kind, step.length + dist, point,
                          f"the crack reaches the outline {dist * 1e3:.4g} mm ahead of its last tip")
        path = np.vstack([path, tip + increment * d])
    return Growth(path[:-1], tuple(steps), None, None, None,
                  f"not decided within {max_steps} increments")
