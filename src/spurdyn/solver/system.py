"""The two-gear system: everything about a run that is constant, as plain arrays.

Generalised coordinates (paper eq. 1): per gear ``g`` (0 = A, 1 = B) the disk rotation
``theta[g]`` since the start of contact, positive along the gear's own sense of
rotation (A clockwise, B counter-clockwise), and the *absolute* displacements ``u`` of
the tooth nodes in the world frame, measured from their initial positions ``X``.
Both teeth's displacements live in one vector, A's block first.

Frames. The world frame is the one of :mod:`spurdyn.geometry.placement`: A's centre
at the origin, B's at ``(0, a)``. A gear turning by ``theta`` along its sense turns its
material by the world angle ``sense * theta`` (``sense`` = -1 for A, +1 for B), so a
point fixed to the disk moves from ``c + Y`` to ``c + R(sense theta) Y``.

The stiffness ``K`` of each tooth is assembled once on the initial world positions
(the disk frame at ``theta = 0``); the elastic displacement is
``w = R^T (Y + u) - Y`` (docs/solver.md derives it and the forces).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import brentq

from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_lumped_mass, assemble_stiffness
from spurdyn.geometry.gear import GearPair
from spurdyn.geometry.placement import mesh_angles, to_world_a, to_world_b
from spurdyn.mesh.tooth import ToothMesh, tooth_mesh
from spurdyn.solver.case import RunCase

#: Sense of rotation of each gear: the world angle is ``SENSE[g] * theta[g]``.
SENSE = np.array([-1.0, 1.0])


def edge_weights(eta: float) -> NDArray[np.float64]:
    """Quadratic shape functions of an element edge (root, middle, tip) at ``eta``."""
    return np.array([0.5 * eta * (eta - 1.0), 1.0 - eta * eta, 0.5 * eta * (eta + 1.0)])


def edge_dweights(eta: float) -> NDArray[np.float64]:
    """``d/deta`` of :func:`edge_weights`."""
    return np.array([eta - 0.5, -2.0 * eta, eta + 0.5])


@dataclass(frozen=True)
class Flank:
    """The active flank of one tooth, as the contact search sees it.

    The flank coordinate ``t`` runs from 0 at the root end of the outline to ``ny`` at
    the tip corner; element row ``r`` covers ``r <= t <= r + 1`` with edge coordinate
    ``eta = 2 (t - r) - 1``. The spline data points sit at fixed material points
    ``t_k`` (evenly spaced over the involute part of the flank).

    Attributes
    ----------
    side_nodes
        ``(2 ny + 1,)`` outline nodes, root to tip (local node numbers of the tooth).
    t0, t1
        Flank coordinates of the first and last data point (``t1 = ny``, the tip).
    data_nodes, data_weights
        ``(n, 3)`` edge nodes and shape weights of each data point.
    """

    side_nodes: NDArray[np.intp]
    t0: float
    t1: float
    data_nodes: NDArray[np.intp]
    data_weights: NDArray[np.float64]

    @property
    def n_data(self) -> int:
        return int(self.data_nodes.shape[0])

    @property
    def h(self) -> float:
        """Spacing of the data points in ``t``."""
        return (self.t1 - self.t0) / (self.n_data - 1)

    def locate(self, t: float) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
        """Edge nodes, shape weights and their ``d/dt`` at flank coordinate ``t``."""
        ny = (self.side_nodes.size - 1) // 2
        row = min(max(int(math.floor(t)), 0), ny - 1)
        eta = 2.0 * (t - row) - 1.0
        return self.side_nodes[2 * row:2 * row + 3], edge_weights(eta), 2.0 * edge_dweights(eta)


def make_flank(mesh: ToothMesh, nodes_world: NDArray[np.float64], centre: NDArray[np.float64],
               r_start: float, n_data: int) -> Flank:
    """The right flank of ``mesh`` with ``n_data`` spline points from radius ``r_start`` up."""
    side = mesh.right_side
    ny = mesh.ny
    xy = nodes_world[side] - centre

    def radius(t: float) -> float:
        row = min(max(int(math.floor(t)), 0), ny - 1)
        p = edge_weights(2.0 * (t - row) - 1.0) @ xy[2 * row:2 * row + 3]
        return float(np.hypot(*p))

    if r_start <= radius(0.0):
        t0 = 0.0
    else:
        t0 = brentq(lambda t: radius(t) - r_start, 0.0, float(ny), xtol=1e-13)
    ts = np.linspace(t0, float(ny), n_data)
    nodes = np.empty((n_data, 3), dtype=np.intp)
    weights = np.empty((n_data, 3))
    for k, t in enumerate(ts):
        row = min(int(math.floor(t)), ny - 1)
        nodes[k] = side[2 * row:2 * row + 3]
        weights[k] = edge_weights(2.0 * (t - row) - 1.0)
    return Flank(side_nodes=side.copy(), t0=float(t0), t1=float(ny), data_nodes=nodes,
                 data_weights=weights)


@dataclass(frozen=True)
class GearBody:
    """One gear of the system: rigid disk plus elastic tooth, in the world frame.

    Attributes
    ----------
    sense
        -1 (clockwise, gear A) or +1 (counter-clockwise, gear B).
    centre
        Disk centre (m).
    inertia
        Disk moment of inertia ``J`` (kg m^2).
    mesh
        The tooth mesh (gear frame).
    X
        ``(N, 2)`` initial world positions of the nodes.
    Y
        ``(2N,)`` initial positions relative to the centre, interleaved.
    stiffness
        ``(2N, 2N)`` stiffness on the initial world positions (CSR).
    mass
        ``(2N,)`` HRZ-lumped nodal masses.
    root_nodes
        Nodes tied to the disk.
    flank
        The active flank.
    base_radius
        Base radius of the gear (m), for roll angles.
    """

    sense: float
    centre: NDArray[np.float64]
    inertia: float
    mesh: ToothMesh
    X: NDArray[np.float64]
    Y: NDArray[np.float64]
    stiffness: sp.csr_matrix
    mass: NDArray[np.float64]
    root_nodes: NDArray[np.intp]
    flank: Flank
    base_radius: float

    @property
    def n_u(self) -> int:
        return int(self.mass.size)

    @property
    def root_dofs(self) -> NDArray[np.intp]:
        r = self.root_nodes
        return np.column_stack([2 * r, 2 * r + 1]).ravel()


@dataclass(frozen=True)
class PairSystem:
    """Both gears, placed so that their teeth just touch at the start of contact.

    Attributes
    ----------
    pair
        The gear pair (gear A drives).
    gears
        ``(A, B)``.
    offsets
        Start of each gear's block in the stacked displacement vector, and its end.
    theta0
        Placement rotations of the tooth meshes (A clockwise, B counter-clockwise).
    """

    pair: GearPair
    gears: tuple[GearBody, GearBody]
    offsets: tuple[int, int, int]
    theta0: tuple[float, float]

    @property
    def n_u(self) -> int:
        return self.offsets[2]

    @property
    def n_lambda(self) -> tuple[int, int]:
        return tuple(2 * g.root_nodes.size for g in self.gears)  # type: ignore[return-value]

    @property
    def n_x(self) -> int:
        """Length of ``x = [lambda_A, lambda_B, p]``."""
        return sum(self.n_lambda) + 1

    @property
    def n_dof(self) -> int:
        """Degrees of freedom: two disk rotations and every tooth displacement."""
        return 2 + self.n_u

    @property
    def mass(self) -> NDArray[np.float64]:
        return np.concatenate([g.mass for g in self.gears])


def _body(gear, mesh: ToothMesh, X: NDArray[np.float64], centre: NDArray[np.float64], sense: float,
          n_spline: int) -> GearBody:
    k = assemble_stiffness(X, mesh.elements, gear.material, gear.face_width).tocsr()
    k.sort_indices()
    m = assemble_lumped_mass(X, mesh.elements, gear.material, gear.face_width)
    # The flank spline covers the whole involute, from the form radius to the tip corner.
    flank = make_flank(mesh, X, centre, float(gear.form_radius), n_spline)
    return GearBody(sense=sense, centre=centre, inertia=gear.disk_inertia, mesh=mesh, X=X,
                    Y=(X - centre).ravel(), stiffness=k, mass=m, root_nodes=mesh.root_nodes.copy(),
                    flank=flank, base_radius=gear.base_radius)


def build_system(pair: GearPair, case: RunCase) -> PairSystem:
    """Mesh both teeth, place them just touching at the start of contact, assemble K and M.

    The exact involutes touch at the start of the path of contact for the rotations of
    :func:`~spurdyn.geometry.placement.mesh_angles`; the meshed flanks (quadratic edges
    through points of the involute) are off by some nanometres, so gear B is then turned
    until the meshed flanks touch (``s = 0``) to round-off.
    """
    from spurdyn.contact.reference import find_contact  # the contact module builds on this one

    if pair.driver != "a":
        raise InputError("pair.driver", "only gear A driving is supported by the solver yet; "
                         "swap gear_a and gear_b")
    theta_a, theta_b = mesh_angles(pair, pair.start_roll_a)
    mesh_a = tooth_mesh(pair.gear_a, case.nx, case.ny)
    mesh_b = tooth_mesh(pair.gear_b, case.nx, case.ny)
    ca, cb = np.array([0.0, 0.0]), np.array([0.0, pair.centre_distance])
    xa = to_world_a(mesh_a.nodes, theta_a)
    fa = make_flank(mesh_a, xa, ca, float(pair.gear_a.form_radius), case.n_spline)
    r_start = float(pair.gear_a.radius_at_roll_angle(pair.start_roll_a))
    ts = np.linspace(fa.t0, fa.t1, 8 * fa.n_data)
    radii = [float(np.hypot(*(fa.locate(t)[1] @ xa[fa.locate(t)[0]]))) for t in ts]
    guess = (float(np.interp(r_start, radii, ts)), float(mesh_b.ny))
    for _ in range(6):
        xb = to_world_b(mesh_b.nodes, theta_b, pair.centre_distance)
        fb = make_flank(mesh_b, xb, cb, float(pair.gear_b.form_radius), case.n_spline)
        c = find_contact(fa, fb, xa, xb, guess)
        guess = (c.alpha, c.beta)
        point = c.weights_b @ xb[c.nodes_b] - cb
        lever = float(c.normal @ np.array([-point[1], point[0]]))
        theta_b += c.s / lever
        if abs(c.s) < 1e-16:
            break
    xb = to_world_b(mesh_b.nodes, theta_b, pair.centre_distance)
    gears = (_body(pair.gear_a, mesh_a, xa, ca, float(SENSE[0]), case.n_spline),
             _body(pair.gear_b, mesh_b, xb, cb, float(SENSE[1]), case.n_spline))
    na, nb = gears[0].n_u, gears[1].n_u
    return PairSystem(pair=pair, gears=gears, offsets=(0, na, na + nb), theta0=(theta_a, theta_b))
