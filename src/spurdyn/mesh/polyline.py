"""A crack that has grown: a polyline from its mouth through its kinks to its tip, its seam
split piece by piece (docs/fracture.md, section 8).

A straight crack's seam is split by one normal (:func:`spurdyn.mesh.cracked.split_seam`). A
kinked one has a normal per piece; an element touching the crack is on the side its nodes
off the crack lie, each measured from the piece nearest it (from a kink, along the two
pieces' mean normal, which is the side for every point whose nearest point of the
polyline is that kink).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["piece_normals", "side_of", "split_polyline_seam", "vertex_normals"]


def piece_normals(path: NDArray[np.float64], sense: float) -> NDArray[np.float64]:
    """``(k - 1, 2)`` each piece's unit normal, its direction turned a quarter counter-
    clockwise times ``sense`` (+1 or -1: the same side of the crack all along)."""
    d = np.diff(path, axis=0)
    d /= np.hypot(*d.T)[:, None]
    return sense * np.column_stack([-d[:, 1], d[:, 0]])


def vertex_normals(path: NDArray[np.float64], sense: float) -> NDArray[np.float64]:
    """``(k, 2)`` a unit normal at each point of the path: the piece's at the ends, the two
    pieces' mean at a kink."""
    n = piece_normals(path, sense)
    out = np.vstack([n[:1], 0.5 * (n[:-1] + n[1:]), n[-1:]])
    return out / np.hypot(*out.T)[:, None]


def side_of(points: NDArray[np.float64], path: NDArray[np.float64], sense: float
            ) -> NDArray[np.float64]:
    """The signed distance of each of ``points`` ``(m, 2)`` from the polyline ``path``,
    positive on the side of its normals (:func:`piece_normals`), measured from its nearest
    point: a piece's interior by the piece's normal, a kink (or an end) by
    :func:`vertex_normals`."""
    a, b = path[:-1], path[1:]
    ab = b - a
    t = np.einsum("mkj,kj->mk", points[:, None, :] - a[None], ab) / np.einsum("kj,kj->k", ab, ab)
    tc = np.clip(t, 0.0, 1.0)
    near = a[None] + tc[..., None] * ab[None]
    dist = np.hypot(*(points[:, None, :] - near).transpose(2, 0, 1))
    k = np.argmin(dist, axis=1)
    rows = np.arange(points.shape[0])
    tk = tc[rows, k]
    normal = piece_normals(path, sense)[k]
    vn = vertex_normals(path, sense)
    normal = np.where((tk <= 0.0)[:, None], vn[k], normal)
    normal = np.where((tk >= 1.0)[:, None], vn[k + 1], normal)
    return np.einsum("mj,mj->m", points - near[rows, k], normal)


def split_polyline_seam(nodes: NDArray[np.float64], elements: NDArray[np.intp],
                        seam: NDArray[np.intp], path: NDArray[np.float64], sense: float
                        ) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.intp],
                                   NDArray[np.float64]]:
    """Double the nodes ``seam`` of the crack ``path`` (its nodes but the tip, mouth first):
    the elements on the side of the normals (:func:`piece_normals` with ``sense``) take the
    twins.

    Returns the nodes with the twins appended, the elements, the ``(S, 2)`` seam (face one,
    face two) and ``(S, 2)`` the crack's normal at each twin (its piece's, a kink's mean).
    Raises ``RuntimeError`` if an element touching the crack lies on both of its sides.
    """
    twin = np.full(nodes.shape[0], -1, dtype=np.intp)
    twin[seam] = nodes.shape[0] + np.arange(seam.size)
    on_crack = np.zeros(nodes.shape[0], dtype=bool)
    on_crack[seam] = True
    tol = 1e-9 * np.ptp(nodes, axis=0).max()
    touching = np.flatnonzero(np.any(twin[elements] >= 0, axis=1))
    rows = elements[touching]
    s = side_of(nodes[rows.ravel()], path, sense).reshape(rows.shape)
    s = np.where(on_crack[rows] | (np.abs(s) <= tol), 0.0, s)
    both = (s.max(axis=1) > 0.0) & (s.min(axis=1) < 0.0)
    if np.any(both):
        # an element at the tip may reach across the last piece's line ahead of the tip:
        # its nodes there do not tell the side
        d = path[-1] - path[-2]
        ahead = (nodes[rows[both].ravel()] - path[-1]) @ d > 0.0
        s[both] = np.where(ahead.reshape(rows[both].shape), 0.0, s[both])
    if np.any((s.max(axis=1) > 0.0) & (s.min(axis=1) < 0.0)):
        raise RuntimeError("an element straddles the crack")
    two = s.max(axis=1) > 0.0
    out = elements.copy()
    out[touching[two]] = np.where(twin[rows[two]] >= 0, twin[rows[two]], rows[two])
    _check_faces(out, seam, twin)
    normals = _twin_normals(nodes[seam], path, sense)
    return (np.concatenate([nodes, nodes[seam]]), out, np.stack([seam, twin[seam]], axis=1),
            normals)


def _check_faces(elements: NDArray[np.intp], seam: NDArray[np.intp], twin: NDArray[np.intp]) -> None:
    """Refuse (``RuntimeError``) a split whose free edges along the crack are not its two
    faces: each of the crack's element edges free once on either side (``seam.size`` edges
    whose mid-side node is the crack's), and no other free edge at a crack node but the
    outline's at the mouth (an element given to the wrong side leaves an edge of the crack
    joined and opens one across the material)."""
    from spurdyn.mesh.gmsh_quads import boundary_edges

    n = int(elements.max()) + 1
    crack = np.zeros(n, dtype=bool)
    crack[seam] = True
    crack[twin[seam]] = True
    mouth = np.zeros(n, dtype=bool)
    mouth[[seam[0], twin[seam[0]]]] = True
    edges = boundary_edges(elements)
    faces = crack[edges[:, 1]]
    stray = ~faces & crack[edges].any(axis=1) & ~mouth[edges].any(axis=1)
    if np.count_nonzero(faces) != seam.size or np.any(stray):
        raise RuntimeError("the crack's faces do not follow the crack")


def _twin_normals(points: NDArray[np.float64], path: NDArray[np.float64], sense: float
                  ) -> NDArray[np.float64]:
    """The crack's unit normal at each of ``points`` (on the crack): its piece's, or at a kink
    the two pieces' mean."""
    vn = vertex_normals(path, sense)
    pn = piece_normals(path, sense)
    out = np.empty_like(points)
    for i, p in enumerate(points):
        at = np.hypot(*(path - p).T)
        k = int(np.argmin(at))
        if at[k] <= 1e-9 * np.ptp(path, axis=0).max():
            out[i] = vn[k]
            continue
        a, b = path[:-1], path[1:]
        ab = b - a
        t = np.clip(np.einsum("kj,kj->k", p - a, ab) / np.einsum("kj,kj->k", ab, ab), 0.0, 1.0)
        out[i] = pn[int(np.argmin(np.hypot(*(a + t[:, None] * ab - p).T)))]
    return out
