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

from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_lumped_mass, assemble_stiffness
from spurdyn.geometry import involute as ivl
from spurdyn.geometry.gear import Gear, GearPair
from spurdyn.geometry.relief import relief_params
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
        Radius of the outline at ``t = 0`` and involute radius at ``t = ny``.
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
            depth = amount * max(0.0, (xi - start) / (tip - start)) ** k
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


def _body(gear: Gear, mesh: ToothMesh, X: NDArray[np.float64], centre: NDArray[np.float64],
          sense: float, ref_angle: float, n_spline: int) -> GearBody:
    k = assemble_stiffness(X, mesh.elements, gear.material, gear.face_width).tocsr()
    k.sort_indices()
    m = assemble_lumped_mass(X, mesh.elements, gear.material, gear.face_width)
    flank = make_flank(mesh, gear, X, centre, ref_angle, n_spline)
    return GearBody(sense=sense, centre=centre, inertia=gear.disk_inertia, mesh=mesh, X=X,
                    Y=(X - centre).ravel(), stiffness=k, mass=m, root_nodes=mesh.root_nodes.copy(),
                    flank=flank, base_radius=gear.base_radius)


def build_system(pair: GearPair, case: RunCase) -> PairSystem:
    """Mesh both teeth, place them just touching at the start of contact, assemble K and M.

    The surfaces of :class:`Flank` are the exact involutes, which touch at the start of
    the path of contact at the rotations of :func:`~spurdyn.geometry.placement.mesh_angles`
    (to round-off; with a tip relief they stand apart by the relief there).
    """
    if pair.driver != "a":
        raise InputError("pair.driver", "only gear A driving is supported by the solver yet; "
                         "swap gear_a and gear_b")
    theta_a, theta_b = mesh_angles(pair, pair.start_roll_a)
    mesh_a = tooth_mesh(pair.gear_a, case.nx, case.ny)
    mesh_b = tooth_mesh(pair.gear_b, case.nx, case.ny)
    ca, cb = np.array([0.0, 0.0]), np.array([0.0, pair.centre_distance])
    xa = to_world_a(mesh_a.nodes, theta_a)
    xb = to_world_b(mesh_b.nodes, theta_b, pair.centre_distance)
    gears = (_body(pair.gear_a, mesh_a, xa, ca, float(SENSE[0]), -theta_a, case.n_spline),
             _body(pair.gear_b, mesh_b, xb, cb, float(SENSE[1]), math.pi + theta_b, case.n_spline))
    na, nb = gears[0].n_u, gears[1].n_u
    return PairSystem(pair=pair, gears=gears, offsets=(0, na, na + nb), theta0=(theta_a, theta_b))
