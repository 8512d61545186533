"""Surface stress recovery (spurdyn.fem.recovery) against fields it must reproduce exactly
and against Lame's thick ring."""

import math

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from spurdyn.fem.assembly import assemble_stiffness
from spurdyn.fem.element import edge_weights, gauss_2d
from spurdyn.fem.material import STEEL, plane_stress_matrix
from spurdyn.fem.recovery import (BARLOW_POINTS, NODE_POINTS, extrapolation_matrix,
                                  outline_tangents, principal_stresses,
                                  surface_stress_operator, tangential_stress)
from spurdyn.geometry import paper_gear
from spurdyn.mesh import tooth_mesh


def test_extrapolation_reproduces_bilinear_fields_at_the_nodes():
    e = extrapolation_matrix()
    rng = np.random.default_rng(0)
    for _ in range(5):
        c = rng.standard_normal(4)
        f = lambda p: c[0] + c[1] * p[:, 0] + c[2] * p[:, 1] + c[3] * p[:, 0] * p[:, 1]  # noqa: E731
        np.testing.assert_allclose(e @ f(BARLOW_POINTS), f(NODE_POINTS), atol=1e-14)
    np.testing.assert_allclose(e.sum(axis=1), 1.0, atol=1e-15)


@pytest.mark.parametrize("grading", [1.0, 6.0])
def test_a_constant_strain_is_recovered_exactly_on_the_curved_tooth_mesh(grading):
    """Patch test: a linear displacement field has a constant stress, which every
    surface node of the (curved, distorted, graded) tooth mesh recovers to round-off."""
    mesh = tooth_mesh(paper_gear(), 4, 14, grading=grading)
    eps = np.array([2e-4, -1e-4, 3e-4])          # exx, eyy, gamma_xy
    x, y = mesh.nodes[:, 0], mesh.nodes[:, 1]
    u = np.column_stack([eps[0] * x + 0.5 * eps[2] * y, eps[1] * y + 0.5 * eps[2] * x]).ravel()
    surface = np.concatenate([mesh.right_side, mesh.left_side[1:]])
    sig = surface_stress_operator(mesh.nodes, mesh.elements, surface, STEEL) @ u
    expect = plane_stress_matrix(STEEL) @ eps
    np.testing.assert_allclose(sig, np.broadcast_to(expect, sig.shape), rtol=1e-9, atol=1e-6)


def test_principal_and_tangential_stresses():
    sig = np.array([[3.0, 1.0, 0.0], [0.0, 0.0, 2.0], [1.0, 1.0, 0.0]])
    hi, lo = principal_stresses(sig)
    np.testing.assert_allclose(hi, [3.0, 2.0, 1.0])
    np.testing.assert_allclose(lo, [1.0, -2.0, 1.0])
    t = outline_tangents(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    np.testing.assert_allclose(t, np.full((3, 2), math.sqrt(0.5)))
    # along 45 deg: (sxx + syy)/2 + txy
    np.testing.assert_allclose(tangential_stress(sig, t), [2.0, 2.0, 1.0])


def _ring(a, b, nr, nt):
    """Quarter ring a <= r <= b, 0 <= theta <= pi/2 in Q8: nodes, elements, node grid."""
    ni, nj = 2 * nr + 1, 2 * nt + 1
    index = -np.ones((ni, nj), dtype=np.intp)
    pts = []
    for j in range(nj):
        for i in range(ni):
            if i % 2 and j % 2:
                continue
            index[i, j] = len(pts)
            r, t = a + (b - a) * i / (ni - 1), 0.5 * math.pi * j / (nj - 1)
            pts.append((r * math.cos(t), r * math.sin(t)))
    el = []
    for ey in range(nt):
        for ex in range(nr):
            i, j = 2 * ex, 2 * ey
            el.append([index[i, j], index[i + 2, j], index[i + 2, j + 2], index[i, j + 2],
                       index[i + 1, j], index[i + 2, j + 1], index[i + 1, j + 2], index[i, j + 1]])
    return np.array(pts), np.array(el), index


def _lame_inner_hoop(nr, nt, a=0.01, b=0.02, p=1e8):
    nodes, elements, index = _ring(a, b, nr, nt)
    k = assemble_stiffness(nodes, elements, STEEL, 1.0).tocsr()
    f = np.zeros(2 * len(nodes))
    inner = index[0, :]
    xi, wq = gauss_2d(3)                       # use the 1-D rule of its first coordinate
    g1 = np.unique(xi[:, 0])
    w1 = np.array([5 / 9, 8 / 9, 5 / 9])
    for e in range(nt):
        edge = inner[2 * e:2 * e + 3]
        for g, w in zip(g1, w1):
            n = edge_weights(g)
            pos = n @ nodes[edge]
            t = np.array([-pos[1], pos[0]]) / a * (0.25 * math.pi * a / nt)   # dx/deta
            ds = math.hypot(*t)
            rhat = pos / math.hypot(*pos)
            for m in range(3):
                f[2 * edge[m]:2 * edge[m] + 2] += w * n[m] * p * rhat * ds
    fixed = np.concatenate([2 * index[:, 0] + 1, 2 * index[:, -1]])   # symmetry
    free = np.setdiff1d(np.arange(2 * len(nodes)), fixed)
    u = np.zeros(2 * len(nodes))
    u[free] = spsolve(k[free][:, free].tocsc(), f[free])
    sig = surface_stress_operator(nodes, elements, inner, STEEL) @ u
    hoop = tangential_stress(sig, outline_tangents(nodes[inner]))
    exact = p * (b * b + a * a) / (b * b - a * a)
    return hoop, exact, sig, nodes[inner]


def test_lame_ring_hoop_stress_at_the_bore_converges():
    """Lame: under an internal pressure p the hoop stress at the bore is
    p (b^2 + a^2) / (b^2 - a^2) and the radial stress -p. The recovered surface stress
    approaches it as the mesh is refined, at the rate of the quadratic elements."""
    errors = []
    for n in (2, 4, 8):
        hoop, exact, sig, pts = _lame_inner_hoop(n, 2 * n)
        errors.append(np.abs(hoop / exact - 1.0).max())
    assert errors[2] < 0.01
    assert errors[1] < errors[0] / 2.5 and errors[2] < errors[1] / 2.5
    # the normal stress at the bore is the pressure, recovered as well
    _, _, sig, pts = _lame_inner_hoop(8, 16)
    rhat = pts / np.hypot(pts[:, 0], pts[:, 1])[:, None]
    normal = tangential_stress(sig, rhat)
    np.testing.assert_allclose(normal, -1e8, rtol=0.03)


def test_the_compact_columns_are_the_operator():
    from spurdyn.fem.recovery import surface_stress_columns

    mesh = tooth_mesh(paper_gear(), 6, 20)
    surface = mesh.right_side[:9]
    full = surface_stress_operator(mesh.nodes, mesh.elements, surface, STEEL)
    compact, dofs = surface_stress_columns(mesh.nodes, mesh.elements, surface, STEEL)
    assert dofs.size < full.shape[2] / 5
    unused = np.setdiff1d(np.arange(full.shape[2]), dofs)
    assert not full[:, :, unused].any()
    u = np.random.default_rng(2).standard_normal(full.shape[2])
    np.testing.assert_allclose(compact @ u[dofs], full @ u, rtol=1e-13, atol=1e-3)
