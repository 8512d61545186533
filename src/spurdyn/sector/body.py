"""One gear of the sector model: K teeth on their rim, the hub held (docs/sector.md).

The stiffness is assembled once over the sector mesh (:mod:`spurdyn.mesh.sector`) and
factorised (when first solved with) with the hub's DOFs removed; a contact's load is the unit normal force spread
over its Hertzian strip on the right flank of tooth ``k`` through the same strip-averaged
shape functions as the paper model's distributed contact
(:func:`spurdyn.contact.strip_numpy.strip_rows`), so a tooth of the sector is loaded
exactly as the paper model's single tooth is.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_stiffness
from spurdyn.fem.factor import factor_spd
from spurdyn.geometry.gear import Gear
from spurdyn.mesh.sector import SectorMesh, cell_mesh, sector_mesh, turn
from spurdyn.mesh.tooth import DEFAULT_GRADING, ToothMesh
from spurdyn.model.flank import Flank, make_flank


@dataclass(frozen=True)
class SectorBody:
    """A gear sector ready for static analysis.

    Attributes
    ----------
    gear
        The gear.
    mesh
        Its sector mesh.
    flank
        The right flank of the single-tooth mesh in the tooth's own frame (strip rows).
    """

    gear: Gear
    mesh: SectorMesh
    flank: Flank
    _free: NDArray[np.intp] = field(repr=False)

    # Assembled and factorised when first asked for: a whole gear reduced by its harmonics
    # (spurdyn.sector.cyclic) never is, which saves the ring's assembly and its memory.
    @cached_property
    def stiffness(self) -> sp.csr_matrix:
        """``(2N, 2N)`` plane-stress stiffness (N/m)."""
        mesh = self.mesh
        k = sp.csr_matrix((mesh.n_dof, mesh.n_dof))
        for width in np.unique(mesh.width):
            sel = mesh.width == width
            k = k + assemble_stiffness(mesh.nodes, mesh.elements[sel], self.gear.material, float(width)).tocsr()
        return k

    @cached_property
    def ties(self) -> sp.csr_matrix | None:
        """``T`` with ``u = T u`` where a node is tied to an edge (``SectorMesh.ties``: a
        cracked cell's nodes on its neighbours' edges): their rows the edge's shape
        functions, their columns empty; ``None`` without ties."""
        ties, w = self.mesh.ties, self.mesh.tie_weights
        if not ties.size:
            return None
        n = self.mesh.n_dof
        tied = np.concatenate([2 * ties[:, 0], 2 * ties[:, 0] + 1])
        keep = np.setdiff1d(np.arange(n), tied)
        rows = np.concatenate([keep] + [2 * ties[:, 0] + a for a in (0, 1) for _ in range(3)])
        cols = np.concatenate([keep] + [2 * ties[:, 1 + e] + a for a in (0, 1) for e in range(3)])
        vals = np.concatenate([np.ones(keep.size)] + [w[:, e] for _ in (0, 1) for e in range(3)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    @cached_property
    def free_stiffness(self) -> sp.csr_matrix:
        """``(n, n)`` the stiffness of the free DOFs (:attr:`free_dofs`), hub held (and the
        tied nodes moving with their edges: ``Tᵀ K T``)."""
        k = self.stiffness if self.ties is None else (self.ties.T @ self.stiffness @ self.ties)
        return k[self._free][:, self._free].tocsr()

    @cached_property
    def _lu(self) -> object:
        return factor_spd(self.free_stiffness)

    def flank_coordinate(self, r: float) -> float:
        """Flank coordinate ``t`` of the involute point of radius ``r``."""
        f = self.flank
        return f.ny * (r - f.r0) / (f.r_tip - f.r0)

    def load(self, k: int, r: float, b: float) -> NDArray[np.float64]:
        """Nodal forces of a unit normal force pressing on the right flank of tooth ``k`` at
        involute radius ``r``, spread over the strip of half-width ``b`` (m; 0: a point)."""
        nodes, w, _ = strip_rows(self.flank, self.flank_coordinate(r), b)
        normal = self.gear.flank_normal(np.asarray(r))
        local = np.zeros((self.mesh.tooth.n_nodes, 2))
        # the mating flank pushes into the tooth, against the outward normal
        np.add.at(local, nodes, -w[:, None] * normal[None, :])
        f = np.zeros(self.mesh.n_dof)
        dofs, values = self.mesh.tooth_dofs(k), turn(local, self.mesh.tooth_angle(k)).ravel()
        absent = dofs < 0           # a cracked tooth's mesh has no node where its mouth splits an edge
        if np.any(values[absent] != 0.0):
            raise InputError("fault", f"a crack on tooth {k} opens on the flank's edge a contact loads "
                             f"({r * 1e3:.4g} mm) on this mesh: give a finer mesh (--mesh) or a lower start_radius")
        np.add.at(f, dofs[~absent], values[~absent])   # a chipped flank's cut node stands in for several
        return f

    @cached_property
    def seam_loads(self) -> NDArray[np.float64]:
        """``(2N, S)`` the nodal forces of a unit compressive force between each pair of a
        crack's faces: along the normal on face two, against it on face one. Its transpose
        maps displacements to the faces' openings (docs/faults.md)."""
        seams, normals = self.mesh.seams, self.mesh.seam_normals
        b = np.zeros((self.mesh.n_dof, seams.shape[0]))
        cols = np.arange(seams.shape[0])
        for face, sign in ((1, 1.0), (0, -1.0)):
            for axis in (0, 1):
                b[2 * seams[:, face] + axis, cols] = sign * normals[:, axis]
        return b

    @cached_property
    def seam_response(self) -> NDArray[np.float64]:
        """``K⁻¹ B``: the displacements under the unit compressions of :attr:`seam_loads`,
        solved once (the crack's blocks of the contact problem do not change with the
        position)."""
        return self.solve(self.seam_loads)

    @cached_property
    def seam_compliance(self) -> NDArray[np.float64]:
        """``Bᵀ K⁻¹ B``: the faces' openings under their unit compressions."""
        return self.openings(self.seam_response)

    def openings(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """``Bᵀ u``: the cracks' openings ``n · (u_two - u_one)`` (m) at their twin pairs
        under the displacements ``u`` (columns allowed) (:attr:`seam_loads`)."""
        seams, normals = self.mesh.seams, self.mesh.seam_normals
        uu = np.asarray(u, dtype=float).reshape(self.mesh.n_nodes, 2, -1)
        jump = uu[seams[:, 1]] - uu[seams[:, 0]]                # (S, 2, k)
        out = np.einsum("sa,sak->sk", normals, jump)
        return out[:, 0] if np.ndim(u) == 1 else out

    def solve(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """Displacements (m) under the nodal forces ``f`` (columns allowed), the hub held."""
        f = np.asarray(f, dtype=float)
        if self.ties is not None:
            u = np.zeros_like(f)
            u[self._free] = self._lu.solve(np.ascontiguousarray((self.ties.T @ f)[self._free]))
            return self.ties @ u
        u = np.zeros_like(f)
        u[self._free] = self._lu.solve(np.ascontiguousarray(f[self._free]))
        return u

    @property
    def free_dofs(self) -> NDArray[np.intp]:
        """The DOFs not held by the hub, in the order :meth:`solve_free` takes them."""
        return self._free

    def solve_free(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """Displacements (m) of the free DOFs under forces ``f`` on them (columns allowed),
        the hub held: :meth:`solve` without the held DOFs."""
        return self._lu.solve(np.ascontiguousarray(f))

    def compliance(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        """``C = F^T K^-1 F`` (m/N) for the load columns ``F``: each load's work-conjugate
        displacement under each other load."""
        return loads.T @ self.solve(loads)


def _hub_and_web(gear: Gear, inner_radius: float | None) -> tuple[float | None, tuple[float, float] | None]:
    """A webbed blank puts the hub at its ``hub_radius`` and a web of its width below its
    ``rim_radius``: ``(inner_radius, web)`` for :func:`~spurdyn.mesh.sector.sector_mesh`."""
    blank = gear.blank
    web = (blank.rim_radius, blank.web_width) if blank is not None and blank.webbed else None
    if inner_radius is None and web is not None:
        inner_radius = blank.hub_radius
    return inner_radius, web


def body_cell(gear: Gear, nx: int, ny: int, grading: float = DEFAULT_GRADING,
              inner_radius: float | None = None) -> ToothMesh:
    """Tooth 0's cell of :func:`sector_body`'s mesh (:func:`~spurdyn.mesh.sector.cell_mesh`):
    where a root crack runs and what a cracked cell is meshed from."""
    inner_radius, web = _hub_and_web(gear, inner_radius)
    return cell_mesh(gear, nx, ny, inner_radius, grading, web=web)


def sector_body(gear: Gear, teeth: int, nx: int, ny: int, first: int | None = None,
                inner_radius: float | None = None, grading: float = DEFAULT_GRADING,
                full_rim: bool = True, missing: frozenset[int] = frozenset(),
                cracked: Mapping[int, Any] | None = None) -> SectorBody:
    """Mesh and assemble ``teeth`` teeth of ``gear`` from tooth ``first`` (on the
    full rim, or with the rim cut at free radial faces: :func:`spurdyn.mesh.sector.sector_mesh`),
    the teeth of ``missing`` broken off at their root, those of ``cracked`` on their cracked
    meshes.
    A webbed blank puts the hub at its ``hub_radius`` and a web of its width below its
    ``rim_radius``."""
    inner_radius, web = _hub_and_web(gear, inner_radius)
    mesh = sector_mesh(gear, teeth, nx, ny, inner_radius, grading, first=first, web=web,
                       full_rim=full_rim, missing=missing, cracked=cracked)
    # held: the hub's DOFs and the tied nodes' (they follow their edges)
    hub = np.concatenate([2 * mesh.hub_nodes, 2 * mesh.hub_nodes + 1, 2 * mesh.ties[:, 0], 2 * mesh.ties[:, 0] + 1])
    free = np.setdiff1d(np.arange(mesh.n_dof), hub)
    tooth = mesh.tooth
    flank = make_flank(tooth, gear, tooth.nodes, np.zeros(2), 0.0, 5)
    return SectorBody(gear=gear, mesh=mesh, flank=flank, _free=free)


def tied_masses(m_full: NDArray[np.float64], ties: NDArray[np.intp],
                 weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """The lumped masses with a tied node's (held: it follows its edge, ``u_t = sum w_j
    u_j``) moved to its edge's three nodes: the diagonal of ``T^T M T`` scaled to the tied
    mass (``m_t w_j^2 / sum w^2``, positive where a quadratic edge's weights are not; the
    total mass kept)."""
    if not ties.size:
        return m_full
    out = m_full.copy()
    share = weights**2 / np.sum(weights**2, axis=1, keepdims=True)
    for axis in (0, 1):
        for e in range(3):
            np.add.at(out, 2 * ties[:, 1 + e] + axis, m_full[2 * ties[:, 0] + axis] * share[:, e])
        out[2 * ties[:, 0] + axis] = 0.0
    return out


__all__ = ["SectorBody", "body_cell", "sector_body", "tied_masses"]
