"""Element matrices and global assembly (the stable time step: :mod:`spurdyn.fem.stable_step`).

All element quantities are evaluated with the 3 x 3 Gauss rule on the Q8
element and vectorised over elements with :func:`numpy.einsum`, so a mesh of
a few thousand nodes assembles in a few milliseconds.

Degrees of freedom are interleaved per node: node ``n`` owns global DOFs
``2 n`` (x) and ``2 n + 1`` (y); an element owns ``[u0x, u0y, u1x, u1y, ...]``.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from spurdyn.fem.element import ElementQuadS2, gauss_2d
from spurdyn.fem.material import Material, plane_stress_matrix

__all__ = [
    "element_stiffness",
    "element_mass",
    "hrz_lump",
    "jacobian_determinants",
    "assemble_stiffness",
    "assemble_lumped_mass",
    "assemble_consistent_mass",
    "element_stress",
    "centroid_stresses",
    "von_mises_plane_stress",
]

_ELEMENT = ElementQuadS2()
_POINTS, _WEIGHTS = gauss_2d(3)
_N = _ELEMENT.shape(_POINTS[:, 0], _POINTS[:, 1])  # (9, 8)
_DN = _ELEMENT.dshape(_POINTS[:, 0], _POINTS[:, 1])  # (9, 8, 2)
_DN_CENTRE = _ELEMENT.dshape(0.0, 0.0)[None]  # (1, 8, 2)


# --------------------------------------------------------------------------
# Kinematics shared by all element routines
# --------------------------------------------------------------------------


def jacobian(
    xy: NDArray[np.float64], dn: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Jacobian matrices and determinants at points.

    ``xy`` is ``(E, 8, 2)``, ``dn`` is ``(G, 8, 2)``; returns ``J (E, G, 2, 2)``
    with ``J[a, b] = d x_b / d xi_a`` and ``det (E, G)``.
    """
    jac = np.einsum("gia,eib->egab", dn, xy)
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    return jac, det


def strain_displacement(
    jac: NDArray[np.float64], det: NDArray[np.float64], dn: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Strain-displacement matrices ``B (E, G, 3, 16)`` from reference derivatives."""
    # Closed-form 2x2 inverse: cheaper and vectorises better than np.linalg.inv.
    inv = np.empty_like(jac)
    inv[..., 0, 0] = jac[..., 1, 1]
    inv[..., 0, 1] = -jac[..., 0, 1]
    inv[..., 1, 0] = -jac[..., 1, 0]
    inv[..., 1, 1] = jac[..., 0, 0]
    inv /= det[..., None, None]
    # dN_i/dx_b = sum_a (J^-1)[b, a] dN_i/dxi_a
    dndx = np.einsum("egba,gia->egib", inv, dn)
    n_el, n_pt = det.shape
    b = np.zeros((n_el, n_pt, 3, 16))
    b[:, :, 0, 0::2] = dndx[..., 0]
    b[:, :, 1, 1::2] = dndx[..., 1]
    b[:, :, 2, 0::2] = dndx[..., 1]
    b[:, :, 2, 1::2] = dndx[..., 0]
    return b


def _check_positive_jacobian(det: NDArray[np.float64], what: str) -> None:
    """Raise if any Jacobian determinant is non-positive (inverted or degenerate)."""
    bad = np.flatnonzero(~(det > 0).all(axis=1))
    if bad.size:
        shown = ", ".join(str(i) for i in bad[:10]) + (", ..." if bad.size > 10 else "")
        raise ValueError(
            f"{what}: Jacobian determinant <= 0 at a Gauss point "
            f"(min {det.min():.3e}) in element(s) {shown}"
        )


def _as_element_xy(xy: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(xy, dtype=float)
    if a.shape != (8, 2):
        raise ValueError(f"xy must have shape (8, 2) (got {a.shape})")
    return a[None]


def as_mesh(
    nodes: ArrayLike, elements: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    nd = np.asarray(nodes, dtype=float)
    el = np.asarray(elements)
    if nd.ndim != 2 or nd.shape[1] != 2:
        raise ValueError(f"nodes must have shape (N, 2) (got {nd.shape})")
    if el.ndim != 2 or el.shape[1] != 8:
        raise ValueError(f"elements must have shape (E, 8) (got {el.shape})")
    if not np.issubdtype(el.dtype, np.integer):
        raise ValueError(f"elements must be integer node indices (got {el.dtype})")
    if el.size and (el.min() < 0 or el.max() >= nd.shape[0]):
        raise ValueError(
            f"elements reference node indices outside [0, {nd.shape[0] - 1}]"
        )
    return nd, el.astype(np.intp, copy=False)


def _check_thickness(thickness: float) -> None:
    if not (thickness > 0 and math.isfinite(thickness)):
        raise ValueError(f"thickness must be > 0 and finite (got {thickness})")


# --------------------------------------------------------------------------
# Batched element matrices (E elements at once)
# --------------------------------------------------------------------------


def _stiffness_batch(
    xy: NDArray[np.float64], d: NDArray[np.float64], thickness: float, what: str
) -> NDArray[np.float64]:
    jac, det = jacobian(xy, _DN)
    _check_positive_jacobian(det, what)
    b = strain_displacement(jac, det, _DN)
    n_el = xy.shape[0]
    db = np.einsum("kl,eglj->egkj", d, b).reshape(n_el, -1, 16)
    wb = (b * (thickness * det * _WEIGHTS)[..., None, None]).reshape(n_el, -1, 16)
    # Sum over Gauss points and stress components as one batched matmul;
    # several times faster than the equivalent three-operand einsum.
    ke = wb.transpose(0, 2, 1) @ db
    # Symmetrise away round-off so downstream symmetric solvers see exact symmetry.
    return 0.5 * (ke + ke.transpose(0, 2, 1))


def _scalar_mass_batch(
    xy: NDArray[np.float64], density: float, thickness: float, what: str
) -> NDArray[np.float64]:
    """Consistent mass for one displacement component, ``(E, 8, 8)``."""
    _, det = jacobian(xy, _DN)
    _check_positive_jacobian(det, what)
    m8 = np.einsum("eg,gi,gj->eij", density * thickness * det * _WEIGHTS, _N, _N)
    return 0.5 * (m8 + m8.transpose(0, 2, 1))


def _expand_to_2d(m8: NDArray[np.float64]) -> NDArray[np.float64]:
    """Place a scalar (8, 8) block on both displacement components -> (16, 16)."""
    out = np.zeros(m8.shape[:-2] + (16, 16))
    out[..., 0::2, 0::2] = m8
    out[..., 1::2, 1::2] = m8
    return out


def _hrz_scalar(m8: NDArray[np.float64]) -> NDArray[np.float64]:
    """HRZ lumping of scalar consistent mass blocks ``(..., 8, 8) -> (..., 8)``."""
    diag = np.diagonal(m8, axis1=-2, axis2=-1)
    total = m8.sum(axis=(-2, -1))
    return diag * (total / diag.sum(axis=-1))[..., None]


def _element_dofs(elements: NDArray[np.intp]) -> NDArray[np.intp]:
    """Global DOF numbers ``(E, 16)`` in the interleaved element order."""
    return np.stack([2 * elements, 2 * elements + 1], axis=-1).reshape(-1, 16)


def _assemble_sparse(
    blocks: NDArray[np.float64], elements: NDArray[np.intp], n_nodes: int
) -> sp.csr_matrix:
    dofs = _element_dofs(elements)
    rows = np.broadcast_to(dofs[:, :, None], blocks.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], blocks.shape).ravel()
    n = 2 * n_nodes
    # COO -> CSR sums the duplicate (shared-node) entries.
    a = sp.coo_matrix((blocks.ravel(), (rows, cols)), shape=(n, n)).tocsr()
    # Duplicates of (i, j) and (j, i) may be summed in different orders; the
    # average makes the result bitwise symmetric for symmetric eigensolvers.
    return ((a + a.T) * 0.5).tocsr()


# --------------------------------------------------------------------------
# Public single-element API
# --------------------------------------------------------------------------


def element_stiffness(
    xy: ArrayLike, d: ArrayLike, thickness: float
) -> NDArray[np.float64]:
    """Stiffness matrix of one Q8 plane-stress element (3 x 3 Gauss).

    Parameters
    ----------
    xy : array_like, shape (8, 2)
        Nodal coordinates [m] in :class:`ElementQuadS2` node order.
    d : array_like, shape (3, 3)
        Constitutive matrix [Pa], e.g. from :func:`plane_stress_matrix`.
    thickness : float
        Out-of-plane thickness [m].

    Returns
    -------
    ndarray, shape (16, 16)
        Symmetric stiffness [N/m], DOF order ``[u0x, u0y, u1x, u1y, ...]``.

    Raises
    ------
    ValueError
        If the Jacobian determinant is <= 0 at any Gauss point.
    """
    _check_thickness(thickness)
    d = np.asarray(d, dtype=float)
    return _stiffness_batch(_as_element_xy(xy), d, thickness, "element_stiffness")[0]


def element_mass(xy: ArrayLike, density: float, thickness: float) -> NDArray[np.float64]:
    """Consistent mass matrix of one Q8 element (3 x 3 Gauss).

    Parameters
    ----------
    xy : array_like, shape (8, 2)
        Nodal coordinates [m].
    density : float
        Mass density [kg/m^3].
    thickness : float
        Out-of-plane thickness [m].

    Returns
    -------
    ndarray, shape (16, 16)
        ``rho t int N^T N dA`` on each displacement component [kg]; x and y
        are uncoupled.
    """
    _check_thickness(thickness)
    m8 = _scalar_mass_batch(_as_element_xy(xy), density, thickness, "element_mass")
    return _expand_to_2d(m8)[0]


def hrz_lump(me: ArrayLike) -> NDArray[np.float64]:
    """Hinton-Rock-Zienkiewicz (HRZ) diagonal lumping of a consistent mass.

    For each displacement direction the diagonal of the consistent mass is
    scaled so that it sums to the element's total mass (the sum of all
    entries of that direction's block).  See ``docs/fem.md``.

    Parameters
    ----------
    me : array_like, shape (16, 16)
        Consistent element mass in interleaved DOF order.

    Returns
    -------
    ndarray, shape (16,)
        Lumped DOF masses [kg]; all positive for a valid Q8 element.
    """
    m = np.asarray(me, dtype=float)
    if m.shape != (16, 16):
        raise ValueError(f"me must have shape (16, 16) (got {m.shape})")
    out = np.empty(16)
    out[0::2] = _hrz_scalar(m[0::2, 0::2])
    out[1::2] = _hrz_scalar(m[1::2, 1::2])
    return out


def element_stress(
    xy: ArrayLike, u_e: ArrayLike, d: ArrayLike
) -> NDArray[np.float64]:
    """Stress at the element centre ``(xi, eta) = (0, 0)``.

    Parameters
    ----------
    xy : array_like, shape (8, 2)
        Nodal coordinates [m].
    u_e : array_like, shape (16,)
        Element displacements [m], interleaved.
    d : array_like, shape (3, 3)
        Constitutive matrix [Pa].

    Returns
    -------
    ndarray, shape (3,)
        ``(sxx, syy, txy)`` [Pa].
    """
    u = np.asarray(u_e, dtype=float)
    if u.shape != (16,):
        raise ValueError(f"u_e must have shape (16,) (got {u.shape})")
    xy3 = _as_element_xy(xy)
    return _centre_stress_batch(xy3, u[None], np.asarray(d, float), "element_stress")[0]


def _centre_stress_batch(
    xy: NDArray[np.float64],
    u: NDArray[np.float64],
    d: NDArray[np.float64],
    what: str,
) -> NDArray[np.float64]:
    jac, det = jacobian(xy, _DN_CENTRE)
    _check_positive_jacobian(det, what)
    b = strain_displacement(jac, det, _DN_CENTRE)[:, 0]  # (E, 3, 16)
    return np.einsum("kl,elj,ej->ek", d, b, u)


def von_mises_plane_stress(sig: ArrayLike) -> NDArray[np.float64]:
    """Von Mises equivalent stress for plane stress.

    Parameters
    ----------
    sig : array_like, shape (..., 3)
        ``(sxx, syy, txy)`` [Pa].

    Returns
    -------
    ndarray, shape (...)
        ``sqrt(sxx^2 - sxx syy + syy^2 + 3 txy^2)`` [Pa].
    """
    s = np.asarray(sig, dtype=float)
    sxx, syy, txy = s[..., 0], s[..., 1], s[..., 2]
    return np.sqrt(sxx**2 - sxx * syy + syy**2 + 3.0 * txy**2)


# --------------------------------------------------------------------------
# Public mesh-level API
# --------------------------------------------------------------------------


def jacobian_determinants(nodes: ArrayLike, elements: ArrayLike) -> NDArray[np.float64]:
    """Jacobian determinants at the 3 x 3 Gauss points of every element.

    Parameters
    ----------
    nodes : array_like, shape (N, 2)
        Node coordinates [m].
    elements : array_like of int, shape (E, 8)
        Connectivity in :class:`ElementQuadS2` node order.

    Returns
    -------
    ndarray, shape (E, 9)
        ``det J`` [m^2 per unit reference area] at the points of
        :func:`gauss_2d` ``(3)`` (``xi`` varying fastest).  Non-positive
        values flag inverted or degenerate elements; no error is raised here.
    """
    nd, el = as_mesh(nodes, elements)
    return jacobian(nd[el], _DN)[1]


def assemble_stiffness(
    nodes: ArrayLike, elements: ArrayLike, material: Material, thickness: float
) -> sp.csr_matrix:
    """Global plane-stress stiffness matrix.

    Parameters
    ----------
    nodes : array_like, shape (N, 2)
        Node coordinates [m].
    elements : array_like of int, shape (E, 8)
        Q8 connectivity.
    material : Material
        Elastic constants.
    thickness : float
        Out-of-plane thickness [m].

    Returns
    -------
    scipy.sparse.csr_matrix, shape (2N, 2N)
        Symmetric stiffness [N/m], DOFs interleaved per node.

    Raises
    ------
    ValueError
        If any element has a Jacobian determinant <= 0 at a Gauss point.
    """
    _check_thickness(thickness)
    nd, el = as_mesh(nodes, elements)
    d = plane_stress_matrix(material)
    ke = _stiffness_batch(nd[el], d, thickness, "assemble_stiffness")
    return _assemble_sparse(ke, el, nd.shape[0])


def assemble_consistent_mass(
    nodes: ArrayLike, elements: ArrayLike, material: Material, thickness: float
) -> sp.csr_matrix:
    """Global consistent mass matrix.

    Parameters
    ----------
    nodes, elements, material, thickness
        As for :func:`assemble_stiffness`.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (2N, 2N)
        Symmetric positive-definite mass [kg].
    """
    _check_thickness(thickness)
    nd, el = as_mesh(nodes, elements)
    m8 = _scalar_mass_batch(nd[el], material.density, thickness, "assemble_consistent_mass")
    return _assemble_sparse(_expand_to_2d(m8), el, nd.shape[0])


def assemble_lumped_mass(
    nodes: ArrayLike, elements: ArrayLike, material: Material, thickness: float
) -> NDArray[np.float64]:
    """Global HRZ-lumped (diagonal) mass.

    Parameters
    ----------
    nodes, elements, material, thickness
        As for :func:`assemble_stiffness`.

    Returns
    -------
    ndarray, shape (2N,)
        DOF masses [kg], interleaved; each direction sums to
        ``density * thickness * area``.  Nodes not used by any element get 0.
    """
    _check_thickness(thickness)
    nd, el = as_mesh(nodes, elements)
    m8 = _scalar_mass_batch(nd[el], material.density, thickness, "assemble_lumped_mass")
    node_mass = np.bincount(el.ravel(), weights=_hrz_scalar(m8).ravel(), minlength=nd.shape[0])
    # Lumped mass is the same for x and y, so interleave one nodal array twice.
    return np.repeat(node_mass, 2)


def centroid_stresses(
    nodes: ArrayLike, elements: ArrayLike, u: ArrayLike, material: Material
) -> NDArray[np.float64]:
    """Stress at the centre of every element (vectorised :func:`element_stress`).

    Parameters
    ----------
    nodes : array_like, shape (N, 2)
        Node coordinates [m].
    elements : array_like of int, shape (E, 8)
        Q8 connectivity.
    u : array_like, shape (2N,)
        Global displacement vector [m], interleaved.
    material : Material
        Elastic constants (plane stress).

    Returns
    -------
    ndarray, shape (E, 3)
        ``(sxx, syy, txy)`` [Pa] at each element centre.
    """
    nd, el = as_mesh(nodes, elements)
    uu = np.asarray(u, dtype=float)
    if uu.shape != (2 * nd.shape[0],):
        raise ValueError(f"u must have shape ({2 * nd.shape[0]},) (got {uu.shape})")
    d = plane_stress_matrix(material)
    return _centre_stress_batch(nd[el], uu[_element_dofs(el)], d, "centroid_stresses")
