"""Fixtures shared by several test files, where pytest-xdist runs each test, and BLAS on one
thread."""

import inspect
import os
import shutil
import tempfile
from pathlib import Path

# BLAS on one thread in the test processes (and the processes they start), unless the caller
# says otherwise: under `make test` two workers share the two cores, and OpenBLAS's own two
# threads each (spinning while they wait) made the sector model's eigen-solves five to six
# times slower on a loaded machine (tests/test_torque_history.py's idling run 57-68 s with two
# threads, 10-13 s with one, a load of 3.6). The sector runs' time loops already step on one
# thread (spurdyn.solvers.sector.run); their models' eigen-solves come before that limit.
if not any(os.environ.get(k) for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")):
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")   # numpy may be loaded already (a plugin)

import pytest

from spurdyn.contact.constants import FLANK
from twin_helpers import Loaded

TESTS = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def loaded():
    """The paper's pair after 1,500 compiled steps at 20,000 rpm (twin_helpers.Loaded)."""
    st = Loaded()
    assert st.S.x[-1] < -100.0                    # pressed together by ~200 N
    assert st.contact.mode == FLANK
    assert 0.05 < st.S.theta[0] < 0.14            # on the torque ramp (non-zero slope)
    return st


#: Where the run's mode store is, and the variables it set as they were (the controller's stash).
_STORE = pytest.StashKey[tuple]()
_STORE_VARIABLES = ("SPURDYN_MODE_CACHE", "SPURDYN_MODE_CACHE_SIZE")


def pytest_configure(config):
    """A mode store (:mod:`spurdyn.store`) of this run's own, empty at its start and shared
    by its workers (which inherit the variable): a gear's modes are computed once a run
    whichever files ask for them, and never come from a run of other code or another day."""
    if hasattr(config, "workerinput"):
        return
    folder = tempfile.mkdtemp(prefix="spurdyn-modes-")
    config.stash[_STORE] = (folder, {k: os.environ.get(k) for k in _STORE_VARIABLES})
    os.environ["SPURDYN_MODE_CACHE"] = folder
    # a run's modes take a few hundred MB; /tmp may be memory
    os.environ["SPURDYN_MODE_CACHE_SIZE"] = "1000"


def pytest_unconfigure(config):
    """The run's store removed, the variables as they were (pytest run in-process)."""
    found = config.stash.get(_STORE, None)
    if found is None:
        return
    folder, before = found
    shutil.rmtree(folder, ignore_errors=True)
    for k, value in before.items():
        if value is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = value


def _shares_a_fixture(item: pytest.Item) -> bool:
    """Whether ``item`` uses a module- or session-scoped fixture of this suite."""
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    for defs in info.name2fixturedefs.values():
        d = defs[-1]
        if d.scope in ("module", "package", "session"):
            try:
                if TESTS in Path(inspect.getfile(d.func)).resolve().parents:
                    return True
            except TypeError:
                pass
    return False


def pytest_collection_modifyitems(config, items):
    """Under ``--dist loadgroup`` (``make test``, ``make check``): the tests of a file that
    share one of its module fixtures (or a session fixture) run on one worker, which builds
    the fixture once; every other test goes to whichever worker is free, so that one long
    file (the sector model's) does not hold up the run on one core. (With pytest 9.2 and
    pytest-xdist 3.8 the groups do not take effect: docs/performance.md, "The test suite's
    time".)"""
    for item in items:
        if _shares_a_fixture(item):
            item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::")[0]))
    if hasattr(config, "workerinput"):
        items.sort(key=_schedule_rank)


def _schedule_rank(item: pytest.Item) -> int:
    """Where a test stands in a worker's collection (pytest-xdist hands out the groups of
    several tests first, then single tests in this order): the slow tests first, so that
    the run ends on the short ones and no core idles while the other finishes a long test
    started last (docs/performance.md, "The test suite's time"). A sort that keeps the order
    of equals, the same on both workers; a serial run keeps the files' order (a file's module
    fixtures are built once)."""
    return 0 if item.get_closest_marker("slow") is not None else 1
