"""Stress recovered at surface nodes of a Q8 mesh, as a linear map of the displacements.

The stress of a Q8 element is most accurate at its 2 x 2 Gauss (Barlow) points; it is
evaluated there and extrapolated bilinearly to the element's nodes, and the values of the
elements that share a node are averaged (``docs/stress.md`` derives it and says why it
was chosen over evaluating the element's own field at the node). For given surface nodes
that is a fixed matrix ``R`` (:func:`surface_stress_operator`): ``sigma = R u`` for any
displacement vector, or for many frames at once.

At a free surface the traction vanishes, so the only stress there is the one along the
surface (:func:`tangential_stress`); it is the largest principal stress where it pulls and
the smallest where it presses.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.fem.assembly import as_mesh, jacobian, strain_displacement
from spurdyn.fem.element import ElementQuadS2
from spurdyn.fem.material import Material, plane_stress_matrix

_G = 1.0 / math.sqrt(3.0)
#: The 2 x 2 Gauss points of the reference square, counter-clockwise from (-, -).
BARLOW_POINTS = np.array([[-_G, -_G], [_G, -_G], [_G, _G], [-_G, _G]])
#: Natural coordinates of the Q8 nodes: corners counter-clockwise, then the mid-sides.
NODE_POINTS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0],
                        [0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])


def extrapolation_matrix() -> NDArray[np.float64]:
    """``(8, 4)``: the nodal values of the bilinear field through the four Gauss-point
    values. In the Gauss points' own coordinates ``(s, t) = sqrt(3) (xi, eta)`` the field
    is ``sum_k (1 + s s_k)(1 + t t_k) / 4 v_k``, with the nodes at ``s, t = 0, +-sqrt(3)``."""
    sk = np.sign(BARLOW_POINTS)
    st = math.sqrt(3.0) * NODE_POINTS
    return 0.25 * (1.0 + st[:, None, 0] * sk[None, :, 0]) * (1.0 + st[:, None, 1] * sk[None, :, 1])


def surface_stress_operator(nodes: ArrayLike, elements: ArrayLike, surface: ArrayLike,
                            material: Material) -> NDArray[np.float64]:
    """The matrix ``R`` of shape ``(n_s, 3, 2 N)``: ``R @ u`` is ``(sxx, syy, txy)`` (Pa) at the
    ``n_s`` nodes ``surface`` for the interleaved displacements ``u`` (m) of the mesh.

    Each element holding a surface node gives that node its Gauss-point stresses
    extrapolated (:func:`extrapolation_matrix`); a node shared by several such elements
    takes their mean. :func:`surface_stress_columns` gives the same map over only the
    displacements it reads.
    """
    compact, dofs = surface_stress_columns(nodes, elements, surface, material)
    r = np.zeros(compact.shape[:2] + (2 * np.asarray(nodes).shape[0],))
    r[:, :, dofs] = compact
    return r


def surface_stress_columns(nodes: ArrayLike, elements: ArrayLike, surface: ArrayLike,
                           material: Material) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """:func:`surface_stress_operator` as ``(R_c, dofs)``: ``R_c @ u[dofs]`` is ``R @ u``,
    ``dofs`` the displacements of the elements that hold a surface node (a few per node,
    where ``R`` has a column for every DOF of the mesh)."""
    nd, el = as_mesh(nodes, elements)
    surf = np.asarray(surface, dtype=np.intp)
    where = {int(n): i for i, n in enumerate(surf)}
    if len(where) != surf.size:
        raise ValueError("surface nodes must be distinct")
    holding = np.flatnonzero(np.isin(el, surf).any(axis=1))
    dn = ElementQuadS2().dshape(BARLOW_POINTS[:, 0], BARLOW_POINTS[:, 1])     # (4, 8, 2)
    jac, det = jacobian(nd[el[holding]], dn)
    b = strain_displacement(jac, det, dn)                                    # (E, 4, 3, 16)
    db = np.einsum("kl,eglj->egkj", plane_stress_matrix(material), b)          # Gauss stresses
    at_nodes = np.einsum("ng,egkj->enkj", extrapolation_matrix(), db)         # (E, 8, 3, 16)
    element_dofs = np.stack([2 * el[holding], 2 * el[holding] + 1], axis=2).reshape(len(holding), 16)
    dofs, column = np.unique(element_dofs, return_inverse=True)
    column = column.reshape(element_dofs.shape)
    r = np.zeros((surf.size, 3, dofs.size))
    count = np.zeros(surf.size)
    for e_local, e in enumerate(holding):
        for n_local, node in enumerate(el[e]):
            i = where.get(int(node))
            if i is not None:
                r[i][:, column[e_local]] += at_nodes[e_local, n_local]
                count[i] += 1.0
    return r / count[:, None, None], dofs


def outline_tangents(points: ArrayLike) -> NDArray[np.float64]:
    """Unit tangents ``(n, 2)`` of a polyline through ``points`` (ordered along it): the
    chord of the two neighbours inside, the end chords at the ends. On a quadratic element
    edge the chord of a mid-side node's neighbours is the edge's exact tangent there."""
    p = np.asarray(points, dtype=float)
    t = np.empty_like(p)
    t[1:-1] = p[2:] - p[:-2]
    t[0] = p[1] - p[0]
    t[-1] = p[-1] - p[-2]
    return t / np.hypot(t[:, 0], t[:, 1])[:, None]


def tangential_stress(sig: ArrayLike, tangents: ArrayLike) -> NDArray[np.float64]:
    """``t . sigma . t`` for stresses ``(..., n, 3)`` (``sxx, syy, txy``) and tangents ``(n, 2)``."""
    s = np.asarray(sig, dtype=float)
    t = np.asarray(tangents, dtype=float)
    tx, ty = t[:, 0], t[:, 1]
    return s[..., 0] * tx * tx + s[..., 1] * ty * ty + 2.0 * s[..., 2] * tx * ty


def principal_stresses(sig: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The largest and smallest principal stresses of plane stresses ``(..., 3)``."""
    s = np.asarray(sig, dtype=float)
    mean = 0.5 * (s[..., 0] + s[..., 1])
    radius = np.hypot(0.5 * (s[..., 0] - s[..., 1]), s[..., 2])
    return mean + radius, mean - radius


__all__ = ["BARLOW_POINTS", "NODE_POINTS", "extrapolation_matrix", "outline_tangents",
           "principal_stresses", "surface_stress_columns", "surface_stress_operator",
           "tangential_stress"]
