"""Reference element and quadrature for 8-node serendipity quadrilaterals.

The element follows the scikit-fem idea of one small class per element: it
knows its reference nodes and how to evaluate its shape functions and their
reference derivatives, nothing about physics or geometry.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ElementQuadS2", "edge_dweights", "edge_weights", "gauss_2d"]


def _frozen(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``a`` marked read-only so shared tables cannot be mutated."""
    a.setflags(write=False)
    return a


class ElementQuadS2:
    """Quadratic 8-node serendipity quadrilateral (Q8) on ``[-1, 1]^2``.

    Node order in reference coordinates ``(xi, eta)``: the corners
    counter-clockwise, then the midsides, each midside following the corner
    with the same index (node 4 lies between corners 0 and 1, and so on)::

        3 --- 6 --- 2
        |           |
        7           5
        |           |
        0 --- 4 --- 1

    Attributes
    ----------
    ref_nodes : ndarray, shape (8, 2)
        Reference coordinates of the nodes (read-only).
    nnodes : int
        Number of nodes, 8.
    dim : int
        Spatial dimension, 2.

    Notes
    -----
    Corner ``i``: ``N = (1 + xi xi_i)(1 + eta eta_i)(xi xi_i + eta eta_i - 1) / 4``.
    Midside with ``xi_i = 0``: ``N = (1 - xi^2)(1 + eta eta_i) / 2``.
    Midside with ``eta_i = 0``: ``N = (1 + xi xi_i)(1 - eta^2) / 2``.
    """

    nnodes: int = 8
    dim: int = 2
    ref_nodes: NDArray[np.float64] = _frozen(
        np.array(
            [
                [-1.0, -1.0],
                [1.0, -1.0],
                [1.0, 1.0],
                [-1.0, 1.0],
                [0.0, -1.0],
                [1.0, 0.0],
                [0.0, 1.0],
                [-1.0, 0.0],
            ]
        )
    )

    def shape(self, xi: ArrayLike, eta: ArrayLike) -> NDArray[np.float64]:
        """Evaluate the shape functions.

        Parameters
        ----------
        xi, eta : array_like
            Reference coordinates; broadcast against each other.

        Returns
        -------
        ndarray, shape (..., 8)
            ``N[..., i]`` is shape function ``i`` at each point.
        """
        xi, eta = np.broadcast_arrays(np.asarray(xi, float), np.asarray(eta, float))
        xi = xi[..., None]
        eta = eta[..., None]
        xc, ec = self.ref_nodes[:4, 0], self.ref_nodes[:4, 1]
        corner = 0.25 * (1 + xi * xc) * (1 + eta * ec) * (xi * xc + eta * ec - 1)
        # Midsides 4 and 6 sit on eta = -1, +1; midsides 5 and 7 on xi = +1, -1.
        n4 = 0.5 * (1 - xi**2) * (1 - eta)
        n5 = 0.5 * (1 + xi) * (1 - eta**2)
        n6 = 0.5 * (1 - xi**2) * (1 + eta)
        n7 = 0.5 * (1 - xi) * (1 - eta**2)
        return np.concatenate([corner, n4, n5, n6, n7], axis=-1)

    def dshape(self, xi: ArrayLike, eta: ArrayLike) -> NDArray[np.float64]:
        """Evaluate the shape-function derivatives with respect to ``(xi, eta)``.

        Parameters
        ----------
        xi, eta : array_like
            Reference coordinates; broadcast against each other.

        Returns
        -------
        ndarray, shape (..., 8, 2)
            ``dN[..., i, 0] = dN_i/dxi`` and ``dN[..., i, 1] = dN_i/deta``.
        """
        xi, eta = np.broadcast_arrays(np.asarray(xi, float), np.asarray(eta, float))
        xi = xi[..., None]
        eta = eta[..., None]
        xc, ec = self.ref_nodes[:4, 0], self.ref_nodes[:4, 1]
        dc_dxi = 0.25 * xc * (1 + eta * ec) * (2 * xi * xc + eta * ec)
        dc_deta = 0.25 * ec * (1 + xi * xc) * (xi * xc + 2 * eta * ec)
        d_dxi = np.concatenate(
            [
                dc_dxi,
                -xi * (1 - eta),
                0.5 * (1 - eta**2),
                -xi * (1 + eta),
                -0.5 * (1 - eta**2),
            ],
            axis=-1,
        )
        d_deta = np.concatenate(
            [
                dc_deta,
                -0.5 * (1 - xi**2),
                -eta * (1 + xi),
                0.5 * (1 - xi**2),
                -eta * (1 - xi),
            ],
            axis=-1,
        )
        return np.stack([d_dxi, d_deta], axis=-1)


def gauss_2d(n: int = 3) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Tensor-product Gauss-Legendre rule on ``[-1, 1]^2``.

    Parameters
    ----------
    n : int, default 3
        Points per direction; the rule integrates polynomials of degree
        ``2 n - 1`` in each variable exactly.

    Returns
    -------
    points : ndarray, shape (n*n, 2)
        ``(xi, eta)`` of each point, ``xi`` varying fastest.
    weights : ndarray, shape (n*n,)
        Weights; they sum to 4, the reference area.
    """
    if int(n) != n or n < 1:
        raise ValueError(f"gauss_2d: n must be a positive integer (got {n!r})")
    x, w = np.polynomial.legendre.leggauss(int(n))
    xi, eta = np.meshgrid(x, x, indexing="xy")
    wx, we = np.meshgrid(w, w, indexing="xy")
    points = np.column_stack([xi.ravel(), eta.ravel()])
    weights = (wx * we).ravel()
    return points, weights


def edge_weights(eta: float) -> NDArray[np.float64]:
    """Quadratic shape functions of an element edge (root, middle, tip) at ``eta``.

    The trace of :class:`ElementQuadS2` on one of its sides, the one home of this
    formula (its compiled twin is :func:`spurdyn.contact.search_compiled.edge_shape`).
    """
    return np.array([0.5 * eta * (eta - 1.0), 1.0 - eta * eta, 0.5 * eta * (eta + 1.0)])


def edge_dweights(eta: float) -> NDArray[np.float64]:
    """``d/deta`` of :func:`edge_weights`."""
    return np.array([eta - 0.5, -2.0 * eta, eta + 0.5])
