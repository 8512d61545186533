"""The twins of iteration_numpy.py and iteration_compiled.py: each compiled function against its NumPy counterpart
(tolerances and the realistic state: tests/twin_helpers.py)."""


import numpy as np
import pytest

from spurdyn.solvers.paper import dynamics_compiled as dyn_c
from spurdyn.solvers.paper import iteration_compiled as it_c
from spurdyn.solvers.paper import iteration_numpy as iteration

from twin_helpers import (  # noqa: F401
    EPS, JZ, Loaded, elastic_np, tangent_np, q_bound, node_size, cross_size, worst, rigid_plus_noise, _synthetic_contact, _gram_ref,
)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_accelerated_update_matches_appendix_b_reference(loaded, n):
    """``accelerated_update`` against :func:`spurdyn.solvers.paper.iteration_numpy.accelerated_update` with
    ``C = scale G M^-1 G^T`` for the three stages' scales and error sizes, from ``x = 0``
    (the update alone), from the state's ``x``, with the contact inactive (``e_p = 0``), and
    with the contact row made the smallest eigenvalue (the other branch of the kernel's
    ``eps_1``). The kernel takes ``eps_1`` from the root block's eigenvalue computed once
    (``fast.root_eigenvalue``) where the reference solves for it each time: the same number
    to round-off. The recursions ``apply_a``/``apply_c`` are compared too.

    Tolerance: ``1e-12`` of the update (the conditioning of ``A_n`` in ``eps_1`` and the
    eigen-solve's round-off, observed ~1e-15) plus ``EPS |x|``.
    """
    st, S = loaded, loaded.S
    m = S.x.size
    h = st.case.dt
    eps_root = st.fast.cfg[6]
    C = np.empty((m, m))
    dyn_c.gram(st.P, S.theta, *st.rows(st.contact), st.contact.normal, st.gth(st.contact), C)
    rng = np.random.default_rng(10 + n)
    # contact row scaled: still G M^-1 G^T of a (lighter-looking) contact, p's eigenvalue smallest
    Cs = C.copy()
    Cs[-1, :] *= 0.1
    Cs[:, -1] *= 0.1
    assert Cs[-1, -1] < eps_root
    big = np.zeros(2)
    for scale, emag in ((0.5 * h * h, 1e-12), (h, 1e-12 / h), (1.0, 1e-12 / h**2)):
        for x0, cmat, active in ((np.zeros(m), C, True), (S.x, C, True), (S.x, C, False),
                                 (np.zeros(m), Cs, True)):
            e = emag * rng.standard_normal(m)
            if not active:
                e[-1] = 0.0
            want = iteration.accelerated_update(x0, e, scale * cmat, n)
            got = x0.copy()
            it_c.accelerated_update(got, e, cmat, scale, n, eps_root, np.empty((m, m)), np.empty(m), e[-1] != 0.0, 0.0)
            tol = 1e-12 * np.abs(want - x0).max() + 4 * EPS * np.abs(x0).max()
            assert worst(got, want) <= tol
            k = int(np.abs(x0).max() > 0)     # the update alone, or on top of x
            unit = np.abs(want - x0).max() if k == 0 else EPS * np.abs(x0).max()
            big[k] = max(big[k], worst(got, want) / unit)
            if not active:
                assert got[-1] == x0[-1]
    # a contact row held at its target (zero error, still in C': its C_pp enters eps_1)
    # against the reference given the same mask
    e = 1e-12 * rng.standard_normal(m)
    e[-1] = 0.0
    want = iteration.accelerated_update(S.x, e, 0.5 * h * h * C, n, np.ones(m, dtype=bool))
    got = S.x.copy()
    it_c.accelerated_update(got, e, C, 0.5 * h * h, n, eps_root, np.empty((m, m)), np.empty(m), True, 0.0)
    assert worst(got, want) <= 1e-12 * np.abs(want - S.x).max() + 4 * EPS * np.abs(S.x).max()
    print(f"accelerated_update n={n}: from x = 0 {big[0]:.1e} of the update; from the state's x "
          f"{big[1]:.2f} EPS |x|")
    # eps_1 matters (b_bar and the b_k depend on it): 1 % off changes the update beyond the tolerance
    e = 1e-12 * rng.standard_normal(m)
    got, got2 = np.zeros(m), np.zeros(m)
    it_c.accelerated_update(got, e, C, 0.5 * h * h, n, eps_root, np.empty((m, m)), np.empty(m), True, 0.0)
    it_c.accelerated_update(got2, e, C, 0.5 * h * h, n, 1.01 * eps_root, np.empty((m, m)), np.empty(m), True, 0.0)
    assert worst(got, got2) > 1e3 * 1e-12 * np.abs(got).max()
    # the recursions themselves
    c1 = C / np.abs(C).sum(1).max()
    b, _, _, _ = iteration.coefficients(n, 0.02)
    for k in range(1, n + 1):
        out = np.empty(m)
        it_c.apply_c(c1, b, k, e, out)
        want = iteration.apply_c(c1, b, k, e)
        assert worst(out, want) <= 1e-13 * np.abs(want).max()
    out = np.empty(m)
    it_c.apply_a(c1, b, n, e, out)
    assert worst(out, iteration.apply_a(c1, b, n, e)) <= 1e-13 * np.abs(out).max()


def test_band_value_matches_its_reference():
    """``band_value`` (compiled) against its NumPy twin, and the rule itself: a contact error
    inside the band is held, one outside is brought inside by its excess (at least the
    margin, at most to zero), keeping its sign."""
    tol, margin = 1e-12, 1e-4
    cases = [0.0, 0.3e-12, -1e-12, 1.0000001e-12, -1.5e-12, 2.5e-12, -7e-9, 1e-12 + 1e-20]
    want = [iteration.band_value(e, tol, margin) for e in cases]
    got = [it_c.band_value(e, tol, margin) for e in cases]
    assert got == want
    for e, t in zip(cases, want):
        if abs(e) <= tol:
            assert t == e
        else:
            assert abs(t) < tol and t * e >= 0.0
    assert want[4] == pytest.approx(-0.5e-12, rel=1e-12)         # excess 0.5 tol: inset 0.5 tol
    assert want[5] == 0.0 and want[6] == 0.0                        # excess beyond tol: aim at zero
    assert want[7] == pytest.approx(tol * (1 - margin), rel=1e-12)  # tiny excess: the margin

