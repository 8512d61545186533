"""The sector model's equations of motion: each gear's coordinates, matrices and contact rows
(docs/sector.md, section 6).

Gear ``g`` has the coordinates ``q_g = (theta_g, u_g)``: the hub's rotation along the gear's
sense of rotation and the elastic displacements of the body's free nodes in the hub's frame
(the nodes on the hub circle are held by the hub). A node moves by ``theta s + u``, with
``s`` the displacement field of a unit turn, so with the body's HRZ-lumped masses ``M`` and
plane-stress stiffness ``K`` the gear's mass, damping and stiffness matrices are

    M_g = [J_hub + s^T M s   (M s)^T]     C_g = [0  0          ]     K_g = [0  0]
          [M s               M      ],          [0  a M + b K  ],           [0  K],

Rayleigh's damping acting on the deformation rate ``u_dot`` only, so that a rigid rotation is
not damped. (The floating frame's velocity terms, centrifugal and Coriolis, are left out: at
20,000 rpm the speed is about 2 % of the lowest tooth mode's frequency.)

A tooth pair, the driver's tooth ``k`` on the driven gear's tooth ``-k``, has the gap along
the line of action

    g = g0 - (r_bA theta_A - r_bB theta_B) + b_A^T u_A + b_B^T u_B,

exact in the rotations for involutes (the base circles unwind the line of action), with
``b_g`` the unit normal load of the pair's Hertzian strip on gear ``g``'s tooth
(:meth:`spurdyn.sector.body.SectorBody.load`; pressing into the tooth, so that a flank that
yields opens the gap) and ``g0`` the two tip reliefs at the contact radii. The pair's force
``F >= 0`` acts through the gap's gradient, the row ``G = dg/dq``, so it does no spurious
work.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from spurdyn.contact.hertz import half_width, involute_curvature_radius
from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.fem.assembly import assemble_lumped_mass
from spurdyn.geometry.corner import corner_contact
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair
from spurdyn.mesh.sector import turn
from spurdyn.sector.body import SectorBody, sector_body
from spurdyn.sector.statics import pairs_in_path


def rotation_field(nodes: NDArray[np.float64], sense: float) -> NDArray[np.float64]:
    """``(2N,)`` nodal displacement per radian of a turn along the gear's sense (+1:
    clockwise in the gear's frame, the driver's; -1: counter-clockwise, the driven gear's,
    whose mirrored frame puts its next tooth on the other side)."""
    return sense * np.column_stack([nodes[:, 1], -nodes[:, 0]]).ravel()


@dataclass(frozen=True)
class GearBlock:
    """One gear of the sector model (SI units).

    Attributes
    ----------
    body
        The meshed, factorised body (:class:`~spurdyn.sector.body.SectorBody`).
    sense
        +1 for the driver, -1 for the driven gear (:func:`rotation_field`).
    first, count
        The body's teeth are ``first .. first + count - 1``; a body of all the gear's teeth
        (``whole``) takes any tooth number round the ring.
    mass
        ``(n,)`` lumped masses of the free DOFs (kg).
    rot
        ``(n,)`` the free DOFs' part of the unit-turn field ``s``.
    inertia
        ``J_hub + s^T M s`` over all nodes (kg m^2).
    hub_inertia, body_inertia
        The hub's part and the meshed body's (kg m^2).
    stiffness
        ``(n, n)`` stiffness of the free DOFs (N/m).
    """

    body: SectorBody
    sense: float
    first: int
    count: int
    mass: NDArray[np.float64]
    rot: NDArray[np.float64]
    inertia: float
    hub_inertia: float
    body_inertia: float
    stiffness: sp.csr_matrix
    _free_of: NDArray[np.intp] = field(repr=False)
    _side_of: NDArray[np.intp] = field(repr=False)

    @property
    def gear(self) -> Gear:
        return self.body.gear

    @property
    def n(self) -> int:
        """Coordinates of the gear: the hub's turn and the free DOFs."""
        return 1 + self.mass.size

    @property
    def whole(self) -> bool:
        return self.count == self.gear.teeth

    def tooth(self, k: int) -> int:
        """The body's number of the gear's tooth ``k`` (round the ring on a whole gear)."""
        if self.whole:
            return self.first + (k - self.first) % self.count
        if not self.first <= k < self.first + self.count:
            raise IndexError(f"tooth {k} is not in the sector {self.first}..{self.first + self.count - 1}")
        return k

    def flank_dofs(self, k: int) -> NDArray[np.intp]:
        """``(2 (2 ny + 1),)`` free-DOF numbers of tooth ``k``'s right flank, root to tip."""
        dofs = self.body.mesh.tooth_dofs(self.tooth(k)).reshape(-1, 2)[self.body.flank.side_nodes]
        return self._free_of[dofs.ravel()]

    def flank_load(self, k: int, r: float, b: float) -> NDArray[np.float64]:
        """The unit strip load of tooth ``k`` at involute radius ``r`` (half-width ``b``) on
        :meth:`flank_dofs`: :meth:`spurdyn.sector.body.SectorBody.load` on the flank alone."""
        body = self.body
        nodes, w, _ = strip_rows(body.flank, body.flank_coordinate(r), b)
        out = np.zeros((body.flank.side_nodes.size, 2))
        # the mating flank pushes into the tooth, against the outward normal
        np.add.at(out, self._side_of[nodes], -w[:, None] * body.gear.flank_normal(np.asarray(r))[None, :])
        return turn(out, body.mesh.tooth_angle(self.tooth(k))).ravel()

    def matrix(self, cm: float, cc: float, ck: float, rayleigh: tuple[float, float]) -> sp.csc_matrix:
        """``cm M_g + cc C_g + ck K_g`` (module docstring) with Rayleigh's ``(a, b)``."""
        a, b = rayleigh
        ms = self.mass * self.rot
        n = self.mass.size
        idx = np.arange(n) + 1
        coupling = sp.coo_matrix((np.concatenate([[self.inertia], ms, ms]),
                                  (np.concatenate([[0], idx, np.zeros(n, np.intp)]),
                                   np.concatenate([[0], np.zeros(n, np.intp), idx]))),
                                 shape=(n + 1, n + 1))
        uu = sp.diags((cm + cc * a) * self.mass) + (ck + cc * b) * self.stiffness
        return (cm * coupling + sp.block_diag([sp.csr_matrix((1, 1)), uu])).tocsc()

    def forces(self, q: NDArray[np.float64], v: NDArray[np.float64],
               rayleigh: tuple[float, float]) -> NDArray[np.float64]:
        """``C_g v + K_g q``: the elastic and damping forces on the gear's coordinates."""
        a, b = rayleigh
        out = np.zeros_like(q)
        u, du = q[1:], v[1:]
        out[1:] = self.stiffness @ (u + b * du) if b else self.stiffness @ u
        if a:
            out[1:] += a * self.mass * du
        return out


#: Mesh cycles from which a run takes the whole gears: a steady state must repeat exactly
#: from one cycle to the next, and a sector's rim changes under the mesh as the pairs move
#: toward its ends (by less than 0.1 % of the stiffness, but more than the settled test's
#: 1e-3 of the peak force from cycle to cycle); the rim is meshed whole anyway (1.5 times the
#: DOFs of a five-tooth sector on the paper's pair).
WHOLE_FROM_CYCLES = 3


def teeth_for(pair: GearPair, cycles: float) -> tuple[tuple[int, int], tuple[int, int]]:
    """``((first, count), (first, count))`` of the driver's and the driven gear's teeth that
    a run of ``cycles`` mesh cycles needs: every tooth that reaches the path of contact (the
    driver's ``0 .. P-1`` at the start, one more entering behind them each cycle; the driven
    gear's the negatives) and a neighbour on each side; a gear's whole ring when that is as
    many teeth as it has, or the run lasts :data:`WHOLE_FROM_CYCLES` cycles or more."""
    n_path = pairs_in_path(pair)
    first = -int(math.ceil(cycles - 1e-9)) - 1
    count = n_path - first + 1
    out = []
    for gear, lo in ((pair.gear_a, first), (pair.gear_b, -(first + count - 1))):
        z = gear.teeth
        whole = count >= z or cycles >= WHOLE_FROM_CYCLES
        out.append((-(z // 2), z) if whole else (lo, count))
    return out[0], out[1]


def gear_block(gear: Gear, sense: float, first: int, count: int, nx: int, ny: int,
               grading: float) -> GearBlock:
    """Mesh, assemble and factorise the gear's body of ``count`` teeth from tooth ``first``
    (all of them if ``count`` is the gear's number of teeth) and build its block."""
    count = min(count, gear.teeth)
    body = sector_body(gear, count, nx, ny, first=first, grading=grading)
    mesh = body.mesh
    m_full = np.zeros(mesh.n_dof)
    for width in np.unique(mesh.width):
        sel = mesh.width == width
        m_full += assemble_lumped_mass(mesh.nodes, mesh.elements[sel], gear.material, float(width))
    s_full = rotation_field(mesh.nodes, sense)
    j_body = float(s_full @ (m_full * s_full))
    # The gear's whole inertia is the paper model's disk and tooth; what the meshed body
    # does not hold is the hub's (a floor of 1e-3 of it where the body holds more).
    j_whole = gear.disk_inertia + gear.tooth_polar_inertia()
    j_hub = max(j_whole - j_body, 1e-3 * j_whole)
    free = body._free
    free_of = np.full(mesh.n_dof, -1, dtype=np.intp)
    free_of[free] = np.arange(free.size)
    side_of = np.full(mesh.tooth.n_nodes, -1, dtype=np.intp)
    side_of[body.flank.side_nodes] = np.arange(body.flank.side_nodes.size)
    return GearBlock(body=body, sense=sense, first=first, count=count, mass=m_full[free],
                     rot=s_full[free], inertia=j_hub + j_body, hub_inertia=j_hub,
                     body_inertia=j_body, stiffness=body.stiffness[free][:, free].tocsr(),
                     _free_of=free_of, _side_of=side_of)


#: How far beyond either end of the path of contact (as a fraction of the angular pitch of
#: the driver's roll) a pair is a contact candidate: a tip corner's rigid gap grows with the
#: square of the roll beyond the end (for the paper's pair 0.4 um at 0.003 rad, 150 um at a
#: quarter pitch), far beyond any loaded approach there (docs/sector.md, 6.2).
REACH = 0.25

#: Step (rad of the driver's roll) of the central difference of a pair's rigid gap.
SLOPE_STEP = 1e-6


def rigid_gap(dp: GearPair, rho: float) -> tuple[float, float, float, float]:
    """``(g, dg/drho, r_a, r_b)``: a pair's gap at the kinematic position of the driver's
    roll ``rho`` (a tip corner's off the path, :func:`spurdyn.geometry.corner.corner_contact`,
    plus the two tip reliefs at the contact radii), its slope, and the contact radii. The
    slope enters the pair's row, so that the force does the work the gap's change asks."""

    def total(x: float) -> tuple[float, float, float]:
        g, r_a, r_b = corner_contact(dp, x)
        return g + float(dp.gear_a.relief_depth(r_a) + dp.gear_b.relief_depth(r_b)), r_a, r_b

    g, r_a, r_b = total(rho)
    slope = (total(rho + SLOPE_STEP)[0] - total(rho - SLOPE_STEP)[0]) / (2.0 * SLOPE_STEP)
    return g, slope, r_a, r_b


def _radii(dp: GearPair, rolls: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The contact radii on the driver and the driven gear at the driver's rolls."""
    rolls = np.atleast_1d(np.asarray(rolls, dtype=float))
    return (np.atleast_1d(dp.gear_a.radius_at_roll_angle(rolls)),
            np.atleast_1d(dp.gear_b.radius_at_roll_angle(np.asarray(dp.roll_b_from_roll_a(rolls)))))


def _half_widths(dp: GearPair, rolls: Any, forces: NDArray[np.float64], estar: float,
                 width: float) -> NDArray[np.float64]:
    """Hertz's half-widths of the pairs' forces at the driver's rolls."""
    return _half_widths_at(dp, _radii(dp, rolls), forces, estar, width)


def _half_widths_at(dp: GearPair, radii: tuple[NDArray[np.float64], NDArray[np.float64]],
                    forces: NDArray[np.float64], estar: float, width: float) -> NDArray[np.float64]:
    """Hertz's half-widths of the pairs' forces at the contact radii ``(r_a, r_b)`` (the
    involutes' curvatures there, a tip corner's too)."""
    ra, rb = radii
    rho_a = [involute_curvature_radius(float(r), dp.gear_a.base_radius) for r in ra]
    rho_b = [involute_curvature_radius(float(r), dp.gear_b.base_radius) for r in rb]
    return np.atleast_1d(half_width(np.asarray(forces, dtype=float), rho_a, rho_b, estar, width))


__all__ = ["GearBlock", "REACH", "SLOPE_STEP", "gear_block", "rigid_gap", "rotation_field", "teeth_for"]
