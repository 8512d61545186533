"""The fillets of a tooth and the stress along them (``docs/stress.md``).

A :class:`RootSurface` holds the outline nodes of both fillets of a tooth mesh, from the
mesh's bottom up to the form radius where the involute begins, and the linear map from
the tooth's displacements to the stress along that surface
(:func:`spurdyn.fem.recovery.surface_stress_operator`). The surface is free, so the stress
along it is its only stress: where it pulls it is the largest principal stress, the one a
tooth breaks by; where it presses, the smallest.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.fem.material import Material
from spurdyn.fem.recovery import outline_tangents, surface_stress_columns, tangential_stress
from spurdyn.mesh.tooth import ToothMesh


@dataclass(frozen=True)
class RootSurface:
    """Both fillets of one tooth mesh and the stress operator along them.

    Attributes
    ----------
    nodes
        Outline nodes of the right fillet (root to form radius), then the left.
    side
        0 for a node of the right outline (``x > 0`` in the gear frame), 1 for the left.
    radius
        Distance of each node from the gear centre (m).
    tangents
        Unit tangents of the outline at the nodes, in the frame of ``positions``.
    operator, dofs
        ``operator @ u[dofs]`` (``(n, 3)``) are the plane stresses at the nodes from the
        tooth's displacements ``u`` (only the DOFs of the elements along the fillets).
    """

    nodes: NDArray[np.intp]
    side: NDArray[np.int8]
    radius: NDArray[np.float64]
    tangents: NDArray[np.float64]
    operator: NDArray[np.float64]
    dofs: NDArray[np.intp]

    def stress(self, u: ArrayLike) -> NDArray[np.float64]:
        """Stress along the surface (Pa, tension positive) for displacements ``u`` of shape
        ``(2 N,)`` or ``(k, 2 N)`` (in the frame of the tangents): ``(n,)`` or ``(k, n)``."""
        sig = np.einsum("ncj,...j->...nc", self.operator, np.asarray(u, dtype=float)[..., self.dofs])
        return tangential_stress(sig, self.tangents)


def fillet_nodes(mesh: ToothMesh, form_radius: float) -> tuple[NDArray[np.intp], NDArray[np.int8]]:
    """Outline nodes below ``form_radius`` on the right outline then the left (each root
    upward), and the side of each (0 right, 1 left)."""
    out, side = [], []
    for k, nodes in enumerate((mesh.right_side, mesh.left_side)):
        r = np.hypot(mesh.nodes[nodes, 0], mesh.nodes[nodes, 1])
        keep = nodes[r < form_radius]
        out.append(keep)
        side.append(np.full(keep.size, k, dtype=np.int8))
    return np.concatenate(out), np.concatenate(side)


def root_surface(mesh: ToothMesh, form_radius: float, material: Material,
                 positions: ArrayLike | None = None) -> RootSurface:
    """The :class:`RootSurface` of ``mesh`` (gear frame) whose displacements are given in
    the frame of ``positions`` (the node positions there; default the mesh's own)."""
    xy = mesh.nodes if positions is None else np.asarray(positions, dtype=float)
    nodes, side = fillet_nodes(mesh, form_radius)
    if nodes.size < 2 * 2:
        raise ValueError("the mesh has fewer than two fillet nodes on a side")
    tangents = np.concatenate([outline_tangents(xy[nodes[side == k]]) for k in (0, 1)])
    operator, dofs = surface_stress_columns(xy, mesh.elements, nodes, material)
    return RootSurface(nodes=nodes, side=side,
                       radius=np.hypot(mesh.nodes[nodes, 0], mesh.nodes[nodes, 1]),
                       tangents=tangents, operator=operator, dofs=dofs)


def peaks(stress: ArrayLike, radius: ArrayLike) -> tuple[NDArray[np.float64], ...]:
    """Per row of ``stress`` (``(k, n)``): the largest stress and the radius where it is, the
    smallest and its radius. Rows without a finite value give NaN."""
    s = np.atleast_2d(np.asarray(stress, dtype=float))
    r = np.asarray(radius, dtype=float)
    rows = np.arange(s.shape[0])
    if np.isfinite(s).all():    # a run's kept samples: the same numbers without the masks (half the time)
        i_hi, i_lo = s.argmax(axis=1), s.argmin(axis=1)
        return s[rows, i_hi], r[i_hi], s[rows, i_lo], r[i_lo]
    finite = np.isfinite(s).any(axis=1)
    hi = np.where(np.isfinite(s), s, -np.inf)
    lo = np.where(np.isfinite(s), s, np.inf)
    i_hi, i_lo = hi.argmax(axis=1), lo.argmin(axis=1)
    nan = np.full(s.shape[0], np.nan)
    return (np.where(finite, hi[rows, i_hi], nan), np.where(finite, r[i_hi], nan),
            np.where(finite, lo[rows, i_lo], nan), np.where(finite, r[i_lo], nan))


__all__ = ["RootSurface", "fillet_nodes", "peaks", "root_surface"]
