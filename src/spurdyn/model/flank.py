"""The active flank of one tooth as the contact search sees it: a data description.

Built once per run by :func:`make_flank` from the tooth mesh placed in the world frame;
the NumPy search (:mod:`spurdyn.contact.search_numpy`) reads it, the compiled one
(:mod:`spurdyn.contact.search_compiled`) its parameter row
(:func:`spurdyn.contact.constants.flank_row`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from spurdyn.fem.element import edge_dweights, edge_weights
from spurdyn.geometry import involute as ivl
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.relief import relief_depth, relief_params
from spurdyn.mesh.tooth import ToothMesh


@dataclass(frozen=True)
class Flank:
    """The active flank of one tooth, as the contact search sees it.

    The flank coordinate ``t`` runs from 0 at the root end of the outline to ``ny`` at
    the tip corner; element row ``r`` covers ``r <= t <= r + 1`` with edge coordinate
    ``eta = 2 (t - r) - 1``. The outline nodes are evenly spaced in (involute) radius, so
    the material point at ``t`` is the point of the flank at involute radius
    ``r(t) = r_0 + (r_1 - r_0) t / ny`` (``r_1`` the tip radius, or a few micrometres
    more with a tip relief: :attr:`~spurdyn.geometry.gear.Gear.flank_end_radius`), moved
    in along the normal by the relief depth there.

    The surface is the exact involute plus the finite-element displacement (the paper:
    the tooth surface is "the initial shape combined with the displacements of rigid
    motion and elastic deformation"). A point at ``t`` is at
    ``c + N(t) (Y + u) + R(sense theta) delta(t)`` with ``delta = Y_exact - N Y`` the
    (nanometre) offset of the involute from the quadratic element edge, carried round by
    the disk; for a rigid rotation this is the exactly rotated involute. The spline data
    points sit at fixed material points ``t_k``, evenly spaced over the involute.

    Attributes
    ----------
    side_nodes
        ``(2 ny + 1,)`` outline nodes, root to tip (local node numbers of the tooth).
    side_Y
        ``(2 ny + 1, 2)`` their initial positions relative to the centre.
    t0, t1
        Flank coordinates of the first and last data point (``t1 = ny``, the tip).
    r0, r_tip
        Radius of the outline at ``t = 0`` and involute radius at ``t = ny``. With rows
        graded along the tooth (``mesh.fillet_rows > 0``) ``r0`` is the flank rows' linear
        law continued to ``t = 0`` (below the fillet's rows; the law holds from the form
        radius, ``t = fillet_rows``, up).
    base_radius, psi_base
        Base radius and polar half-angle of the tooth at the base circle.
    ref_angle
        World angle of the gear frame at ``theta = 0``.
    data_nodes, data_weights
        ``(n, 3)`` edge nodes and shape weights of each data point.
    data_delta
        ``(n, 2)`` ``delta`` at each data point.
    relief
        ``(amount, start_roll, exponent, tip_roll)`` of the tip relief
        (:func:`spurdyn.geometry.relief.relief_params`; amount 0 for none).
    """

    side_nodes: NDArray[np.intp]
    side_Y: NDArray[np.float64]
    t0: float
    t1: float
    r0: float
    r_tip: float
    base_radius: float
    psi_base: float
    ref_angle: float
    data_nodes: NDArray[np.intp]
    data_weights: NDArray[np.float64]
    data_delta: NDArray[np.float64]
    relief: tuple[float, float, float, float] = (0.0, 0.0, 1.0, 1.0)

    @property
    def ny(self) -> int:
        return (self.side_nodes.size - 1) // 2

    @property
    def n_data(self) -> int:
        return int(self.data_nodes.shape[0])

    @property
    def h(self) -> float:
        """Spacing of the data points in ``t``."""
        return (self.t1 - self.t0) / (self.n_data - 1)

    def locate(self, t: float) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
        """Edge nodes, shape weights and their ``d/dt`` at flank coordinate ``t``."""
        row = min(max(int(math.floor(t)), 0), self.ny - 1)
        eta = 2.0 * (t - row) - 1.0
        return self.side_nodes[2 * row:2 * row + 3], edge_weights(eta), 2.0 * edge_dweights(eta)

    def exact(self, t: float) -> NDArray[np.float64]:
        """Initial position (relative to the centre) of the involute point at ``t``."""
        r = self.r0 + (self.r_tip - self.r0) * t / self.ny
        alpha = math.acos(min(self.base_radius / r, 1.0))
        chi = self.psi_base - float(ivl.inv(alpha))
        x, y = r * math.sin(chi), r * math.cos(chi)
        amount, start, k, tip = self.relief
        if amount > 0.0:
            xi = math.sqrt(max(r * r - self.base_radius**2, 0.0)) / self.base_radius
            depth = float(relief_depth(xi, amount, start, tip, k))
            chi_t = self.psi_base - math.tan(alpha)          # the involute's normal
            x -= depth * math.cos(chi_t)
            y += depth * math.sin(chi_t)
        c, s = math.cos(self.ref_angle), math.sin(self.ref_angle)
        return np.array([c * x - s * y, s * x + c * y])

    def delta(self, t: float) -> NDArray[np.float64]:
        """``Y_exact(t) - N(t) Y``: the involute's offset from the element edge."""
        row = min(max(int(math.floor(t)), 0), self.ny - 1)
        w = edge_weights(2.0 * (t - row) - 1.0)
        return self.exact(t) - w @ self.side_Y[2 * row:2 * row + 3]


def make_flank(mesh: ToothMesh, gear: Gear, nodes_world: NDArray[np.float64],
               centre: NDArray[np.float64], ref_angle: float, n_data: int) -> Flank:
    """The right flank of ``mesh`` with ``n_data`` spline points over the involute."""
    side = mesh.right_side
    ny = mesh.ny
    side_y = nodes_world[side] - centre
    r0 = float(np.hypot(*side_y[0]))
    r_tip = float(gear.flank_end_radius)
    if mesh.fillet_rows:
        # rows even in radius on the fillet and on the flank apart (mesh.tooth.row_radii):
        # the flank's linear law r(t), continued down to t = 0, gives r0
        n_f = mesh.fillet_rows
        r_form = float(np.hypot(*side_y[2 * n_f]))
        r0 = r_tip - ny * (r_tip - r_form) / (ny - n_f)
    t0 = ny * (float(gear.form_radius) - r0) / (r_tip - r0)
    ts = np.linspace(max(t0, 0.0), float(ny), n_data)
    nodes = np.empty((n_data, 3), dtype=np.intp)
    weights = np.empty((n_data, 3))
    for k, t in enumerate(ts):
        row = min(int(math.floor(t)), ny - 1)
        nodes[k] = side[2 * row:2 * row + 3]
        weights[k] = edge_weights(2.0 * (t - row) - 1.0)
    flank = Flank(side_nodes=side.copy(), side_Y=side_y, t0=float(ts[0]), t1=float(ny), r0=r0,
                  r_tip=r_tip, base_radius=float(gear.base_radius),
                  psi_base=float(gear.half_angle_base), ref_angle=float(ref_angle),
                  data_nodes=nodes, data_weights=weights, data_delta=np.zeros((n_data, 2)),
                  relief=relief_params(gear))
    object.__setattr__(flank, "data_delta", np.array([flank.delta(t) for t in ts]))
    return flank
