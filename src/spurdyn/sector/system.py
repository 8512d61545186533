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
from typing import Any, Mapping

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from spurdyn.contact.hertz import half_width, involute_curvature_radius
from spurdyn.contact.strip_numpy import strip_weights
from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_lumped_mass
from spurdyn.geometry.corner import corner_contacts
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair
from spurdyn.sector.body import SectorBody, sector_body, tied_masses
from spurdyn.sector.packs import GapArrays
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
        The meshed body (factorised when first solved with) (:class:`~spurdyn.sector.body.SectorBody`).
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
    _free_of: NDArray[np.intp] = field(repr=False)
    _side_of: NDArray[np.intp] = field(repr=False)
    _left: NDArray[np.intp] = field(repr=False)
    #: Body teeth broken off (their flanks carry no contact), and whether a tooth is on a
    #: cracked mesh: a gear with either is not a ring of identical cells.
    missing: frozenset[int] = frozenset()
    cracked: bool = False

    @property
    def gear(self) -> Gear:
        return self.body.gear

    @property
    def stiffness(self) -> sp.csr_matrix:
        """``(n, n)`` stiffness of the free DOFs (N/m), assembled when first asked for."""
        return self.body.free_stiffness

    @property
    def n(self) -> int:
        """Coordinates of the gear: the hub's turn and the free DOFs."""
        return 1 + self.mass.size

    @property
    def whole(self) -> bool:
        return self.count == self.gear.teeth

    @property
    def cyclic(self) -> bool:
        """A whole ring of identical teeth: a flank's flexibility depends on the teeth's
        distance alone (a faulty gear's does not)."""
        return self.whole and not self.missing and not self.cracked

    def tooth(self, k: int) -> int:
        """The body's number of the gear's tooth ``k`` (round the ring on a whole gear)."""
        if self.whole:
            return self.first + (k - self.first) % self.count
        if not self.first <= k < self.first + self.count:
            raise IndexError(f"tooth {k} is not in the sector {self.first}..{self.first + self.count - 1}")
        return k

    def flank_dofs(self, k: int, side: int = 0) -> NDArray[np.intp]:
        """``(2 (2 ny + 1),)`` free-DOF numbers of tooth ``k``'s right flank (``side`` 0, the
        drive flank) or left flank (1, the back flank, node for node the right one's mirror
        image across the tooth's centre line), root to tip."""
        if self.tooth(k) in self.missing:       # its nodes went with it, but the rim's
            raise IndexError(f"tooth {k} has no flank: it is missing")
        nodes = self.body.flank.side_nodes if side == 0 else self._left
        dofs = self.body.mesh.tooth_dofs(self.tooth(k)).reshape(-1, 2)[nodes]
        absent = dofs[:, 0] < 0
        if absent.any():
            # a cracked tooth's mesh has no node where the crack's mouth splits the fillet's
            # edge: the nearest node kept along the side stands in (below the active profile,
            # where the strips' weights are zero; docs/faults.md, section 8)
            kept = np.flatnonzero(~absent)
            dofs[absent] = dofs[kept[np.abs(kept[None, :] - np.flatnonzero(absent)[:, None]).argmin(axis=1)]]
        return self._free_of[dofs.ravel()]

    def flank_load(self, k: int, r: float, b: float, side: int = 0) -> NDArray[np.float64]:
        """The unit strip load of tooth ``k`` at involute radius ``r`` (half-width ``b``) on
        :meth:`flank_dofs` of ``side``: :meth:`spurdyn.sector.body.SectorBody.load` on the
        flank alone (on the left flank its mirror image)."""
        local = self.flank_loads(np.array([r]), np.array([b]))[0]
        return (local.reshape(-1, 2) @ self.turn_of(k, side).T).ravel()

    def flank_loads(self, r: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        """``(p, 2 (2 ny + 1))`` unit strip loads at involute radii ``r`` with half-widths
        ``b`` on a flank in tooth 0's frame (:meth:`flank_load` turns them to tooth ``k``)."""
        body = self.body
        w = strip_weights(body.flank, body.flank_coordinate(r), b)
        # the mating flank pushes into the tooth, against the outward normal
        normal = body.gear.flank_normal(np.asarray(r, dtype=float))
        return (-w[:, :, None] * normal[:, None, :]).reshape(w.shape[0], -1)

    def turn_of(self, k: int, side: int = 0) -> NDArray[np.float64]:
        """``(2, 2)`` the map taking a vector at a node of tooth 0's right flank to tooth
        ``k``'s flank ``side``, node by node (``v_k = v_0 @ Q.T``): the turn of
        :func:`spurdyn.mesh.sector.turn`, after, for the left flank, the mirror ``x -> -x``
        across the tooth's centre line (tooth 0 lies along +y)."""
        a = self.body.mesh.tooth_angle(self.tooth(k))
        c, s = math.cos(a), math.sin(a)
        q = np.array([[c, s], [-s, c]])
        return q * np.array([-1.0, 1.0]) if side else q

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


def back_roll_sum(dp: GearPair) -> float:
    """``Sigma = psi_bA + 2 alpha_w`` (rad): the sum of the rolls of one driver tooth's two
    flanks on their lines of action (docs/sector.md, 6.7). The driver's tooth ``k``, whose drive
    flank is at the roll ``rho = rho_start + theta_A + k p``, has its back flank at the roll
    ``Sigma - rho`` on the back line of action (the drive line's mirror image across the line
    of centres), facing the back flank of the driven gear's tooth ``-k + 1``."""
    return 2.0 * dp.gear_a.half_angle_base + 2.0 * dp.working_pressure_angle


def back_teeth(dp: GearPair, cycles: float, reach: float) -> tuple[int, int]:
    """``(lo, hi)``: the driver's teeth whose back flank comes within ``reach`` (rad of roll)
    of the back path of contact over a run of ``cycles`` mesh cycles from the start of a
    cycle, and one more on each side (the transmission error moves the rolls a little)."""
    pitch = 2.0 * math.pi / dp.gear_a.teeth
    sigma = back_roll_sum(dp)
    r0, r1 = dp.start_roll_a, dp.end_roll_a
    hi = int(math.floor((sigma - 2.0 * r0 + reach) / pitch))
    lo = int(math.ceil((sigma - r0 - r1 - reach) / pitch - cycles - 1e-9))
    return lo - 1, hi + 1


def covered_turns(dp: GearPair, drive: tuple[int, int], back: tuple[int, int] | None,
                  reach: float) -> tuple[float, float]:
    """``(theta_lo, theta_hi)``: the driver's turns between which a run's contacts, the drive
    flanks of its teeth ``drive[0] .. drive[1]`` and the back flanks of ``back[0] .. back[1]``,
    hold every tooth near its path (docs/sector.md, 6.8). Drive flank ``k`` is near its path
    for ``theta`` in ``[-reach - k p, rho_end - rho_start + reach - k p]``, a back flank for
    ``[Sigma - rho_start - rho_end - reach - k p, Sigma - 2 rho_start + reach - k p]``: the
    bounds are where the first tooth outside either set comes near."""
    pitch = 2.0 * math.pi / dp.gear_a.teeth
    r0, r1 = dp.start_roll_a, dp.end_roll_a
    hi = -reach - (drive[0] - 1) * pitch
    lo = r1 - r0 + reach - (drive[1] + 1) * pitch
    if back is not None:
        sigma = back_roll_sum(dp)
        hi = min(hi, sigma - r0 - r1 - reach - (back[0] - 1) * pitch)
        lo = max(lo, sigma - 2.0 * r0 + reach - (back[1] + 1) * pitch)
    return lo, hi


def teeth_for(pair: GearPair, cycles: float, back: bool = False,
              teeth: int | None = None) -> tuple[tuple[int, int], tuple[int, int]]:
    """``((first, count), (first, count))`` of the driver's and the driven gear's teeth that
    a run of ``cycles`` mesh cycles needs: every tooth that reaches the path of contact (the
    driver's ``0 .. P-1`` at the start, one more entering behind them each cycle; the driven
    gear's the negatives), with ``back`` every pair of back flanks near the back path
    (:func:`back_teeth`: the driver's ``k`` and the driven gear's ``-k + 1``), and a
    neighbour on each side; a gear's whole ring when that is as many teeth as it has, or the
    run lasts :data:`WHOLE_FROM_CYCLES` cycles or more.

    ``pair`` has the driver as gear A (:func:`~spurdyn.sector.statics.driving_pair`).
    ``teeth`` (``RunSettings.teeth``, ``--teeth K``) asks for ``K`` teeth per gear instead:
    the whole gear where ``K`` reaches its number of teeth, else those needed and the rest
    as further neighbours, one more behind the mesh than ahead of it where they do not
    split evenly.

    Raises
    ------
    InputError
        ``teeth``, fewer than a gear needs (and fewer than it has).
    """
    n_path = pairs_in_path(pair)
    lo_a, hi_a = -int(math.ceil(cycles - 1e-9)) - 1, n_path
    lo_b, hi_b = -hi_a, -lo_a
    if back:
        k_lo, k_hi = back_teeth(pair, cycles, REACH * 2.0 * math.pi / pair.gear_a.teeth)
        lo_a, hi_a = min(lo_a, k_lo - 1), max(hi_a, k_hi + 1)
        lo_b, hi_b = min(lo_b, -k_hi), max(hi_b, -k_lo + 2)
    out = []
    for g, (gear, lo, hi) in enumerate(((pair.gear_a, lo_a, hi_a), (pair.gear_b, lo_b, hi_b))):
        z, need = gear.teeth, hi - lo + 1
        if teeth is None:
            whole = need >= z or cycles >= WHOLE_FROM_CYCLES
        elif teeth >= z:
            whole = True
        elif teeth < need:
            raise InputError("teeth", f"must be at least {need}: the teeth of the "
                             f"{'driver' if g == 0 else 'driven gear'} that a run of "
                             f"{cycles:g} mesh cycles meets, with a neighbour on each side "
                             f"(or {z}, the whole gear; got {teeth})")
        else:
            # the driver's teeth enter from below (lower numbers), the driven gear's from above
            extra = teeth - need
            more, less = extra - extra // 2, extra // 2
            lo, hi = (lo - more, hi + less) if g == 0 else (lo - less, hi + more)
            whole = False
        out.append((-(z // 2), z) if whole else (lo, hi - lo + 1))
    return out[0], out[1]


def gear_block(gear: Gear, sense: float, first: int, count: int, nx: int, ny: int,
               grading: float, missing: frozenset[int] = frozenset(),
               cracked: Mapping[int, Any] | None = None) -> GearBlock:
    """Mesh and assemble the gear's body of ``count`` teeth from tooth ``first``
    (all of them if ``count`` is the gear's number of teeth) and build its block; the body
    teeth of ``missing`` broken off, those of ``cracked`` on their cracked meshes
    (:func:`~spurdyn.sector.body.sector_body`)."""
    count = min(count, gear.teeth)
    body = sector_body(gear, count, nx, ny, first=first, grading=grading, missing=missing, cracked=cracked)
    mesh = body.mesh
    m_full = np.zeros(mesh.n_dof)
    for width in np.unique(mesh.width):
        sel = mesh.width == width
        m_full += assemble_lumped_mass(mesh.nodes, mesh.elements[sel], gear.material, float(width))
    m_full = tied_masses(m_full, mesh.ties, mesh.tie_weights)
    s_full = rotation_field(mesh.nodes, sense)
    j_body = float(s_full @ (m_full * s_full))
    # The gear's whole inertia is the paper model's disk and tooth; what the meshed body
    # does not hold is the hub's (a floor of 1e-3 of it where the body holds more).
    j_whole = gear.disk_inertia + gear.tooth_polar_inertia()
    j_hub = max(j_whole - j_body, 1e-3 * j_whole)
    free = body.free_dofs
    free_of = np.full(mesh.n_dof, -1, dtype=np.intp)
    free_of[free] = np.arange(free.size)
    side_of = np.full(mesh.tooth.n_nodes, -1, dtype=np.intp)
    side_of[body.flank.side_nodes] = np.arange(body.flank.side_nodes.size)
    return GearBlock(body=body, sense=sense, first=first, count=count, mass=m_full[free],
                     rot=s_full[free], inertia=j_hub + j_body, hub_inertia=j_hub,
                     body_inertia=j_body,
                     _free_of=free_of, _side_of=side_of,
                     _left=mirror_nodes(mesh.tooth.nodes, body.flank.side_nodes),
                     missing=frozenset(int(k) for k in missing), cracked=bool(cracked))


def mirror_nodes(nodes: NDArray[np.float64], side: NDArray[np.intp]) -> NDArray[np.intp]:
    """The nodes at the mirror images ``(-x, y)`` of the nodes ``side`` of a tooth mesh whose
    centre line is the y axis (the left flank's nodes of the right flank's, in its order).
    The tooth mesh is symmetric node for node; a mesh that is not is refused."""
    from scipy.spatial import cKDTree

    dist, idx = cKDTree(nodes).query(nodes[side] * np.array([-1.0, 1.0]))
    scale = float(np.abs(nodes).max())
    if dist.max() > 1e-9 * scale:
        raise ValueError(f"the tooth mesh is not symmetric: a flank node's mirror image is "
                         f"{dist.max():.3g} m from the nearest node")
    return idx.astype(np.intp)


#: How far beyond either end of the path of contact (as a fraction of the angular pitch of
#: the driver's roll) a pair is a contact candidate: a tip corner's rigid gap grows with the
#: square of the roll beyond the end (for the paper's pair 0.4 um at 0.003 rad, 150 um at a
#: quarter pitch), far beyond any loaded approach there (docs/sector.md, 6.2).
REACH = 0.25

#: Step (rad of the driver's roll) of the central difference of a pair's rigid gap.
SLOPE_STEP = 1e-6


def total_gaps(dp: GearPair, rho: ArrayLike) -> tuple[NDArray[np.float64], ...]:
    """``(g, r_a, r_b)`` at the driver's rolls ``rho``: the corners' gaps
    (:func:`~spurdyn.geometry.corner.corner_contacts`) and the two tip reliefs at the contact
    radii, and those radii (m), each an array of ``rho``'s shape."""
    g, r_a, r_b = corner_contacts(dp, rho)
    return g + (dp.gear_a.relief_depth(r_a) + dp.gear_b.relief_depth(r_b)), r_a, r_b


def rigid_gaps(dp: GearPair, rho: ArrayLike, side: ArrayLike = 0) -> tuple[NDArray[np.float64], ...]:
    """``(g, dg/drho, r_a, r_b)`` at the driver's rolls ``rho`` (1-D): :func:`rigid_gap` at
    each roll, with ``side`` (a number, or one a roll) choosing each slope's difference.

    Parameters
    ----------
    dp
        The pair, the driver as gear A.
    rho
        ``(n,)`` the driver's rolls (rad).
    side
        0 for a central difference, +1/-1 for one to the right/left.

    Returns
    -------
    g, slope, r_a, r_b
        ``(n,)`` the gaps (m), their slopes (m/rad) and the contact radii (m).
    """
    rho = np.atleast_1d(np.asarray(rho, dtype=float))
    side = np.broadcast_to(np.asarray(side), rho.shape)
    right, left = side >= 0, side <= 0
    # one evaluation at the rolls and at the steps either side that the slopes ask
    every = np.concatenate([rho, rho[right] + SLOPE_STEP, rho[left] - SLOPE_STEP])
    total, r_a, r_b = total_gaps(dp, every)
    n, n_right = rho.size, int(np.count_nonzero(right))
    g = total[:n]
    hi, lo = g.copy(), g.copy()
    hi[right], lo[left] = total[n:n + n_right], total[n + n_right:]
    slope = (hi - lo) / (np.where(side == 0, 2.0, 1.0) * SLOPE_STEP)
    return g, slope, r_a[:n], r_b[:n]


def rigid_gap(dp: GearPair, rho: float, side: int = 0) -> tuple[float, float, float, float]:
    """``(g, dg/drho, r_a, r_b)``: a pair's gap at the kinematic position of the driver's
    roll ``rho`` (a tip corner's off the path, :func:`spurdyn.geometry.corner.corner_contact`,
    plus the two tip reliefs at the contact radii), its slope, and the contact radii. The
    slope enters the pair's row, so that the force does the work the gap's change asks; it
    is a central difference, or with ``side`` +1/-1 one to the right/left (where the slope
    jumps: the path's ends, a relief's start). One roll of :func:`rigid_gaps`."""
    g, slope, r_a, r_b = rigid_gaps(dp, np.array([float(rho)]), side)
    return float(g[0]), float(slope[0]), float(r_a[0]), float(r_b[0])


def contact_radii(dp: GearPair, rolls: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The contact radii on the driver and the driven gear at the driver's rolls."""
    rolls = np.atleast_1d(np.asarray(rolls, dtype=float))
    return (np.atleast_1d(dp.gear_a.radius_at_roll_angle(rolls)),
            np.atleast_1d(dp.gear_b.radius_at_roll_angle(np.asarray(dp.roll_b_from_roll_a(rolls)))))


def half_widths(dp: GearPair, rolls: Any, forces: NDArray[np.float64], estar: float,
                width: float) -> NDArray[np.float64]:
    """Hertz's half-widths of the pairs' forces at the driver's rolls."""
    return half_widths_at(dp, contact_radii(dp, rolls), forces, estar, width)


def half_widths_at(dp: GearPair, radii: tuple[NDArray[np.float64], NDArray[np.float64]],
                    forces: NDArray[np.float64], estar: float, width: float) -> NDArray[np.float64]:
    """Hertz's half-widths of the pairs' forces at the contact radii ``(r_a, r_b)`` (the
    involutes' curvatures there, a tip corner's too)."""
    ra, rb = radii
    rho_a = involute_curvature_radius(np.asarray(ra, dtype=float), dp.gear_a.base_radius)
    rho_b = involute_curvature_radius(np.asarray(rb, dtype=float), dp.gear_b.base_radius)
    return np.atleast_1d(half_width(np.asarray(forces, dtype=float), rho_a, rho_b, estar, width))


#: Points per radian of the driver's roll of a :class:`GapTable` (the tip corner's gap
#: varies as the square of the roll beyond the path; interpolated between points
#: 1e-4 rad apart, its error is below 1e-10 m, docs/sector.md 6.2).
GAP_TABLE_DENSITY = 1e4


@dataclass(frozen=True)
class GapTable:
    """:func:`rigid_gap` tabulated over the driver's rolls: the gap a cubic Hermite
    interpolant of its values and slopes at the points (so that the slope read is the
    interpolant's own derivative), the contact radii linear. The points are evenly spaced
    between breaks (the path's ends, the reliefs' starts), where the slope may jump: a break
    is two points, the left one with the slope from the left, the right one from the right."""

    rho: NDArray[np.float64]
    gap: NDArray[np.float64]
    slope: NDArray[np.float64]
    r_a: NDArray[np.float64]
    r_b: NDArray[np.float64]

    def at(self, rho: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """``(g, dg/drho, r_a, r_b)`` at the rolls ``rho`` (within the table)."""
        x = np.asarray(rho, dtype=float)
        i = np.clip(np.searchsorted(self.rho, x, side="right") - 1, 0, self.rho.size - 2)
        i += self.rho[i + 1] == self.rho[i]         # a break's left point starts no interval
        x0 = self.rho[i]
        h = self.rho[i + 1] - x0
        u = (x - x0) / h
        g0, g1 = self.gap[i], self.gap[i + 1]
        d0, d1 = self.slope[i] * h, self.slope[i + 1] * h
        u2, u3 = u * u, u * u * u
        gap = (2 * u3 - 3 * u2 + 1) * g0 + (u3 - 2 * u2 + u) * d0 + (-2 * u3 + 3 * u2) * g1 + (u3 - u2) * d1
        slope = ((6 * u2 - 6 * u) * g0 + (3 * u2 - 4 * u + 1) * d0 + (-6 * u2 + 6 * u) * g1
                 + (3 * u2 - 2 * u) * d1) / h
        r_a = self.r_a[i] + u * (self.r_a[i + 1] - self.r_a[i])
        r_b = self.r_b[i] + u * (self.r_b[i + 1] - self.r_b[i])
        return gap, slope, r_a, r_b

    def compiled(self) -> GapArrays:
        """The table's twin for the compiled loops (:data:`~spurdyn.sector.packs.GapArrays`)."""
        return GapArrays(self.rho, self.gap, self.slope, self.r_a, self.r_b)


def gap_table(dp: GearPair, reach: float) -> GapTable:
    """:func:`rigid_gap` of ``dp`` tabulated over the driver's rolls of the path of contact
    and ``reach`` (rad) beyond either end, at :data:`GAP_TABLE_DENSITY` points a radian or
    more, with breaks at the path's ends and the reliefs' starts."""
    lo, hi = dp.start_roll_a - reach, dp.end_roll_a + reach
    breaks = {dp.start_roll_a, dp.end_roll_a}
    if dp.gear_a.tip_relief > 0.0 and dp.gear_a.tip_relief_start_roll is not None:
        breaks.add(float(dp.gear_a.tip_relief_start_roll))
    if dp.gear_b.tip_relief > 0.0 and dp.gear_b.tip_relief_start_roll is not None:
        breaks.add((dp.line_of_centres_length - dp.gear_b.tip_relief_start_roll * dp.gear_b.base_radius)
                   / dp.gear_a.base_radius)
    edges = [lo, *sorted(b for b in breaks if lo < b < hi), hi]
    rolls, sides = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        xs = np.linspace(a, b, max(int(math.ceil((b - a) * GAP_TABLE_DENSITY)), 1) + 1)
        # a segment's ends take the slope from inside it (the table's own ends too)
        side = np.zeros(xs.size, dtype=np.intp)
        side[0], side[-1] = 1, -1
        rolls.append(xs)
        sides.append(side)
    rho = np.concatenate(rolls)
    gap, slope, r_a, r_b = rigid_gaps(dp, rho, np.concatenate(sides))
    return GapTable(rho=rho, gap=gap, slope=slope, r_a=r_a, r_b=r_b)


__all__ = ["GAP_TABLE_DENSITY", "GapTable", "GearBlock", "REACH", "SLOPE_STEP", "back_roll_sum", "back_teeth", "contact_radii", "covered_turns",
           "gap_table", "gear_block", "half_widths", "half_widths_at",
           "mirror_nodes", "rigid_gap", "rigid_gaps", "total_gaps", "rotation_field", "teeth_for"]
