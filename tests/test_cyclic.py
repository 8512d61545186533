"""A whole gear's modes by its cyclic symmetry (:mod:`spurdyn.sector.cyclic`, docs/sector.md
6.9): one cell's harmonics hold the ring's energies, the modes found harmonic by harmonic
are the whole-ring eigen-solve's (:func:`~spurdyn.sector.reduced.reduce_gear` with
``method="ring"``), and so are the flank flexibility, the statics and a run on them."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from spurdyn import store
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector import cyclic, reduced
from spurdyn.sector.cyclic import FlankStatics, ring_cell
from spurdyn.sector.reduced import reduce_gear
from spurdyn.sector.system import gear_block

#: The paper's gear with 18 teeth (an even count: harmonic z / 2 is real) and 19 (odd), on
#: a coarse mesh; modes below 80 kHz (26 eigenmodes, 117 with the flank shapes).
GEAR = paper_pair().gear_a
TOP = 80e3


def _block(z: int, first: int | None = None, count: int | None = None):
    gear = dataclasses.replace(GEAR, teeth=z)
    return gear_block(gear, 1.0, -(z // 2) if first is None else first, count or z, 2, 4, 1.0)


@pytest.fixture(scope="module")
def even():
    return _block(18)


@pytest.fixture(scope="module")
def both(even):
    """The even gear reduced both ways (the ring's solve takes some seconds)."""
    return even, reduce_gear(even, TOP), reduce_gear(even, TOP, method="ring")


@pytest.mark.parametrize("z", [18, 19])
def test_a_cells_harmonics_hold_the_rings_energies(z):
    """A field of harmonic ``h`` spread round the ring has ``z`` times the harmonic's
    strain and kinetic energies, is zero on the hub and continuous across the cells' edges
    (the ring's stiffness sees every edge)."""
    blk = _block(z)
    cell = ring_cell(blk.body)
    rng = np.random.default_rng(3)
    everything = np.arange(blk.body.mesh.n_dof)
    held = np.setdiff1d(everything, blk.body.free_dofs)
    for h in sorted({0, 1, 4, z // 2}):
        k, m, t = cell.harmonic(h)
        x = rng.standard_normal(cell.n_ind) + (1j * rng.standard_normal(cell.n_ind) if k.dtype == complex else 0)
        ring = cell.at(everything, (t @ x)[:, None], h)[:, 0]
        assert np.abs(ring[held]).max() == 0.0
        u = ring[blk.body.free_dofs]
        strain, kinetic = np.vdot(u, blk.stiffness @ u).real, np.vdot(u, blk.mass * u).real
        assert strain == pytest.approx(z * np.vdot(x, k @ x).real, rel=1e-12)
        assert kinetic == pytest.approx(z * np.vdot(x, m * x).real, rel=1e-12)


def test_only_a_whole_ring_of_equal_cells_is_cyclic():
    assert ring_cell(_block(18, first=-2, count=5).body) is None


@pytest.mark.parametrize("z", [18, 19])
def test_the_cyclic_modes_are_modes_of_the_ring(z):
    """Without the ring's solve: the modes are M-orthonormal and diagonalise K over the whole
    ring, those below the top frequency are its eigenmodes, and the turning inertia's share
    is ``Phi^T M s``."""
    blk = _block(z)
    red = reduce_gear(blk, TOP)
    phi = red.phi_rows(np.arange(blk.mass.size))
    np.testing.assert_allclose(phi.T @ (blk.mass[:, None] * phi), np.eye(red.m), rtol=0, atol=1e-12)
    kphi = blk.stiffness @ phi
    np.testing.assert_allclose(phi.T @ kphi, np.diag(red.omega2), rtol=0, atol=1e-11 * red.omega2.max())
    below = red.omega2 < (2 * math.pi * TOP) ** 2
    resid = kphi[:, below] - (blk.mass[:, None] * phi[:, below]) * red.omega2[below]
    assert np.abs(resid).max() <= 1e-8 * np.abs(kphi[:, below]).max()
    np.testing.assert_allclose(red.coupling, phi.T @ (blk.mass * blk.rot), rtol=0, atol=1e-12 * np.abs(red.coupling).max())


@pytest.mark.slow
def test_the_cyclic_reduction_is_the_whole_rings(both):
    """Against the whole-ring solve: the eigenmodes' frequencies to 1e-11, every kept
    frequency to 1e-8 (the ring's Ritz step on its ill-conditioned basis is good to some
    5e-9 above the top here, 4.5e-7 on the design pair's pinion: docs/sector.md 6.9), and
    to 1e-10 against that step on an orthonormalised basis; the modes' flexibility at the flanks, the
    static flexibility and the residual to round-off (the ring's
    factor and the harmonics' solve the same statics to some 1e-11 of the largest entry)."""
    blk, cyc, ring = both
    assert cyc.m == ring.m
    target = (2 * math.pi * TOP) ** 2
    below = ring.omega2 < target
    np.testing.assert_allclose(cyc.omega2[below], ring.omega2[below], rtol=1e-11)
    np.testing.assert_allclose(cyc.omega2, ring.omega2, rtol=1e-8)
    # the whole ring's Ritz step redone on an M-orthonormalised basis: the harmonics' to 1e-10
    np.testing.assert_allclose(cyc.omega2, _orthonormal_ritz(blk, target), rtol=1e-10)
    for k in (blk.first, blk.first + 5):
        for side in (0, 1):
            a, b = cyc.modes_at(k, side), ring.modes_at(k, side)
            np.testing.assert_allclose((a / cyc.omega2) @ a.T, (b / ring.omega2) @ b.T, rtol=0,
                                       atol=1e-10 * np.abs(b).max() ** 2 / ring.omega2.min())
    for s in (0, 1):
        for t in (0, 1):
            want = ring.flank_flex(s, t)
            np.testing.assert_allclose(cyc.flank_flex(s, t), want, rtol=0, atol=1e-10 * np.abs(want).max())
    want = ring.static_response(blk.first + 3, 1)
    np.testing.assert_allclose(cyc.static_response(blk.first + 3, 1), want, rtol=0, atol=1e-10 * np.abs(want).max())
    want = ring.residual(blk.first + 4, blk.first + 2)
    np.testing.assert_allclose(cyc.residual(blk.first + 4, blk.first + 2), want, rtol=0, atol=1e-9 * np.abs(want).max())


def _orthonormal_ritz(blk, target: float) -> np.ndarray:
    """The whole-ring reduction's Ritz values on its basis M-orthonormalised (the shapes
    against the modes and among themselves, twice): the same span, no digits lost."""
    w2, vec = reduced._held_modes(blk, target)
    m = blk.mass
    shapes = blk.body.solve_free(np.column_stack([m * blk.rot, reduced._flank_loads(blk)]))
    for _ in range(2):
        shapes = shapes - vec @ (vec.T @ (m[:, None] * shapes))
        lam, u = np.linalg.eigh(shapes.T @ (m[:, None] * shapes))
        shapes = shapes @ u / np.sqrt(lam)
    basis = np.column_stack([vec, shapes])
    kr = basis.T @ (blk.stiffness @ basis)
    return np.linalg.eigvalsh(0.5 * (kr + kr.T))


def test_the_statics_read_the_flank_flexibility(even):
    """:class:`FlankStatics` gives the ring factor's compliance between drive-flank loads,
    and solves for loads anywhere else."""
    statics = FlankStatics(reduce_gear(even, TOP))
    body = even.body
    r = 0.5 * (body.flank.r0 + body.flank.r_tip)
    loads = np.column_stack([body.load(k, r, 1e-4) for k in (0, 1, -8, 8)])
    want = body.compliance(loads)
    np.testing.assert_allclose(statics.compliance(loads), want, rtol=0, atol=1e-10 * np.abs(want).max())
    loads[body.free_dofs[-1]] = 1.0                                  # on the rim: solved
    np.testing.assert_allclose(statics.compliance(loads), body.compliance(loads), rtol=1e-12)


def test_the_statics_kept_blocks_are_each_pair_of_teeths(even):
    """The blocks :class:`FlankStatics` keeps between calls (a mesh cycle asks for the same
    few some 600 times) are those of the pair of teeth asked for: after loads on other
    teeth (the same tooth distances at other teeth among them), a compliance is the one a
    fresh object computes, bit for bit."""
    reduction = reduce_gear(even, TOP)
    warm = FlankStatics(reduction)
    body = even.body
    r = 0.5 * (body.flank.r0 + body.flank.r_tip)
    for teeth in ((0, 1), (-8, -7), (2, 5), (-3, 0)):
        warm.compliance(np.column_stack([body.load(k, r, 1e-4) for k in teeth]))
    loads = np.column_stack([body.load(k, r, 1e-4) for k in (1, 2, -7, 4)])
    assert np.array_equal(warm.compliance(loads), FlankStatics(reduction).compliance(loads))


def test_the_store_gives_the_cyclic_modes_back_bit_for_bit(even, tmp_path, monkeypatch):
    monkeypatch.setenv("SPURDYN_MODE_CACHE", str(tmp_path))
    first = reduce_gear(even, TOP)
    assert len(store.entries(tmp_path)) == 1
    monkeypatch.setattr(reduced, "cyclic_modes", lambda *a: pytest.fail("the store's entry was not used"))
    again = reduce_gear(even, TOP)
    for name in ("y", "harm", "omega2", "coupling", "flex"):
        assert np.array_equal(getattr(first, name), getattr(again, name)), name
    assert isinstance(again, cyclic.CyclicGear)


def test_the_statics_and_fillet_maps_a_block_of_rows_at_a_time_are_the_whole_fields(even, monkeypatch):
    """The harmonics' static response formed :data:`cyclic.ROW_CHUNK` rows at a time (37
    here: many blocks and a short last one) against it formed over all the rows at once,
    as before the blocks (the fillets' maps then took a whole gear's field at every
    tooth's fillets in one piece): the same to round-off, at rows all round the ring and
    in the fillet maps of every tooth."""
    from spurdyn.sector.fillets import GearFillets

    monkeypatch.setenv("SPURDYN_MODE_CACHE", "off")       # the maps computed both times
    red = reduce_gear(even, TOP)
    rows = np.arange(0, even.mass.size, 3)
    gear = type("Gear", (), {"block": even, "reduced": red})()
    found = {}
    chunk = 37
    for size in (chunk, rows.size + 1):
        monkeypatch.setattr(cyclic, "ROW_CHUNK", size)
        fl = GearFillets(gear)
        found[size] = (red.static_rows(even.first + 2, rows), fl._static, fl._modes)
    assert rows.size % chunk and rows.size > 4 * chunk
    for new, old in zip(found[chunk], found[rows.size + 1]):
        assert new.shape == old.shape
        np.testing.assert_allclose(new, old, rtol=0, atol=1e-13 * np.abs(old).max())


@pytest.mark.parametrize("h", [0, 4])
def test_a_harmonics_unit_loads_solved_together_are_the_columns_one_by_one(even, h):
    """The static response's solve of all a flank's unit loads in one call on one BLAS
    thread (``together``, the fillet maps' path) against the columns one by one: the same
    to round-off on a real (0) and a complex (4) harmonic (measured: the same bits), and
    BLAS's thread count as it was."""
    from threadpoolctl import threadpool_info, threadpool_limits

    cell = ring_cell(even.body)
    k, _, _ = cell.harmonic(h)
    solve = cyclic._RealForm(k)
    loads = np.hstack([cyclic._unit_loads(cell, even, side) for side in (0, 1)])
    # the suite runs BLAS on one thread (conftest): two here, so a count not restored shows
    with threadpool_limits(limits=2, user_api="blas"):
        threads = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
        one, together = solve(loads), solve(loads, together=True)
        assert [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"] == threads
    assert together.dtype == one.dtype and np.abs(one).max() > 0.0
    np.testing.assert_allclose(together, one, rtol=0, atol=1e-14 * np.abs(one).max())
