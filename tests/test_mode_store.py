"""The mode store (:mod:`spurdyn.store`): a body's modes read back are the computed ones to
the last bit, an entry that does not match its body is never used, a broken entry is
computed again, and the store keeps to its size."""

from __future__ import annotations

import os
import threading

import numpy as np
import pytest

from spurdyn import store
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector import reduced
from spurdyn.sector.reduced import reduce_gear
from spurdyn.sector.system import gear_block

#: Three teeth of the paper's gear on a coarse mesh (a few seconds a reduction: the tests
#: that reduce one are slow).
GEAR = paper_pair().gear_a
TOP = 40e3


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """An empty store of this test's own."""
    monkeypatch.setenv("SPURDYN_MODE_CACHE", str(tmp_path / "modes"))
    reduced._HELD.clear()
    return tmp_path / "modes"


@pytest.fixture(scope="module")
def block():
    return gear_block(GEAR, 1.0, 0, 3, 2, 8, 1.0)


def _same(a, b) -> None:
    for name in ("phi", "omega2", "coupling"):
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and x.shape == y.shape and x.flags.c_contiguous == y.flags.c_contiguous
        assert np.array_equal(x, y), name


@pytest.mark.slow
def test_modes_read_back_are_the_computed_ones_bit_for_bit(folder, block, monkeypatch):
    first = reduce_gear(block, TOP)
    assert len(store.entries(folder)) == 1
    # computed again in a process that never saw them: neither the store nor the memo
    monkeypatch.setenv("SPURDYN_MODE_CACHE", store.OFF)
    reduced._HELD.clear()
    fresh = reduce_gear(block, TOP)
    monkeypatch.setenv("SPURDYN_MODE_CACHE", str(folder))
    reduced._HELD.clear()
    calls = []
    monkeypatch.setattr(reduced, "_lanczos", lambda *a: calls.append(a))
    again = reduce_gear(block, TOP)
    assert not calls, "the store's entry was not used"
    _same(first, fresh)
    _same(first, again)


@pytest.mark.slow
def test_a_body_that_differs_is_not_served_anothers_modes(folder, block):
    reduce_gear(block, TOP)
    other = gear_block(GEAR, 1.0, 0, 3, 3, 8, 1.0)          # another mesh
    lower = reduce_gear(block, 0.5 * TOP)                   # another kept frequency
    red = reduce_gear(other, TOP)
    assert len(store.entries(folder)) == 3
    assert lower.m < reduce_gear(block, TOP).m
    assert red.phi.shape[0] == other.mass.size


@pytest.mark.slow
def test_a_broken_entry_is_computed_again_and_replaced(folder, block):
    first = reduce_gear(block, TOP)
    (entry,) = store.entries(folder)
    entry.write_bytes(entry.read_bytes()[:1000])
    reduced._HELD.clear()
    again = reduce_gear(block, TOP)
    _same(first, again)
    (entry,) = store.entries(folder)
    assert store.load(entry.stem) is not None


def test_the_store_drops_what_was_read_longest_ago_beyond_its_size(folder, monkeypatch):
    data = np.zeros(125_000)                                 # 1 MB an entry
    for i in range(3):
        store.save(f"k{i}", x=data)
        os.utime(folder / f"k{i}.npz", (1e9 + i, 1e9 + i))       # saved in this order
    store.load("k0")                                         # read last: kept
    monkeypatch.setenv("SPURDYN_MODE_CACHE_SIZE", "2.5")
    store.save("k3", x=data)
    assert sorted(p.stem for p in store.entries(folder)) == ["k0", "k3"]
    assert store.clear() == 2 and store.entries(folder) == []


def test_writers_of_one_entry_at_once_leave_it_whole(folder):
    data = np.random.default_rng(1).normal(size=(400, 300))
    threads = [threading.Thread(target=store.save, args=("same",), kwargs={"x": data}) for _ in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert np.array_equal(store.load("same")["x"], data)
    assert list(folder.glob("*.part")) == []


@pytest.mark.slow
def test_a_store_turned_off_writes_nothing(tmp_path, monkeypatch, block):
    monkeypatch.setenv("SPURDYN_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("SPURDYN_MODE_CACHE", "off")
    assert store.store_folder() is None
    reduce_gear(block, TOP)
    store.save("k", x=np.zeros(3))
    assert store.load("k") is None and list(tmp_path.rglob("*.npz")) == []


def test_spurdyn_cache_tells_the_store_and_clears_it(folder, capsys):
    from spurdyn.cli.main import main

    store.save("k", x=np.zeros(125_000))
    assert main(["cache"]) == 0
    assert f"{folder}: 1 entries, 1.0 MB" in capsys.readouterr().out
    assert main(["cache", "--clear"]) == 0
    assert "1 entries removed" in capsys.readouterr().out
    assert store.entries(folder) == []


@pytest.mark.slow
def test_a_flanks_static_response_read_back_is_the_solved_one(folder, block, monkeypatch):
    solved = reduce_gear(block, TOP).static_response(1, 1)
    read = reduce_gear(block, TOP)
    monkeypatch.setattr(type(block.body), "solve_free", lambda self, rhs: pytest.fail("solved again"))
    again = read.static_response(1, 1)
    assert again.dtype == solved.dtype and np.array_equal(again, solved)


@pytest.mark.parametrize("variable, value", [("SPURDYN_MODE_CACHE_SIZE", "abc"),
                                             ("SPURDYN_MODE_CACHE_SIZE", "-1"),
                                             ("SPURDYN_MODE_CACHE_SIZE", "inf")])
def test_a_bad_store_size_is_refused_in_one_line(folder, monkeypatch, capsys, variable, value):
    from spurdyn.cli.main import main

    monkeypatch.setenv(variable, value)
    assert main(["cache"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and variable in err[0] and "Traceback" not in err[0]


def test_a_store_that_is_a_file_is_refused_in_one_line(tmp_path, monkeypatch, capsys):
    from spurdyn.cli.main import main

    path = tmp_path / "modes"
    path.write_text("not a folder")
    monkeypatch.setenv("SPURDYN_MODE_CACHE", str(path))
    assert main(["cache"]) == 2
    (err,) = capsys.readouterr().err.strip().splitlines()
    assert "SPURDYN_MODE_CACHE" in err and "not a folder" in err


def test_a_write_that_fails_leaves_nothing_behind(folder, monkeypatch):
    def full_disk(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(np, "savez", full_disk)
    store.save("k", x=np.zeros(10))
    assert list(folder.iterdir()) == []


def test_an_entry_is_readable_by_whoever_may_read_the_folder(folder):
    old = os.umask(0o022)
    try:
        store.save("k", x=np.zeros(10))
    finally:
        os.umask(old)
    assert (folder / "k.npz").stat().st_mode & 0o777 == 0o644


def test_the_code_revision_does_not_hang_on_the_order_the_blas_libraries_loaded(monkeypatch):
    """threadpoolctl lists the libraries in the order a process loaded them (NumPy's and
    SciPy's OpenBLAS come either way round): the key must not see it."""
    libs = [{"internal_api": "openblas", "version": v, "architecture": "x", "num_threads": 2} for v in ("1", "2")]
    monkeypatch.setattr(store, "threadpool_info", lambda: libs)
    first = store.code_revision(__name__)
    monkeypatch.setattr(store, "threadpool_info", lambda: libs[::-1])
    assert store.code_revision(__name__) == first
    monkeypatch.setattr(store, "threadpool_info", lambda: libs[:1])
    assert store.code_revision(__name__) != first
