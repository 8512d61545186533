"""Loaded tooth contact analysis of the sector model over one mesh cycle (docs/sector.md).

At a position of the mesh cycle the tooth pairs ``j = 0, 1, ...`` that the path of contact
holds touch at the driver's roll angles ``rho_j = rho + j p`` (``p = 2 pi / z``): the pair
``j`` is the driver's tooth ``+j`` (its right flanks lead) and the driven gear's tooth
``-j``. With both hubs held and the driver's hub turned so that its flanks advance by ``e``
along the line of action (the loaded static transmission error), the pairs' normal forces
``F`` satisfy, for the pairs in contact (the active set),

    (C_A + C_B + c_H I) F + g = e,      sum F = W = T / r_b,      F >= 0,

and the pairs out of contact have ``(C F)_j + g_j >= e``. ``C_g`` is each sector's
compliance between the strip loads of all the pairs (the rim couples them), ``c_H`` the
strip's curvature compliance (:func:`spurdyn.contact.hertz.strip_compliance`) and ``g_j``
the pair's unloaded gap along the line of action (the two tip reliefs). The strips'
half-widths follow their forces; a fixed-point iteration on them converges in a few
passes. The mesh stiffness of the position is the tangent one of the active set,
``k = 1^T C_AA^-1 1``; the single-pair stiffness of pair ``j`` is ``1 / C_jj``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from collections.abc import Mapping
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.contact.hertz import effective_modulus, half_width, involute_curvature_radius, strip_compliance
from spurdyn.geometry.pair import GearPair
from spurdyn.model.loading import static_force
from spurdyn.sector.body import SectorBody, sector_body

#: Positions of one mesh cycle (the issue's 41).
DEFAULT_POSITIONS = 41
#: Samples of the cycle in :attr:`MeshCycle.stiffness_mean`.
MEAN_SAMPLES = 4000
#: Relative change of the pair forces between passes that ends the half-width iteration.
FORCE_TOL = 1e-10


def driving_pair(pair: GearPair) -> GearPair:
    """The pair with the driver as gear A (the analysis' frame)."""
    if pair.driver == "a":
        return pair
    return GearPair(gear_a=pair.gear_b, gear_b=pair.gear_a,
                    centre_distance=pair.centre_distance, driver="a")


def pairs_in_path(pair: GearPair) -> int:
    """Most tooth pairs the path of contact holds at once: ``ceil(eps_alpha)``."""
    return int(math.ceil(pair.contact_ratio - 1e-12))


def default_teeth(pair: GearPair) -> int:
    """Teeth per gear by default: every tooth that carries load in a mesh cycle and one
    neighbour on each side, at most the gear's teeth."""
    return min(pairs_in_path(pair) + 2, pair.gear_a.teeth, pair.gear_b.teeth)


@dataclass(frozen=True)
class MeshCycle:
    """The quasi-static mesh cycle of a loaded pair (driver's roll angles, SI).

    Attributes
    ----------
    roll
        ``(n,)`` driver's roll angle of pair 0 at each position (rad), over one pitch.
    force
        ``(n, P)`` normal force of each tooth pair (N; 0 out of contact or off the path).
    transmission_error
        ``(n,)`` loaded static transmission error along the line of action (m): how far the
        driver's flanks advance beyond the rigid kinematics to carry the load.
    stiffness
        ``(n,)`` mesh stiffness ``1^T C_AA^-1 1`` (N/m).
    single_pair
        ``(n, P)`` single-pair stiffness ``1 / C_jj`` of each pair on the path (N/m; NaN off it).
    half_width
        ``(n, P)`` strip half-widths (m).
    load
        ``W``, the total normal force (N).
    torque
        The driver's torque (N m).
    teeth
        Teeth per gear modelled.
    inner_radius
        Hub radii of driver and driven (m).
    n_dof
        DOFs of the two sectors.
    path
        The driver's roll angles at the start and the end of the path of contact (rad).
    """

    roll: NDArray[np.float64]
    force: NDArray[np.float64]
    transmission_error: NDArray[np.float64]
    stiffness: NDArray[np.float64]
    single_pair: NDArray[np.float64]
    half_width: NDArray[np.float64]
    load: float
    torque: float
    teeth: int
    inner_radius: tuple[float, float]
    n_dof: int
    path: tuple[float, float] = (0.0, 0.0)

    @property
    def share(self) -> NDArray[np.float64]:
        """``(n, P)`` each pair's share of the load."""
        return self.force / self.load

    @property
    def pitch(self) -> float:
        """The cycle's span of the driver's roll (rad)."""
        return float(self.roll[-1] - self.roll[0])

    def effective(self, phase: ArrayLike) -> NDArray[np.float64]:
        """``(P, n)`` each pair's effective stiffness ``k_j = (F_j / W) k`` (N/m) at the
        phases ``phase`` (rad of the driver's roll from the start of the path): linear
        between the positions, and zero exactly where the pair is off the path, so that a
        pair's entry and exit are sharp jumps rather than ramps one position wide."""
        phase = np.atleast_1d(np.asarray(phase, dtype=float))
        at = self.roll - self.roll[0]
        on = np.isfinite(self.single_pair)
        k = np.where(on, self.force / self.load * self.stiffness[:, None], 0.0)
        out = np.zeros((k.shape[1], phase.size))
        length = self.path[1] - self.path[0]
        for j in range(k.shape[1]):
            inside = (phase >= -j * self.pitch) & (phase <= length - j * self.pitch)
            if inside.any() and on[:, j].any():
                out[j, inside] = np.interp(phase[inside], at[on[:, j]], k[on[:, j], j])
        return out

    @property
    def stiffness_mean(self) -> float:
        """Mean mesh stiffness over the cycle (N/m), of :meth:`effective` summed over the
        pairs on a fine grid (the sharp entries and exits weighed by where they fall, not
        by the positions either side)."""
        grid = (np.arange(MEAN_SAMPLES) + 0.5) * (self.pitch / MEAN_SAMPLES)
        return float(self.effective(grid).sum(axis=0).mean())

    @property
    def single_pair_max(self) -> float:
        """Largest mesh stiffness where one pair carries the load (N/m): ISO's ``c' b``."""
        one = (self.force > 0).sum(axis=1) == 1
        return float(self.stiffness[one].max()) if one.any() else float("nan")

    @property
    def transmission_error_pp(self) -> float:
        return float(self.transmission_error.max() - self.transmission_error.min())

    def summary(self) -> dict[str, Any]:
        """The figures of ``spurdyn stiffness --json``."""
        return {
            "torque_Nm": self.torque,
            "load_N": self.load,
            "teeth_per_gear": self.teeth,
            "rim_inner_radius_m": list(self.inner_radius),
            "n_dof": self.n_dof,
            "positions": int(self.roll.size),
            "mesh_stiffness_mean_N_per_m": self.stiffness_mean,
            "mesh_stiffness_min_N_per_m": float(self.stiffness.min()),
            "mesh_stiffness_max_N_per_m": float(self.stiffness.max()),
            "single_pair_stiffness_max_N_per_m": self.single_pair_max,
            "transmission_error_mean_m": float(np.mean(self.transmission_error[:-1])),
            "transmission_error_pp_m": self.transmission_error_pp,
            "load_share_max": float(self.share.max()),
        }


def _active_set(c: NDArray[np.float64], g: NDArray[np.float64], w: float,
                coupled: NDArray[np.bool_] | None = None) -> tuple[NDArray[np.float64], float, NDArray[np.bool_]]:
    """Forces ``F >= 0`` and approach ``e`` with ``sum F = w`` over the ``coupled`` rows (the
    pairs; all without it) and ``(C F + g)_j = e`` (pairs) or ``= 0`` (a crack's faces)
    where ``F_j > 0``, ``>=`` elsewhere (the complementarity), by an active-set loop."""
    n = g.size
    on_e = np.ones(n) if coupled is None else np.asarray(coupled, dtype=float)
    active = on_e > 0.0
    for _ in range(4 * n + 4):
        idx = np.flatnonzero(active)
        m = idx.size
        a = np.zeros((m + 1, m + 1))
        a[:m, :m] = c[np.ix_(idx, idx)]
        a[:m, m] = -on_e[idx]
        a[m, :m] = on_e[idx]
        rhs = np.concatenate([-g[idx], [w]])
        sol = np.linalg.solve(a, rhs)
        f = np.zeros(n)
        f[idx] = sol[:m]
        e = float(sol[m])
        if (f[idx] < 0).any():
            active[idx[np.argmin(f[idx])]] = False
            continue
        gap = c @ f + g - e * on_e
        closed = (~active) & (gap < -1e-15 * max(abs(e), 1e-30))
        if closed.any():
            active[np.flatnonzero(closed)[np.argmin(gap[closed])]] = True
            continue
        return f, e, active
    raise RuntimeError("the contact active set did not settle")     # pragma: no cover


def _blocks(body: SectorBody, loads: NDArray[np.float64]) -> NDArray[np.float64]:
    """``[L B]ᵀ K⁻¹ [L B]`` of the contacts' loads ``L`` and the body's crack faces ``B``,
    the faces' responses solved once (:attr:`SectorBody.seam_response`); ``Bᵀ K⁻¹ L`` is
    ``(K⁻¹ B)ᵀ L`` (``K`` symmetric)."""
    u = body.solve(loads)
    if not body.mesh.seams.shape[0]:
        return loads.T @ u
    lb = loads.T @ body.seam_response
    return np.block([[loads.T @ u, lb], [lb.T, body.seam_compliance]])


def _with_seams(body_a: SectorBody, body_b: SectorBody, la: NDArray[np.float64], lb: NDArray[np.float64],
                strip: NDArray[np.float64]) -> NDArray[np.float64]:
    """The compliance of the contacts (columns ``la``, ``lb`` on the two bodies, the strips'
    ``strip`` on the diagonal) and of the cracks' faces of either body after them
    (:attr:`SectorBody.seam_loads`): each body's blocks from its own flexibility."""
    n, sa, sb = la.shape[1], body_a.mesh.seams.shape[0], body_b.mesh.seams.shape[0]
    ca, cb = _blocks(body_a, la), _blocks(body_b, lb)
    c = np.zeros((n + sa + sb, n + sa + sb))
    c[:n, :n] = ca[:n, :n] + cb[:n, :n] + np.diag(strip)
    for cg, faces in ((ca, slice(n, n + sa)), (cb, slice(n + sa, n + sa + sb))):
        c[:n, faces], c[faces, :n], c[faces, faces] = cg[:n, n:], cg[n:, :n], cg[n:, n:]
    return c


@dataclass(frozen=True)
class ContactLaw:
    """What every position shares: the pair (driver as A), the two sectors, the load and
    the strips' law."""

    pair: GearPair
    bodies: tuple[SectorBody, SectorBody]
    load: float
    estar: float
    width: float
    pairs: int

    @property
    def c_h(self) -> float:
        return strip_compliance(self.estar, self.width)


def contact_law(pair: GearPair, torque: float, bodies: tuple[SectorBody, SectorBody]) -> ContactLaw:
    dp = driving_pair(pair)
    ga, gb = dp.gear_a, dp.gear_b
    estar = effective_modulus(ga.material.young, ga.material.poisson, gb.material.young, gb.material.poisson)
    return ContactLaw(dp, bodies, static_force(pair, torque), estar, min(ga.face_width, gb.face_width),
                pairs_in_path(dp))


#: A contact of a tooth pair (docs/faults.md): ``(pair j, its share of the face width, its
#: unloaded gap beyond the pair's own, m)``. A healthy pair is one contact ``(j, 1, 0)``; a
#: spalled flank splits its pair into the intact face and the pit's.
Contact = tuple[int, float, float]
#: Given the pairs on the path and both gears' roll angles at them, their contacts.
Contacts = Callable[[list[int], NDArray[np.float64], NDArray[np.float64]], list[Contact]]


def healthy_contacts(js: list[int], roll_a: NDArray[np.float64], roll_b: NDArray[np.float64]) -> list[Contact]:
    """Every pair one contact over the whole face."""
    return [(j, 1.0, 0.0) for j in js]


def solve_position(law: ContactLaw, rho: float, contacts: Contacts = healthy_contacts,
                   bodies: tuple[SectorBody, SectorBody] | None = None) -> tuple[
        list[int], NDArray[np.float64], float, NDArray[np.float64], NDArray[np.bool_]]:
    """The pairs on the path at the driver's roll ``rho`` of pair 0, their forces, the
    approach ``e``, and the compliance matrix and active set of their ``contacts`` (module
    docstring; one contact per pair unless a fault splits one) and, after them, of the
    bodies' cracks' face pairs (docs/faults.md); ``bodies`` replace the law's (a faulty
    sector)."""
    return _position(law, rho, contacts, bodies)[:5]


def position_displacements(law: ContactLaw, rho: float, contacts: Contacts = healthy_contacts,
                           bodies: tuple[SectorBody, SectorBody] | None = None, faces: bool = True) -> tuple[
        NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], list[int], NDArray[np.float64]]:
    """Both bodies' displacements (m) at one position (:func:`solve_position`): each body's
    ``K⁻¹ (L f + B λ)`` with the contacts' forces ``f`` and its crack's face forces ``λ``
    the complementarity solve found; also the face forces of both bodies (driver's first),
    the pairs on the path and their forces. Without ``faces`` the cracks' faces are left
    free (no contact rows: the solution where no face closes, found without the faces'
    responses; the caller checks the openings, :meth:`SectorBody.openings`)."""
    js, pair_f, _, _, _, full, la, lb = _position(law, rho, contacts, bodies, faces)
    body_a, body_b = law.bodies if bodies is None else bodies
    n, sa = la.shape[1], body_a.mesh.seams.shape[0] if faces else 0
    faces_f = full[n:]
    out = []
    for body, loads, lam in ((body_a, la, faces_f[:sa]), (body_b, lb, faces_f[sa:])):
        u = body.solve(loads @ full[:n]) if n else np.zeros(body.mesh.n_dof)
        out.append(u + body.seam_response @ lam if lam.size else u)
    return out[0], out[1], faces_f, js, pair_f


def _position(law: ContactLaw, rho: float, contacts: Contacts,
              bodies: tuple[SectorBody, SectorBody] | None, faces: bool = True) -> tuple[Any, ...]:
    """:func:`solve_position`'s figures, then the whole force vector (contacts, then the
    faces) and the contacts' load columns on either body; without ``faces`` the cracks'
    faces free."""
    dp, w = law.pair, law.load
    body_a, body_b = law.bodies if bodies is None else bodies
    ga, gb = dp.gear_a, dp.gear_b
    pitch = 2.0 * math.pi / ga.teeth
    js = [j for j in range(law.pairs) if rho + j * pitch <= dp.end_roll_a + 1e-12]
    rolls = np.array([rho + j * pitch for j in js])
    rolls_b = np.asarray(dp.roll_b_from_roll_a(rolls), dtype=float)
    parts = contacts(js, rolls, rolls_b)
    where = [js.index(j) for j, _, _ in parts]
    share = np.array([s for _, s, _ in parts])
    ra = ga.radius_at_roll_angle(rolls)[where]
    rb = gb.radius_at_roll_angle(rolls_b)[where]
    rho_a = np.array([involute_curvature_radius(float(r), ga.base_radius) for r in ra])
    rho_b = np.array([involute_curvature_radius(float(r), gb.base_radius) for r in rb])
    g = np.asarray(ga.relief_depth(ra) + gb.relief_depth(rb), dtype=float) + np.array([x for _, _, x in parts])
    f = w * share / max(share.sum(), 1.0) if parts else np.zeros(0)
    c = np.zeros((0, 0))
    active = np.zeros(0, dtype=bool)
    e = math.nan
    seams = body_a.mesh.seams.shape[0] + body_b.mesh.seams.shape[0] if faces else 0
    coupled = np.arange(len(parts) + seams) < len(parts)
    f_new = np.zeros(len(parts) + seams)
    la = lb = np.zeros((body_a.mesh.n_dof, 0))
    for _ in range(50 if parts else 0):
        b = np.atleast_1d(half_width(f, rho_a, rho_b, law.estar, law.width * share))
        la = np.column_stack([body_a.load(j, float(r), float(bb)) for (j, _, _), r, bb in zip(parts, ra, b)])
        lb = np.column_stack([body_b.load(-j, float(r), float(bb)) for (j, _, _), r, bb in zip(parts, rb, b)])
        if seams:
            c = _with_seams(body_a, body_b, la, lb, law.c_h / share)
        else:
            c = body_a.compliance(la) + body_b.compliance(lb) + np.diag(law.c_h / share)
        c = 0.5 * (c + c.T)            # symmetric to round-off (Maxwell-Betti)
        f_new, e, active = _active_set(c, np.concatenate([g, np.zeros(seams)]), w, coupled)
        done = np.max(np.abs(f_new[:len(parts)] - f)) <= FORCE_TOL * w
        f = f_new[:len(parts)]
        if done:
            break
    pair_f = np.zeros(len(js))
    np.add.at(pair_f, np.asarray(where, dtype=np.intp), f)
    return js, pair_f, e, c, active, f_new, la, lb


def pair_forces_at(pair: GearPair, torque: float, roll: float,
                   bodies: tuple[SectorBody, SectorBody]) -> NDArray[np.float64]:
    """The forces (N) of the pairs ``0, 1, ...`` on the path at the driver's roll angle
    ``roll`` of pair 0 (one position of :func:`mesh_cycle`)."""
    return solve_position(contact_law(pair, torque, bodies), roll)[1]


def sector_firsts(dp: GearPair, teeth: int) -> tuple[int, int]:
    """The first body tooth of the driver's and the driven gear's sectors of ``teeth`` teeth:
    the loaded teeth are the driver's 0 .. n-1 and the driven's 0 .. -(n-1), a neighbour
    either side when the sector has room."""
    n_pairs = pairs_in_path(dp)
    extra = max(teeth - n_pairs, 0)
    before = (extra + 1) // 2
    return -before, -(n_pairs - 1) - (extra - before)


def sector_bodies(dp: GearPair, teeth: int, nx: int, ny: int,
                  inner_radius: tuple[float | None, float | None] = (None, None), grading: float = 1.0,
                  missing: tuple[frozenset[int], frozenset[int]] = (frozenset(), frozenset()),
                  cracked: tuple[Mapping[int, Any], Mapping[int, Any]] = ({}, {})) -> tuple[
        SectorBody, SectorBody]:
    """The two sectors of the driving pair ``dp`` (:func:`sector_firsts`), the body teeth of
    ``missing`` broken off, those of ``cracked`` on their cracked meshes."""
    first_a, first_b = sector_firsts(dp, teeth)
    return (sector_body(dp.gear_a, teeth, nx, ny, first=first_a, inner_radius=inner_radius[0],
                        grading=grading, missing=missing[0], cracked=cracked[0]),
            sector_body(dp.gear_b, teeth, nx, ny, first=first_b, inner_radius=inner_radius[1],
                        grading=grading, missing=missing[1], cracked=cracked[1]))


def mesh_cycle(pair: GearPair, torque: float, nx: int, ny: int, teeth: int | None = None,
               positions: int = DEFAULT_POSITIONS, inner_radius: tuple[float | None, float | None] = (None, None),
               grading: float = 1.0, bodies: tuple[SectorBody, SectorBody] | None = None) -> MeshCycle:
    """The loaded tooth contact analysis of ``pair`` under the driver's ``torque`` (N m) at
    ``positions`` positions over one mesh cycle (module docstring)."""
    dp = driving_pair(pair)
    ga, gb = dp.gear_a, dp.gear_b
    n_pairs = pairs_in_path(dp)
    k_teeth = default_teeth(dp) if teeth is None else int(teeth)
    if bodies is None:
        body_a, body_b = sector_bodies(dp, k_teeth, nx, ny, inner_radius, grading)
    else:
        body_a, body_b = bodies
    law = contact_law(pair, torque, (body_a, body_b))
    pitch = 2.0 * math.pi / ga.teeth
    rolls = dp.start_roll_a + pitch * np.arange(positions) / (positions - 1)
    n = rolls.size
    force = np.zeros((n, n_pairs))
    te = np.zeros(n)
    stiff = np.zeros(n)
    single = np.full((n, n_pairs), np.nan)
    bw = np.zeros((n, n_pairs))
    for i, rho in enumerate(rolls):
        js, f, e, c, active = solve_position(law, float(rho))
        idx = np.flatnonzero(active)
        force[i, js] = f
        te[i] = e
        stiff[i] = float(np.sum(np.linalg.inv(c[np.ix_(idx, idx)])))
        single[i, js] = 1.0 / np.diag(c)
        ra = ga.radius_at_roll_angle(np.array([rho + j * pitch for j in js]))
        rb = gb.radius_at_roll_angle(np.asarray(dp.roll_b_from_roll_a(np.array([rho + j * pitch for j in js]))))
        bw[i, js] = np.atleast_1d(half_width(
            f, [involute_curvature_radius(float(r), ga.base_radius) for r in ra],
            [involute_curvature_radius(float(r), gb.base_radius) for r in rb], law.estar, law.width))
    return MeshCycle(roll=rolls, force=force, transmission_error=te, stiffness=stiff,
                     single_pair=single, half_width=bw, load=law.load, torque=float(torque),
                     teeth=k_teeth, inner_radius=(body_a.mesh.inner_radius, body_b.mesh.inner_radius),
                     n_dof=body_a.mesh.n_dof + body_b.mesh.n_dof,
                     path=(dp.start_roll_a, dp.end_roll_a))


__all__ = ["Contact", "Contacts", "DEFAULT_POSITIONS", "healthy_contacts", "MeshCycle", "default_teeth", "driving_pair", "mesh_cycle",
           "pair_forces_at", "pairs_in_path", "position_displacements", "sector_bodies", "sector_firsts", "solve_position"]
