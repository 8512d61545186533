"""The interaction integral (Yau, Wang & Corten 1980) in the domain form of Moran & Shih (1987)
on Q8 meshes: K_I and K_II at a crack tip from a plane-stress displacement field.

docs/fracture.md, sections 2 to 4, has the derivation. In the tip's frame (``x1`` ahead of the
crack), with the field ``1`` the finite elements' and ``2`` a unit mode's near-tip field
(:mod:`spurdyn.fracture.williams`),

    I = int_A [s_ij u2_i,1 + s2_ij u_i,1 - s_ik e2_ik delta_1j] q,j dA = 2 K_m / E'

where ``q`` is 1 at the tip and 0 on the domain's outer edge. ``q`` is 1 on the nodes of the
first ``d`` rings of elements around the tip and 0 elsewhere, interpolated by the elements'
shape functions, so only ring ``d + 1`` carries ``q,j``: the tip's own elements, where the
field is least accurate, are never integrated. Where the elements' width varies (a web), ``q``
is 0 on every node of an element whose width is not the tip's, so each domain lies in one
width, where the domain form holds (docs/fracture.md, section 8.7).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import as_mesh, jacobian, strain_displacement
from spurdyn.fem.element import ElementQuadS2, gauss_2d
from spurdyn.fem.material import Material, plane_stress_matrix
from spurdyn.fracture.williams import MODES, effective_modulus, williams_fields
from spurdyn.mesh.gmsh_quads import boundary_edges

__all__ = ["DEFAULT_RINGS", "TipFactors", "element_rings", "stress_intensity"]

#: The domains by default: ``q = 1`` on the first 2 and 3 rings of elements around the tip.
DEFAULT_RINGS = (2, 3)

_ELEMENT = ElementQuadS2()
_POINTS, _WEIGHTS = gauss_2d(3)
_N = _ELEMENT.shape(_POINTS[:, 0], _POINTS[:, 1])      # (9, 8)
_DN = _ELEMENT.dshape(_POINTS[:, 0], _POINTS[:, 1])    # (9, 8, 2)


@dataclass(frozen=True)
class TipFactors:
    """The stress intensity factors at one tip, one value per domain.

    Attributes
    ----------
    rings
        ``(R,)`` the domains: ``q = 1`` on the nodes of this many rings of elements.
    k_i, k_ii
        ``(R,)`` K_I and K_II (Pa sqrt(m)) of each domain.
    radius
        ``(R,)`` the largest distance from the tip of a node with ``q = 1`` (m).
    """

    rings: NDArray[np.intp]
    k_i: NDArray[np.float64]
    k_ii: NDArray[np.float64]
    radius: NDArray[np.float64]


def element_rings(elements: NDArray[np.intp], tip: int, count: int) -> NDArray[np.intp]:
    """Each element's ring around node ``tip``: 1 for the elements holding it, ``k + 1`` for
    those sharing a node with ring ``k`` and in none before; 0 beyond ring ``count``."""
    ring = np.zeros(elements.shape[0], dtype=np.intp)
    reached = np.zeros(int(elements.max()) + 1, dtype=bool)
    reached[tip] = True
    for k in range(1, count + 1):
        new = (ring == 0) & reached[elements].any(axis=1)
        ring[new] = k
        reached[elements[new].ravel()] = True
    return ring


def _frame(ahead: ArrayLike) -> NDArray[np.float64]:
    """The rotation ``R`` whose rows are the tip frame's axes: ``x_local = R x_global``."""
    a = np.asarray(ahead, dtype=float)
    if a.shape != (2,) or not np.all(np.isfinite(a)) or not np.hypot(*a) > 0.0:
        raise InputError("ahead", f"must be a non-zero vector (2,) along the crack (got {a!r})")
    c, s = a / np.hypot(*a)
    return np.array([[c, s], [-s, c]])


def _check_inside(nodes: NDArray[np.float64], elements: NDArray[np.intp], inner: NDArray[np.bool_],
                  tip: int, rot: NDArray[np.float64], rings: int) -> None:
    """Refuse a domain whose ``q = 1`` reaches the outline off the crack's faces (a loaded or
    free edge there adds a term the domain form leaves out)."""
    edge = np.unique(boundary_edges(elements))
    local = (nodes[edge] - nodes[tip]) @ rot.T
    size = float(np.ptp(nodes, axis=0).max())
    on_faces = (np.abs(local[:, 1]) < 1e-9 * size) & (local[:, 0] < 1e-9 * size)
    if np.any(inner[edge] & ~on_faces):
        raise InputError("rings", f"the domain of {rings} rings of elements reaches the "
                         "outline; give fewer rings or a finer mesh at the tip")


def _ring_integral(xy: NDArray[np.float64], ue: NDArray[np.float64], qe: NDArray[np.float64],
                   tip_xy: NDArray[np.float64], rot: NDArray[np.float64], material: Material
                   ) -> NDArray[np.float64]:
    """``I`` of both modes over the elements ``xy`` (E, 8, 2) with displacements ``ue``
    (E, 8, 2) and nodal ``q`` ``qe`` (E, 8), in the tip's frame."""
    jac, det = jacobian(xy, _DN)
    b = strain_displacement(jac, det, _DN)                 # (E, G, 3, 16)
    dndx = np.stack([b[:, :, 0, 0::2], b[:, :, 1, 1::2]], axis=-1)   # (E, G, 8, 2)
    # the field's and q's gradients turned into the tip's frame: G' = R G R^T, q' = R q
    grad = rot @ np.einsum("egnj,eni->egij", dndx, ue) @ rot.T
    dq = np.einsum("egnj,en->egj", dndx, qe) @ rot.T
    eps = np.stack([grad[..., 0, 0], grad[..., 1, 1], grad[..., 0, 1] + grad[..., 1, 0]], -1)
    s = eps @ plane_stress_matrix(material).T              # isotropic: D of the turned strain
    sig = np.stack([np.stack([s[..., 0], s[..., 2]], -1), np.stack([s[..., 2], s[..., 1]], -1)], -2)
    x = (np.einsum("gn,enk->egk", _N, xy) - tip_xy) @ rot.T
    weight = det * _WEIGHTS
    out = np.empty(len(MODES))
    for m, mode in enumerate(MODES):
        _, grad2, s2 = williams_fields(x, mode, material)
        sig2 = np.stack([np.stack([s2[..., 0], s2[..., 2]], -1),
                         np.stack([s2[..., 2], s2[..., 1]], -1)], -2)
        w12 = np.einsum("egij,egij->eg", sig, grad2)        # s_ij u2_i,j = s_ij e2_ij
        flux = (np.einsum("egij,egi->egj", sig, grad2[..., 0])
                + np.einsum("egij,egi->egj", sig2, grad[..., 0]))
        flux[..., 0] -= w12
        out[m] = np.sum(np.einsum("egj,egj->eg", flux, dq) * weight)
    return out


def _other_width(elements: NDArray[np.intp], tip: int, widths: ArrayLike | None,
                 n_nodes: int) -> NDArray[np.bool_]:
    """The nodes of elements whose width is not that of the tip's elements (none without
    ``widths``); refused if the tip's own elements differ in width."""
    other = np.zeros(n_nodes, dtype=bool)
    if widths is None:
        return other
    w = np.asarray(widths, dtype=float)
    if w.shape != (elements.shape[0],):
        raise ValueError(f"widths must have one value an element ({elements.shape[0]}, got {w.shape})")
    own = np.unique(w[(elements == tip).any(axis=1)])
    if own.size != 1:
        raise InputError("rings", "the crack's tip lies on a change of width; the domain "
                         "form needs one width round the tip")
    other[elements[w != own[0]].ravel()] = True
    return other


def stress_intensity(nodes: ArrayLike, elements: ArrayLike, u: ArrayLike, material: Material,
                     tip: int, ahead: ArrayLike, rings: tuple[int, ...] = DEFAULT_RINGS,
                     widths: ArrayLike | None = None) -> TipFactors:
    """K_I and K_II at a crack tip by the interaction integral, one value per domain.

    Parameters
    ----------
    nodes, elements
        The Q8 mesh (m): ``(N, 2)`` and ``(E, 8)``, the crack's faces apart (twin nodes on a
        seam, :func:`spurdyn.mesh.cracked.split_seam`), the tip one node.
    u
        ``(2 N,)`` the displacements (m), interleaved, of a plane-stress solution with
        traction-free crack faces and no load inside the domains.
    material
        Elastic constants.
    tip
        The tip's node.
    ahead
        ``(2,)`` the direction the crack would run on (from the crack into the material).
    rings
        The domains: ``q = 1`` on the nodes of the first ``k`` rings of elements for each ``k``.
    widths
        ``(E,)`` each element's out-of-plane width (m) where it varies (a web): ``q`` is then
        0 on every node of an element whose width is not the tip's, so each domain stays in
        the tip's width, where the domain form holds (docs/fracture.md, section 8.7).

    Returns
    -------
    TipFactors

    Raises
    ------
    InputError
        ``ahead`` for a zero vector, ``rings`` for a ring count below 1 or a domain reaching
        the outline off the crack's faces.
    """
    nd, el = as_mesh(nodes, elements)
    uu = np.asarray(u, dtype=float).reshape(-1, 2)
    if uu.shape != nd.shape:
        raise ValueError(f"u must have {2 * nd.shape[0]} values (got {uu.size})")
    rot = _frame(ahead)
    wanted = np.asarray(rings, dtype=np.intp)
    if wanted.ndim != 1 or wanted.size == 0 or wanted.min() < 1:
        raise InputError("rings", f"must be ring counts of at least 1 (got {rings!r})")
    ring = element_rings(el, tip, int(wanted.max()) + 1)
    other = _other_width(el, tip, widths, nd.shape[0])
    values, radius = [], []
    for d in wanted:
        inner = np.zeros(nd.shape[0], dtype=bool)
        inner[el[(ring >= 1) & (ring <= d)].ravel()] = True
        inner &= ~other
        _check_inside(nd, el, inner, tip, rot, int(d))
        # q varies only in the elements holding nodes of both kinds: ring d + 1, and where
        # a width changes, the elements of the tip's width beside the change
        q = inner[el]
        band = el[(ring >= 1) & q.any(axis=1) & ~q.all(axis=1)]
        values.append(_ring_integral(nd[band], uu[band], inner[band].astype(float), nd[tip],
                                     rot, material))
        radius.append(float(np.max(np.hypot(*(nd[inner] - nd[tip]).T))))
    k = 0.5 * effective_modulus(material) * np.array(values)
    return TipFactors(rings=wanted, k_i=k[:, 0], k_ii=k[:, 1], radius=np.array(radius))
