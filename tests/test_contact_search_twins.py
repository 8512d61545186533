"""The twins of contact/search_numpy.py and contact/search_compiled.py (material points, sliding terms): each compiled function against its NumPy counterpart
(tolerances and the realistic state: tests/twin_helpers.py)."""

import dataclasses

import numpy as np
import pytest

from spurdyn.contact import search_numpy as cref
from spurdyn.contact import search_compiled as search_c
from spurdyn.contact.constants import F
from spurdyn.solvers.paper import dynamics_numpy as dyn_np

from twin_helpers import (  # noqa: F401
    EPS, JZ, Loaded, elastic_np, tangent_np, q_bound, node_size, cross_size, worst, rigid_plus_noise, _synthetic_contact, _gram_ref,
)


def test_edge_rows_and_surface_points_match_the_flank(loaded):
    """``edge_at``/``contact_rows`` are :meth:`Flank.locate`; ``data_positions`` (positions,
    velocities) is :func:`spurdyn.contact.search_numpy.data_values`; ``material_point``
    (positions, velocities, accelerations) is :func:`~spurdyn.contact.search_numpy.surface_point`,
    each to ``EPS`` times the size of the terms summed."""
    st, P, S = loaded, loaded.P, loaded.S
    rng = np.random.default_rng(2)
    acc = 1e5 * rng.standard_normal(S.u.size)          # nodal accelerations of the size of a run's
    al = np.array([3e4, -2e4])
    vmats = st.ref.velocity_mats(S.theta, S.omega)
    amats = st.ref.acceleration_mats(S.theta, S.omega, al)
    nd = P.fl_nodes.shape[1]
    out = np.empty((nd, 2))
    big = np.zeros(5)
    for g, gb in enumerate(st.system.gears):
        fl = gb.flank
        r = dyn_np.rot(gb.sense * S.theta[g])
        xg = gb.X + st.block(g, S.u).reshape(-1, 2)
        vg, ag = st.block(g, S.v).reshape(-1, 2), st.block(g, acc).reshape(-1, 2)
        tol_x = 4 * EPS * np.abs(xg).max()
        tol_v = 4 * EPS * (np.abs(vg).max() + abs(S.omega[g]) * 1e-6)
        tol_a = 4 * EPS * (np.abs(ag).max() + (abs(al[g]) + S.omega[g] ** 2) * 1e-6)
        search_c.data_positions(P, g, S.theta[g], 0.0, S.u, out, 0)
        big[0] = max(big[0], worst(out, cref.data_values(fl, xg, r)))
        assert worst(out, cref.data_values(fl, xg, r)) <= tol_x
        search_c.data_positions(P, g, S.theta[g], S.omega[g], S.v, out, 1)
        big[1] = max(big[1], worst(out, cref.data_values(fl, vg, vmats[g])))
        assert worst(out, cref.data_values(fl, vg, vmats[g])) <= tol_v
        for t in (fl.t0, 3.0, 4.3, 7.5, 9.99, fl.t1 - 1e-9, fl.t1):
            nodes, w, row = search_c.edge_at(P.fpar[g], P.side[g], t)
            ln, lw, _ = fl.locate(t)
            assert np.array_equal(nodes, ln + g * st.na) and row == min(int(t), fl.ny - 1)
            assert worst(w, lw) <= 4 * EPS
            got = [search_c.material_point(P, g, t, S.theta[g], S.u, 0, 0.0, 0.0),
                   search_c.material_point(P, g, t, S.theta[g], S.v, 1, S.omega[g], 0.0),
                   search_c.material_point(P, g, t, S.theta[g], acc, 2, S.omega[g], al[g])]
            want = [cref.surface_point(fl, t, xg, r), cref.surface_point(fl, t, vg, vmats[g]),
                    cref.surface_point(fl, t, ag, amats[g])]
            for kind, tol in enumerate((tol_x, tol_v, tol_a)):
                big[2 + kind] = max(big[2 + kind], worst(got[kind], want[kind]))
                assert worst(got[kind], want[kind]) <= tol
        # displacements 1e-12 m larger show
        search_c.data_positions(P, g, S.theta[g], 0.0, S.u + 1e-12, out, 0)
        assert worst(out, cref.data_values(fl, xg, r)) > 100 * tol_x
    cn, cw = np.empty(6, np.int64), np.empty(6)
    c = st.contact
    search_c.contact_rows(P, c.alpha, c.beta, cn, cw)
    assert np.array_equal(cn, st.rows(c)[0]) and worst(cw, st.rows(c)[1]) <= 4 * EPS
    print("data/material points (positions m, velocities m/s; points: m, m/s, m/s^2):", big)


def _sliding_tolerance(P, S, va, vb, ad, bd):
    """Round-off of the sliding terms: that of the splines' derivatives, ``~6 EPS |P| / h^2``
    and ``6 EPS |V| / h`` (``h`` the data spacing), times the rates."""
    hs = P.fpar[:, F.h].min()
    psize = max(np.abs(va).max(), np.abs(vb).max())
    vsize = np.abs(S.v).max()
    return 6 * EPS * ((ad * ad + bd * bd) * psize / hs**2 + 2 * (abs(ad) + abs(bd)) * vsize / hs)


@pytest.mark.parametrize("mode", [cref.FLANK, cref.CORNER_A, cref.CORNER_B])
def test_sliding_terms_match_appendix_a_reference(loaded, mode):
    """``search_c.sliding`` against :func:`spurdyn.contact.search_numpy.sliding_acceleration` at
    the state's contact pair (the state's positions and velocities; the position splines
    left by ``search``), in each mode's formula for ``alpha_dot``, ``beta_dot``.

    The terms are ``alpha_dot^2 n . P''`` and ``2 alpha_dot n . V'`` of splines through ~5 cm
    positions and ~100 m/s velocities: their round-off is that of the splines' derivatives,
    ``~6 EPS |P| / h^2`` and ``6 EPS |V| / h`` (``h`` the data spacing), times the rates.
    """
    st, P, S = loaded, loaded.P, loaded.S
    c = dataclasses.replace(st.contact, mode=mode)
    nd = P.fl_nodes.shape[1]
    va, vb, Ma, Mb = (np.empty((nd, 2)) for _ in range(4))
    a, b, mode_s, _, _, _ = search_c.search(P, S.theta, S.u, np.array([c.alpha, c.beta]), va, vb, Ma, Mb)
    assert mode_s == cref.FLANK and abs(a - c.alpha) < 1e-9 and abs(b - c.beta) < 1e-9
    got = search_c.sliding(P, S.theta, S.omega, S.u, S.v, c.alpha, c.beta, mode, c.normal[0], c.normal[1],
                            va, vb, Ma, Mb)
    gb = st.system.gears
    pos = [gb[g].X + st.block(g, S.u).reshape(-1, 2) for g in range(2)]
    vel = [st.block(g, S.v).reshape(-1, 2) for g in range(2)]
    rots = [dyn_np.rot(gb[g].sense * S.theta[g]) for g in range(2)]
    want, ad, bd = cref.sliding_acceleration(gb[0].flank, gb[1].flank, *pos, *rots, *vel,
                                             *st.ref.velocity_mats(S.theta, S.omega), c)
    tol = _sliding_tolerance(P, S, va, vb, ad, bd)
    assert abs(got - want) <= tol
    assert abs(want) > 1e6 * tol
    print(f"sliding mode {mode}: {abs(got - want):.1e} m/s^2 (tol {tol:.1e}, extra {want:.3e})")
    # velocities a part in 1e9 larger change the terms (quadratic in them) beyond that
    got2 = search_c.sliding(P, S.theta, S.omega, S.u, S.v * (1 + 1e-9), c.alpha, c.beta, mode,
                             c.normal[0], c.normal[1], va, vb, Ma, Mb)
    assert abs(got2 - got) > 10 * tol



@pytest.mark.parametrize("mode", [cref.FLANK, cref.CORNER_A, cref.CORNER_B])
def test_the_strips_search_and_sliding_terms_on_the_rigid_flanks_match_the_reference(loaded, mode):
    """With ``rigid`` (the distributed contact, docs/solver.md section 11.2) ``search`` finds
    the pair, mode and normal of the rigidly turned flanks and the deformed flanks' gap
    there, as :func:`~spurdyn.contact.search_numpy.find_contact` with ``locate``; ``sliding``
    takes the pair's rates from the rigid flanks and the terms from the deformed ones, as
    ``sliding_acceleration`` with ``rates_from`` (tolerance as in the test above)."""
    st, P, S = loaded, loaded.P, loaded.S
    nd = P.fl_nodes.shape[1]
    va, vb, Ma, Mb = (np.empty((nd, 2)) for _ in range(4))
    guess = np.array([st.contact.alpha, st.contact.beta])
    a, b, mode_s, nx, ny, s = search_c.search(P, S.theta, S.u, guess, va, vb, Ma, Mb, True)
    gb = st.system.gears
    pos = [gb[g].X + st.block(g, S.u).reshape(-1, 2) for g in range(2)]
    vel = [st.block(g, S.v).reshape(-1, 2) for g in range(2)]
    rots = [dyn_np.rot(gb[g].sense * S.theta[g]) for g in range(2)]
    located = dyn_np.rigid_flanks(st.system, S.theta, S.omega)
    c = cref.find_contact(gb[0].flank, gb[1].flank, *pos, *rots, tuple(guess), locate=tuple(located[:2]))
    assert mode_s == c.mode == cref.FLANK
    assert abs(a - c.alpha) < 1e-9 and abs(b - c.beta) < 1e-9
    assert worst(np.array([nx, ny]), c.normal) < 1e-12 and abs(s - c.s) < 1e-15
    # the deformed flanks' own pair lies elsewhere: the state's teeth are loaded
    assert abs(a - st.contact.alpha) + abs(b - st.contact.beta) > 1e-6
    c = dataclasses.replace(c, mode=mode)
    got = search_c.sliding(P, S.theta, S.omega, S.u, S.v, a, b, mode, nx, ny, va, vb, Ma, Mb, True)
    want, ad, bd = cref.sliding_acceleration(gb[0].flank, gb[1].flank, *pos, *rots, *vel,
                                             *st.ref.velocity_mats(S.theta, S.omega), c,
                                             rates_from=tuple(located))
    tol = _sliding_tolerance(P, S, va, vb, ad, bd)
    assert abs(got - want) <= tol
    assert abs(want) > 1e6 * tol
    # the deformed flanks' velocities a part in 1e9 larger change the terms beyond that
    got2 = search_c.sliding(P, S.theta, S.omega, S.u, S.v * (1 + 1e-9), a, b, mode, nx, ny,
                             va, vb, Ma, Mb, True)
    assert abs(got2 - got) > 10 * tol
